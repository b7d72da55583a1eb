//! The reduced solver and a maximal engine side by side on one scene: trajectory error,
//! energy and momentum drift, constraint violation, constraint-force error, cost — measured by
//! the report's own loop ([`measure::track`]) against the report's reference: the scene's
//! closed form where it has one, otherwise the reduced solution at
//! [`REFERENCE_TOLERANCE`].

use crate::Error;
use crate::measure::relative_energy_error;
use crate::measure::{self, Sample};
use crate::plan::{REFERENCE_TOLERANCE, reference_method};
use crate::reference::{ReferenceKind, closed_form};
use lagrange::{Output, State};
use lagrange_maximal::{BuildError, Engine, Settings, build};
use lagrange_scenes::{Params, Scene};
use lagrange_testing::{max_abs, max_abs_diff, nan_max};
use serde::Serialize;
use std::collections::BTreeMap;

/// The outcome of one comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// The maximal engine.
    pub engine: Engine,
    /// Its settings.
    pub settings: Settings,
    /// Deviations of the simulated scene from the requested one (carried by the reference too).
    pub deviations: Vec<String>,
    /// What [`errors`](Self::errors) are measured against.
    pub reference: ReferenceKind,
    /// Sample times.
    pub times: Vec<f64>,
    /// `‖q − q_ref‖∞` at each sample (positions in m, angles in rad), `q_ref` the scene's
    /// closed form where it has one, otherwise the reduced solution.
    pub errors: Vec<f64>,
    /// Largest of [`errors`](Self::errors).
    pub max_error: f64,
    /// Error at the last sample.
    pub final_error: f64,
    /// `max |E − E₀| / |E₀|` of the engine's bodies, where the scene conserves energy.
    pub energy_drift: Option<f64>,
    /// The same for the reduced solution at the reference tolerance (the solver's own
    /// conservation, for scale), run whether or not the errors use a closed form.
    pub reference_energy_drift: Option<f64>,
    /// `max |p_j − p_j(0)|` over the cyclic coordinates, from the engine's read-back state.
    pub momentum_drift: Option<f64>,
    /// Largest constraint violation over the samples, where the engine measures one.
    pub constraint_violation: Option<f64>,
    /// Largest error of the engine's constraint forces against the reduced solver's reaction
    /// forces at the engine's own state, relative to the largest force on a body (reaction,
    /// weight or potential force), where the engine exposes them and the scene
    /// has no generalized forces `Q` (the reduced reactions then include `Q`, which acts along
    /// a coordinate and belongs to no single body).
    pub force_error: Option<f64>,
    /// Steps the engine took.
    pub steps: usize,
    /// Wall time per engine step (s).
    pub seconds_per_step: f64,
    /// The engine's body poses `(x, y, φ)` at each sample, bodies in the reduced model's order
    /// (the frames of an animation, [`crate::animation`]).
    pub poses: Vec<Vec<[f64; 3]>>,
}

/// Run `scene` from `initial` to `t_end` in `engine` and in the reduced solver, sampling every
/// `every` seconds (rounded to whole rapier steps), and compare: the errors against the scene's
/// closed form where it has one for this state (as the report measures them), otherwise
/// against the reduced solution.
///
/// # Errors
/// [`Error::Build`] with `BuildError::Unbuildable` when the engine cannot build the scene;
/// [`Error::Reference`] when the reduced reference run fails; any error of the engine's run.
pub fn compare(
    engine: Engine,
    scene: &dyn Scene,
    params: &Params,
    initial: &State,
    settings: &Settings,
    t_end: f64,
    every: f64,
) -> Result<Comparison, Error> {
    let id = scene.id();
    let mut built = build(engine, scene, params, initial, settings)?;
    let params = &built.params;
    // Sample times: on the rapier step grid.
    let grid = if engine.is_rapier() { settings.dt } else { every };
    let stride = (every / grid).round().max(1.0) * grid;
    let count = ((t_end - initial.t) / stride).round() as usize;
    let times: Vec<f64> = (0..=count).map(|k| initial.t + k as f64 * stride).collect();
    // The reduced reference, with the same deviations.
    let mut reduced = scene.build(params)?;
    let reference = reduced
        .simulate(initial, *times.last().unwrap_or(&initial.t), reference_method(), &Output::Times(times.clone()))
        .map_err(|source| Error::Reference { scene: id.to_string(), source })?;
    let conserves = reduced.conserves_energy();
    let cyclic: Vec<usize> =
        reduced.cyclic_coordinates().iter().enumerate().filter(|(_, c)| **c).map(|(j, _)| j).collect();
    let p0 = reduced.momenta(initial.t, &initial.q, &initial.qdot)?.to_vec();
    let (mut momentum_drift, mut force_error) = (0.0, None::<f64>);
    let mut poses = Vec::with_capacity(times.len());
    let read_back = built.read_back.clone();
    let masses: Vec<f64> = read_back.bodies().iter().map(|b| b.mass).collect();
    let g = read_back.gravity();
    let comparable = !reduced.has_external_forces();
    // The closed form where the scene has one: near a singular configuration the reduced
    // solution itself is only as exact as its solve there.
    let exact = closed_form(scene, params, initial, &times)?;
    let kind = if exact.is_some() { ReferenceKind::ClosedForm } else { ReferenceKind::Reduced };
    let error = |k: usize, q: &[f64]| max_abs_diff(q, exact.as_ref().map_or_else(|| reference.q(k), |e| &e[k]));
    let pass = measure::track(&mut built, reduced.as_mut(), initial, &times, error, |sample| {
        let Sample { t, q, qdot, bodies, simulation, reduced } = sample;
        poses.push(bodies.iter().map(|b| b.pose).collect());
        if !cyclic.is_empty() {
            let p = reduced.momenta(t, q, qdot)?;
            for &j in &cyclic {
                momentum_drift = nan_max(momentum_drift, (p[j] - p0[j]).abs());
            }
        }
        if let Some(forces) = simulation.constraint_forces().filter(|_| comparable) {
            let expected = reduced.reaction_forces(t, q, qdot)?.map(<[f64]>::to_vec).unwrap_or_default();
            if expected.len() == forces.len() {
                // Relative to the forces acting on the bodies (reactions, weights, potential
                // forces): a reaction that vanishes (a free particle) is compared with the
                // forces that move it, not with its own round-off.
                let mut potential_force = vec![0.0; forces.len()];
                read_back.potential(t, bodies, Some(&mut potential_force));
                let weight = masses.iter().fold(0.0_f64, |m, mass| m.max(mass * g));
                let scale = max_abs(&expected).max(max_abs(&potential_force)).max(weight).max(f64::MIN_POSITIVE);
                force_error = Some(nan_max(force_error.unwrap_or(0.0), max_abs_diff(&forces, &expected) / scale));
            }
        }
        Ok(())
    })?;
    let reference_energy_drift = conserves.then(|| relative_energy_error(&reference.energy));
    let errors = pass.errors;
    let steps = pass.steps;
    Ok(Comparison {
        engine,
        settings: *settings,
        deviations: built.deviations,
        reference: kind,
        max_error: errors.iter().copied().fold(0.0, nan_max),
        final_error: errors.last().copied().unwrap_or(0.0),
        times,
        errors,
        energy_drift: pass.energy_error,
        reference_energy_drift,
        momentum_drift: (!cyclic.is_empty()).then_some(momentum_drift),
        constraint_violation: pass.constraint_violation,
        force_error,
        steps,
        seconds_per_step: if steps > 0 { pass.advance_time / steps as f64 } else { 0.0 },
        poses,
    })
}

/// The interval of the times where [`compare`] measures the errors over `t_end` simulated
/// seconds with rapier's step `dt`: a hundred samples; with a step longer than that, one sample
/// per step (a sample between two steps would measure the rounding of its time, not the
/// engine).
pub fn sample_interval(t_end: f64, dt: f64) -> f64 {
    (t_end / 100.0).max(dt)
}

/// Comparisons of one scene in several engines, as a table: what was compared, under which
/// settings, and one [`Row`] per engine. Serialized, it is `lagrange compare --json`
/// (docs/cli-json.md, field by field); [`render::terminal::comparison`](crate::render::terminal::comparison)
/// prints it.
#[derive(Clone, Debug, Serialize)]
pub struct Table {
    /// The scene's id.
    pub scene: String,
    /// Every parameter by name, overrides applied.
    pub parameters: BTreeMap<String, f64>,
    /// The initial time.
    pub t0: f64,
    /// The initial coordinates.
    pub q0: Vec<f64>,
    /// The initial velocities.
    pub qdot0: Vec<f64>,
    /// rapier's step (s).
    pub dt: f64,
    /// rapier's substeps per step.
    pub substeps: usize,
    /// The Cartesian engine's tolerance.
    pub tol: f64,
    /// The end of the runs (s).
    pub t_end: f64,
    /// Interval of the times where errors are measured.
    pub every: f64,
    /// Tolerance of the reduced solution the engines are measured against; `None` when every
    /// row is measured against the scene's closed form.
    pub reference_tol: Option<f64>,
    /// One row per engine, in the order run.
    pub rows: Vec<Row>,
}

impl Table {
    /// The table of `rows`, comparisons of `scene` with `params` from `initial` to `t_end` under
    /// `settings`, sampled every `every` seconds.
    pub fn new(
        scene: &dyn Scene,
        params: &Params,
        initial: &State,
        settings: &Settings,
        (t_end, every): (f64, f64),
        rows: Vec<Row>,
    ) -> Table {
        // Rows measured against a computed reference (no closed form, or not for every row).
        let computed = rows.iter().any(|r| r.reference == Some(ReferenceKind::Reduced.name()));
        Table {
            scene: scene.id().to_string(),
            parameters: params.iter().map(|(spec, value)| (spec.name.to_string(), value)).collect(),
            t0: initial.t,
            q0: initial.q.clone(),
            qdot0: initial.qdot.clone(),
            dt: settings.dt,
            substeps: settings.substeps,
            tol: settings.tolerance,
            t_end,
            every,
            reference_tol: computed.then_some(REFERENCE_TOLERANCE),
            rows,
        }
    }
}

/// One engine's row of a [`Table`]: what [`compare`] measured, or why the engine cannot build
/// the scene.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// The engine's name.
    pub engine: &'static str,
    /// Present when the engine cannot build the scene: why.
    pub unbuildable: Option<String>,
    /// Where the engine's build departs from the scene (see [`Comparison::deviations`]).
    pub deviations: Vec<String>,
    /// `closed_form` or `reduced_dop853`: what the errors are measured against.
    pub reference: Option<&'static str>,
    /// See [`Comparison::max_error`].
    pub max_error: Option<f64>,
    /// See [`Comparison::final_error`].
    pub final_error: Option<f64>,
    /// See [`Comparison::energy_drift`].
    pub energy_drift: Option<f64>,
    /// See [`Comparison::reference_energy_drift`].
    pub reference_energy_drift: Option<f64>,
    /// See [`Comparison::momentum_drift`].
    pub momentum_drift: Option<f64>,
    /// See [`Comparison::constraint_violation`].
    pub constraint_violation: Option<f64>,
    /// See [`Comparison::force_error`].
    pub force_error: Option<f64>,
    /// The engine's steps.
    pub steps: Option<usize>,
    /// Wall time of one step (µs).
    pub microseconds_per_step: Option<f64>,
}

impl Row {
    /// The row of `engine` from what [`compare`] returned: its measurements, or the reason it
    /// cannot build the scene.
    ///
    /// # Errors
    /// Any other error of the comparison, returned as it is.
    pub fn new(engine: Engine, result: Result<Comparison, Error>) -> Result<Row, Error> {
        let empty = |reason: Option<String>| Row {
            engine: engine.name(),
            unbuildable: reason,
            deviations: Vec::new(),
            reference: None,
            max_error: None,
            final_error: None,
            energy_drift: None,
            reference_energy_drift: None,
            momentum_drift: None,
            constraint_violation: None,
            force_error: None,
            steps: None,
            microseconds_per_step: None,
        };
        match result {
            Err(Error::Build(BuildError::Unbuildable { reason, .. })) => Ok(empty(Some(reason))),
            Err(source) => Err(source),
            Ok(c) => Ok(Row {
                deviations: c.deviations,
                reference: Some(c.reference.name()),
                max_error: Some(c.max_error),
                final_error: Some(c.final_error),
                energy_drift: c.energy_drift,
                reference_energy_drift: c.reference_energy_drift,
                momentum_drift: c.momentum_drift,
                constraint_violation: c.constraint_violation,
                force_error: c.force_error,
                steps: Some(c.steps),
                microseconds_per_step: Some(c.seconds_per_step * 1e6),
                ..empty(None)
            }),
        }
    }
}
