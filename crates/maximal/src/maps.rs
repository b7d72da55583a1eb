//! Between generalized and maximal coordinates, resolved once per scene ([`ReadBack`]): the
//! initial body states of a scene (from its reduced model's poses), the scene-specific inverse
//! maps `q = g(z)` used to read any maximal engine back into generalized coordinates, the
//! bodies' energy, and the forces of the scene's potential on its bodies.

use crate::BodyState;
use crate::scenes::{MaximalScene, MaximalVisitor};
use lagrange::graph::GraphMechanism;
use lagrange::num_dual::Dual64;
use lagrange::{Body, CoordinateKind, Error, Mechanism, Pose, State};
use lagrange_scenes::{ClosedForm, MechanismVisitor, Params, Scene, visit_mechanism};
use std::f64::consts::PI;
use std::sync::Arc;

/// What reads one scene's bodies back, resolved once from the scene and its parameters: the
/// bodies (masses and inertias, in the reduced model's order), gravity, which coordinates are
/// angles, and the scene's map between body states and generalized coordinates — its joint
/// graph, or its hand-written inverse map `q = g(z)` with its reduced model's poses and
/// potential. Every build carries one ([`Built::read_back`](crate::Built::read_back)); reading a
/// run back costs no lookup.
#[derive(Clone)]
pub struct ReadBack(Arc<Resolved>);

struct Resolved {
    bodies: Vec<Body>,
    gravity: f64,
    angles: Vec<bool>,
    map: Map,
}

enum Map {
    /// A joint graph: forward kinematics, the joints' values, its springs' potential.
    Graph(Arc<GraphMechanism>),
    /// A hand-written maximal description, with the reduced model's poses and potential
    /// (`None` for a scene that is no body mechanism, the charged particle: its coordinates
    /// are its one body's position).
    Scene { inverse: Box<dyn InverseMap>, reduced: Option<Box<dyn ReducedPoses>> },
}

/// A scene's hand-written inverse map over dual numbers (object-safe).
trait InverseMap: Send + Sync {
    fn generalized(&self, t: Dual64, z: &[[Dual64; 3]]) -> Vec<Dual64>;
}

impl<T: MaximalScene> InverseMap for T {
    fn generalized(&self, t: Dual64, z: &[[Dual64; 3]]) -> Vec<Dual64> {
        MaximalScene::generalized(self, t, z)
    }
}

/// A reduced model's poses and potential, at body states (object-safe).
trait ReducedPoses: Send + Sync {
    fn bodies(&self) -> Vec<Body>;
    fn body_states(&self, state: &State) -> Result<Vec<BodyState>, Error>;
    fn potential(&self, t: f64, q: &[f64], states: &[BodyState], gradient: Option<&mut [f64]>) -> (f64, bool);
}

impl<M: Mechanism + Send + Sync> ReducedPoses for M {
    fn bodies(&self) -> Vec<Body> {
        Mechanism::description(self).bodies.clone()
    }

    fn body_states(&self, state: &State) -> Result<Vec<BodyState>, Error> {
        states_of(self, state)
    }

    fn potential(&self, t: f64, q: &[f64], states: &[BodyState], gradient: Option<&mut [f64]>) -> (f64, bool) {
        let q: Vec<Dual64> = q.iter().map(|v| Dual64::from(*v)).collect();
        let mut poses: Vec<Pose<Dual64>> = states
            .iter()
            .map(|s| Pose::new(Dual64::from(s.pose[0]), Dual64::from(s.pose[1]), Dual64::from(s.pose[2])))
            .collect();
        let t = Dual64::from(t);
        let Some(value) = Mechanism::potential(self, t, &q, &poses) else { return (0.0, false) };
        if let Some(gradient) = gradient {
            for (r, g) in gradient.iter_mut().enumerate() {
                let (b, c) = (r / 3, r % 3);
                set_eps(&mut poses[b], c, 1.0);
                *g = Mechanism::potential(self, t, &q, &poses).map_or(0.0, |v| v.eps);
                set_eps(&mut poses[b], c, 0.0);
            }
        }
        (value.re, true)
    }
}

impl ReadBack {
    /// Resolve `scene` with `params`: its joint graph if it is one, otherwise its hand-written
    /// maximal description.
    ///
    /// # Errors
    /// Invalid parameters, a graph that is not a mechanism, or a scene with neither a joint
    /// graph nor a hand-written description.
    pub fn new(scene: &dyn Scene, params: &Params) -> Result<Self, Error> {
        if let Some(mechanism) = crate::scenes::graph(scene, params)? {
            return Ok(Self::graph(Arc::new(mechanism)));
        }
        struct Inverse;
        impl MaximalVisitor for Inverse {
            type Output = Box<dyn InverseMap>;
            fn visit<T: MaximalScene>(self, scene: T) -> Box<dyn InverseMap> {
                Box::new(scene)
            }
        }
        struct Reduced;
        impl MechanismVisitor for Reduced {
            type Output = Box<dyn ReducedPoses>;
            fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, m: M) -> Box<dyn ReducedPoses> {
                Box::new(m)
            }
        }
        let reduced = visit_mechanism(scene.id(), params, Reduced)?;
        let inverse = crate::scenes::visit(scene, params, Inverse)?;
        let bodies = match &reduced {
            Some(reduced) => reduced.bodies(),
            None => vec![Body::point("particle", params.get("mass"))],
        };
        let angles = scene.coordinates(params)?.iter().map(|c| c.kind == CoordinateKind::Angle).collect();
        Ok(Self(Arc::new(Resolved { bodies, gravity: gravity(params), angles, map: Map::Scene { inverse, reduced } })))
    }

    /// The read-back of a resolved joint graph.
    pub fn graph(mechanism: Arc<GraphMechanism>) -> Self {
        let description = Mechanism::description(&*mechanism);
        let bodies = description.bodies.clone();
        let gravity = description.gravity;
        let angles = description.coordinates.iter().map(|c| c.kind == CoordinateKind::Angle).collect();
        Self(Arc::new(Resolved { bodies, gravity, angles, map: Map::Graph(mechanism) }))
    }

    /// The bodies (masses and inertias, in the reduced model's order).
    pub fn bodies(&self) -> &[Body] {
        &self.0.bodies
    }

    /// Gravity `g` (0 where the scene has none).
    pub fn gravity(&self) -> f64 {
        self.0.gravity
    }

    /// The resolved joint graph, for a scene that is one.
    pub fn mechanism(&self) -> Option<&Arc<GraphMechanism>> {
        match &self.0.map {
            Map::Graph(mechanism) => Some(mechanism),
            Map::Scene { .. } => None,
        }
    }

    /// The body states of the reduced model at `state`: poses `p_b(q, t)` and velocities
    /// `ṗ_b = J_b q̇ + ∂p_b/∂t` (one dual pass along `(q̇, 1)`) — the initial condition of every
    /// maximal build.
    ///
    /// # Errors
    /// A state of the wrong size.
    pub fn body_states(&self, state: &State) -> Result<Vec<BodyState>, Error> {
        match &self.0.map {
            Map::Graph(mechanism) => graph_body_states(mechanism, state),
            Map::Scene { reduced: Some(reduced), .. } => reduced.body_states(state),
            // The charged particle: its coordinates are already Cartesian.
            Map::Scene { reduced: None, .. } => Ok(vec![BodyState {
                pose: [state.q[0], state.q[1], 0.0],
                velocity: [state.qdot[0], state.qdot[1], 0.0],
            }]),
        }
    }

    /// `(q, q̇)` from body states: `q = g(z)` (a joint graph's joint values, or the scene's
    /// inverse map, written by hand independently of the reduced model's poses),
    /// `q̇ = (∂g/∂z) ż + ∂g/∂t` (one dual pass). A joint graph's angles come out on the branch
    /// of the bodies' angles ([`graph_generalized`]); a hand-written map's angles are unwrapped
    /// to the branch nearest `reference` (the previous read-back carried forward, or the
    /// initial state).
    pub fn generalized(&self, t: f64, bodies: &[BodyState], reference: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let inverse = match &self.0.map {
            Map::Graph(mechanism) => return graph_generalized(mechanism, bodies),
            Map::Scene { inverse, .. } => inverse,
        };
        let z: Vec<[Dual64; 3]> =
            bodies.iter().map(|b| std::array::from_fn(|c| Dual64::new(b.pose[c], b.velocity[c]))).collect();
        let q = inverse.generalized(Dual64::new(t, 1.0), &z);
        let mut values: Vec<f64> = q.iter().map(|v| v.re).collect();
        for (i, angle) in self.0.angles.iter().enumerate() {
            if *angle && i < reference.len() {
                values[i] += 2.0 * PI * ((reference[i] - values[i]) / (2.0 * PI)).round();
            }
        }
        (values, q.iter().map(|v| v.eps).collect())
    }

    /// Energy of body states: `Σ ½ m |v|² + ½ I ω² + Σ m g y + V(t, q, poses)`, with `q` from
    /// the inverse map for the potential's coordinate terms.
    pub fn energy(&self, t: f64, states: &[BodyState]) -> f64 {
        let g = self.0.gravity;
        let mut energy = 0.0;
        for (b, s) in self.0.bodies.iter().zip(states) {
            let v = s.velocity;
            energy +=
                0.5 * b.mass * (v[0] * v[0] + v[1] * v[1]) + 0.5 * b.inertia * v[2] * v[2] + b.mass * g * s.pose[1];
        }
        // A scene without a potential (the charged particle: the magnetic force does no work)
        // has kinetic and gravitational energy only.
        let (value, has_potential) = self.potential(t, states, None);
        if has_potential { energy + value } else { energy }
    }

    /// The scene's potential `V` at body states and, with `gradient`, `∂V/∂p_b` (3B): minus
    /// the potential's force and torque on each body, to apply in engines that integrate
    /// bodies. The flag says whether the scene has a potential.
    pub fn potential(&self, t: f64, states: &[BodyState], gradient: Option<&mut [f64]>) -> (f64, bool) {
        match &self.0.map {
            Map::Graph(mechanism) => graph_potential(mechanism, states, gradient),
            Map::Scene { reduced: None, .. } => (0.0, false),
            Map::Scene { reduced: Some(reduced), .. } => {
                let reference = vec![0.0; states.len() * 3];
                let (q, _) = self.generalized(t, states, &reference);
                reduced.potential(t, &q, states, gradient)
            }
        }
    }
}

impl std::fmt::Debug for ReadBack {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kind = if self.mechanism().is_some() { "joint graph" } else { "hand-written" };
        f.debug_struct("ReadBack").field("kind", &kind).field("bodies", &self.0.bodies.len()).finish()
    }
}

/// Gravity `g` of a scene (0 where it has none).
fn gravity(params: &Params) -> f64 {
    if params.specs().iter().any(|s| s.name == "gravity") { params.get("gravity") } else { 0.0 }
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
    let n = m.description().coordinates.len();
    if state.q.len() != n || state.qdot.len() != n {
        return Err(Error::DimensionMismatch { what: "state", expected: n, got: state.q.len() });
    }
    let q: Vec<Dual64> = state.q.iter().zip(&state.qdot).map(|(q, v)| Dual64::new(*q, *v)).collect();
    let mut poses = vec![Pose::<Dual64>::default(); m.description().bodies.len()];
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
    let mut q = vec![Dual64::from(0.0); mechanism.description().coordinates.len()];
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
