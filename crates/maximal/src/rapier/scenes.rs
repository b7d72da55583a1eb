//! One rapier construction per scene and joint mode (docs/rapier.md#constructions-per-scene), written as a [`Plan`]:
//! which bodies, which joints with which anchors, which couplings and per-step forces, and the
//! deviations from the requested scene that rapier needs.

use super::plan::{BodySpec, ColliderSpec, JointKind, JointMode, JointSpec, Motion, Plan, Shape, StepForces};
use crate::maps::ReadBack;
use crate::scenes::{MaximalScene, MaximalVisitor};
use crate::{BodyState, BuildError, Engine};
use lagrange::{Body, Error, State};
use lagrange_scenes::{Params, Scene};

/// Relative inertia `I_b = 1e-2 m r²` given to point bobs on impulse revolute joints, which
/// freeze the rotation of a body with zero inertia (docs/rapier.md#bodies-and-mass).
pub(crate) const COMPOUND_BOB: f64 = 1e-2;

/// Mass given to massless movable pulleys of multibody Atwood machines, whose coordinate would
/// otherwise move no mass (a singular mass matrix, docs/rapier.md#couplings).
const MASSIVE_PULLEY: f64 = 0.5;

/// Why the Atwood family has no impulse-joint build.
pub(crate) const NO_PULLEY_JOINT: &str = "impulse joints have no pulley or gear constraint (rapier has no gear, \
     rack-and-pinion or pulley joint, and the lever-and-pin-slot substitute adds its own inertia)";

/// Why the driven pendulum has no multibody build.
pub(crate) const NO_RHEONOMIC_MULTIBODY: &str = "a rapier multibody propagates neither the velocity nor the \
     acceleration of a kinematic root to its links, so the bob would miss the support's motion \
     (measured: an error of 0.28 rad that does not shrink with the step)";

/// The plan of `scene` in `mode`, starting from the reduced `initial` state: the scene's own
/// construction ([`MaximalScene::rapier`]) with the deviations its joints need.
///
/// # Errors
/// [`BuildError::Invalid`] for invalid parameters or a state of the wrong size;
/// [`BuildError::Unbuildable`] when `mode` cannot express the scene.
pub(crate) fn plan(
    engine: Engine,
    mode: JointMode,
    scene: &dyn Scene,
    params: &Params,
    initial: &State,
) -> Result<Plan, BuildError> {
    struct Planner<'a> {
        engine: Engine,
        mode: JointMode,
        scene: &'a dyn Scene,
        params: &'a Params,
        initial: &'a State,
    }
    impl MaximalVisitor for Planner<'_> {
        type Output = Result<Plan, BuildError>;
        fn visit<T: MaximalScene>(self, _: T) -> Self::Output {
            let Planner { engine, mode, scene: registered, params, initial } = self;
            if let Some(reason) = T::rapier_unbuildable(mode) {
                return Err(BuildError::Unbuildable { engine, scene: T::ID.into(), reason: reason.into() });
            }
            let (params, deviations) = with_deviations(T::rapier_deviations(mode == JointMode::Multibody), params)?;
            let scene = T::from_params(&params)?;
            let mut draft = Draft::new(mode, registered, &params, initial)?;
            scene.rapier(&mut draft, initial);
            Ok(draft.finish(T::ID, params, deviations, initial.t))
        }
    }
    check_input(scene, params, initial)?;
    if scene.joint_graph(params)?.is_some() {
        // A joint-graph scene: the deviations it declares on its parameters, then the graph's
        // plan (the graph resolved once, with them).
        let (params, deviations) = with_deviations(scene.rapier_deviations(mode == JointMode::Multibody), params)?;
        let mechanism =
            crate::scenes::graph(scene, &params)?.ok_or_else(|| lagrange_scenes::unknown_scene(scene.id()))?;
        let built = super::graph::plan(engine, mode, scene.id(), &mechanism, initial)?;
        // The graph's own deviations, carried by the scene's parameters `<body>.inertia` (a
        // registered joint-graph scene has them) so that the reference simulates them too.
        let mut params = params;
        for (body, inertia) in &built.inertias {
            let name = format!("{body}.inertia");
            if params.spec(&name).is_none() {
                return Err(Error::Inconsistent {
                    what: format!(
                        "{}: rapier needs body `{body}` with inertia {inertia:e}, which no parameter sets",
                        scene.id()
                    ),
                }
                .into());
            }
            params.set(&name, *inertia)?;
        }
        let mut plan = built.plan;
        plan.params = params;
        plan.deviations = deviations.into_iter().chain(built.deviations).collect();
        return Ok(plan);
    }
    crate::scenes::visit(scene, params, Planner { engine, mode, scene, params, initial })?
}

/// Parameters and state are valid and fit the scene (before any `Params::get`).
pub(crate) fn check_input(scene: &dyn Scene, params: &Params, initial: &State) -> Result<(), BuildError> {
    let n = scene.coordinates(params)?.len();
    for (what, values) in [("q", &initial.q), ("q̇", &initial.qdot)] {
        if values.len() != n {
            return Err(Error::DimensionMismatch { what, expected: n, got: values.len() }.into());
        }
    }
    if !(initial.t.is_finite() && initial.q.iter().chain(&initial.qdot).all(|v| v.is_finite())) {
        return Err(
            Error::NonFinite { stage: lagrange::error::Stage::State, t: initial.t, q: initial.q.clone() }.into()
        );
    }
    Ok(())
}

/// The parameters rapier simulates, and one sentence per change (the scene's
/// `SceneType::rapier_deviations`): compound bobs for impulse revolute joints, massive
/// movable pulleys for multibody couplings.
fn with_deviations(changes: &[(&str, &str, &str)], params: &Params) -> Result<(Params, Vec<String>), Error> {
    let mut params = params.clone();
    let mut deviations = Vec::new();
    for &(name, mass, length) in changes {
        if params.get(name) != 0.0 {
            continue;
        }
        if mass.is_empty() {
            params.set(name, MASSIVE_PULLEY)?;
            deviations.push(format!(
                "{name} = {MASSIVE_PULLEY} kg instead of 0: a massless movable pulley's coordinate moves \
                 no mass and makes the multibody mass matrix singular (docs/rapier.md#couplings)"
            ));
        } else {
            let value = COMPOUND_BOB * params.get(mass) * params.get(length).powi(2);
            params.set(name, value)?;
            deviations.push(format!(
                "{name} = {COMPOUND_BOB:e} {mass} {length}² = {value:e} kg m² instead of 0: an impulse \
                 revolute joint freezes the rotation of a body without inertia, so the bob is a compound bob"
            ));
        }
    }
    Ok((params, deviations))
}

/// A plan being written.
pub(crate) struct Draft {
    /// Impulse or multibody joints.
    pub(crate) mode: JointMode,
    /// The reduced model's bodies (masses, inertias).
    reduced_bodies: Vec<Body>,
    /// The reduced model's body states at the initial state.
    pub(crate) states: Vec<BodyState>,
    bodies: Vec<BodySpec>,
    joints: Vec<JointSpec>,
    /// Per-step forces.
    pub(crate) forces: StepForces,
    gravity: f64,
    read_back: ReadBack,
}

impl Draft {
    /// Polar coordinates for a multibody (`ground → revolute → massless arm → prismatic → particle`,
    /// the arm turned by `θ = q[1]` and the particle at `q[0]` along `axis` in the arm's frame), or
    /// the free particle for impulse joints.
    pub(crate) fn polar(&mut self, initial: &State, axis: [f64; 2]) {
        if self.mode == JointMode::Impulse {
            self.reduced(0);
            return;
        }
        let ground = self.ground();
        let arm = self.massless(BodyState { pose: [0.0, 0.0, initial.q[1]], velocity: [0.0, 0.0, initial.qdot[1]] });
        let particle = self.reduced(0);
        self.revolute(ground, arm, [0.0, 0.0], [0.0, 0.0]);
        self.prismatic(arm, particle, axis, [0.0, 0.0], [0.0, 0.0]);
    }

    fn new(mode: JointMode, scene: &dyn Scene, params: &Params, initial: &State) -> Result<Self, Error> {
        let read_back = ReadBack::new(scene, params)?;
        Ok(Self {
            mode,
            reduced_bodies: read_back.bodies().to_vec(),
            states: read_back.body_states(initial)?,
            bodies: Vec::new(),
            joints: Vec::new(),
            forces: StepForces::default(),
            gravity: read_back.gravity(),
            read_back,
        })
    }

    fn push(&mut self, body: BodySpec) -> usize {
        self.bodies.push(body);
        self.bodies.len() - 1
    }

    /// The fixed ground at the origin.
    pub(crate) fn ground(&mut self) -> usize {
        self.push(BodySpec::ground())
    }

    /// A fixed body at `pose` (an incline carrying a collider).
    pub(crate) fn fixed(&mut self, pose: [f64; 3]) -> usize {
        let initial = BodyState { pose, velocity: [0.0; 3] };
        self.push(BodySpec { motion: Motion::Ground, mass: 0.0, inertia: 0.0, initial, reduced: None, collider: None })
    }

    /// Give plan body `body` a collider of `shape` with friction coefficient `friction`. A dynamic
    /// body then takes its mass from the shape (density = its mass / the shape's area) and the
    /// shape's inertia about its centre (a ball: `½ m R²`), recorded in the plan body.
    pub(crate) fn collider(&mut self, body: usize, shape: Shape, friction: f64) {
        let spec = &mut self.bodies[body];
        let density = if spec.motion == Motion::Dynamic { spec.mass / shape.area() } else { 0.0 };
        if spec.motion == Motion::Dynamic {
            spec.inertia = match shape {
                Shape::Ball { radius } => 0.5 * spec.mass * radius * radius,
                Shape::Cuboid { half_extents: [hx, hy] } => spec.mass * (hx * hx + hy * hy) / 3.0,
            };
        }
        spec.collider = Some(ColliderSpec { shape, density, friction });
    }

    /// Reduced body `r`, with its mass, inertia and initial state.
    pub(crate) fn reduced(&mut self, r: usize) -> usize {
        let (body, initial) = (&self.reduced_bodies[r], self.states[r]);
        let spec = BodySpec {
            motion: Motion::Dynamic,
            mass: body.mass,
            inertia: body.inertia,
            initial,
            reduced: Some(r),
            collider: None,
        };
        self.push(spec)
    }

    /// A massless, inertia-free link of a multibody (an arm, a slider).
    pub(crate) fn massless(&mut self, initial: BodyState) -> usize {
        self.push(BodySpec { motion: Motion::Dynamic, mass: 0.0, inertia: 0.0, initial, reduced: None, collider: None })
    }

    /// The kinematic support of a driven pendulum at its place at `t`.
    pub(crate) fn support(&mut self, amplitude: f64, frequency: f64, t: f64) -> usize {
        let motion = Motion::Support { amplitude, frequency };
        let (sin, cos) = (frequency * t).sin_cos();
        let initial =
            BodyState { pose: [amplitude * sin, 0.0, 0.0], velocity: [amplitude * frequency * cos, 0.0, 0.0] };
        self.push(BodySpec { motion, mass: 0.0, inertia: 0.0, initial, reduced: None, collider: None })
    }

    fn joint(
        &mut self,
        parent: usize,
        child: usize,
        kind: JointKind,
        anchor_parent: [f64; 2],
        anchor_child: [f64; 2],
    ) -> usize {
        self.joints.push(JointSpec { parent, child, anchor_parent, anchor_child, kind, closing: false });
        self.joints.len() - 1
    }

    pub(crate) fn revolute(
        &mut self,
        parent: usize,
        child: usize,
        anchor_parent: [f64; 2],
        anchor_child: [f64; 2],
    ) -> usize {
        self.joint(parent, child, JointKind::Revolute, anchor_parent, anchor_child)
    }

    pub(crate) fn prismatic(
        &mut self,
        parent: usize,
        child: usize,
        axis: [f64; 2],
        anchor_parent: [f64; 2],
        anchor_child: [f64; 2],
    ) -> usize {
        self.joint(parent, child, JointKind::Prismatic { axis }, anchor_parent, anchor_child)
    }

    /// A rope between the two bodies' centres.
    pub(crate) fn rope(&mut self, parent: usize, child: usize, length: f64) -> usize {
        self.joint(parent, child, JointKind::Rope { length }, [0.0, 0.0], [0.0, 0.0])
    }

    fn finish(self, scene: &str, params: Params, deviations: Vec<String>, t0: f64) -> Plan {
        Plan {
            scene: scene.into(),
            mode: self.mode,
            params,
            read_back: Some(self.read_back),
            deviations,
            gravity: self.gravity,
            reduced_bodies: self.states.len(),
            bodies: self.bodies,
            joints: self.joints,
            couplings: Vec::new(),
            forces: self.forces,
            t0,
            graph: None,
        }
    }
}
