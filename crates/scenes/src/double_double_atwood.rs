//! Double-double Atwood machine: two movable pulleys, each with two masses (docs/scenes.md#double_double_atwood; the
//! lecture's homework remark).

use crate::params::{GRAVITY, param_table, scene_params};
use crate::uniform_acceleration::{ConstantForce, constant_force_scene, hang_at_depths};
use crate::{Domain, SceneType};
use lagrange::graph::{GROUND, GraphJoint, JointGraph};
use lagrange::{Body, Bounds, Coordinate, Description, Error, Mechanism, Pose, Scalar, State};

scene_params! {
    /// A fixed upper pulley whose rope (length `l`) carries movable pulley A (depth `x`) and
    /// movable pulley B (depth `l − x`); B's rope (length `l'`) carries `m2`, `m3`; A's rope
    /// (length `l''`) carries `m4`, `m5`. Radii neglected, depths downward from the upper pulley:
    /// `x_A = x`, `x_B = l − x`, `x₂ = (l − x) + x'`, `x₃ = (l − x) + (l' − x')`, `x₄ = x + x''`,
    /// `x₅ = x + (l'' − x'')`; body `i` at `(0, −x_i)`; `q = (x, x', x'')` (docs/scenes.md#double_double_atwood). The
    /// pulleys are point bodies of masses `m_A`, `m_B` (0 in docs/scenes.md).
    pub struct DoubleDoubleAtwood {
        /// Mass `m₂` (kg), at `x'` below pulley B.
        pub mass_2: f64 = ["m2", "kg", 10.0, Domain::Positive, "mass on pulley B's rope, side x'"],
        /// Mass `m₃` (kg), at `l' − x'` below pulley B.
        pub mass_3: f64 = ["m3", "kg", 10.5, Domain::Positive, "mass on pulley B's rope, other side"],
        /// Mass `m₄` (kg), at `x''` below pulley A.
        pub mass_4: f64 = ["m4", "kg", 11.0, Domain::Positive, "mass on pulley A's rope, side x''"],
        /// Mass `m₅` (kg), at `l'' − x''` below pulley A.
        pub mass_5: f64 = ["m5", "kg", 10.5, Domain::Positive, "mass on pulley A's rope, other side"],
        /// Upper rope length `l` (m).
        pub rope_length: f64 = ["l", "m", 5.0, Domain::Positive, "length of the upper rope"],
        /// Pulley B's rope length `l'` (m).
        pub rope_length_b: f64 = ["l'", "m", 4.0, Domain::Positive, "length of pulley B's rope"],
        /// Pulley A's rope length `l''` (m).
        pub rope_length_a: f64 = ["l''", "m", 4.0, Domain::Positive, "length of pulley A's rope"],
        /// Pulley A's mass `m_A` (kg).
        pub pulley_a_mass: f64 = ["m_A", "kg", 0.0, Domain::NonNegative, "mass of movable pulley A (0: massless)"],
        /// Pulley B's mass `m_B` (kg).
        pub pulley_b_mass: f64 = ["m_B", "kg", 0.0, Domain::NonNegative, "mass of movable pulley B (0: massless)"],
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
    }
    /// The machine with the parameters in [`PARAMS`]' order.
    fn with_values;
    derived {
        description: Description = Description {
            coordinates: vec![Coordinate::length("x"), Coordinate::length("x'"), Coordinate::length("x''")],
            bodies: vec![
                Body::point("pulley A", pulley_a_mass),
                Body::point("pulley B", pulley_b_mass),
                Body::point("mass 2", mass_2),
                Body::point("mass 3", mass_3),
                Body::point("mass 4", mass_4),
                Body::point("mass 5", mass_5),
            ],
            gravity,
            constant_mass_matrix: true,
            ..Description::default()
        },
    }
}

impl DoubleDoubleAtwood {
    /// A double-double Atwood machine: the hanging masses `[m2, m3, m4, m5]`, the rope lengths
    /// `[l, l', l'']` (upper rope, B's rope, A's rope) and the pulley masses `[m_A, m_B]`
    /// (together the order of [`PARAMS`]), and gravity `g`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first parameter outside its domain ([`PARAMS`]).
    pub fn new(masses: [f64; 4], rope_lengths: [f64; 3], pulley_masses: [f64; 2], gravity: f64) -> Result<Self, Error> {
        let ([m2, m3, m4, m5], [l, l_b, l_a], [m_a, m_b]) = (masses, rope_lengths, pulley_masses);
        Self::with_values(m2, m3, m4, m5, l, l_b, l_a, m_a, m_b, gravity)
    }

    /// The constant mass matrix, from
    /// `T = ½ (m_A + m_B) ẋ² + ½ m2 (ẋ' − ẋ)² + ½ m3 (ẋ + ẋ')² + ½ m4 (ẋ + ẋ'')² + ½ m5 (ẋ − ẋ'')²`
    /// (docs/scenes.md#double_double_atwood's `T` plus the pulleys, which move with `ẋ_A = ẋ`, `ẋ_B = −ẋ`):
    /// `M = [[m_A + m_B + m2 + m3 + m4 + m5, m3 − m2, m4 − m5], [m3 − m2, m2 + m3, 0], [m4 − m5, 0, m4 + m5]]`.
    pub fn mass_matrix(&self) -> [[f64; 3]; 3] {
        let (m2, m3, m4, m5) = (self.mass_2, self.mass_3, self.mass_4, self.mass_5);
        let pulleys = self.pulley_a_mass + self.pulley_b_mass;
        [[pulleys + m2 + m3 + m4 + m5, m3 - m2, m4 - m5], [m3 - m2, m2 + m3, 0.0], [m4 - m5, 0.0, m4 + m5]]
    }

    /// The constant generalized gravity force `F = −∂V/∂q` from
    /// `V = −g (m_A x_A + m_B x_B + m2 x₂ + m3 x₃ + m4 x₄ + m5 x₅)` (docs/scenes.md#double_double_atwood plus the pulleys):
    /// `F = g (m_A − m_B − m2 − m3 + m4 + m5, m2 − m3, m4 − m5)`.
    pub fn applied_force(&self) -> [f64; 3] {
        let (m2, m3, m4, m5, g) = (self.mass_2, self.mass_3, self.mass_4, self.mass_5, self.gravity);
        [g * (self.pulley_a_mass - self.pulley_b_mass - m2 - m3 + m4 + m5), g * (m2 - m3), g * (m4 - m5)]
    }

    /// The constant `(ẍ, ẍ', ẍ'')`. With massless pulleys, docs/scenes.md#double_double_atwood's effective-mass closed
    /// forms `ẍ = g (m4 m5 (m2 + m3) − m2 m3 (m4 + m5)) / (m4 m5 (m2 + m3) + m2 m3 (m4 + m5))`,
    /// `ẍ' = (m2 − m3)/(m2 + m3) (g + ẍ)`, `ẍ'' = (m4 − m5)/(m4 + m5) (g − ẍ)`; otherwise
    /// `M q̈ = F` ([`mass_matrix`](Self::mass_matrix), [`applied_force`](Self::applied_force)) by
    /// Cramer's rule.
    pub fn acceleration(&self) -> [f64; 3] {
        let (m2, m3, m4, m5, g) = (self.mass_2, self.mass_3, self.mass_4, self.mass_5, self.gravity);
        if self.pulley_a_mass == 0.0 && self.pulley_b_mass == 0.0 {
            let (b_pair, a_pair) = (m2 * m3 * (m4 + m5), m4 * m5 * (m2 + m3));
            let x_ddot = g * (a_pair - b_pair) / (a_pair + b_pair);
            return [x_ddot, (m2 - m3) / (m2 + m3) * (g + x_ddot), (m4 - m5) / (m4 + m5) * (g - x_ddot)];
        }
        let m = self.mass_matrix();
        let f = self.applied_force();
        // Cramer's rule: replace column j of M by F.
        let determinant = det3(m);
        let with_column = |j: usize| {
            let mut replaced = m;
            for (row, value) in replaced.iter_mut().zip(f) {
                row[j] = value;
            }
            det3(replaced) / determinant
        };
        [with_column(0), with_column(1), with_column(2)]
    }
}

/// The determinant of a 3 × 3 matrix, expanded along the first row.
fn det3(m: [[f64; 3]; 3]) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

impl Mechanism for DoubleDoubleAtwood {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (x, x_b, x_a) = (q[0], q[1], q[2]);
        // Depths below the upper pulley: pulleys A and B, then the masses below each.
        let depth_a = x;
        let depth_b = -x + self.rope_length;
        let depths = [
            depth_a,
            depth_b,
            depth_b + x_b,
            depth_b - x_b + self.rope_length_b,
            depth_a + x_a,
            depth_a - x_a + self.rope_length_a,
        ];
        hang_at_depths(world_from_body, depths);
    }

    /// Every rope segment keeps a non-negative length (radii neglected): the upper rope's `x`
    /// to A and `l − x` to B, B's rope's `x'` to `m2` and `l' − x'` to `m3`, A's rope's `x''`
    /// to `m4` and `l'' − x''` to `m5` (no mass passes through a pulley).
    fn admissible(&self, _t: f64, q: &[f64], _qdot: &[f64], bounds: &mut Bounds) -> bool {
        let (x, x_b, x_a) = (q[0], q[1], q[2]);
        bounds.at_least("upper rope to A, x", x, 0.0);
        bounds.at_least("upper rope to B, l − x", self.rope_length - x, 0.0);
        bounds.at_least("B's rope to m2, x'", x_b, 0.0);
        bounds.at_least("B's rope to m3, l' − x'", self.rope_length_b - x_b, 0.0);
        bounds.at_least("A's rope to m4, x''", x_a, 0.0);
        bounds.at_least("A's rope to m5, l'' − x''", self.rope_length_a - x_a, 0.0);
        true
    }
}

impl ConstantForce<3> for DoubleDoubleAtwood {
    fn qddot(&self) -> [f64; 3] {
        self.acceleration()
    }

    /// [`mass_matrix`](Self::mass_matrix), [`applied_force`](Self::applied_force) and
    /// `V₀ = −g ((m_B + m2 + m3) l + m3 l' + m5 l'')`.
    fn constant_terms(&self) -> ([[f64; 3]; 3], [f64; 3], f64) {
        let (m2, m3, m5) = (self.mass_2, self.mass_3, self.mass_5);
        let lengths = m3 * self.rope_length_b + m5 * self.rope_length_a;
        let potential_at_zero = -self.gravity * ((self.pulley_b_mass + m2 + m3) * self.rope_length + lengths);
        (self.mass_matrix(), self.applied_force(), potential_at_zero)
    }
}

impl SceneType for DoubleDoubleAtwood {
    const ID: &'static str = "double_double_atwood";
    const TITLE: &'static str = "Double-double Atwood machine";
    const REFERENCE: &'static str = "docs/scenes.md#double_double_atwood; the lecture (docs/scenes.md#the-lecture), homework remark (massive pulleys beyond the lecture)";
    param_table!();

    /// `x = 3.5`, `x' = 0.5`, `x'' = 3.3`, `q̇ = (−1.2, 1.2, −1.1)`: each rope set moving against
    /// its constant acceleration (`q̈ = (0.23, −0.24, 0.22)` with the default parameters), so that
    /// each turns back near `t = 5` s and every rope segment stays positive for the report's
    /// 10 s (also with the rapier multibody build's 0.5 kg pulleys, which change `ẍ` by 2 %).
    fn default_state(&self) -> State {
        State::new(0.0, [3.5, 0.5, 3.3], [-1.2, 1.2, -1.1])
    }

    constant_force_scene!();

    /// Vertical slides below the upper pulley for pulley A (`x`) and pulley B (coupled:
    /// `l − x`), below B for `m2` (`x'`) and `m3` (coupled: `l' − x'`), below A for `m4`
    /// (`x''`) and `m5` (coupled: `l'' − x''`).
    fn joint_graph(&self) -> Option<JointGraph> {
        let (o, down) = ([0.0, 0.0], [0.0, -1.0]);
        let names: Vec<String> = self.description.bodies.iter().map(|b| b.name.clone()).collect();
        let [a, b, m2, m3, m4, m5] = [0, 1, 2, 3, 4, 5].map(|i| names[i].as_str());
        Some(
            crate::scene::graph_of(Self::ID, self)
                .with_joint(GraphJoint::prismatic("x", GROUND, o, a, o, down))
                .with_joint(GraphJoint::prismatic("x'", b, o, m2, o, down))
                .with_joint(GraphJoint::prismatic("x''", a, o, m4, o, down))
                .with_joint(GraphJoint::prismatic("upper rope", GROUND, o, b, o, down))
                .with_joint(GraphJoint::prismatic("rope of B", b, o, m3, o, down))
                .with_joint(GraphJoint::prismatic("rope of A", a, o, m5, o, down))
                .with_coupling("upper rope", "x", -1.0, self.rope_length)
                .with_coupling("rope of B", "x'", -1.0, self.rope_length_b)
                .with_coupling("rope of A", "x''", -1.0, self.rope_length_a),
        )
    }

    /// A massless movable pulley makes rapier's multibody mass matrix singular
    /// (docs/rapier.md#couplings), so the multibody build gives it mass.
    fn rapier_deviations(multibody: bool) -> &'static [crate::RapierDeviation] {
        if multibody { &[("pulley_a_mass", "", ""), ("pulley_b_mass", "", "")] } else { &[] }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Params;
    use crate::scene_of;
    use crate::testing::{
        ENGINE_VS_CLOSED_FORM, assert_close, assert_engine_matches_closed_form_along, assert_exact_solution_consistent,
    };
    use lagrange::Model;

    fn with_pulley_masses(m_a: f64, m_b: f64) -> Params {
        let mut params = scene_of::<DoubleDoubleAtwood>().default_params();
        params.set("m_A", m_a).unwrap();
        params.set("m_B", m_b).unwrap();
        params
    }

    #[test]
    fn engine_matches_closed_form_with_massless_and_massive_pulleys() {
        // (m_A, m_B) = (0, 0), (0.6, 0), (0, 0.9), (0.3, 1.2), on the way through (0, 0) and (0.3, 0.9).
        let rows = [
            (0.5, [-0.4, 0.3, 1.5], [1.2, -0.5, 0.2]),
            (1.0, [2.0, 1.9, -0.3], [-3.0, 2.0, 0.9]),
            (3.0, [4.5, -0.7, 0.8], [0.7, 0.1, -1.4]),
            (7.0, [-1.5, 2.5, 2.2], [-0.2, -1.1, 0.05]),
        ];
        let changes = [("m_A", 0.6), ("m_A", 0.0), ("m_B", 0.9), ("m_A", 0.3), ("m_B", 1.2)];
        assert_engine_matches_closed_form_along::<DoubleDoubleAtwood, 3>(&rows, &changes);
    }

    /// The hand-derived `M` and `F` with pulley masses are the engine's: `M` entry by entry,
    /// and `F = M q̈_engine`.
    #[test]
    fn derived_mass_matrix_and_force_with_pulley_masses_match_the_engine() {
        for (m_a, m_b) in [(0.6, 0.0), (0.3, 1.2)] {
            let scene = DoubleDoubleAtwood::from_params(&with_pulley_masses(m_a, m_b)).unwrap();
            let model = Model::new(scene.clone()).unwrap();
            let mut ws = model.workspace();
            let q = [2.0, 1.0, 1.0];
            let engine_mass_matrix = lagrange::mass_matrix(&model, &mut ws, 0.0, &q, &[0.0; 3]).unwrap().to_vec();
            let derived: Vec<f64> = scene.mass_matrix().concat();
            let scale = derived.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            assert_close("M", &derived, &engine_mass_matrix, ENGINE_VS_CLOSED_FORM * scale);
            let qddot = lagrange::accelerations(&model, &mut ws, 0.0, &q, &[0.3, -0.2, 0.1]).unwrap().to_vec();
            let force: Vec<f64> = (0..3).map(|i| (0..3).map(|j| derived[3 * i + j] * qddot[j]).sum()).collect();
            let expected = scene.applied_force();
            assert_close("F = M q̈", &expected, &force, ENGINE_VS_CLOSED_FORM * scale * scene.gravity * 10.0);
        }
    }

    /// Cramer's rule at vanishing pulley masses reproduces docs/scenes.md#double_double_atwood's effective-mass forms,
    /// and replacing pulley A by a mass (`μ₄₅ → m1`) gives the double Atwood machine.
    #[test]
    fn cramer_branch_agrees_with_the_effective_mass_closed_forms() {
        let massless = DoubleDoubleAtwood::from_params(&with_pulley_masses(0.0, 0.0)).unwrap();
        let nearly = DoubleDoubleAtwood::from_params(&with_pulley_masses(1e-300, 0.0)).unwrap();
        assert_close("m_A → 0", &massless.acceleration(), &nearly.acceleration(), 1e-14);
        // docs/scenes.md#double_double_atwood sympy form of ẍ'.
        let (m2, m3, m4, m5, g) =
            (massless.mass_2, massless.mass_3, massless.mass_4, massless.mass_5, massless.gravity);
        let denominator = m2 * m3 * m4 + m2 * m3 * m5 + m2 * m4 * m5 + m3 * m4 * m5;
        let x_prime_ddot = 2.0 * g * m4 * m5 * (m2 - m3) / denominator;
        let x_second_ddot = 2.0 * g * m2 * m3 * (m4 - m5) / denominator;
        assert_close("ẍ', ẍ''", &[x_prime_ddot, x_second_ddot], &massless.acceleration()[1..], 1e-14);
        // μ₄₅ = 4 m4 m5/(m4 + m5) = m1 reproduces the double Atwood ẍ.
        let m1 = 4.0 * m4 * m5 / (m4 + m5);
        let double = crate::DoubleAtwood::new(m1, m2, m3, 5.0, 2.0, 0.0, g).unwrap();
        assert_close("ẍ vs double Atwood", &double.acceleration(), &massless.acceleration()[..2], 1e-14);
    }

    #[test]
    fn exact_solution_is_consistent() {
        for (m_a, m_b) in [(0.0, 0.0), (0.3, 1.2)] {
            let params = with_pulley_masses(m_a, m_b);
            let initial = State::new(0.5, [2.0, 1.0, 1.0], [0.1, 0.0, -0.3]);
            assert_exact_solution_consistent(scene_of::<DoubleDoubleAtwood>(), &params, &initial, &[0.5, 2.0]);
        }
    }
}
