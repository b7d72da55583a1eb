//! The hanging chain in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{Anchor, Constraint, pin};
use crate::rapier::scenes::Draft;
use lagrange::{Scalar, State};
use lagrange_scenes::Chain;

impl MaximalScene for Chain {
    /// Each link's orientation is its angle from the downward vertical.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        z.iter().map(|link| link[2]).collect()
    }

    /// Uniform links of length l: link 1's top end (0, l/2) pinned to the origin, each link's
    /// top end pinned to the previous link's bottom end (0, −l/2).
    fn constraints(&self, names: &[String]) -> Vec<Constraint> {
        let half = 0.5 * self.link_length;
        let mut c = vec![pin(Anchor::on(0, 0.0, half), Anchor::ORIGIN, format!("{} pinned at the origin", names[0]))];
        for i in 1..names.len() {
            let name = format!("{} pinned to {}", names[i], names[i - 1]);
            c.push(pin(Anchor::on(i, 0.0, half), Anchor::on(i - 1, 0.0, -half), name));
        }
        c
    }

    /// Rods hinged at their ends: pivot i at the top of rod i, the bottom of rod i − 1.
    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        let half = 0.5 * self.link_length;
        let mut parent = draft.ground();
        let mut anchor = [0.0, 0.0];
        for r in 0..draft.states.len() {
            let link = draft.reduced(r);
            draft.revolute(parent, link, anchor, [0.0, half]);
            (parent, anchor) = (link, [0.0, -half]);
        }
    }
}
