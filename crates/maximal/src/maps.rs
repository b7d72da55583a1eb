//! Between generalized and maximal coordinates: the initial body states of a scene (from its
//! reduced model's poses), the scene-specific inverse maps `q = g(z)` used to read any maximal
//! engine back into generalized coordinates, the bodies' energy, and the forces of the scene's
//! potential on its bodies.

use crate::BodyState;
use crate::scenes::{MaximalScene, MaximalVisitor};
use lagrange::graph::GraphMechanism;
use lagrange::num_dual::Dual64;
use lagrange::{Body, Error, Mechanism, Pose, State};
use lagrange_scenes::{ClosedForm, MechanismVisitor, Params, visit_mechanism};
use std::f64::consts::PI;

/// The bodies of a scene (masses and inertias, in the reduced model's order).
///
/// # Errors
/// Invalid parameters or an unknown scene.
pub fn bodies(scene: &str, params: &Params) -> Result<Vec<Body>, Error> {
    if let Some(mechanism) = crate::scenes::graph(scene, params)? {
        return Ok(mechanism.bodies().to_vec());
    }
    struct Bodies;
    impl MechanismVisitor for Bodies {
        type Output = Vec<Body>;
        fn visit<M: Mechanism + ClosedForm + Clone + 'static>(self, m: M) -> Vec<Body> {
            m.bodies().to_vec()
        }
    }
    Ok(match visit_mechanism(scene, params, Bodies)? {
        Some(bodies) => bodies,
        None => vec![Body::point("particle", params.get("mass"))],
    })
}

/// Gravity `g` of a scene (0 where it has none).
pub fn gravity(params: &Params) -> f64 {
    if params.specs().iter().any(|s| s.name == "gravity") { params.get("gravity") } else { 0.0 }
}

/// The body states of the scene's reduced model at `state`: poses `p_b(q, t)` and velocities
/// `ṗ_b = J_b q̇ + ∂p_b/∂t` (one dual pass along `(q̇, 1)`) — the initial condition of every
/// maximal build.
///
/// # Errors
/// Invalid parameters, an unknown scene, or a state of the wrong size.
pub fn body_states(scene: &str, params: &Params, state: &State) -> Result<Vec<BodyState>, Error> {
    if let Some(mechanism) = crate::scenes::graph(scene, params)? {
        return graph_body_states(&mechanism, state);
    }
    struct States<'a>(&'a State);
    impl MechanismVisitor for States<'_> {
        type Output = Result<Vec<BodyState>, Error>;
        fn visit<M: Mechanism + ClosedForm + Clone + 'static>(self, m: M) -> Self::Output {
            states_of(&m, self.0)
        }
    }
    match visit_mechanism(scene, params, States(state))? {
        Some(states) => states,
        // The charged particle: its coordinates are already Cartesian.
        None => {
            Ok(vec![BodyState { pose: [state.q[0], state.q[1], 0.0], velocity: [state.qdot[0], state.qdot[1], 0.0] }])
        }
    }
}

/// `(q, q̇)` of a scene from body states: `q = g(z)` (the scene's inverse map, written by hand
/// independently of the reduced model's poses), `q̇ = (∂g/∂z) ż + ∂g/∂t` (one dual pass).
/// Angles are unwrapped to the branch nearest `reference` (the previous read-back, or the
/// initial state).
///
/// # Errors
/// Invalid parameters or an unknown scene.
pub fn generalized(
    scene: &str,
    params: &Params,
    t: f64,
    bodies: &[BodyState],
    reference: &[f64],
) -> Result<(Vec<f64>, Vec<f64>), Error> {
    if let Some(mechanism) = crate::scenes::graph(scene, params)? {
        return Ok(graph_generalized(&mechanism, bodies));
    }
    let z: Vec<[Dual64; 3]> =
        bodies.iter().map(|b| std::array::from_fn(|c| Dual64::new(b.pose[c], b.velocity[c]))).collect();
    struct Inverse<'a>(Dual64, &'a [[Dual64; 3]]);
    impl MaximalVisitor for Inverse<'_> {
        type Output = Vec<Dual64>;
        fn visit<T: MaximalScene>(self, scene: T) -> Vec<Dual64> {
            scene.generalized(self.0, self.1)
        }
    }
    let q = crate::scenes::visit(scene, params, Inverse(Dual64::new(t, 1.0), &z))?;
    let coordinates = lagrange_scenes::find(scene).map(|s| s.coordinates(params)).transpose()?.unwrap_or_default();
    let mut values: Vec<f64> = q.iter().map(|v| v.re).collect();
    for (i, c) in coordinates.iter().enumerate() {
        if c.kind == lagrange::CoordinateKind::Angle && i < reference.len() {
            values[i] += 2.0 * PI * ((reference[i] - values[i]) / (2.0 * PI)).round();
        }
    }
    Ok((values, q.iter().map(|v| v.eps).collect()))
}

/// Energy of body states: `Σ ½ m |v|² + ½ I ω² + Σ m g y + V(t, q, poses)`, with `q` from the
/// inverse map for the potential's coordinate terms.
///
/// # Errors
/// Invalid parameters or an unknown scene.
pub fn energy(scene: &str, params: &Params, t: f64, states: &[BodyState]) -> Result<f64, Error> {
    let bodies = bodies(scene, params)?;
    let g = gravity(params);
    let mut energy = 0.0;
    for (b, s) in bodies.iter().zip(states) {
        let v = s.velocity;
        energy += 0.5 * b.mass * (v[0] * v[0] + v[1] * v[1]) + 0.5 * b.inertia * v[2] * v[2] + b.mass * g * s.pose[1];
    }
    // A scene without a potential (the charged particle: the magnetic force does no work) has
    // kinetic and gravitational energy only.
    let (value, has_potential) = potential(scene, params, t, states, None)?;
    Ok(if has_potential { energy + value } else { energy })
}

/// The scene's potential `V` at body states and, with `gradient`, `∂V/∂p_b` (3B): minus the
/// potential's force and torque on each body, to apply in engines that integrate bodies.
///
/// # Errors
/// Invalid parameters or an unknown scene.
pub fn potential(
    scene: &str,
    params: &Params,
    t: f64,
    states: &[BodyState],
    gradient: Option<&mut [f64]>,
) -> Result<(f64, bool), Error> {
    if let Some(mechanism) = crate::scenes::graph(scene, params)? {
        return Ok(graph_potential(&mechanism, states, gradient));
    }
    struct Potential<'a> {
        q: Vec<f64>,
        t: f64,
        states: &'a [BodyState],
        gradient: Option<&'a mut [f64]>,
    }
    impl MechanismVisitor for Potential<'_> {
        type Output = (f64, bool);
        fn visit<M: Mechanism + ClosedForm + Clone + 'static>(self, m: M) -> (f64, bool) {
            let q: Vec<Dual64> = self.q.iter().map(|v| Dual64::from(*v)).collect();
            let mut poses: Vec<Pose<Dual64>> = self
                .states
                .iter()
                .map(|s| Pose::new(Dual64::from(s.pose[0]), Dual64::from(s.pose[1]), Dual64::from(s.pose[2])))
                .collect();
            let t = Dual64::from(self.t);
            let Some(value) = m.potential(t, &q, &poses) else { return (0.0, false) };
            if let Some(gradient) = self.gradient {
                for (r, g) in gradient.iter_mut().enumerate() {
                    let (b, c) = (r / 3, r % 3);
                    set_eps(&mut poses[b], c, 1.0);
                    *g = m.potential(t, &q, &poses).map_or(0.0, |v| v.eps);
                    set_eps(&mut poses[b], c, 0.0);
                }
            }
            (value.re, true)
        }
    }
    let reference = vec![0.0; states.len() * 3];
    let (q, _) = generalized(scene, params, t, states, &reference)?;
    Ok(visit_mechanism(scene, params, Potential { q, t, states, gradient })?.unwrap_or((0.0, false)))
}

fn set_eps(pose: &mut Pose<Dual64>, component: usize, eps: f64) {
    match component {
        0 => pose.x.eps = eps,
        1 => pose.y.eps = eps,
        _ => pose.angle.eps = eps,
    }
}

/// The body states of a joint graph's reduced model at `state`: poses by forward kinematics,
/// velocities by one dual pass along `(q̇, 1)`.
///
/// # Errors
/// A state of the wrong size.
pub fn graph_body_states(mechanism: &GraphMechanism, state: &State) -> Result<Vec<BodyState>, Error> {
    states_of(mechanism, state)
}

/// The body states of mechanism `m` at `state`: poses `p_b(q, t)` and velocities
/// `ṗ_b = J_b q̇ + ∂p_b/∂t` (one dual pass along `(q̇, 1)`).
fn states_of<M: Mechanism>(m: &M, state: &State) -> Result<Vec<BodyState>, Error> {
    let n = m.coordinates().len();
    if state.q.len() != n || state.qdot.len() != n {
        return Err(Error::DimensionMismatch { what: "state", expected: n, got: state.q.len() });
    }
    let q: Vec<Dual64> = state.q.iter().zip(&state.qdot).map(|(q, v)| Dual64::new(*q, *v)).collect();
    let mut poses = vec![Pose::<Dual64>::default(); m.bodies().len()];
    m.poses(Dual64::new(state.t, 1.0), &q, &mut poses);
    Ok(poses
        .iter()
        .map(|p| BodyState { pose: [p.x.re, p.y.re, p.angle.re], velocity: [p.x.eps, p.y.eps, p.angle.eps] })
        .collect())
}

/// `(q, q̇)` of a joint graph from body states: every coordinate joint's value from its two
/// bodies (relative or absolute angle, slide along the axis; [`GraphMechanism::coordinates_of`])
/// and its rate by one dual pass. Angles come out on the branch of the bodies' angles, which
/// every build reports continuous (rapier's are unwrapped after every step): a crank that has
/// turned twice reads `θ₀ + 4π`, however rarely it is read.
pub fn graph_generalized(mechanism: &GraphMechanism, bodies: &[BodyState]) -> (Vec<f64>, Vec<f64>) {
    let poses: Vec<Pose<Dual64>> = bodies
        .iter()
        .map(|b| {
            Pose::new(
                Dual64::new(b.pose[0], b.velocity[0]),
                Dual64::new(b.pose[1], b.velocity[1]),
                Dual64::new(b.pose[2], b.velocity[2]),
            )
        })
        .collect();
    let mut q = vec![Dual64::from(0.0); mechanism.coordinates().len()];
    mechanism.coordinates_of(&poses, &mut q);
    (q.iter().map(|v| v.re).collect(), q.iter().map(|v| v.eps).collect())
}

/// A joint graph's spring potential at body states and, with `gradient`, `∂V/∂p_b` (3B); the
/// flag says whether the graph has springs.
pub fn graph_potential(mechanism: &GraphMechanism, states: &[BodyState], gradient: Option<&mut [f64]>) -> (f64, bool) {
    let poses: Vec<Pose<f64>> = states.iter().map(|s| Pose::from_array(s.pose)).collect();
    if let Some(gradient) = gradient {
        mechanism.potential_gradient(&poses, gradient);
    }
    (mechanism.force_potential(&poses), mechanism.has_potential())
}
