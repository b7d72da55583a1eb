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

/// Random regular parameters for `scene`.
pub fn regular_params(scene: &dyn Scene, rng: &mut impl Rng) -> Params {
    let mut params = scene.default_params();
    for spec in scene.params() {
        params.set(spec.name, regular_value(spec, rng)).expect("sampled inside the domain");
    }
    params
}

/// The extreme parameter sets of a scene: every mass parameter in turn scaled to 1e-6 and 1e6
/// of the others (mass ratios 1e-6 and 1e6), open angular intervals at both ends within 1e-8,
/// and inertias `I/a²` = 1e8.
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
                // I/a² = 1e8 for a pulley of radius a.
                let radius = scene.params().iter().find(|s| s.name == "pulley_radius").map_or(1.0, |s| s.default);
                push(format!("{} = 1e8 a²", spec.name), 1e8 * radius * radius);
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
/// positive); velocities in ±3; brought onto the constraints of a constrained scene.
pub fn state(scene: &dyn Scene, params: &Params, rng: &mut impl Rng, index: usize) -> State {
    let default = scene.default_state(params).expect("valid parameters");
    let coordinates = scene.coordinates(params).expect("valid parameters");
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
    let state = State::new(rng.random_range(0.0..2.0), q, qdot);
    // With constraints among the coordinates, the nearest state on them (positions and
    // velocities), where the scene's equations describe its motion.
    let system = scene.build(params).expect("valid parameters");
    if system.constraint_counts() == (0, 0) {
        return state;
    }
    system.assemble(&state, &vec![false; state.q.len()]).expect("a sampled state assembles")
}
