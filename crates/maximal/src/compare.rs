//! The reduced solver and a maximal engine side by side on one scene: trajectory error,
//! energy and momentum drift, constraint violation, constraint-force error, cost.

use crate::{BuildError, Engine, Settings, build, maps};
use lagrange::{Method, Output, State, Tolerances};
use lagrange_scenes::{Params, Scene};
use std::time::Instant;

/// Tolerance of the reduced reference solution: far below any maximal engine's error
/// (the Cartesian engine runs at 1e-12 by default).
pub const REFERENCE_TOLERANCE: f64 = 1e-13;

/// The outcome of one comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// The maximal engine.
    pub engine: Engine,
    /// Its settings.
    pub settings: Settings,
    /// Deviations of the simulated scene from the requested one (carried by the reference too).
    pub deviations: Vec<String>,
    /// Sample times.
    pub times: Vec<f64>,
    /// `‖q − q_ref‖∞` at each sample (positions in m, angles in rad).
    pub errors: Vec<f64>,
    /// Largest of [`errors`](Self::errors).
    pub max_error: f64,
    /// Error at the last sample.
    pub final_error: f64,
    /// `max |E − E₀| / |E₀|` of the engine's bodies, where the scene conserves energy.
    pub energy_drift: Option<f64>,
    /// The same for the reduced reference (the solver's own conservation, for scale).
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
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// Run `scene` from `initial` to `t_end` in `engine` and in the reduced solver, sampling every
/// `every` seconds (rounded to whole rapier steps), and compare.
///
/// # Errors
/// [`BuildError::Unbuildable`] when the engine cannot build the scene; any error of either run.
pub fn compare(
    engine: Engine,
    scene: &dyn Scene,
    params: &Params,
    initial: &State,
    settings: &Settings,
    t_end: f64,
    every: f64,
) -> Result<Comparison, BuildError> {
    let id = scene.id();
    let built = build(engine, id, params, initial, settings)?;
    let params = &built.params;
    let mut simulation = built.simulation;
    // Sample times: on the rapier step grid.
    let grid = if engine.is_rapier() { settings.dt } else { every };
    let stride = (every / grid).round().max(1.0) * grid;
    let count = ((t_end - initial.t) / stride).round() as usize;
    let times: Vec<f64> = (0..=count).map(|k| initial.t + k as f64 * stride).collect();
    // The reduced reference, with the same deviations.
    let mut reduced = scene.build(params)?;
    let reference = reduced.simulate(
        initial,
        *times.last().unwrap_or(&initial.t),
        Method::Adaptive { tol: Tolerances::uniform(REFERENCE_TOLERANCE) },
        &Output::Times(times.clone()),
    )?;
    let conserves = reduced.conserves_energy();
    let cyclic: Vec<usize> =
        reduced.cyclic_coordinates().iter().enumerate().filter(|(_, c)| **c).map(|(j, _)| j).collect();
    let p0 = reduced.momenta(initial.t, &initial.q, &initial.qdot)?.to_vec();
    let e0 = maps::energy(id, params, initial.t, &simulation.bodies())?;
    let mut errors = Vec::with_capacity(times.len());
    let (mut energy_drift, mut momentum_drift, mut violation, mut force_error): (f64, f64, Option<f64>, Option<f64>) =
        (0.0, 0.0, None, None);
    let masses: Vec<f64> = maps::bodies(id, params)?.iter().map(|b| b.mass).collect();
    let g = maps::gravity(params);
    let mut q_previous = initial.q.clone();
    let mut wall = 0.0;
    for (k, &t) in times.iter().enumerate() {
        let start = Instant::now();
        simulation.advance_to(t)?;
        wall += start.elapsed().as_secs_f64();
        let bodies = simulation.bodies();
        let (q, qdot) = maps::generalized(id, params, t, &bodies, &q_previous)?;
        errors.push(q.iter().zip(reference.q(k)).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max));
        q_previous.clone_from(&q);
        energy_drift = energy_drift.max((maps::energy(id, params, t, &bodies)? - e0).abs());
        if !cyclic.is_empty() {
            let p = reduced.momenta(t, &q, &qdot)?;
            for &j in &cyclic {
                momentum_drift = momentum_drift.max((p[j] - p0[j]).abs());
            }
        }
        if let Some(v) = simulation.constraint_violation() {
            violation = Some(violation.unwrap_or(0.0).max(v));
        }
        let comparable = !reduced.has_generalized_force();
        if let Some(forces) = simulation.constraint_forces().filter(|_| comparable) {
            let expected = reduced.reaction_forces(t, &q, &qdot)?.map(<[f64]>::to_vec).unwrap_or_default();
            if expected.len() == forces.len() {
                // Relative to the forces acting on the bodies (reactions, weights, potential
                // forces): a reaction that vanishes (a free particle) is compared with the
                // forces that move it, not with its own round-off.
                let mut potential_force = vec![0.0; forces.len()];
                maps::potential(id, params, t, &bodies, Some(&mut potential_force))?;
                let weight = masses.iter().fold(0.0_f64, |m, mass| m.max(mass * g));
                let scale = max_abs(&expected).max(max_abs(&potential_force)).max(weight).max(f64::MIN_POSITIVE);
                let residual = forces.iter().zip(&expected).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                force_error = Some(force_error.unwrap_or(0.0).max(residual / scale));
            }
        }
    }
    let reference_energy_drift = conserves.then(|| {
        let h0 = reference.energy[0];
        reference.energy.iter().map(|h| (h - h0).abs()).fold(0.0, f64::max) / h0.abs().max(f64::MIN_POSITIVE)
    });
    let steps = simulation.steps();
    Ok(Comparison {
        engine,
        settings: *settings,
        deviations: built.deviations,
        max_error: errors.iter().cloned().fold(0.0, f64::max),
        final_error: errors.last().copied().unwrap_or(0.0),
        times,
        errors,
        energy_drift: conserves.then(|| energy_drift / e0.abs().max(f64::MIN_POSITIVE)),
        reference_energy_drift,
        momentum_drift: (!cyclic.is_empty()).then_some(momentum_drift),
        constraint_violation: violation,
        force_error,
        steps,
        seconds_per_step: if steps > 0 { wall / steps as f64 } else { 0.0 },
    })
}
