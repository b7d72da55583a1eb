//! Random (seeded) scene parameters and states, including the extreme cases of docs/validation.md#extreme_parameters.

use lagrange::{CoordinateKind, State};
use lagrange_scenes::{Domain, ParamSpec, Params, Scene};
use rand::Rng;
use std::f64::consts::FRAC_PI_2;

/// A regular parameter value: log-uniform over a decade around 1 for masses and lengths,
/// uniform for angles, integers and signed values.
pub fn regular_value(spec: &ParamSpec, rng: &mut impl Rng) -> f64 {
    match spec.domain {
        Domain::Positive => match spec.unit {
            "m/s²" => rng.random_range(1.0..20.0),
            _ => 10f64.powf(rng.random_range(-0.7..0.7)),
        },
        Domain::NonNegative => match spec.unit {
            "m/s²" => rng.random_range(1.0..20.0),
            _ => rng.random_range(0.0..3.0),
        },
        Domain::Finite => rng.random_range(-2.0..2.0),
        Domain::OpenInterval(lo, hi) => lo + (hi - lo) * rng.random_range(0.05..0.95),
        Domain::Integer { min, max } => rng.random_range(min..=max.min(min + 7)) as f64,
    }
}

/// Random regular parameters for `scene` ([`regular_value`] for each). A combination the
/// scene refuses as a whole — a linkage whose links cannot close — is drawn again, each time
/// with the draws pulled halfway closer to the defaults (which the scene accepts), so that
/// scenes with tightly coupled geometry (Andrews' squeezer, lengths ~0.03 m) still get varied
/// parameters. Scenes whose parameters are independent keep their first draw.
pub fn regular_params(scene: &dyn Scene, rng: &mut impl Rng) -> Params {
    let defaults = scene.default_params();
    for attempt in 0..64 {
        let spread = 0.5_f64.powi(attempt);
        let mut params = defaults.clone();
        for spec in scene.params() {
            let drawn = regular_value(spec, rng);
            let value = match spec.domain {
                Domain::Integer { .. } => drawn,
                _ => spec.default + spread * (drawn - spec.default),
            };
            params.set(spec.name, value).expect("sampled inside the domain");
        }
        if scene.default_state(&params).is_ok() {
            return params;
        }
    }
    panic!("{}: no accepted parameters within 64 draws towards the defaults", scene.id())
}

/// The extreme parameter sets of a scene: every mass parameter in turn scaled to 1e-6 and 1e6
/// of the others (mass ratios 1e-6 and 1e6), open angular intervals at both ends within 1e-8,
/// and inertias `I/a²` = 1e8 (pulleys) or 1e8 times their default.
pub fn extreme_params(scene: &dyn Scene) -> Vec<(String, Params)> {
    let mut sets = Vec::new();
    for spec in scene.params() {
        let base = scene.default_params();
        let mut push = |label: String, value: f64| {
            let mut params = base.clone();
            params.set(spec.name, value).expect("extreme value inside the domain");
            sets.push((label, params));
        };
        match (spec.unit, spec.domain) {
            ("kg", Domain::Positive) => {
                push(format!("{} × 1e-6", spec.name), spec.default * 1e-6);
                push(format!("{} × 1e6", spec.name), spec.default * 1e6);
            }
            ("kg m²", _) => {
                // I/a² = 1e8 for a pulley of radius a; otherwise 1e8 times the inertia's own
                // default (1 kg m² where that is 0, a point bob): the squeezer's 4e-7 kg m²
                // link at 1e8 kg m² would be 1e14 times its neighbours, a mass matrix the
                // engine rightly calls singular.
                match scene.params().iter().find(|s| s.name == "pulley_radius") {
                    Some(radius) => push(format!("{} = 1e8 a²", spec.name), 1e8 * radius.default * radius.default),
                    None if spec.default > 0.0 => push(format!("{} × 1e8", spec.name), 1e8 * spec.default),
                    None => push(format!("{} = 1e8", spec.name), 1e8),
                }
            }
            ("rad", Domain::OpenInterval(lo, hi)) => {
                push(format!("{} = {lo} + 1e-8", spec.name), lo + 1e-8);
                push(format!("{} = {hi} − 1e-8", spec.name), hi - 1e-8);
            }
            _ => {}
        }
    }
    sets
}

/// A random state: angles anywhere, with every fourth state putting them at the extremes
/// 1e-8 and π/2 − 1e-8; lengths as offsets from the default state (so that radii stay
/// positive); velocities in ±3. A constrained scene's state is the default state moved at
/// random and brought onto the constraints by the smallest change.
pub fn state(scene: &dyn Scene, params: &Params, rng: &mut impl Rng, index: usize) -> State {
    let default = scene.default_state(params).expect("valid parameters");
    let coordinates = scene.coordinates(params).expect("valid parameters");
    let mut system = scene.build(params).expect("valid parameters");
    if system.constraint_counts() != (0, 0) {
        return constrained_state(system.as_mut(), &default, rng);
    }
    let mut q = default.q.clone();
    for (qi, c) in q.iter_mut().zip(&coordinates) {
        *qi = match (c.kind, index % 4) {
            (CoordinateKind::Angle, 1) => 1e-8,
            (CoordinateKind::Angle, 2) => FRAC_PI_2 - 1e-8,
            (CoordinateKind::Angle, _) => rng.random_range(-3.0..3.0),
            (CoordinateKind::Length, _) => *qi * rng.random_range(0.5..1.5) + rng.random_range(-0.3..0.3),
        };
    }
    let qdot = (0..q.len()).map(|_| rng.random_range(-3.0..3.0)).collect::<Vec<_>>();
    State::new(rng.random_range(0.0..2.0), q, qdot)
}

/// A random state on the constraints of a constrained `system`: the default state with every
/// coordinate moved by up to ±1 (radians or metres, times the coordinate's own size where that
/// is larger), velocities in ±3, then brought onto the constraints by the smallest change
/// (positions and velocities), where the scene's equations describe its motion. Coordinates
/// drawn anywhere would mostly be far from every closed configuration of a linkage, and
/// Gauss–Newton from there may end at a singular one (a toggle, where it converges only
/// linearly) or not at all; a draw whose assembly fails is drawn again with half the spread,
/// which ends at the (consistent) default state. A draw that lands near a singular
/// configuration ([`near_singular`]) is drawn again too: there the engine's regularized solve
/// departs from the exact one by design, and its own tests (tests/checks/singular.rs, the
/// singular scenes) check it.
fn constrained_state(system: &mut dyn lagrange::System, default: &State, rng: &mut impl Rng) -> State {
    for attempt in 0..32 {
        let spread = 0.5_f64.powi(attempt);
        let q: Vec<f64> =
            default.q.iter().map(|&qi| qi + spread * qi.abs().max(1.0) * rng.random_range(-1.0..1.0)).collect();
        let qdot = (0..q.len()).map(|_| rng.random_range(-3.0..3.0)).collect::<Vec<_>>();
        let state = State::new(rng.random_range(0.0..2.0), q, qdot);
        if let Ok(state) = system.assemble(&state, &vec![false; state.q.len()])
            && !near_singular(system, &state)
        {
            return state;
        }
    }
    panic!("no state of the constrained scene assembles away from singular configurations within 32 draws")
}

/// Whether the constraint Jacobian `G` at `state` is near a loss of rank: a singular value
/// between `1e-12` and `1e-4` of the largest (a row about to become dependent, as a linkage
/// nears its flat position: the smallest singular value is about the distance to it). Rows
/// dependent everywhere (a redundant constraint) leave singular values at the round-off,
/// below `1e-12`, and do not count.
fn near_singular(system: &mut dyn lagrange::System, state: &State) -> bool {
    let singular = constraint_singular_values(system, state);
    let largest = singular.iter().copied().fold(0.0, f64::max);
    singular.iter().any(|&s| s > 1e-12 * largest && s < 1e-4 * largest)
}

/// `κ(G)²` over the rows of `G` that are not dependent everywhere (singular values above
/// `1e-12` of the largest), 1 without constraints: the factor by which the constrained solve
/// through `S = G M⁻¹ Gᵀ` can amplify round-off beyond the mass matrix's own condition
/// (`κ(S) ≤ κ(M) κ(G)²`).
pub fn constraint_condition(system: &mut dyn lagrange::System, state: &State) -> f64 {
    let singular = constraint_singular_values(system, state);
    let largest = singular.iter().copied().fold(0.0, f64::max);
    let smallest = singular.iter().copied().filter(|&s| s > 1e-12 * largest).fold(f64::INFINITY, f64::min);
    if largest > 0.0 && smallest.is_finite() { (largest / smallest).powi(2) } else { 1.0 }
}

/// The singular values of the constraint Jacobian at `state` (none without constraints).
fn constraint_singular_values(system: &mut dyn lagrange::System, state: &State) -> Vec<f64> {
    let n = state.q.len();
    let Ok(Some(g)) = system.constraint_jacobian(state.t, &state.q, &state.qdot) else {
        return Vec::new();
    };
    let rows = g.len() / n.max(1);
    nalgebra::DMatrix::from_row_slice(rows, n, g).singular_values().iter().copied().collect()
}
