//! Running every method family of one scene over its sweep: which engines can build the scene
//! (and whether a rapier build honours substeps), then every run, measured against the
//! reference of the problem it actually simulates.

use crate::Error;
use crate::measure::{self, Measured};
use crate::plan::{CARTESIAN_CHECK_TOLERANCE, Family, Plan, Setting};
use crate::reference::{Reference, ReferenceKind, References};
use lagrange::{Coordinate, Method, State};
use lagrange_maximal::{BuildError, Engine, Settings, build};
use lagrange_scenes::{Params, Scene};

/// Whether a family can run on a scene.
#[derive(Clone, Debug, PartialEq)]
pub enum Availability {
    /// It runs; a rapier build may ignore substeps.
    Ready {
        /// Whether more substeps change the run (false for scenes driven by per-step forces).
        honours_substeps: bool,
    },
    /// The engine cannot express the scene.
    Unbuildable(String),
    /// The build failed for another reason.
    Failed(String),
}

/// What will run on one scene.
pub struct ScenePlan {
    /// The scene.
    pub scene: &'static dyn Scene,
    /// Its default parameters.
    pub params: Params,
    /// Its default initial state.
    pub initial: State,
    /// The report's plan on the scene's own span of time, if it has one
    /// ([`Plan::scaled_to`]), else the report's plan.
    pub plan: Plan,
    /// Each family with its availability and sweep.
    pub families: Vec<(Family, Availability, Vec<Setting>)>,
}

impl ScenePlan {
    /// Probe every family on `scene` (one cheap build each) and lay out the sweeps.
    ///
    /// # Errors
    /// Invalid default parameters or state (a bug in the scene).
    pub fn new(scene: &'static dyn Scene, plan: &Plan) -> Result<ScenePlan, Error> {
        let params = scene.default_params();
        let initial = scene.default_state(&params).map_err(|e| Error::scene(scene.id(), e))?;
        let plan = &scene.horizon().map_or_else(|| plan.clone(), |horizon| plan.scaled_to(horizon));
        let families = Family::ALL
            .into_iter()
            .map(|family| {
                let availability = match family {
                    Family::Maximal(engine) => probe(engine, scene, &params, &initial, plan),
                    _ => Availability::Ready { honours_substeps: false },
                };
                let settings = match availability {
                    Availability::Ready { honours_substeps } => plan.settings(family, honours_substeps),
                    _ => Vec::new(),
                };
                (family, availability, settings)
            })
            .collect();
        Ok(ScenePlan { scene, params, initial, plan: plan.clone(), families })
    }

    /// Number of runs.
    pub fn runs(&self) -> usize {
        self.families.iter().map(|(_, _, settings)| settings.len()).sum()
    }
}

/// Build `engine` once and take one step; for rapier, also find out whether substeps matter: a
/// build that applies per-step forces runs one substep per step whatever is asked
/// ([`MaximalSimulation::substeps`](lagrange_maximal::MaximalSimulation::substeps)).
fn probe(engine: Engine, scene: &dyn Scene, params: &Params, initial: &State, plan: &Plan) -> Availability {
    let dt = plan.rapier.first().map_or(1.0 / 60.0, |&(dt, _)| dt);
    let settings = Settings { dt, substeps: 2, tolerance: CARTESIAN_CHECK_TOLERANCE };
    let probed = build(engine, scene, params, initial, &settings).and_then(|mut built| {
        if engine.is_rapier() {
            built.simulation.advance_to(initial.t + dt)?;
        }
        Ok(built.simulation.substeps())
    });
    match probed {
        Ok(substeps) => Availability::Ready { honours_substeps: engine.is_rapier() && substeps == 2 },
        Err(BuildError::Unbuildable { reason, .. }) => Availability::Unbuildable(reason),
        Err(e) => Availability::Failed(e.to_string()),
    }
}

/// One run: its setting and what it measured, or why it failed.
pub struct Run {
    /// The setting.
    pub setting: Setting,
    /// The measurement, or the failure as a sentence.
    pub outcome: Result<Measured, Error>,
}

/// Every run of one family.
pub struct FamilyRuns {
    /// The family.
    pub family: Family,
    /// Whether it could run.
    pub availability: Availability,
    /// Deviations the engine needs (from its builds).
    pub deviations: Vec<String>,
    /// Reference kind of its errors.
    pub reference: Option<ReferenceKind>,
    /// The runs, in sweep order.
    pub runs: Vec<Run>,
    /// The rapier substep `h` (s) below which the sweep stopped because the error had stopped
    /// falling there ([`floor_reached`]).
    pub floor: Option<f64>,
    /// Settings of the sweep not run because they lie below the floor.
    pub skipped: usize,
}

/// The substep `h` of a rapier setting (`None` for other settings).
fn substep(setting: Setting) -> Option<f64> {
    match setting {
        Setting::Rapier { dt, substeps } => Some(dt / substeps as f64),
        _ => None,
    }
}

/// The smallest substep at which a rapier sweep has reached its floor: a run whose error is no
/// smaller than that of a run at a coarser substep (rapier is first order in `h`, so a finer
/// substep that does not reduce the error shows round-off — f32 — or coupling drift in charge).
/// Finer substeps would cost more and draw no new point of the front; the sweep stops there.
pub fn floor_reached(runs: &[Run]) -> Option<f64> {
    let measured: Vec<(f64, f64)> =
        runs.iter().filter_map(|run| Some((substep(run.setting)?, run.outcome.as_ref().ok()?.max_error()))).collect();
    measured
        .iter()
        .filter(|&&(h, error)| measured.iter().any(|&(coarser, e)| coarser > h * (1.0 + 1e-9) && error >= e))
        .map(|&(h, _)| h)
        .reduce(f64::min)
}

/// Every run of one scene.
pub struct SceneRuns {
    /// The scene.
    pub scene: &'static dyn Scene,
    /// Its coordinates.
    pub coordinates: Vec<Coordinate>,
    /// Whether it conserves energy.
    pub conserves_energy: bool,
    /// The scene's own reference.
    pub reference: Reference,
    /// The saved times (s).
    pub times: Vec<f64>,
    /// One entry per family.
    pub families: Vec<FamilyRuns>,
}

impl SceneRuns {
    /// Run every family of `scene_plan`, calling `progress` before each run with a label.
    ///
    /// # Errors
    /// A failing scene build or reference (runs that fail are recorded, not errors).
    pub fn execute(scene_plan: &ScenePlan, mut progress: impl FnMut(&str)) -> Result<SceneRuns, Error> {
        let ScenePlan { scene, params, initial, plan, .. } = scene_plan;
        let scene = *scene;
        let id = scene.id();
        let system = scene.build(params).map_err(|e| Error::scene(id, e))?;
        let coordinates = scene.coordinates(params).map_err(|e| Error::scene(id, e))?;
        let conserves_energy = system.conserves_energy();
        let mut references = References::default();
        let reference = references.get(scene, params, initial, &plan.times)?.clone();
        let mut families = Vec::new();
        for (family, availability, settings) in &scene_plan.families {
            let mut result = FamilyRuns {
                family: *family,
                availability: availability.clone(),
                deviations: Vec::new(),
                reference: None,
                runs: Vec::new(),
                floor: None,
                skipped: 0,
            };
            for &setting in settings {
                progress(&format!("{id}: {} {}", family.name(), setting.describe()));
                if let (Some(floor), Some(h)) = (result.floor, substep(setting))
                    && h < floor * (1.0 - 1e-9)
                {
                    result.skipped += 1;
                    continue;
                }
                let outcome = match *family {
                    Family::Maximal(engine) => run_maximal(engine, scene_plan, setting, &mut references, &mut result),
                    family => {
                        result.reference = Some(reference.kind);
                        reduced_method(family, setting).and_then(|method| {
                            measure::reduced(system.as_ref(), initial, &plan.times, method, &reference, &plan.timing)
                        })
                    }
                };
                let outcome = outcome.and_then(|m| if m.is_finite() { Ok(m) } else { Err(Error::NonFinite) });
                result.runs.push(Run { setting, outcome });
                result.floor = floor_reached(&result.runs);
            }
            families.push(result);
        }
        Ok(SceneRuns { scene, coordinates, conserves_energy, reference, times: plan.times.clone(), families })
    }
}

/// One run of a maximal engine: build it (its deviations choose the reference), then measure.
fn run_maximal(
    engine: Engine,
    scene_plan: &ScenePlan,
    setting: Setting,
    references: &mut References,
    result: &mut FamilyRuns,
) -> Result<Measured, Error> {
    let ScenePlan { scene, params, initial, plan, .. } = scene_plan;
    let settings = maximal_settings(setting);
    let built = build(engine, *scene, params, initial, &settings)?;
    let reference = references.get(*scene, &built.params, initial, &plan.times)?;
    result.deviations.clone_from(&built.deviations);
    result.reference = Some(reference.kind);
    let (times, timing) = (&plan.times, &plan.timing);
    let problem = measure::Problem { scene: *scene, params, initial, times };
    measure::maximal(&problem, engine, &settings, built, reference, timing)
}

fn maximal_settings(setting: Setting) -> Settings {
    match setting {
        Setting::Rapier { dt, substeps } => Settings { dt, substeps, tolerance: CARTESIAN_CHECK_TOLERANCE },
        Setting::Tolerance { tol } => Settings { tolerance: tol, ..Settings::default() },
        Setting::Step { dt } => Settings { dt, ..Settings::default() },
    }
}

/// The reduced method of `family` at `setting`.
///
/// # Errors
/// [`Error::NoSuchSetting`] when the family does not take the setting (a bug in the plan): the
/// run is recorded as failed, never silently replaced by another method.
fn reduced_method(family: Family, setting: Setting) -> Result<Method, Error> {
    match (family, setting) {
        (Family::Reduced(kind), Setting::Step { dt }) if kind.is_fixed_step() => Ok(kind.with(dt)),
        (Family::Reduced(kind), Setting::Tolerance { tol }) if !kind.is_fixed_step() => Ok(kind.with(tol)),
        (family, setting) => Err(Error::NoSuchSetting { family: family.name(), setting: setting.describe() }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(substeps: usize, error: f64) -> Run {
        let measured = Measured {
            errors: vec![0.0, error],
            energy_error: None,
            constraint_violation: None,
            steps: 1,
            wall_time: 0.0,
            timed_repetitions: 1,
        };
        Run { setting: Setting::Rapier { dt: 1.0 / 60.0, substeps }, outcome: Ok(measured) }
    }

    #[test]
    fn a_sweep_reaches_its_floor_where_the_error_stops_falling() {
        // First order: the error falls 4× per 4× finer substep, no floor.
        let falling = [run(1, 0.24), run(4, 0.06), run(16, 0.015), run(64, 3.8e-3)];
        assert_eq!(floor_reached(&falling), None);
        // f32 round-off: the error rises at 64 substeps; the floor is h = 1/3840 s.
        let rising = [run(1, 0.24), run(4, 0.059), run(16, 0.0104), run(64, 0.0127)];
        let floor = floor_reached(&rising).expect("floor");
        assert!((floor * 3840.0 - 1.0).abs() < 1e-12, "{floor}");
        // Equal errors at equal h (two settings with the same substep) are no floor.
        let same = [run(4, 0.06), Run { setting: Setting::Rapier { dt: 1.0 / 240.0, substeps: 1 }, ..run(4, 0.06) }];
        assert_eq!(floor_reached(&same), None);
    }
}
