//! The Cartesian pendulum in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{Anchor, Constraint, Joint, no_turning};
use crate::rapier::plan::JointMode;
use crate::rapier::scenes::Draft;
use crate::sketch::{LinkKind, Sketch};
use lagrange::{Scalar, State};
use lagrange_scenes::NonminimalPendulum;

impl MaximalScene for NonminimalPendulum {
    /// The bob's position is the coordinates.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        vec![z[0][0], z[0][1]]
    }

    /// The rod from the origin to the point bob: its distance from the origin is `l`, and it
    /// does not turn (the reduced model's point bob keeps its frame) — two equations for the
    /// bob's three pose coordinates, leaving the reduced model's `2 − 1` degrees of freedom.
    fn constraints(&self, names: &[String]) -> Vec<Constraint> {
        let rod = Joint::Distance { from: Anchor::on(0, 0.0, 0.0), to: Anchor::ORIGIN, length: self.length };
        vec![Constraint { name: "rod from the origin".into(), joint: rod }, no_turning(0, names)]
    }

    /// Impulse joints: a revolute joint would freeze the rotation of the point bob (no inertia)
    /// and the scene has no bob inertia to give it, so the rod is a rope from the origin to the
    /// bob's centre, exact while it is in tension (as the driven pendulum's). Multibody: a
    /// revolute joint at the origin, the bob's anchor at the origin's place in the bob's initial
    /// frame, so that the bob's frame turns with the rod in rapier (from the rod's initial rate
    /// `(x ẏ − y ẋ)/r²`); its angle is not read back (the coordinates are the bob's position).
    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        match draft.mode {
            JointMode::Impulse => {
                let (ground, bob) = (draft.ground(), draft.reduced(0));
                draft.rope(ground, bob, self.length);
            }
            JointMode::Multibody => {
                let ([x, y, _], [vx, vy, _]) = (draft.states[0].pose, draft.states[0].velocity);
                draft.states[0].velocity[2] = (x * vy - y * vx) / (x * x + y * y);
                let (ground, bob) = (draft.ground(), draft.reduced(0));
                draft.revolute(ground, bob, [0.0, 0.0], [-x, -y]);
            }
        }
    }

    /// The bob on a rod from the origin.
    fn sketch(&self) -> Sketch {
        Sketch::particle_from_origin(Some(LinkKind::Rod))
    }
}
