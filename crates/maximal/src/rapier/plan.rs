//! What to build in rapier, independent of the precision: bodies with their mass, inertia and
//! initial state, the joints between them, the multibody couplings, and the per-step forces.
//! [`super::scenes`] writes one plan per scene and joint mode; `world.rs` turns a plan into a
//! rapier world (once for f64, once for f32).

use crate::BodyState;
use lagrange::graph::GraphMechanism;
use lagrange_scenes::Params;
use std::sync::Arc;

/// Impulse joints (maximal coordinates, velocity-level constraints solved by PGS) or multibody
/// joints (reduced coordinates along a tree, Featherstone-style).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum JointMode {
    /// `ImpulseJointSet`.
    Impulse,
    /// `MultibodyJointSet`.
    Multibody,
}

/// How a plan body moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Motion {
    /// The fixed ground at the origin.
    Ground,
    /// A dynamic body.
    Dynamic,
    /// A kinematic, position-based body moved before every step to `(A sin ωt, 0)`.
    Support {
        /// Amplitude `A` (m).
        amplitude: f64,
        /// Angular frequency `ω` (rad/s).
        frequency: f64,
    },
    /// A body of the plan's joint graph that rapier leaves out (an inert fixed body): it has no
    /// mass and no inertia, and a coupled joint of its own moves it (an Atwood pulley without
    /// inertia, whose link would move no mass). Its state follows from the graph's forward
    /// kinematics at the coordinates read back from the other bodies.
    Derived {
        /// The graph body.
        body: usize,
    },
    /// A kinematic, position-based body moved before every step to the pose of body `body` of
    /// the plan's joint graph, a function of time alone (driven and fixed joints from the
    /// ground).
    Kinematic {
        /// The graph body.
        body: usize,
    },
}

/// One rapier body.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BodySpec {
    /// How it moves.
    pub motion: Motion,
    /// Mass (kg); 0 means massless for multibodies and infinite for impulse joints.
    pub mass: f64,
    /// Moment of inertia about the centre of mass (kg m²); same meaning of 0 as the mass.
    pub inertia: f64,
    /// Initial pose and velocity of the centre of mass (the body frame's origin).
    pub initial: BodyState,
    /// Its index in the reduced model's body order, if it is one of the reduced bodies.
    pub reduced: Option<usize>,
    /// Its collider, if it touches others. A dynamic body with a collider takes its mass and
    /// inertia from the collider's shape and density (`mass` and `inertia` above then record
    /// what the shape gives, for the read-back).
    pub collider: Option<ColliderSpec>,
}

impl BodySpec {
    /// The fixed ground at the origin.
    pub(crate) fn ground() -> BodySpec {
        BodySpec {
            motion: Motion::Ground,
            mass: 0.0,
            inertia: 0.0,
            initial: BodyState::default(),
            reduced: None,
            collider: None,
        }
    }
}

/// A collider's shape (parry2d), centred on the body frame's origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Shape {
    /// A disc of `radius` (rapier's 2D ball): inertia `½ m R²` about its centre.
    Ball {
        /// Radius (m).
        radius: f64,
    },
    /// A rectangle with half-widths along the body's x and y axes.
    Cuboid {
        /// Half-extents (m).
        half_extents: [f64; 2],
    },
}

/// A collider attached to a plan body: its shape, the density that gives the body its mass
/// (dynamic bodies), the friction coefficient (both colliders of a contact carry the same, and
/// rapier averages them) and no restitution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ColliderSpec {
    /// Shape.
    pub shape: Shape,
    /// Density (kg/m² in 2D); ignored on fixed bodies.
    pub density: f64,
    /// Coulomb friction coefficient.
    pub friction: f64,
}

impl Shape {
    /// Area (m²): what the density multiplies into a mass.
    pub fn area(&self) -> f64 {
        match *self {
            Shape::Ball { radius } => std::f64::consts::PI * radius * radius,
            Shape::Cuboid { half_extents } => 4.0 * half_extents[0] * half_extents[1],
        }
    }
}

/// What a joint constrains.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum JointKind {
    /// The anchors coincide; the relative angle is free (coordinate: `φ_child − φ_parent`).
    Revolute,
    /// The child's anchor slides along `axis` (parent frame) through the parent's anchor and the
    /// relative angle is locked (coordinate: the anchors' separation along `axis`).
    Prismatic {
        /// Unit slide direction in the parent's (and, unrotated, the child's) frame.
        axis: [f64; 2],
    },
    /// The anchors stay at most `length` apart (tension only).
    Rope {
        /// Rope length (m).
        length: f64,
    },
    /// The anchors coincide and the child is turned by `angle` from the parent.
    Fixed {
        /// `φ_child − φ_parent` (rad).
        angle: f64,
    },
}

/// A joint between two plan bodies, anchored at points given in each body's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct JointSpec {
    /// Index of the parent body (body 1 in rapier).
    pub parent: usize,
    /// Index of the child body (body 2 in rapier).
    pub child: usize,
    /// Anchor in the parent's frame.
    pub anchor_parent: [f64; 2],
    /// Anchor in the child's frame.
    pub anchor_child: [f64; 2],
    /// Type.
    pub kind: JointKind,
    /// A loop-closing joint: an impulse joint in both joint modes (with multibody joints, the
    /// others form a spanning tree and this one closes a loop between two of its links).
    pub closing: bool,
}

/// A multibody coupling `q_to = coeff · q_from + offset` between the coordinates of two joints
/// (a rope over a pulley, a pulley turning with its rope).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Coupling {
    /// Index of the driving joint.
    pub from: usize,
    /// Index of the coupled joint.
    pub to: usize,
    /// `coeff`.
    pub coeff: f64,
    /// `offset`, from the initial coordinates.
    pub offset: f64,
}

/// Forces applied with `add_force`/`add_torque` before every step, from the body states at the
/// start of the step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct StepForces {
    /// The scene's potential `V` acts: `−∂V/∂p_b` on every reduced body.
    pub potential: bool,
    /// Linear damping `c` of the oscillator: `−c ẋ` along x on reduced body 0.
    pub damping: f64,
    /// `e B` of the charged particle: the Lorentz force `e B (ẏ, −ẋ)` on reduced body 0.
    pub lorentz: f64,
    /// The plan's joint graph has force elements that depend on the state or on time (springs,
    /// dampers, varying torques or forces): its wrenches ([`GraphMechanism::body_wrenches`])
    /// are applied per step.
    pub graph_varying: bool,
    /// The plan's joint graph has only constant torques and forces (applied in every substep).
    pub graph_constant: bool,
}

impl StepForces {
    /// Whether any state-dependent force is applied per step (the scene then runs with one
    /// substep).
    pub fn any(&self) -> bool {
        self.potential || self.damping != 0.0 || self.lorentz != 0.0 || self.graph_varying
    }
}

/// A complete, precision-independent description of a rapier build.
#[derive(Clone, Debug)]
pub(crate) struct Plan {
    /// Scene id.
    pub scene: String,
    /// Joint mode.
    pub mode: JointMode,
    /// The parameters simulated (the requested ones plus the deviations).
    pub params: Params,
    /// The read-back of the scene or graph simulated (bodies, potential, inverse map); `None`
    /// for a plan written by hand, with no potential.
    pub read_back: Option<crate::maps::ReadBack>,
    /// One sentence per deviation from the requested scene.
    pub deviations: Vec<String>,
    /// Gravity `g` (along −y).
    pub gravity: f64,
    /// Every rapier body.
    pub bodies: Vec<BodySpec>,
    /// Every joint, parents before children; for multibodies the joints that are not
    /// [`JointSpec::closing`] form a tree rooted at the ground.
    pub joints: Vec<JointSpec>,
    /// Multibody couplings.
    pub couplings: Vec<Coupling>,
    /// Number of bodies of the reduced model.
    pub reduced_bodies: usize,
    /// Per-step forces.
    pub forces: StepForces,
    /// Time of the initial state.
    pub t0: f64,
    /// The joint graph the plan was built from (its force elements and kinematic bodies), if
    /// any; its bodies are the reduced bodies.
    pub graph: Option<Arc<GraphMechanism>>,
}

/// The rotation of `v` by `angle`.
pub(crate) fn rotate(angle: f64, v: [f64; 2]) -> [f64; 2] {
    let (sin, cos) = angle.sin_cos();
    [cos * v[0] - sin * v[1], sin * v[0] + cos * v[1]]
}

/// `ω × r` in the plane.
fn cross(omega: f64, r: [f64; 2]) -> [f64; 2] {
    [-omega * r[1], omega * r[0]]
}

/// World position and velocity of a point fixed in a body at `local`.
pub(crate) fn point_of(body: &BodyState, local: [f64; 2]) -> ([f64; 2], [f64; 2]) {
    let arm = rotate(body.pose[2], local);
    let spin = cross(body.velocity[2], arm);
    ([body.pose[0] + arm[0], body.pose[1] + arm[1]], [body.velocity[0] + spin[0], body.velocity[1] + spin[1]])
}

impl JointSpec {
    /// The joint's coordinate and its rate for the two bodies' states (revolute: relative angle;
    /// prismatic: anchor separation along the axis; rope: anchor distance) — rapier's multibody
    /// joint coordinate for the same anchors.
    pub fn coordinate(&self, parent: &BodyState, child: &BodyState) -> (f64, f64) {
        let (p1, v1) = point_of(parent, self.anchor_parent);
        let (p2, v2) = point_of(child, self.anchor_child);
        let (d, d_dot) = ([p2[0] - p1[0], p2[1] - p1[1]], [v2[0] - v1[0], v2[1] - v1[1]]);
        match self.kind {
            JointKind::Revolute => (child.pose[2] - parent.pose[2], child.velocity[2] - parent.velocity[2]),
            JointKind::Prismatic { axis } => {
                // q = d·u with u turning with the parent: q̇ = ḋ·u + d·(ω₁ × u).
                let u = rotate(parent.pose[2], axis);
                let u_dot = cross(parent.velocity[2], u);
                (d[0] * u[0] + d[1] * u[1], d_dot[0] * u[0] + d_dot[1] * u[1] + d[0] * u_dot[0] + d[1] * u_dot[1])
            }
            JointKind::Rope { .. } => {
                let length = d[0].hypot(d[1]);
                let rate = if length > 0.0 { (d[0] * d_dot[0] + d[1] * d_dot[1]) / length } else { 0.0 };
                (length, rate)
            }
            JointKind::Fixed { .. } => (0.0, 0.0),
        }
    }

    /// How far the two bodies are from satisfying the joint (m or rad): the anchors' separation
    /// (revolute), the offset from the slide line and the relative rotation (prismatic), the
    /// departure from the rope length, slack included (rope).
    pub fn violation(&self, parent: &BodyState, child: &BodyState) -> f64 {
        let (p1, _) = point_of(parent, self.anchor_parent);
        let (p2, _) = point_of(child, self.anchor_child);
        let d = [p2[0] - p1[0], p2[1] - p1[1]];
        match self.kind {
            JointKind::Revolute => d[0].hypot(d[1]),
            JointKind::Prismatic { axis } => {
                let u = rotate(parent.pose[2], axis);
                let off_axis = (d[0] * u[1] - d[1] * u[0]).abs();
                off_axis.max(wrap(child.pose[2] - parent.pose[2]).abs())
            }
            JointKind::Rope { length } => (d[0].hypot(d[1]) - length).abs(),
            JointKind::Fixed { angle } => d[0].hypot(d[1]).max(wrap(child.pose[2] - parent.pose[2] - angle).abs()),
        }
    }
}

/// `angle` brought into `[−π, π]`.
pub(crate) fn wrap(angle: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    angle - TAU * ((angle + PI) / TAU).floor()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(pose: [f64; 3], velocity: [f64; 3]) -> BodyState {
        BodyState { pose, velocity }
    }

    /// The prismatic coordinate rate is the time derivative of the coordinate (central
    /// difference along the rigid motion of both bodies).
    #[test]
    fn prismatic_rate_is_the_derivative_of_the_coordinate() {
        let joint = JointSpec {
            parent: 0,
            child: 1,
            anchor_parent: [0.3, -0.2],
            anchor_child: [0.1, 0.4],
            kind: JointKind::Prismatic { axis: [0.6, -0.8] },
            closing: false,
        };
        let (parent, child) = (state([0.5, 1.0, 0.7], [0.2, -0.3, 1.1]), state([2.0, -1.0, 0.7], [-0.4, 0.9, 1.1]));
        let at = |s: f64| {
            let advance = |b: &BodyState| state(std::array::from_fn(|c| b.pose[c] + s * b.velocity[c]), b.velocity);
            joint.coordinate(&advance(&parent), &advance(&child)).0
        };
        let h = 1e-6;
        let expected = (at(h) - at(-h)) / (2.0 * h);
        let (_, got) = joint.coordinate(&parent, &child);
        assert!((got - expected).abs() < 1e-8, "expected {expected}, got {got}, residual {:e}", got - expected);
    }

    #[test]
    fn wrap_brings_angles_into_the_principal_range() {
        for (angle, expected) in [(0.5, 0.5), (7.0, 7.0 - std::f64::consts::TAU), (-4.0, -4.0 + std::f64::consts::TAU)]
        {
            assert!((wrap(angle) - expected).abs() < 1e-15, "wrap({angle}) = {}, expected {expected}", wrap(angle));
        }
    }
}
