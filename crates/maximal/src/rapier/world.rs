//! A [`Plan`] running in rapier. This one source is compiled twice: as `double::world` against
//! rapier2d-f64 and as `single::world` against rapier2d (f32); the parent module supplies
//! `rapier` (the crate) and the conversions `real` (f64 → `Real`) and `wide` (`Real` → f64),
//! used only where values cross the rapier API.

use super::rapier::math::{Pose, Real, Vector};
use super::rapier::prelude::{
    ColliderBuilder, FixedJointBuilder, GenericJoint, IntegrationParameters, MassProperties, Multibody,
    MultibodyDofCoupling, MultibodyIndex, PhysicsWorld, PrismaticJointBuilder, RevoluteJointBuilder, RigidBodyBuilder,
    RigidBodyHandle, RopeJointBuilder,
};
use super::{real, wide};
use crate::rapier::plan::{ColliderSpec, JointKind, JointMode, JointSpec, Motion, Plan, Shape, wrap};
use crate::{BodyState, Engine, MaximalSimulation, Settings};
use lagrange::{Error, Mechanism};

/// PGS sweeps per substep for multibodies with couplings: the couplings of one multibody are
/// coupled through its mass matrix, and Gauss–Seidel needs several sweeps to solve them to
/// round-off (docs/rapier.md#couplings: 64 sweeps give 1e-12 accelerations for the double Atwood).
const COUPLING_PGS_ITERATIONS: usize = 128;

/// PGS sweeps per substep for plans with loop-closing joints: Andrews' squeezer couples bodies
/// of 3.65 g and 70 g through four loops, and one sweep leaves a joint residual that does not
/// shrink steadily with the step (measured: its error went 2.0e-3, 1.3e-3, 1.2e-3 at
/// dt = 1e-5, 5e-6, 2.5e-6; with 16 sweeps 6.2e-3, 3.3e-3, 1.7e-3, first order;
/// docs/rapier.md#loops).
const LOOP_PGS_ITERATIONS: usize = 16;

/// A scene running in rapier: the world, the handles of the plan's bodies and, for
/// multibodies, their link ids.
pub(crate) struct RapierSimulation {
    engine: Engine,
    plan: Plan,
    world: PhysicsWorld,
    /// The rapier handle of each plan body.
    handles: Vec<RigidBodyHandle>,
    /// Multibody mode: the multibody, each plan body's link id, and each joint's child link id.
    multibody: Option<MultibodyLinks>,
    /// The step `dt` (s).
    dt: f64,
    /// Steps taken.
    steps: usize,
    /// Each plan body's angle after the last step, unwrapped along the motion.
    angles: Vec<f64>,
    /// Impulse mode: what the last step started from, for the constraint forces.
    last_step: Option<LastStep>,
}

/// Where the plan's bodies and joints are in the multibody.
struct MultibodyLinks {
    index: MultibodyIndex,
    /// Link id of each plan body.
    body_links: Vec<usize>,
    /// Link id of each joint's child (its coordinate's owner; for a loop-closing joint, only
    /// the child's link).
    joint_links: Vec<usize>,
}

/// The start of the last step: every plan body's state, `∂V/∂p_b` applied during it (3B,
/// reduced order; empty when the scene has no per-step forces), and the spring's and torque's
/// wrench on each plan body (empty without them).
struct LastStep {
    start: Vec<BodyState>,
    gradient: Vec<f64>,
    applied: Vec<[f64; 3]>,
}

impl RapierSimulation {
    /// The world of `plan` at its initial state.
    ///
    /// # Errors
    /// [`Error::Inconsistent`] if rapier refuses a multibody joint (a plan whose non-closing
    /// joints are not a tree).
    pub(crate) fn new(engine: Engine, plan: Plan, settings: &Settings) -> Result<Self, Error> {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, -real(plan.gravity));
        world.integration_parameters = integration_parameters(&plan, settings);
        let handles: Vec<RigidBodyHandle> = plan.bodies.iter().map(|b| world.insert_body(body_builder(b))).collect();
        for (body, &handle) in plan.bodies.iter().zip(&handles) {
            if let Some(collider) = &body.collider {
                world.insert_collider(collider_builder(collider), Some(handle));
            }
        }
        let multibody = match plan.mode {
            JointMode::Multibody if plan.joints.iter().any(|j| !j.closing) => {
                Some(assemble_multibody(&mut world, &plan, &handles)?)
            }
            // Free bodies (a disc on an incline) are the same in both modes.
            JointMode::Impulse | JointMode::Multibody => None,
        };
        // Every joint with impulse joints; only the loop-closing ones with multibody joints,
        // where they act between links of the multibody (docs/rapier.md#loops).
        for joint in plan.joints.iter().filter(|j| plan.mode == JointMode::Impulse || j.closing) {
            world.insert_impulse_joint(handles[joint.parent], handles[joint.child], generic_joint(joint));
        }
        let angles = plan.bodies.iter().map(|b| b.initial.pose[2]).collect();
        Ok(Self { engine, plan, world, handles, multibody, dt: settings.dt, steps: 0, angles, last_step: None })
    }

    /// The state of plan body `b` now: pose (angle unwrapped) and velocity of its centre.
    /// Multibody links are read from the link pose and the body jacobian times the generalized
    /// velocities, not from the rigid body's velocity, which lags one substep (docs/rapier.md#multibody-joints).
    fn state(&self, b: usize) -> BodyState {
        let (x, y, angle, velocity) = match (&self.multibody, self.plan.bodies[b].motion) {
            (Some(links), Motion::Dynamic) => {
                let mb = self.multibody_ref(links.index);
                let link_id = links.body_links[b];
                let pose = mb.link(link_id).map_or(Pose::IDENTITY, |link| *link.local_to_world());
                let twist = mb.body_jacobian(link_id) * mb.generalized_velocity();
                let velocity = [wide(twist[0]), wide(twist[1]), wide(twist[2])];
                (pose.translation.x, pose.translation.y, pose.rotation.angle(), velocity)
            }
            _ => {
                let rb = &self.world.bodies[self.handles[b]];
                let (pose, v) = (rb.position(), rb.linvel());
                (
                    pose.translation.x,
                    pose.translation.y,
                    pose.rotation.angle(),
                    [wide(v.x), wide(v.y), wide(rb.angvel())],
                )
            }
        };
        let previous = self.angles[b];
        BodyState { pose: [wide(x), wide(y), previous + wrap(wide(angle) - previous)], velocity }
    }

    fn multibody_ref(&self, index: MultibodyIndex) -> &Multibody {
        // The multibody exists from construction on: nothing removes it.
        self.world.multibody_joints.get_multibody(index).expect("the plan's multibody exists")
    }

    /// The reduced model's body states from every plan body's state (`plan_states`), with the
    /// left-out pulleys reported from their rope.
    fn reduced_states(&self, plan_states: &[BodyState]) -> Vec<BodyState> {
        let mut reduced = vec![BodyState::default(); self.plan.reduced_bodies];
        for (spec, state) in self.plan.bodies.iter().zip(plan_states) {
            if let Some(r) = spec.reduced {
                reduced[r] = *state;
            }
        }
        // Bodies rapier leaves out: by forward kinematics at the coordinates (and rates) read
        // back from the others, whose angles are unwrapped along the motion.
        if let Some(graph) = &self.plan.graph
            && self.plan.bodies.iter().any(|b| matches!(b.motion, Motion::Derived { .. }))
        {
            use lagrange::num_dual::Dual64;
            let poses: Vec<lagrange::Pose<Dual64>> = reduced
                .iter()
                .map(|s| {
                    lagrange::Pose::new(
                        Dual64::new(s.pose[0], s.velocity[0]),
                        Dual64::new(s.pose[1], s.velocity[1]),
                        Dual64::new(s.pose[2], s.velocity[2]),
                    )
                })
                .collect();
            let mut q = vec![Dual64::from(0.0); graph.description().coordinates.len()];
            graph.coordinates_of(&poses, &mut q);
            for spec in &self.plan.bodies {
                if let Motion::Derived { body } = spec.motion {
                    let p = graph.body_pose(body, Dual64::new(self.t(), 1.0), &q);
                    reduced[body] =
                        BodyState { pose: [p.x.re, p.y.re, p.angle.re], velocity: [p.x.eps, p.y.eps, p.angle.eps] };
                }
            }
        }
        reduced
    }

    fn plan_states(&self) -> Vec<BodyState> {
        (0..self.plan.bodies.len()).map(|b| self.state(b)).collect()
    }

    /// Replace every reduced body's user force and torque by the scene's per-step forces at the
    /// start of the step; returns `∂V/∂p_b` (3B; zeros without a potential) and the spring's and
    /// torque's wrench on each plan body (empty without them).
    fn apply_step_forces(&mut self, t: f64, plan_states: &[BodyState]) -> Result<(Vec<f64>, Vec<[f64; 3]>), Error> {
        let forces = self.plan.forces;
        let reduced = self.reduced_states(plan_states);
        let mut gradient = vec![0.0; 3 * reduced.len()];
        if let Some(read_back) = self.plan.read_back.as_ref().filter(|_| forces.potential) {
            read_back.potential(t, &reduced, Some(&mut gradient));
        }
        // The spring at the start of the step (D from the body's pose then), the constant torque,
        // a joint graph's force elements.
        let mut applied = Vec::new();
        if self.plan.graph.is_some() {
            applied = vec![[0.0; 3]; self.plan.bodies.len()];
            if let Some(graph) = &self.plan.graph {
                let poses: Vec<lagrange::Pose<f64>> =
                    reduced.iter().map(|s| lagrange::Pose::from_array(s.pose)).collect();
                let velocities: Vec<[f64; 3]> = reduced.iter().map(|s| s.velocity).collect();
                let mut wrench = vec![0.0; 3 * reduced.len()];
                graph.body_wrenches(t, &poses, &velocities, &mut wrench);
                if !wrench.iter().all(|w| w.is_finite()) {
                    return Err(Error::NonFinite { stage: lagrange::error::Stage::AppliedForce, t, q: wrench });
                }
                for (b, spec) in self.plan.bodies.iter().enumerate() {
                    if let (Some(r), Motion::Dynamic) = (spec.reduced, spec.motion) {
                        applied[b] = [wrench[3 * r], wrench[3 * r + 1], wrench[3 * r + 2]];
                    }
                }
            }
        }
        for (b, (spec, &handle)) in self.plan.bodies.iter().zip(&self.handles).enumerate() {
            let extra = applied.get(b);
            if spec.reduced.is_none() && extra.is_none() {
                continue;
            }
            let (mut force, mut torque) = ([0.0; 2], 0.0);
            if let Some(r) = spec.reduced {
                let v = reduced[r].velocity;
                force = [-gradient[3 * r], -gradient[3 * r + 1]];
                torque = -gradient[3 * r + 2];
                if r == 0 {
                    // Damping −c ẋ on the oscillator, Lorentz e B (ẏ, −ẋ) on the charged particle.
                    force[0] += -forces.damping * v[0] + forces.lorentz * v[1];
                    force[1] += -forces.lorentz * v[0];
                }
            }
            if let Some(w) = extra {
                force = [force[0] + w[0], force[1] + w[1]];
                torque += w[2];
            }
            if let Some(rb) = self.world.bodies.get_mut(handle) {
                rb.reset_forces(false);
                rb.reset_torques(false);
                rb.add_force(Vector::new(real(force[0]), real(force[1])), false);
                rb.add_torque(real(torque), false);
            }
        }
        Ok((gradient, applied))
    }

    /// One rapier step of `dt`.
    fn step(&mut self) -> Result<(), Error> {
        let t = self.t();
        let start = self.plan_states();
        let forces = self.plan.forces;
        let (gradient, applied) = if forces.any() || forces.graph_constant {
            self.apply_step_forces(t, &start)?
        } else {
            (Vec::new(), Vec::new())
        };
        // Move the kinematic support to where it is at the end of the step.
        for (spec, &handle) in self.plan.bodies.iter().zip(&self.handles) {
            if let Motion::Support { amplitude, frequency } = spec.motion
                && let Some(rb) = self.world.bodies.get_mut(handle)
            {
                let x = amplitude * (frequency * (t + self.dt)).sin();
                rb.set_next_kinematic_translation(Vector::new(real(x), 0.0));
            }
            // A graph body driven from the ground: its pose at the end of the step (a function of
            // time alone, whatever the coordinates).
            if let (Motion::Kinematic { body }, Some(graph)) = (spec.motion, &self.plan.graph)
                && let Some(rb) = self.world.bodies.get_mut(handle)
            {
                let q = vec![0.0; graph.description().coordinates.len()];
                let [x, y, angle] = graph.body_pose(body, t + self.dt, &q).to_array();
                rb.set_next_kinematic_position(Pose::new(Vector::new(real(x), real(y)), real(angle)));
            }
        }
        self.world.step();
        self.steps += 1;
        for b in 0..self.plan.bodies.len() {
            let state = self.state(b);
            if !state.pose.iter().chain(&state.velocity).all(|v| v.is_finite()) {
                return Err(Error::Diverged {
                    t: self.t(),
                    step: self.steps,
                    quantity: format!("rapier body {b} state {state:?}"),
                });
            }
            self.angles[b] = state.pose[2];
        }
        if self.plan.mode == JointMode::Impulse {
            self.last_step = Some(LastStep { start, gradient, applied });
        }
        Ok(())
    }

    /// Multibody coupling residual `|q_to − coeff q_from − offset|`, largest over the couplings.
    fn coupling_residual(&self, links: &MultibodyLinks) -> f64 {
        let mb = self.multibody_ref(links.index);
        let coordinate = |j: usize| {
            let link = links.joint_links[j];
            mb.link(link).map_or(f64::NAN, |l| wide(l.joint().coords()[free_axis(&self.plan.joints[j])]))
        };
        self.plan
            .couplings
            .iter()
            .map(|c| (coordinate(c.to) - c.coeff * coordinate(c.from) - c.offset).abs())
            .fold(0.0, f64::max)
    }
}

impl MaximalSimulation for RapierSimulation {
    fn engine(&self) -> Engine {
        self.engine
    }

    fn t(&self) -> f64 {
        self.plan.t0 + self.steps as f64 * self.dt
    }

    /// Whole steps of `dt` up to the step nearest `t`.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for a non-finite `t` or one before the current time;
    /// [`Error::Diverged`] if a body state becomes non-finite.
    fn advance_to(&mut self, t: f64) -> Result<(), Error> {
        let target = ((t - self.plan.t0) / self.dt).round();
        if !target.is_finite() {
            return Err(Error::InvalidSetting { what: "time", value: t, why: "must be finite" });
        }
        if target < self.steps as f64 {
            return Err(Error::InvalidSetting { what: "time", value: t, why: "lies before the current time" });
        }
        // `target` is a non-negative whole number here.
        let target = target as usize;
        while self.steps < target {
            self.step()?;
        }
        Ok(())
    }

    /// Every reduced body's pose and velocity (centre of mass); a massless Atwood pulley that
    /// rapier leaves out turns with its rope. For point bodies (no inertia) the angle is the
    /// rapier body's, which the reduced model ignores.
    fn bodies(&self) -> Vec<BodyState> {
        self.reduced_states(&self.plan_states())
    }

    /// Impulse joints: the largest anchor separation (revolute), offset from the slide line or
    /// relative rotation (prismatic), or departure from the rope length (rope); `None` for a
    /// free body. Multibodies: the largest coupling residual and violation of the loop-closing
    /// impulse joints, `None` without either (the tree's joints hold by construction).
    fn constraint_violation(&self) -> Option<f64> {
        let violation = |j: &JointSpec| j.violation(&self.state(j.parent), &self.state(j.child));
        let impulse = self.plan.joints.iter().filter(|j| self.multibody.is_none() || j.closing);
        let joints = impulse.clone().next().is_some().then(|| impulse.map(violation).fold(0.0, f64::max));
        let couplings = match &self.multibody {
            Some(links) if !self.plan.couplings.is_empty() => Some(self.coupling_residual(links)),
            _ => None,
        };
        match (joints, couplings) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        }
    }

    /// Impulse joints, after at least one step: `R_b = (Δ(m_b v_b), Δ(I_b ω_b))/dt − F_b^gravity
    /// − w_b + ∂V/∂p_b` over the last step (`w_b` the spring's and torque's wrench), as
    /// `lagrange::reaction_forces` defines it. This is the sum
    /// of the joint impulses rapier applied to the body during the step divided by `dt` (plus
    /// the non-potential applied forces, damping and Lorentz, which the reduced model also
    /// leaves in its reactions). It is read from the momentum balance because
    /// `ImpulseJoint::impulses` keeps only the last substep's impulses, in rows that the solver
    /// has Gram–Schmidt-orthogonalised (`JointConstraintHelper::finalize_constraints`).
    /// Multibodies: `None` (rapier does not expose their joint forces).
    fn constraint_forces(&mut self) -> Option<Vec<f64>> {
        if self.multibody.is_some() {
            return None;
        }
        let last = self.last_step.as_ref()?;
        let mut forces = vec![0.0; 3 * self.plan.reduced_bodies];
        for (b, spec) in self.plan.bodies.iter().enumerate() {
            let Some(r) = spec.reduced else { continue };
            let (before, now) = (last.start[b].velocity, self.state(b).velocity);
            let gradient = |c: usize| last.gradient.get(3 * r + c).copied().unwrap_or(0.0);
            forces[3 * r] = spec.mass * (now[0] - before[0]) / self.dt + gradient(0);
            forces[3 * r + 1] = spec.mass * ((now[1] - before[1]) / self.dt + self.plan.gravity) + gradient(1);
            forces[3 * r + 2] = spec.inertia * (now[2] - before[2]) / self.dt + gradient(2);
            if let Some(w) = last.applied.get(b) {
                (0..3).for_each(|c| forces[3 * r + c] -= w[c]);
            }
        }
        Some(forces)
    }

    fn steps(&self) -> usize {
        self.steps
    }

    fn substeps(&self) -> usize {
        self.world.integration_parameters.num_solver_iterations
    }
}

/// Every integration parameter the comparison depends on, explicitly (docs/rapier.md#integration-parameters, #integration-parameters):
/// `substeps` substeps per step (1 for scenes driven by per-step forces, which are constant over
/// a step: more would make the map non-symplectic, §1.5); one PGS sweep for impulse joints
/// (more only tighten the joint error, §2.1), enough for coupled multibodies and for loops; no stabilization
/// sweeps (they make the impulse scheme dissipative, §2.1); no speed or correction caps; no joint
/// warm-start; no CCD; contacts re-computed every step (no recycling of old contact points,
/// which would stale a rolling contact) and never clustered.
fn integration_parameters(plan: &Plan, settings: &Settings) -> IntegrationParameters {
    IntegrationParameters {
        dt: real(settings.dt),
        num_solver_iterations: if plan.forces.any() { 1 } else { settings.substeps },
        num_internal_pgs_iterations: if !plan.couplings.is_empty() {
            COUPLING_PGS_ITERATIONS
        } else if plan.joints.iter().any(|j| j.closing) {
            LOOP_PGS_ITERATIONS
        } else {
            1
        },
        num_internal_stabilization_iterations: 0,
        warmstart_joints: false,
        length_unit: 1.0,
        normalized_max_linear_velocity: Real::MAX,
        normalized_max_corrective_velocity: Real::MAX,
        max_ccd_substeps: 0,
        contact_recycling: false,
        ..IntegrationParameters::default()
    }
}

/// A rigid body at the plan body's initial pose: the fixed ground, the kinematic support, or a
/// dynamic body with explicit mass properties (or, with a collider, those of its shape), never
/// sleeping and not clamped in its angular speed.
fn body_builder(body: &crate::rapier::plan::BodySpec) -> RigidBodyBuilder {
    let [x, y, angle] = body.initial.pose;
    let pose = Pose::new(Vector::new(real(x), real(y)), real(angle));
    let builder = match body.motion {
        Motion::Ground => RigidBodyBuilder::fixed(),
        Motion::Support { .. } | Motion::Kinematic { .. } => RigidBodyBuilder::kinematic_position_based(),
        // Left out: an inert body that nothing touches.
        Motion::Derived { .. } => RigidBodyBuilder::fixed(),
        Motion::Dynamic => {
            let [vx, vy, omega] = body.initial.velocity;
            let builder = RigidBodyBuilder::dynamic();
            let builder = match body.collider {
                Some(_) => builder,
                None => builder.additional_mass_properties(MassProperties::new(
                    Vector::ZERO,
                    real(body.mass),
                    real(body.inertia),
                )),
            };
            builder.linvel(Vector::new(real(vx), real(vy))).angvel(real(omega)).allow_fast_rotation(true)
        }
    };
    builder.pose(pose).can_sleep(false)
}

/// The rapier collider of a plan collider: its parry shape with its density, friction and no
/// restitution (rapier averages both colliders' coefficients).
fn collider_builder(collider: &ColliderSpec) -> ColliderBuilder {
    let builder = match collider.shape {
        Shape::Ball { radius } => ColliderBuilder::ball(real(radius)),
        Shape::Cuboid { half_extents: [hx, hy] } => ColliderBuilder::cuboid(real(hx), real(hy)),
    };
    builder.density(real(collider.density)).friction(real(collider.friction)).restitution(0.0)
}

/// The rapier joint of a plan joint (frames at the anchors; a prismatic joint's frames turned so
/// that their x axis is the slide axis in both bodies).
fn generic_joint(joint: &JointSpec) -> GenericJoint {
    let point = |p: [f64; 2]| Vector::new(real(p[0]), real(p[1]));
    let (anchor1, anchor2) = (point(joint.anchor_parent), point(joint.anchor_child));
    match joint.kind {
        JointKind::Revolute => RevoluteJointBuilder::new().local_anchor1(anchor1).local_anchor2(anchor2).into(),
        JointKind::Prismatic { axis } => {
            PrismaticJointBuilder::new(point(axis)).local_anchor1(anchor1).local_anchor2(anchor2).into()
        }
        JointKind::Rope { length } => {
            RopeJointBuilder::new(real(length)).local_anchor1(anchor1).local_anchor2(anchor2).into()
        }
        // The frames meet when the child is turned by `angle` from the parent.
        JointKind::Fixed { angle } => FixedJointBuilder::new()
            .local_frame1(Pose::new(anchor1, 0.0))
            .local_frame2(Pose::new(anchor2, real(-angle)))
            .into(),
    }
}

/// The joint's free axis in rapier's spatial coordinates (0 = along the prismatic axis,
/// 2 = angle).
fn free_axis(joint: &JointSpec) -> usize {
    match joint.kind {
        JointKind::Prismatic { .. } => 0,
        JointKind::Revolute | JointKind::Rope { .. } | JointKind::Fixed { .. } => 2,
    }
}

/// Insert the plan's joints as one multibody rooted at the ground and bring it to the initial
/// state (docs/rapier.md#constructions-per-scene): fix the root, zero the default joint damping (docs/rapier.md#multibody-joints), displace every
/// joint coordinate from 0 to its initial value, set the generalized velocities, then add the
/// couplings with the link ids read after all inserts.
fn assemble_multibody(
    world: &mut PhysicsWorld,
    plan: &Plan,
    handles: &[RigidBodyHandle],
) -> Result<MultibodyLinks, Error> {
    let inconsistent = |what: &str| Error::Inconsistent { what: format!("rapier multibody of {}: {what}", plan.scene) };
    let tree = || plan.joints.iter().filter(|j| !j.closing);
    for joint in tree() {
        if matches!(joint.kind, JointKind::Rope { .. }) {
            return Err(inconsistent("a rope is not a multibody joint"));
        }
        world
            .insert_multibody_joint(handles[joint.parent], handles[joint.child], generic_joint(joint))
            .ok_or_else(|| inconsistent("the joints do not form a tree"))?;
    }
    let link_of = |handle: RigidBodyHandle| world.multibody_joints.rigid_body_link(handle).copied();
    let root = tree().next().and_then(|j| link_of(handles[j.parent])).ok_or_else(|| inconsistent("no joint"))?;
    let mut body_links = Vec::with_capacity(handles.len());
    for (spec, &handle) in plan.bodies.iter().zip(handles) {
        match link_of(handle) {
            Some(link) if link.multibody == root.multibody => body_links.push(link.id),
            _ if spec.motion == Motion::Dynamic => return Err(inconsistent("a body outside the multibody")),
            _ => body_links.push(0),
        }
    }
    let joint_links: Vec<usize> = plan.joints.iter().map(|j| body_links[j.child]).collect();
    let mb = world.multibody_joints.get_multibody_mut(root.multibody).ok_or_else(|| inconsistent("no multibody"))?;
    mb.forward_kinematics(&world.bodies, true);
    mb.damping_mut().fill(0.0);
    let mut displacement = vec![0.0; mb.ndofs()];
    let mut velocity = vec![0.0; mb.ndofs()];
    // A fixed joint has no degree of freedom in the multibody (and no slot in its vectors).
    let moves = |j: &JointSpec| !j.closing && !matches!(j.kind, JointKind::Fixed { .. });
    for (joint, &link_id) in plan.joints.iter().zip(&joint_links).filter(|(j, _)| moves(j)) {
        let link = mb.link(link_id).ok_or_else(|| inconsistent("a joint without a link"))?;
        let (q, qdot) = joint.coordinate(&plan.bodies[joint.parent].initial, &plan.bodies[joint.child].initial);
        displacement[link.assembly_id()] = real(q);
        velocity[link.assembly_id()] = real(qdot);
    }
    mb.apply_displacements(&displacement);
    mb.forward_kinematics(&world.bodies, false);
    mb.update_rigid_bodies(&mut world.bodies, true);
    mb.generalized_velocity_mut().copy_from_slice(&velocity);
    for coupling in &plan.couplings {
        mb.add_dof_coupling(MultibodyDofCoupling {
            link1: joint_links[coupling.from],
            dof1: 0,
            axis1: free_axis(&plan.joints[coupling.from]),
            link2: joint_links[coupling.to],
            dof2: 0,
            axis2: free_axis(&plan.joints[coupling.to]),
            coeff: real(coupling.coeff),
            offset: real(coupling.offset),
        });
    }
    // Poses and jacobians of the displaced state.
    mb.forward_kinematics(&world.bodies, false);
    Ok(MultibodyLinks { index: root.multibody, body_links, joint_links })
}
