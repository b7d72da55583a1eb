//! The pendulum with a horizontally driven support in maximal coordinates.

use super::{MaximalScene, angle_from_down};
use crate::cartesian::constraints::{Anchor, Constraint, Joint, no_turning};
use crate::rapier::plan::JointMode;
use crate::rapier::scenes::{Draft, NO_RHEONOMIC_MULTIBODY};
use crate::sketch::{self, Link, LinkKind, Sketch, Slide};
use lagrange::{Scalar, State};
use lagrange_scenes::DrivenPendulum;

impl MaximalScene for DrivenPendulum {
    /// Support at (A sin ωt, 0).
    fn generalized<S: Scalar>(&self, t: S, z: &[[S; 3]]) -> Vec<S> {
        let support = (t * self.drive_frequency).sin() * self.amplitude;
        vec![angle_from_down(z[0][0] - support, z[0][1])]
    }

    /// The point bob at distance l from the moving support (A sin ωt, 0): a rheonomic rod (the
    /// bob's pose angle is 0 in the reduced model, so the rod is a distance constraint).
    fn constraints(&self, names: &[String]) -> Vec<Constraint> {
        let support = Anchor::Driven { amplitude: self.amplitude, frequency: self.drive_frequency };
        let rod = Joint::Distance { from: Anchor::on(0, 0.0, 0.0), to: support, length: self.length };
        vec![Constraint { name: "rod to the driven support".into(), joint: rod }, no_turning(0, names)]
    }

    fn rapier_unbuildable(mode: JointMode) -> Option<&'static str> {
        (mode == JointMode::Multibody).then_some(NO_RHEONOMIC_MULTIBODY)
    }

    /// A rope from the moving support to the point bob's centre: the rod of a point bob without
    /// inertia, exact while the rod is in tension.
    fn rapier(&self, draft: &mut Draft, initial: &State) {
        let support = draft.support(self.amplitude, self.drive_frequency, initial.t);
        let bob = draft.reduced(0);
        draft.rope(support, bob, self.length);
    }

    /// The bob on a rod from the support, which slides along a horizontal rail.
    fn sketch(&self) -> Sketch {
        let support =
            sketch::Anchor::Harmonic { centre: [0.0, 0.0], amplitude: self.amplitude, frequency: self.drive_frequency };
        let rod = Link { kind: LinkKind::Rod, a: support.clone(), b: sketch::Anchor::Body { body: 0, at: [0.0, 0.0] } };
        let rail = Slide { at: sketch::Anchor::World { at: [0.0, 0.0] }, axis: [1.0, 0.0] };
        Sketch {
            links: vec![rod],
            pins: vec![support],
            slides: vec![rail],
            ..Sketch::of_bodies(&[lagrange::Body::point("bob", 1.0)])
        }
    }
}
