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

/// The kind of a joint, with its one degree of freedom.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointKind {
    /// Rotation about a point fixed in both bodies (`parent_anchor` in the parent,
    /// `child_anchor` in the child); the coordinate is an angle.
    Revolute {
        /// Whether the angle is relative to the parent or absolute.
        angle: AngleReference,
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
            kind: JointKind::Revolute { angle: AngleReference::Parent },
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
            kind: JointKind::Revolute { angle: AngleReference::World },
        }
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
