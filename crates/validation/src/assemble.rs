//! From the runs of a scene to its entry in `report.json`: the fronts of every family, ours
//! (the reduced solver's three integrators together) against each rapier f64 engine, and the
//! per-run rows ([`scene_report`]); and the scenes' entries with the stability suite into the
//! whole report ([`report`]).

use crate::pareto::{EqualError, EqualTime, Front, Point, TimeToError};
use crate::plan::{
    ACCURACY_LEVELS, CARTESIAN_CHECK_TOLERANCE, EQUAL_ERROR, ERROR_RATIO_TARGET, Family, Plan, SAMPLE_INTERVAL,
    Setting, TIME_RATIO_TARGET,
};
use crate::runs::{Availability, FamilyRuns, SceneRuns};
use crate::schema::{
    FrontPoint, MethodReport, Plots, ReferenceReport, Report, RunReport, SCHEMA_VERSION, SceneReport, SettingsReport,
    Summary, Targets, TimingReport, Versus,
};
use crate::stability::StabilityReport;
use lagrange_maximal::Engine;

/// The whole report of the runs made under `plan`: the `scenes`' entries ([`scene_report`]) and
/// the `stability` suite, with the plan's settings, the timing policy and the targets;
/// `generator` names the front end that made it (`lagrange-cli 0.1.0`), `total_wall_time_s` is
/// its wall time.
pub fn report(
    plan: &Plan,
    scenes: Vec<SceneReport>,
    stability: StabilityReport,
    generator: String,
    total_wall_time_s: f64,
) -> Report {
    Report {
        schema_version: SCHEMA_VERSION,
        generator,
        mode: if plan.quick { "quick" } else { "full" },
        horizon_s: plan.horizon,
        sample_interval_s: SAMPLE_INTERVAL,
        samples: plan.times.len(),
        timing: TimingReport {
            warmup_runs: plan.timing.warmup,
            max_timed_repetitions: plan.timing.repetitions,
            repetition_budget_s: plan.timing.budget,
            measured_is_timed_above_s: plan.timing.measured_is_timed_above,
            statistic: "minimum wall time (std::time::Instant) of the timed part of a run: the whole \
                        simulate call for the reduced solver, the advance_to calls through the saved times \
                        for a maximal engine (building it and reading it back are not timed)",
        },
        targets: Targets {
            error_ratio_at_equal_time: ERROR_RATIO_TARGET,
            time_ratio_at_equal_error: TIME_RATIO_TARGET,
            equal_error: EQUAL_ERROR,
        },
        scenes,
        stability,
        total_wall_time_s,
    }
}

/// The front of the successful runs of the families `which` selects.
fn front_of(families: &[FamilyRuns], which: impl Fn(Family) -> bool) -> Front {
    Front::new(families.iter().enumerate().filter(|(_, f)| which(f.family)).flat_map(|(i, f)| {
        f.runs.iter().enumerate().filter_map(move |(j, run)| {
            let m = run.outcome.as_ref().ok()?;
            Some(Point { time: m.wall_time, error: m.max_error(), family: i, run: j })
        })
    }))
}

fn front_points(families: &[FamilyRuns], front: &Front) -> Vec<FrontPoint> {
    front
        .points
        .iter()
        .map(|p| {
            let (i, j) = (p.family, p.run);
            FrontPoint {
                method: families[i].family.name(),
                setting: families[i].runs[j].setting.describe(),
                wall_time_s: p.time,
                max_error: p.error,
            }
        })
        .collect()
}

fn settings_report(setting: Setting) -> SettingsReport {
    match setting {
        Setting::Step { dt } => SettingsReport { dt: Some(dt), tolerance: None, substeps: None, h: None },
        Setting::Tolerance { tol } => SettingsReport { dt: None, tolerance: Some(tol), substeps: None, h: None },
        Setting::Rapier { dt, substeps } => {
            SettingsReport { dt: Some(dt), tolerance: None, substeps: Some(substeps), h: Some(dt / substeps as f64) }
        }
    }
}

fn status(availability: &Availability) -> (&'static str, Option<String>) {
    match availability {
        Availability::Ready { .. } => ("ok", None),
        Availability::Unbuildable(reason) => ("unbuildable", Some(reason.clone())),
        Availability::Failed(reason) => ("failed", Some(reason.clone())),
    }
}

/// Errors outside this range are not used for the observed order: above it the run is not yet
/// in its asymptotic regime (errors of order the motion itself), below it round-off and the
/// reference's own error take over.
const ORDER_RANGE: (f64, f64) = (1e-11, 1e-2);

/// The upper end of the range for rapier's first-order sweeps: a first-order error `C h` is
/// linear in `h` as soon as the substep is small against the motion's time scale, which on the
/// closed loops is where the errors are still 1e-2 to 1e-1 (the four-bar over 2 s: 7.7e-2,
/// 3.7e-2, 1.8e-2 at `h` = 1/960, 1/1920, 1/3840, ratios 2.1 and 2.0), while a fourth-order
/// method at such errors is still far from its asymptotic ratio (the four-bar's RK4: 2.6).
const FIRST_ORDER_MAX_ERROR: f64 = 1e-1;

/// The observed order of convergence of a fixed-step sweep in its step (rk4, variational) or
/// substep `h` (rapier): the median over successive runs of `ln(e₁/e₂) / ln(h₁/h₂)`, with `e` the
/// largest error over the saved times, using runs whose errors lie in `ORDER_RANGE`; `None`
/// for tolerance sweeps and where fewer than two such runs exist.
pub fn observed_order(runs: &[crate::runs::Run]) -> Option<f64> {
    let points: Vec<(f64, f64)> = runs
        .iter()
        .filter_map(|run| {
            let (h, largest) = match run.setting {
                Setting::Step { dt } => (dt, ORDER_RANGE.1),
                Setting::Rapier { dt, substeps } => (dt / substeps as f64, FIRST_ORDER_MAX_ERROR),
                Setting::Tolerance { .. } => return None,
            };
            let error = run.outcome.as_ref().ok()?.max_error();
            (error > ORDER_RANGE.0 && error < largest).then_some((h, error))
        })
        .collect();
    let mut slopes: Vec<f64> = points
        .windows(2)
        .filter(|w| (w[0].0 / w[1].0) > 1.0 + 1e-9)
        .map(|w| (w[0].1 / w[1].1).ln() / (w[0].0 / w[1].0).ln())
        .collect();
    if slopes.is_empty() {
        return None;
    }
    slopes.sort_by(f64::total_cmp);
    Some(slopes[slopes.len() / 2])
}

fn method_report(index: usize, family: &FamilyRuns, own_front: &Front) -> MethodReport {
    let (status, reason) = status(&family.availability);
    let on_front = |j: usize| own_front.points.iter().any(|p| p.family == index && p.run == j);
    let per_step = match family.availability {
        Availability::Ready { honours_substeps: false } if matches!(family.family, Family::Maximal(e) if e.is_rapier()) => {
            Some("the build applies per-step forces and runs one substep per step whatever is asked: swept over dt alone".to_string())
        }
        _ => None,
    };
    let floor = family.floor.map(|h| {
        let skipped = match family.skipped {
            0 => String::new(),
            1 => ": the 1 finer setting of the sweep was not run".to_string(),
            k => format!(": the {k} finer settings of the sweep were not run"),
        };
        format!("the error stopped falling at h = 1/{:.0} s (the floor){skipped}", 1.0 / h)
    });
    let note = match (per_step, floor) {
        (Some(a), Some(b)) => Some(format!("{a}; {b}")),
        (a, b) => a.or(b),
    };
    MethodReport {
        method: family.family.name(),
        solver: family.family.solver(),
        status,
        reason,
        deviations: family.deviations.clone(),
        reference: family.reference.map(|k| k.name()),
        note,
        observed_order: observed_order(&family.runs),
        runs: family
            .runs
            .iter()
            .enumerate()
            .map(|(j, run)| match &run.outcome {
                Ok(m) => RunReport {
                    settings: settings_report(run.setting),
                    status: "ok",
                    reason: None,
                    max_error: Some(m.max_error()),
                    final_error: Some(m.final_error()),
                    energy_error: m.energy_error,
                    constraint_violation: m.constraint_violation,
                    wall_time_s: Some(m.wall_time),
                    timed_repetitions: m.timed_repetitions,
                    steps: Some(m.steps),
                    on_front: on_front(j),
                },
                Err(reason) => RunReport {
                    settings: settings_report(run.setting),
                    status: "failed",
                    reason: Some(reason.to_string()),
                    max_error: None,
                    final_error: None,
                    energy_error: None,
                    constraint_violation: None,
                    wall_time_s: None,
                    timed_repetitions: 0,
                    steps: None,
                    on_front: false,
                },
            })
            .collect(),
    }
}

/// Ours against `engine`.
fn versus(runs: &SceneRuns, ours: &Front, engine: Engine) -> Versus {
    let family = runs.families.iter().find(|f| f.family == Family::Maximal(engine));
    let (status, reason) = family.map_or(("failed", Some("not run".to_string())), |f| status(&f.availability));
    let rapier = front_of(&runs.families, |f| f == Family::Maximal(engine));
    let (equal_time, equal_error) = match &reason {
        Some(reason) => (
            EqualTime::none(format!("{engine} {status}: {reason}"), ERROR_RATIO_TARGET),
            EqualError::none(EQUAL_ERROR, format!("{engine} {status}: {reason}"), TIME_RATIO_TARGET),
        ),
        None => (
            EqualTime::new(ours, &rapier, ERROR_RATIO_TARGET),
            EqualError::new(ours, &rapier, EQUAL_ERROR, TIME_RATIO_TARGET),
        ),
    };
    Versus {
        rapier: engine.name(),
        status,
        reason,
        rapier_front: front_points(&runs.families, &rapier),
        error_ratio_at_equal_time: equal_time,
        time_ratio_at_equal_error: equal_error,
    }
}

/// The scene's entry in `report.json`.
pub fn scene_report(runs: &SceneRuns, plots: Plots, wall_time: f64) -> SceneReport {
    let ours = front_of(&runs.families, Family::is_reduced);
    let methods = runs
        .families
        .iter()
        .enumerate()
        .map(|(i, f)| method_report(i, f, &front_of(&runs.families, |g| g == f.family)))
        .collect();
    let cartesian_agreement = runs
        .families
        .iter()
        .find(|f| f.family == Family::Maximal(Engine::Cartesian))
        .and_then(|f| f.runs.iter().find(|r| r.setting == Setting::Tolerance { tol: CARTESIAN_CHECK_TOLERANCE }))
        .and_then(|r| r.outcome.as_ref().ok())
        .map(|m| m.max_error());
    let published = crate::reference::published(runs.scene.id());
    SceneReport {
        scene: runs.scene.id(),
        title: runs.scene.title(),
        coordinates: runs.coordinates.iter().map(|c| c.name.clone()).collect(),
        conserves_energy: runs.conserves_energy,
        horizon_s: runs.scene.horizon(),
        reference: ReferenceReport {
            kind: runs.reference.kind.name(),
            tolerance: runs.reference.kind.tolerance(),
            cartesian_tolerance: CARTESIAN_CHECK_TOLERANCE,
            cartesian_agreement,
            published_source: published.map(|p| p.source),
            published_agreement: published.and_then(|p| runs.reference.published_agreement(&p, &runs.times)),
        },
        methods,
        summary: Summary {
            ours: Family::OURS.iter().map(|f| f.name()).collect(),
            ours_front: front_points(&runs.families, &ours),
            versus: Family::RAPIER_F64.iter().map(|&engine| versus(runs, &ours, engine)).collect(),
            time_to_error: ACCURACY_LEVELS.iter().map(|&error| TimeToError::new(&ours, error)).collect(),
        },
        plots,
        scene_wall_time_s: wall_time,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measure::Measured;
    use crate::runs::Run;

    fn run(dt: f64, error: f64) -> Run {
        let measured = Measured {
            errors: vec![0.0, error],
            energy_error: None,
            constraint_violation: None,
            steps: 1,
            wall_time: 0.0,
            timed_repetitions: 1,
        };
        Run { setting: Setting::Step { dt }, outcome: Ok(measured) }
    }

    /// Fourth order: the error falls 16× per halving; the saturated coarse run and the
    /// round-off floor are left out.
    #[test]
    fn the_observed_order_is_the_median_slope_in_the_asymptotic_range() {
        let runs = [run(0.1, 0.5), run(0.05, 1.6e-4), run(0.025, 1e-5), run(0.0125, 6.25e-7), run(0.00625, 3e-12)];
        let order = observed_order(&runs).expect("three runs in range");
        assert!((order - 4.0).abs() < 1e-9, "{order}");
        assert_eq!(observed_order(&runs[..1]), None);
    }
}
