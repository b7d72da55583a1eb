//! The reduced solver and a maximal engine side by side on one scene: trajectory error,
//! energy and momentum drift, constraint violation, constraint-force error, cost — measured by
//! the report's own loop ([`measure::track`]) against the report's reference: the scene's
//! closed form where it has one, otherwise the reduced solution at
//! [`REFERENCE_TOLERANCE`](crate::plan::REFERENCE_TOLERANCE).

use crate::Error;
use crate::measure::relative_energy_error;
use crate::measure::{self, Sample};
use crate::plan::reference_method;
use crate::reference::{ReferenceKind, closed_form};
use lagrange::{Output, State};
use lagrange_maximal::{Engine, Settings, build};
use lagrange_scenes::{Params, Scene};
use lagrange_testing::{max_abs, max_abs_diff, nan_max};

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
    })
}
