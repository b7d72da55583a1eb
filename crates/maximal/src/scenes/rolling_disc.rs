//! The disc rolling down an incline in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{Constraint, Frame, VelocityConstraint, X, Y, linear};
use crate::rapier::plan::Shape;
use crate::rapier::scenes::Draft;
use crate::sketch::{Anchor, Figure, Sketch, Slide};
use lagrange::{Scalar, State};
use lagrange_scenes::RollingDisc;

/// Half-length of the incline's cuboid (m): the disc stays on it for `|s| < 1000` m.
const INCLINE_HALF_LENGTH: f64 = 1000.0;

/// Friction coefficient of the contact, in units of the least one that rolls, `tan α / 3`
/// (a uniform disc needs a friction force `m g sin α / 3` against `μ m g cos α`).
const FRICTION_MARGIN: f64 = 3.0;

/// The least friction coefficient of the contact: on flat ground (`α = 0`) a rolling disc needs
/// no friction force, but without any a perturbation of the contact would let it slide.
const MIN_FRICTION: f64 = 0.1;

impl MaximalScene for RollingDisc {
    /// `s` = the centre's distance down the incline direction `(−cosα, −sinα)` from the origin;
    /// `φ` = the disc's angle.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        let (sin, cos) = self.incline.sin_cos();
        vec![-(z[0][0] * cos + z[0][1] * sin), z[0][2]]
    }

    /// The contact: the centre stays on the line through the origin parallel to the incline,
    /// `R` above its surface: `sinα x − cosα y = 0`.
    fn constraints(&self, _names: &[String]) -> Vec<Constraint> {
        let (sin, cos) = self.incline.sin_cos();
        vec![linear(&[(0, X, sin), (0, Y, -cos)], 0.0, "disc centre on the line R above the incline")]
    }

    /// Rolling without slipping: the material point of the disc at the contact,
    /// `R (sinα, −cosα)` from the centre, has no velocity along the incline `(cosα, sinα)`.
    fn velocity_constraints(&self) -> Vec<VelocityConstraint> {
        let (sin, cos) = self.incline.sin_cos();
        vec![VelocityConstraint {
            name: "rolling: the contact point does not slide".into(),
            body: 0,
            arm: ([self.radius * sin, -self.radius * cos], Frame::World),
            direction: ([cos, sin], Frame::World),
        }]
    }

    /// rapier has no rolling joint: the disc is a contact (docs/rapier.md#contact-the-rolling-disc),
    /// the same in both joint modes (a free body). A ball collider of radius `R` whose density
    /// gives the mass `m` (parry's ball: inertia `½ m R²`, the disc's) on a fixed cuboid turned
    /// by `α`, its surface exactly `R` below the line of centres through the origin; friction
    /// `μ = |tan α|` on both (three times the least that rolls; at least [`MIN_FRICTION`]), no
    /// restitution.
    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        let (sin, cos) = self.incline.sin_cos();
        let (radius, half_thickness) = (self.radius, self.radius);
        // On flat ground (or nearly) no friction is needed to roll; a little keeps it rolling.
        let friction = (FRICTION_MARGIN * self.incline.tan().abs() / 3.0).max(MIN_FRICTION);
        let depth = radius + half_thickness;
        let incline = draft.fixed([depth * sin, -depth * cos, self.incline]);
        draft.collider(incline, Shape::Cuboid { half_extents: [INCLINE_HALF_LENGTH, half_thickness] }, friction);
        let disc = draft.reduced(0);
        draft.collider(disc, Shape::Ball { radius }, friction);
    }

    /// The disc on the incline (its centre runs along the line through the origin at angle α).
    fn sketch(&self) -> Sketch {
        let (sin, cos) = self.incline.sin_cos();
        let incline = Slide { at: Anchor::World { at: [self.radius * sin, -self.radius * cos] }, axis: [cos, sin] };
        Sketch { bodies: vec![Figure::Disc { radius: self.radius }], slides: vec![incline], ..Sketch::of_bodies(&[]) }
    }
}
