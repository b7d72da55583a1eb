//! The cart pendulum in maximal coordinates.

use super::{MaximalScene, angle_from_down};
use crate::cartesian::constraints::{Anchor, Constraint, Y, fix, no_turning, pin};
use crate::rapier::plan::JointMode;
use crate::rapier::scenes::Draft;
use lagrange::{Scalar, State};
use lagrange_scenes::CartPendulum;

impl MaximalScene for CartPendulum {
    /// Cart, bob: `X = x_cart`, `θ` = the rod's angle from the downward vertical.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        vec![z[0][0], angle_from_down(z[1][0] - z[0][0], z[1][1] - z[0][1])]
    }

    /// Cart (0) on the rail y = 0, not turning; the bob (1) hangs from the cart by a rod of
    /// length r: the rod end (0, r) in the bob's frame is pinned to the cart's centre. For a
    /// point bob the pin fixes φ_bob too (the rod's direction); for a compound bob φ_bob is the
    /// rod's angle θ either way.
    fn constraints(&self, names: &[String]) -> Vec<Constraint> {
        vec![
            fix(0, Y, 0.0, "cart on the rail (y = 0)".into()),
            no_turning(0, names),
            pin(Anchor::on(1, 0.0, self.rod_length), Anchor::on(0, 0.0, 0.0), "rod pin of the bob on the cart".into()),
        ]
    }

    fn rapier_deviations(mode: JointMode) -> &'static [(&'static str, &'static str, &'static str)] {
        match mode {
            JointMode::Impulse => &[("bob_inertia", "bob_mass", "rod_length")],
            JointMode::Multibody => &[],
        }
    }

    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        let (ground, cart, bob) = (draft.ground(), draft.reduced(0), draft.reduced(1));
        draft.prismatic(ground, cart, [1.0, 0.0], [0.0, 0.0], [0.0, 0.0]);
        draft.revolute(cart, bob, [0.0, 0.0], [0.0, self.rod_length]);
    }
}
