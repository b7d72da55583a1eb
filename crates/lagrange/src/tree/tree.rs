//! A planar kinematic tree: bodies hung from each other or from the ground by one-coordinate
//! joints, described once and usable as a [`Mechanism`].

#[cfg(doc)]
use super::joint::Sense;
use super::joint::{AngleReference, Joint, JointKind, Parent};
use crate::{Body, Description, Error, Mechanism, Pose, Scalar};

/// How far a prismatic axis may be from unit length (relative), so that `q` is a length.
const UNIT_AXIS_TOLERANCE: f64 = 1e-12;

/// Precomputed data of one joint, for the articulated-body algorithm.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Link {
    /// Parent body, `None` for the ground.
    pub parent: Option<usize>,
    /// Whether the joint is revolute.
    pub revolute: bool,
    /// Whether a revolute joint's angle is absolute ([`AngleReference::World`]).
    pub absolute: bool,
    /// `+1` if a revolute joint's angle turns counter-clockwise, `−1` clockwise; `+1` for a
    /// prismatic joint (whose direction is its axis).
    pub sense: f64,
    /// Parent anchor (parent frame).
    pub parent_anchor: [f64; 2],
    /// Child anchor (child frame).
    pub child_anchor: [f64; 2],
    /// Prismatic axis (parent frame); unused for revolute joints.
    pub axis: [f64; 2],
    /// Mass of the child.
    pub mass: f64,
    /// Inertia of the child about its centre of mass.
    pub inertia: f64,
}

/// A planar kinematic tree: body `i` hangs from its parent (an earlier body, or the ground) by
/// joint `i`, whose coordinate is `q_i` — so there are as many coordinates as bodies, in the
/// same order, parents before children.
///
/// A `Tree` is a [`Mechanism`] by itself (poses by forward kinematics), and a mechanism that
/// writes its poses by hand can describe itself as one through [`Mechanism::tree`]: then
/// [`Model::new`](crate::Model::new) checks at probe states that the tree reproduces the
/// mechanism's poses, and [`accelerations`](crate::accelerations) runs the articulated-body
/// algorithm, `O(n)`, instead of assembling and factoring `M`, `O(n³)`.
///
/// Forward kinematics, for joint `i` from parent `p` (pose `(x_p, y_p, φ_p)`; the ground is
/// `(0, 0, 0)`), with `R(φ)` the rotation by `φ`:
/// - revolute: `φ_i = φ_p + σ_i q_i` (relative) or `φ_i = σ_i q_i` (absolute), with `σ_i = 1`
///   for a counter-clockwise joint and `−1` for a clockwise one ([`Joint::clockwise`]), and the
///   anchors meet:
///   `(x_i, y_i) = (x_p, y_p) + R(φ_p) parent_anchor − R(φ_i) child_anchor`;
/// - prismatic: `φ_i = φ_p` and
///   `(x_i, y_i) = (x_p, y_p) + R(φ_p) (parent_anchor + q_i axis) − R(φ_i) child_anchor`.
///
/// # Example: a pendulum on a cart
///
/// ```
/// use lagrange::tree::{Joint, Parent, Tree};
/// use lagrange::{Body, Model, accelerations};
///
/// let (r, g) = (1.5, 9.81);
/// let tree = Tree::new(
///     vec![
///         // The cart slides along x on the ground.
///         Joint::prismatic("X", Parent::Ground, [0.0, 0.0], [1.0, 0.0], [0.0, 0.0]),
///         // The bob hangs a distance r below its pivot on the cart; θ from the downward vertical.
///         Joint::absolute_revolute("θ", Parent::Body(0), [0.0, 0.0], [0.0, r]),
///     ],
///     vec![Body::point("cart", 2.0), Body::point("bob", 1.0)],
///     g,
/// )?;
/// let model = Model::new(tree)?;
/// assert!(model.uses_tree_path());
/// let mut ws = model.workspace();
/// let qddot = accelerations(&model, &mut ws, 0.0, &[0.0, 0.3], &[0.0, 0.5])?;
/// // The lecture's closed form: Ẍ = m sinθ (r θ̇² + g cosθ) / (M + m sin²θ).
/// let (s, c) = 0.3_f64.sin_cos();
/// approx::assert_relative_eq!(qddot[0], s * (r * 0.25 + g * c) / (2.0 + s * s), max_relative = 1e-14);
/// # Ok::<(), lagrange::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Tree {
    joints: Vec<Joint>,
    /// Coordinates (the joints'), bodies and gravity.
    description: Description,
    links: Vec<Link>,
}

impl Tree {
    /// A tree of `bodies`, body `i` hung by `joints[i]`, under gravity `g` along −y.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if there are not as many joints as bodies;
    /// [`Error::InvalidParameter`] for an empty tree, a parent that does not come before its
    /// child, a non-finite anchor, a prismatic axis that is not a unit vector, a non-finite or
    /// negative mass or inertia, or a non-finite `g`.
    pub fn new(joints: Vec<Joint>, bodies: Vec<Body>, gravity: f64) -> Result<Self, Error> {
        if joints.len() != bodies.len() {
            return Err(Error::DimensionMismatch {
                what: "joints (one per body)",
                expected: bodies.len(),
                got: joints.len(),
            });
        }
        if joints.is_empty() {
            return Err(invalid("bodies", 0.0, "a tree needs at least one body"));
        }
        if !gravity.is_finite() {
            return Err(invalid("g", gravity, "must be finite"));
        }
        for (i, (joint, body)) in joints.iter().zip(&bodies).enumerate() {
            let name = &joint.coordinate.name;
            if let Parent::Body(p) = joint.parent
                && p >= i
            {
                return Err(invalid(
                    &format!("parent of joint `{name}` (body {i})"),
                    p as f64,
                    "must be a body listed before its child (parents before children)",
                ));
            }
            for (what, point) in [("parent_anchor", joint.parent_anchor), ("child_anchor", joint.child_anchor)] {
                for value in point {
                    if !value.is_finite() {
                        return Err(invalid(&format!("{what} of joint `{name}`"), value, "must be finite"));
                    }
                }
            }
            if let JointKind::Prismatic { axis } = joint.kind {
                let norm = axis[0].hypot(axis[1]);
                let unit = (norm - 1.0).abs() <= UNIT_AXIS_TOLERANCE; // false for NaN
                if !unit {
                    return Err(invalid(&format!("axis of joint `{name}`"), norm, "must be a unit vector"));
                }
            }
            for (what, value) in [("mass", body.mass), ("inertia", body.inertia)] {
                if !(value.is_finite() && value >= 0.0) {
                    return Err(invalid(&format!("{what} of {}", body.name), value, "must be finite and non-negative"));
                }
            }
        }
        let links = joints
            .iter()
            .zip(&bodies)
            .map(|(joint, body)| Link {
                parent: match joint.parent {
                    Parent::Ground => None,
                    Parent::Body(p) => Some(p),
                },
                revolute: matches!(joint.kind, JointKind::Revolute { .. }),
                absolute: matches!(joint.kind, JointKind::Revolute { angle: AngleReference::World, .. }),
                sense: match joint.kind {
                    JointKind::Revolute { sense, .. } => sense.sign(),
                    JointKind::Prismatic { .. } => 1.0,
                },
                parent_anchor: joint.parent_anchor,
                child_anchor: joint.child_anchor,
                axis: match joint.kind {
                    JointKind::Prismatic { axis } => axis,
                    JointKind::Revolute { .. } => [0.0, 0.0],
                },
                mass: body.mass,
                inertia: body.inertia,
            })
            .collect();
        let coordinates = joints.iter().map(|j| j.coordinate.clone()).collect();
        let description = Description { coordinates, bodies, gravity, ..Description::default() };
        Ok(Self { joints, description, links })
    }

    /// The joints, joint `i` hanging body `i`.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// Number of bodies (= joints = coordinates).
    pub fn len(&self) -> usize {
        self.description.bodies.len()
    }

    /// Always `false`: a tree has at least one body.
    pub fn is_empty(&self) -> bool {
        self.description.bodies.is_empty()
    }

    pub(crate) fn links(&self) -> &[Link] {
        &self.links
    }
}

impl Mechanism for Tree {
    fn description(&self) -> &Description {
        &self.description
    }

    /// Forward kinematics, parents before children.
    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        for (i, link) in self.links.iter().enumerate() {
            // The parent's pose and rotation (the ground: identity).
            let (parent_pose, (parent_sin, parent_cos)) = match link.parent {
                None => (Pose::default(), (S::zero(), S::one())),
                Some(p) => (world_from_body[p], world_from_body[p].angle.sin_cos()),
            };
            // The joint's point in the parent frame, and the child's orientation.
            let (mut ax, mut ay) = (S::from(link.parent_anchor[0]), S::from(link.parent_anchor[1]));
            let angle = if !link.revolute {
                ax += q[i] * link.axis[0];
                ay += q[i] * link.axis[1];
                parent_pose.angle
            } else if link.absolute {
                q[i] * link.sense
            } else {
                parent_pose.angle + q[i] * link.sense
            };
            // World position of the joint, then of the child's centre of mass.
            let joint_x = parent_pose.x + parent_cos * ax - parent_sin * ay;
            let joint_y = parent_pose.y + parent_sin * ax + parent_cos * ay;
            let (sin, cos) = if link.revolute { angle.sin_cos() } else { (parent_sin, parent_cos) };
            let [cx, cy] = link.child_anchor;
            world_from_body[i] = Pose::new(joint_x - cos * cx + sin * cy, joint_y - sin * cx - cos * cy, angle);
        }
    }

    fn tree(&self) -> Option<&Tree> {
        Some(self)
    }
}

fn invalid(name: &str, value: f64, why: &str) -> Error {
    Error::InvalidParameter { name: name.to_string(), value, why: why.to_string() }
}
