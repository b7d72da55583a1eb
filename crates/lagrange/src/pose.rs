//! Planar poses.

use crate::Scalar;

/// Where a body is in the plane: the position of its centre of mass and its orientation.
///
/// `world_from_body` poses are what a [`Mechanism`](crate::Mechanism) writes for every body as a
/// function of the generalized coordinates and time. The angle is counter-clockwise, in radians;
/// it only matters for bodies with rotational inertia.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose<S> {
    /// Horizontal position of the centre of mass.
    pub x: S,
    /// Vertical position of the centre of mass (gravity acts along −y).
    pub y: S,
    /// Orientation, counter-clockwise.
    pub angle: S,
}

impl<S: Scalar> Pose<S> {
    /// A pose from its three components.
    pub fn new(x: S, y: S, angle: S) -> Self {
        Self { x, y, angle }
    }

    /// A point mass (or a body whose orientation never changes) at `(x, y)`; angle 0.
    pub fn point(x: S, y: S) -> Self {
        Self { x, y, angle: S::zero() }
    }

    /// The components `(x, y, angle)` as an array.
    pub fn to_array(self) -> [S; 3] {
        [self.x, self.y, self.angle]
    }

    /// The pose from components `(x, y, angle)`.
    pub fn from_array(a: [S; 3]) -> Self {
        Self { x: a[0], y: a[1], angle: a[2] }
    }
}

impl<S: Scalar> Default for Pose<S> {
    fn default() -> Self {
        Self { x: S::zero(), y: S::zero(), angle: S::zero() }
    }
}
