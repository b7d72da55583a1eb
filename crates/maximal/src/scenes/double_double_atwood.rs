//! The double-double Atwood machine in maximal coordinates.

use super::MaximalScene;
use crate::cartesian::constraints::{Constraint, Y, hanging, linear};
use crate::rapier::plan::JointMode;
use crate::rapier::scenes::{DOWN, Draft, NO_PULLEY_JOINT};
use lagrange::{Scalar, State};
use lagrange_scenes::DoubleDoubleAtwood;

impl MaximalScene for DoubleDoubleAtwood {
    /// Bodies A, B, m2, m3, m4, m5: x = depth of A, x' = m2 below B, x'' = m4 below A.
    fn generalized<S: Scalar>(&self, _t: S, z: &[[S; 3]]) -> Vec<S> {
        vec![-z[0][1], z[1][1] - z[2][1], z[0][1] - z[4][1]]
    }

    /// Pulleys A (0) and B (1), m2 (2), m3 (3) on B, m4 (4), m5 (5) on A, all on x = 0, not
    /// turning. Upper rope: x_A + x_B = l; B's rope: (x2 − x_B) + (x3 − x_B) = l';
    /// A's rope: (x4 − x_A) + (x5 − x_A) = l'' (depths).
    fn constraints(&self, names: &[String]) -> Vec<Constraint> {
        let (l, l_b, l_a) = (self.rope_length, self.rope_length_b, self.rope_length_a);
        let mut c: Vec<Constraint> = (0..6).flat_map(|b| hanging(b, 0.0, names)).collect();
        c.push(linear(&[(0, Y, -1.0), (1, Y, -1.0)], -l, "upper rope"));
        c.push(linear(&[(2, Y, -1.0), (3, Y, -1.0), (1, Y, 2.0)], -l_b, "rope of pulley B"));
        c.push(linear(&[(4, Y, -1.0), (5, Y, -1.0), (0, Y, 2.0)], -l_a, "rope of pulley A"));
        c
    }

    fn rapier_unbuildable(mode: JointMode) -> Option<&'static str> {
        (mode == JointMode::Impulse).then_some(NO_PULLEY_JOINT)
    }

    fn rapier_deviations(mode: JointMode) -> &'static [(&'static str, &'static str, &'static str)] {
        match mode {
            JointMode::Multibody => &[("pulley_a_mass", "", ""), ("pulley_b_mass", "", "")],
            JointMode::Impulse => &[],
        }
    }

    /// Bodies A, B, m2, m3, m4, m5: A and B on the upper rope, m2, m3 hang from B and m4, m5
    /// from A.
    fn rapier(&self, draft: &mut Draft, _initial: &State) {
        let ground = draft.ground();
        let [a, b, m2, m3, m4, m5] = [0, 1, 2, 3, 4, 5].map(|r| draft.reduced(r));
        let upper_a = draft.prismatic(ground, a, DOWN, [0.0, 0.0], [0.0, 0.0]);
        let upper_b = draft.prismatic(ground, b, DOWN, [0.0, 0.0], [0.0, 0.0]);
        let rope_b2 = draft.prismatic(b, m2, DOWN, [0.0, 0.0], [0.0, 0.0]);
        let rope_b3 = draft.prismatic(b, m3, DOWN, [0.0, 0.0], [0.0, 0.0]);
        let rope_a4 = draft.prismatic(a, m4, DOWN, [0.0, 0.0], [0.0, 0.0]);
        let rope_a5 = draft.prismatic(a, m5, DOWN, [0.0, 0.0], [0.0, 0.0]);
        draft.couple(upper_a, upper_b, -1.0);
        draft.couple(rope_b2, rope_b3, -1.0);
        draft.couple(rope_a4, rope_a5, -1.0);
    }
}
