//! Joints of a planar kinematic tree: one per body, each with one coordinate.

use crate::Coordinate;

/// What a joint hangs its body from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Parent {
    /// The fixed ground (the world frame: origin at `(0, 0)`, orientation 0).
    Ground,
    /// The body with this index in the tree; it must come before the child.
    Body(usize),
}

/// What a revolute joint's coordinate measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum AngleReference {
    /// The angle of the child relative to its parent: `φ_child = φ_parent + q` (robotics'
    /// joint angle).
    Parent,
    /// The child's orientation in the world: `φ_child = q`, whatever the parent does (the
    /// lecture's absolute angles). With the child's centre of mass straight below the joint
    /// at `q = 0` (`child_anchor = (0, d)`, `d > 0`), `q` is the angle from the downward
    /// vertical, counter-clockwise — the `θ_i` of the chain and the double pendulum.
    World,
}

/// Which way a revolute joint's angle turns as its coordinate grows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Sense {
    /// Counter-clockwise (the mathematical sense; the default).
    #[default]
    CounterClockwise,
    /// Clockwise: the angle the joint adds is `−q` (e.g. an angle measured clockwise from the
    /// vertical, as some textbooks draw it).
    Clockwise,
}

impl Sense {
    /// `+1` counter-clockwise, `−1` clockwise.
    pub fn sign(self) -> f64 {
        match self {
            Sense::CounterClockwise => 1.0,
            Sense::Clockwise => -1.0,
        }
    }
}

/// The kind of a joint, with its one degree of freedom.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointKind {
    /// Rotation about a point fixed in both bodies (`parent_anchor` in the parent,
    /// `child_anchor` in the child); the coordinate is an angle.
    Revolute {
        /// Whether the angle is relative to the parent or absolute.
        angle: AngleReference,
        /// Which way the angle turns as the coordinate grows.
        sense: Sense,
    },
    /// Translation along `axis` (a unit vector fixed in the parent frame); the child keeps the
    /// parent's orientation and its `child_anchor` sits at `parent_anchor + q · axis` in the
    /// parent frame. The coordinate is a length.
    Prismatic {
        /// Unit direction of the slide, in the parent frame.
        axis: [f64; 2],
    },
}

/// The joint that connects one body of a [`Tree`](super::Tree) to its parent.
///
/// Body frames are the frames of the poses a [`Mechanism`](crate::Mechanism) writes: origin at
/// the body's centre of mass, turned by the body's angle `φ`. Anchors are points in those frames
/// (the ground's frame is the world's).
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// The joint's generalized coordinate (name; its kind follows the joint: angle or length).
    pub coordinate: Coordinate,
    /// The body (or the ground) the child hangs from.
    pub parent: Parent,
    /// The joint's point in the parent frame (for a prismatic joint, where `q = 0`).
    pub parent_anchor: [f64; 2],
    /// The joint's point in the child frame (relative to the child's centre of mass).
    pub child_anchor: [f64; 2],
    /// Revolute or prismatic.
    pub kind: JointKind,
}

impl Joint {
    /// A revolute joint whose angle is relative to the parent: `φ_child = φ_parent + q`.
    pub fn revolute(name: impl Into<String>, parent: Parent, parent_anchor: [f64; 2], child_anchor: [f64; 2]) -> Self {
        Self {
            coordinate: Coordinate::angle(name),
            parent,
            parent_anchor,
            child_anchor,
            kind: JointKind::Revolute { angle: AngleReference::Parent, sense: Sense::CounterClockwise },
        }
    }

    /// A revolute joint whose angle is the child's orientation in the world: `φ_child = q`
    /// (see [`AngleReference::World`]).
    pub fn absolute_revolute(
        name: impl Into<String>,
        parent: Parent,
        parent_anchor: [f64; 2],
        child_anchor: [f64; 2],
    ) -> Self {
        Self {
            coordinate: Coordinate::angle(name),
            parent,
            parent_anchor,
            child_anchor,
            kind: JointKind::Revolute { angle: AngleReference::World, sense: Sense::CounterClockwise },
        }
    }

    /// The same joint with its coordinate counted the other way: a revolute joint's angle
    /// turns clockwise ([`Sense::Clockwise`]; applied twice, counter-clockwise again), a
    /// prismatic joint's axis is reversed.
    ///
    /// ```
    /// use lagrange::tree::{Joint, Parent, Tree};
    /// use lagrange::{Body, Model, accelerations};
    ///
    /// // A pendulum whose angle θ is measured clockwise from the downward vertical.
    /// let joint = Joint::absolute_revolute("θ", Parent::Ground, [0.0, 0.0], [0.0, 1.0]).clockwise();
    /// let model = Model::new(Tree::new(vec![joint], vec![Body::point("bob", 1.0)], 9.81)?)?;
    /// let mut ws = model.workspace();
    /// let qddot = accelerations(&model, &mut ws, 0.0, &[0.3], &[0.0])?;
    /// // θ̈ = −g sinθ / l, whichever way θ is counted.
    /// approx::assert_relative_eq!(qddot[0], -9.81 * 0.3_f64.sin(), max_relative = 1e-14);
    /// # Ok::<(), lagrange::Error>(())
    /// ```
    pub fn clockwise(mut self) -> Self {
        match &mut self.kind {
            JointKind::Revolute { sense, .. } => {
                *sense = match sense {
                    Sense::CounterClockwise => Sense::Clockwise,
                    Sense::Clockwise => Sense::CounterClockwise,
                }
            }
            JointKind::Prismatic { axis } => *axis = [-axis[0], -axis[1]],
        }
        self
    }

    /// A prismatic joint along the unit `axis` (parent frame): the child's `child_anchor` at
    /// `parent_anchor + q · axis`.
    pub fn prismatic(
        name: impl Into<String>,
        parent: Parent,
        parent_anchor: [f64; 2],
        axis: [f64; 2],
        child_anchor: [f64; 2],
    ) -> Self {
        Self {
            coordinate: Coordinate::length(name),
            parent,
            parent_anchor,
            child_anchor,
            kind: JointKind::Prismatic { axis },
        }
    }
}
