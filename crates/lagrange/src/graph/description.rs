//! The joint-graph description: plain data, written once by the user.

use crate::tree::{AngleReference, Sense};
use crate::{Error, Scalar};

/// The name that stands for the fixed ground in [`GraphJoint::parent`], [`GraphJoint::child`]
/// and [`Point::body`]; no body may take it.
pub const GROUND: &str = "ground";

/// A planar mechanism as bodies and joints: the one description from which the reduced model
/// ([`GraphMechanism`](super::GraphMechanism)), the Cartesian model and the rapier builds
/// (crate `lagrange-maximal`) follow.
///
/// Body frames have their origin at the body's centre of mass and turn with the body's angle
/// `φ`; anchors and points of application are given in them (the ground's frame is the
/// world's). Gravity `g` acts along −y.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct JointGraph {
    /// Name of the mechanism, for messages and reports (a scene file's graph takes the file's
    /// id when it has none).
    #[cfg_attr(feature = "serde", serde(default))]
    pub name: String,
    /// The bodies; their order is the order of the reduced model's bodies.
    pub bodies: Vec<GraphBody>,
    /// The joints; the order of the coordinate joints is the order of the coordinates.
    pub joints: Vec<GraphJoint>,
    /// Couplings between joint coordinates (gears, pulleys).
    #[cfg_attr(feature = "serde", serde(default))]
    pub couplings: Vec<Coupling>,
    /// Springs, dampers, torques and forces.
    #[cfg_attr(feature = "serde", serde(default))]
    pub forces: Vec<ForceElement>,
    /// Gravitational acceleration `g` (m/s²) along −y.
    #[cfg_attr(feature = "serde", serde(default))]
    pub gravity: f64,
}

/// A rigid body of a [`JointGraph`].
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct GraphBody {
    /// Unique name (not [`GROUND`]).
    pub name: String,
    /// Mass (kg), finite and ≥ 0.
    pub mass: f64,
    /// Moment of inertia about the centre of mass (kg m²), finite and ≥ 0.
    pub inertia: f64,
    /// The body's shape, centred on its centre of mass, when its mass properties come from it
    /// ([`GraphBody::from_shape`]); the rapier builds then take them from the parry shape.
    #[cfg_attr(feature = "serde", serde(default))]
    pub shape: Option<Shape>,
}

/// A planar shape centred on a body's centre of mass, of uniform density.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Shape {
    /// A disc of `radius` (m): area `π R²`, inertia `½ m R²`.
    Disc {
        /// Radius (m).
        radius: f64,
    },
    /// A rectangle of half-extents `(a, b)` along the body's axes (m): area `4ab`, inertia
    /// `m (a² + b²) / 3`.
    Rectangle {
        /// Half-widths along the body's x and y axes (m).
        half_extents: [f64; 2],
    },
}

impl Shape {
    /// Area (m²).
    pub fn area(&self) -> f64 {
        match *self {
            Shape::Disc { radius } => std::f64::consts::PI * radius * radius,
            Shape::Rectangle { half_extents: [a, b] } => 4.0 * a * b,
        }
    }

    /// Moment of inertia about the centre of a body of mass `mass` with this shape.
    pub fn inertia(&self, mass: f64) -> f64 {
        match *self {
            Shape::Disc { radius } => 0.5 * mass * radius * radius,
            Shape::Rectangle { half_extents: [a, b] } => mass * (a * a + b * b) / 3.0,
        }
    }
}

impl GraphBody {
    /// A point mass (no rotational inertia).
    pub fn point(name: impl Into<String>, mass: f64) -> Self {
        Self { name: name.into(), mass, inertia: 0.0, shape: None }
    }

    /// A rigid body with mass and moment of inertia about its centre of mass.
    pub fn rigid(name: impl Into<String>, mass: f64, inertia: f64) -> Self {
        Self { name: name.into(), mass, inertia, shape: None }
    }

    /// A body of uniform `density` (kg/m²) filling `shape`: its mass and inertia come from it.
    pub fn from_shape(name: impl Into<String>, shape: Shape, density: f64) -> Self {
        let mass = density * shape.area();
        Self { name: name.into(), mass, inertia: shape.inertia(mass), shape: Some(shape) }
    }
}

/// What a joint constrains.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum JointType {
    /// The anchors coincide; the relative angle is the joint's coordinate.
    Revolute,
    /// The child keeps the parent's orientation and its anchor slides along `axis` (a unit
    /// vector in the parent frame) through the parent's anchor; the slide is the coordinate.
    Prismatic {
        /// Unit slide direction in the parent's frame.
        axis: [f64; 2],
    },
    /// The anchors coincide and the child is turned by `angle` from the parent: no coordinate.
    Fixed {
        /// `φ_child − φ_parent` (rad).
        angle: f64,
    },
}

/// Whether a joint belongs to the spanning tree of the reduced model.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Role {
    /// Chosen automatically: joints join the tree in the order they are listed, unless they
    /// would close a loop (the default).
    #[default]
    Auto,
    /// A tree joint (an error if the joints marked so form a loop).
    Tree,
    /// A loop-closing joint: its constraints join the reduced model as `Φ(q, t) = 0`.
    Closing,
}

/// A value as a function of time: `c + r t + A sin(ω t + φ₀)` (a constant, a ramp, a
/// harmonic drive, or their sum).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Profile {
    /// `c`.
    #[cfg_attr(feature = "serde", serde(default))]
    pub constant: f64,
    /// `r` (per second).
    #[cfg_attr(feature = "serde", serde(default))]
    pub rate: f64,
    /// `A`.
    #[cfg_attr(feature = "serde", serde(default))]
    pub amplitude: f64,
    /// `ω` (rad/s).
    #[cfg_attr(feature = "serde", serde(default))]
    pub frequency: f64,
    /// `φ₀` (rad).
    #[cfg_attr(feature = "serde", serde(default))]
    pub phase: f64,
}

impl Profile {
    /// The constant `c`.
    pub fn constant(c: f64) -> Self {
        Self { constant: c, ..Self::default() }
    }

    /// `A sin(ω t)`.
    pub fn harmonic(amplitude: f64, frequency: f64) -> Self {
        Self { amplitude, frequency, ..Self::default() }
    }

    /// `c + r t`.
    pub fn ramp(start: f64, rate: f64) -> Self {
        Self { constant: start, rate, ..Self::default() }
    }

    /// The value at `t`.
    pub fn at<S: Scalar>(&self, t: S) -> S {
        let mut value = t * self.rate + self.constant;
        if self.amplitude != 0.0 {
            value += (t * self.frequency + self.phase).sin() * self.amplitude;
        }
        value
    }

    /// Whether the value changes with time.
    pub fn varies(&self) -> bool {
        self.rate != 0.0 || (self.amplitude != 0.0 && self.frequency != 0.0)
    }

    fn values(&self) -> [(&'static str, f64); 5] {
        [
            ("constant", self.constant),
            ("rate", self.rate),
            ("amplitude", self.amplitude),
            ("frequency", self.frequency),
            ("phase", self.phase),
        ]
    }

    pub(crate) fn check(&self, element: &str) -> Result<(), Error> {
        for (what, value) in self.values() {
            if !value.is_finite() {
                return Err(super::invalid(element, format!("its profile's {what} is {value}, not finite")));
            }
        }
        Ok(())
    }
}

/// A joint between two bodies, or a body and the ground.
///
/// Its coordinate (revolute and prismatic joints that are neither driven nor coupled, and belong
/// to the spanning tree) is named after the joint:
/// - revolute, [`AngleReference::Parent`]: `q = σ (φ_child − φ_parent)`, with `σ = ±1` the
///   joint's [`Sense`]; [`AngleReference::World`]: `q = σ φ_child` (the lecture's absolute
///   angles);
/// - prismatic: `q = (a_child − a_parent) · u`, the anchors' separation along the axis `u`
///   turned with the parent.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct GraphJoint {
    /// Unique name; also the name of its coordinate.
    pub name: String,
    /// Revolute, prismatic or fixed.
    pub kind: JointType,
    /// One body (or [`GROUND`]).
    pub parent: String,
    /// The other body (or [`GROUND`]).
    pub child: String,
    /// The joint's point in the parent's frame (for a prismatic joint, where `q = 0`).
    pub parent_anchor: [f64; 2],
    /// The joint's point in the child's frame.
    pub child_anchor: [f64; 2],
    /// What a revolute joint's angle is measured from.
    #[cfg_attr(feature = "serde", serde(default = "parent_reference"))]
    pub angle: AngleReference,
    /// Which way a revolute joint's angle turns as it grows.
    #[cfg_attr(feature = "serde", serde(default))]
    pub sense: Sense,
    /// A prescribed coordinate `q(t)` (a driven joint): no free coordinate, the joint moves its
    /// child as the profile says.
    #[cfg_attr(feature = "serde", serde(default))]
    pub drive: Option<Profile>,
    /// Tree or loop-closing joint.
    #[cfg_attr(feature = "serde", serde(default))]
    pub role: Role,
}

#[cfg(feature = "serde")]
fn parent_reference() -> AngleReference {
    AngleReference::Parent
}

impl GraphJoint {
    fn new(
        name: impl Into<String>,
        kind: JointType,
        parent: impl Into<String>,
        parent_anchor: [f64; 2],
        child: impl Into<String>,
        child_anchor: [f64; 2],
    ) -> Self {
        Self {
            name: name.into(),
            kind,
            parent: parent.into(),
            child: child.into(),
            parent_anchor,
            child_anchor,
            angle: AngleReference::Parent,
            sense: Sense::CounterClockwise,
            drive: None,
            role: Role::Auto,
        }
    }

    /// A revolute joint: `parent_anchor` on `parent` meets `child_anchor` on `child`; its angle
    /// is relative to the parent.
    pub fn revolute(
        name: impl Into<String>,
        parent: impl Into<String>,
        parent_anchor: [f64; 2],
        child: impl Into<String>,
        child_anchor: [f64; 2],
    ) -> Self {
        Self::new(name, JointType::Revolute, parent, parent_anchor, child, child_anchor)
    }

    /// A prismatic joint along the unit `axis` (parent frame).
    pub fn prismatic(
        name: impl Into<String>,
        parent: impl Into<String>,
        parent_anchor: [f64; 2],
        child: impl Into<String>,
        child_anchor: [f64; 2],
        axis: [f64; 2],
    ) -> Self {
        Self::new(name, JointType::Prismatic { axis }, parent, parent_anchor, child, child_anchor)
    }

    /// A fixed joint: the anchors meet and the child is turned by `angle` from the parent.
    pub fn fixed(
        name: impl Into<String>,
        parent: impl Into<String>,
        parent_anchor: [f64; 2],
        child: impl Into<String>,
        child_anchor: [f64; 2],
        angle: f64,
    ) -> Self {
        Self::new(name, JointType::Fixed { angle }, parent, parent_anchor, child, child_anchor)
    }

    /// The same joint measuring the child's angle in the world ([`AngleReference::World`]).
    pub fn absolute(mut self) -> Self {
        self.angle = AngleReference::World;
        self
    }

    /// The same joint with its angle counted clockwise.
    pub fn clockwise(mut self) -> Self {
        self.sense = Sense::Clockwise;
        self
    }

    /// The same joint driven: its coordinate is `profile(t)`.
    pub fn driven(mut self, profile: Profile) -> Self {
        self.drive = Some(profile);
        self
    }

    /// The same joint as a loop-closing joint ([`Role::Closing`]).
    pub fn closing(mut self) -> Self {
        self.role = Role::Closing;
        self
    }

    /// The same joint as a tree joint ([`Role::Tree`]).
    pub fn in_tree(mut self) -> Self {
        self.role = Role::Tree;
        self
    }
}

/// `q_joint = ratio · q_source + offset`: a gear, a belt, a rope over a pulley.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Coupling {
    /// The coupled joint (it has no coordinate of its own).
    pub joint: String,
    /// The driving joint, a tree joint.
    pub source: String,
    /// `ratio`.
    pub ratio: f64,
    /// `offset` (rad or m).
    #[cfg_attr(feature = "serde", serde(default))]
    pub offset: f64,
}

/// A point fixed in a body (or in the ground), in that body's frame.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Point {
    /// The body, or [`GROUND`].
    pub body: String,
    /// Position in the body's frame (m).
    pub at: [f64; 2],
}

impl Point {
    /// The point `at` of `body`.
    pub fn on(body: impl Into<String>, at: [f64; 2]) -> Self {
        Self { body: body.into(), at }
    }

    /// The fixed point `at` of the world.
    pub fn world(at: [f64; 2]) -> Self {
        Self { body: GROUND.into(), at }
    }
}

/// A force element of a [`JointGraph`].
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(tag = "type", rename_all = "snake_case"))]
pub enum ForceElement {
    /// A linear spring between two points: `V = ½ k (L − l₀)²`, `L` their distance.
    Spring {
        /// One end.
        a: Point,
        /// The other end.
        b: Point,
        /// Stiffness `k` (N/m), ≥ 0.
        stiffness: f64,
        /// Natural length `l₀` (m), ≥ 0.
        rest_length: f64,
    },
    /// A linear damper between two points: the force on `b` is `−c L̇ e`, `e` the unit vector
    /// from `a` to `b` (and the opposite on `a`).
    Damper {
        /// One end.
        a: Point,
        /// The other end.
        b: Point,
        /// Damping coefficient `c` (N s/m), ≥ 0.
        coefficient: f64,
    },
    /// A spring on a revolute or prismatic joint's coordinate (a torsion spring, or a linear
    /// spring along a slide): `V = ½ k (q − q₀)²`.
    JointSpring {
        /// The joint.
        joint: String,
        /// Stiffness `k` (N m/rad or N/m), ≥ 0.
        stiffness: f64,
        /// Rest value `q₀`.
        rest: f64,
    },
    /// A damper on a revolute or prismatic joint's coordinate: generalized force `−c q̇`.
    JointDamper {
        /// The joint.
        joint: String,
        /// Coefficient `c` (N m s/rad or N s/m), ≥ 0.
        coefficient: f64,
    },
    /// A torque on a body (counter-clockwise, N m), reacting on the ground.
    Torque {
        /// The body.
        body: String,
        /// `τ(t)`.
        torque: Profile,
    },
    /// A force `(F_x(t), F_y(t))` in the world frame at a point of a body.
    Force {
        /// Point of application.
        at: Point,
        /// `F_x(t)`, `F_y(t)` (N).
        force: [Profile; 2],
    },
}

impl JointGraph {
    /// An empty mechanism named `name` under gravity `g` along −y.
    pub fn new(name: impl Into<String>, gravity: f64) -> Self {
        Self {
            name: name.into(),
            bodies: Vec::new(),
            joints: Vec::new(),
            couplings: Vec::new(),
            forces: Vec::new(),
            gravity,
        }
    }

    /// Add a body.
    pub fn with_body(mut self, body: GraphBody) -> Self {
        self.bodies.push(body);
        self
    }

    /// Add a joint.
    pub fn with_joint(mut self, joint: GraphJoint) -> Self {
        self.joints.push(joint);
        self
    }

    /// Add a coupling `q_joint = ratio · q_source + offset`.
    pub fn with_coupling(
        mut self,
        joint: impl Into<String>,
        source: impl Into<String>,
        ratio: f64,
        offset: f64,
    ) -> Self {
        self.couplings.push(Coupling { joint: joint.into(), source: source.into(), ratio, offset });
        self
    }

    /// Add a force element.
    pub fn with_force(mut self, force: ForceElement) -> Self {
        self.forces.push(force);
        self
    }
}
