//! Double Atwood machine, optionally with a massive movable pulley (docs/scenes.md#double_atwood; the lecture (docs/scenes.md#the-lecture)).

use crate::checks::fixed;
use crate::params::{GRAVITY, param_table, scene_params};
use crate::uniform_acceleration::{ConstantForce, constant_force_scene, hang_at_depths};
use crate::{Domain, SceneType};
use lagrange::graph::{GROUND, GraphJoint, JointGraph};
use lagrange::{Body, Bounds, Coordinate, Description, Mechanism, Pose, Scalar, State};

scene_params! {
    /// A fixed upper pulley whose rope (length `l`) carries `m1` on one end and a movable pulley on
    /// the other; the movable pulley's rope (length `l'`) carries `m2` and `m3`. Radii neglected,
    /// depths measured downward from the upper pulley: `x₁ = x`, movable pulley at `x_p = l − x`,
    /// `x₂ = (l − x) + x'`, `x₃ = (l − x) + (l' − x')`; body `i` at `(0, −x_i)`; `q = (x, x')`
    /// (docs/scenes.md#double_atwood). The movable pulley is a point body of mass `m_p` (0 in the lecture).
    pub struct DoubleAtwood {
        /// Mass `m₁` (kg) on the upper rope.
        pub mass_1: f64 = ["m1", "kg", 20.6, Domain::Positive, "mass on the upper rope"],
        /// Mass `m₂` (kg) on the lower rope, at `x'` below the movable pulley.
        pub mass_2: f64 = ["m2", "kg", 10.0, Domain::Positive, "mass on the lower rope, side x'"],
        /// Mass `m₃` (kg) on the lower rope, at `l' − x'` below the movable pulley.
        pub mass_3: f64 = ["m3", "kg", 10.5, Domain::Positive, "mass on the lower rope, other side"],
        /// Upper rope length `l` (m).
        pub rope_length: f64 = ["l", "m", 10.0, Domain::Positive, "length of the upper rope"],
        /// Lower rope length `l'` (m).
        pub lower_rope_length: f64 = ["l'", "m", 4.0, Domain::Positive, "length of the lower rope"],
        /// Movable pulley mass `m_p` (kg); 0 for the lecture's massless pulley.
        pub lower_pulley_mass: f64 = ["m_p", "kg", 0.0, Domain::NonNegative, "mass of the movable pulley (0: the lecture's massless pulley)"],
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
    }
    /// A double Atwood machine with masses `m1`, `m2`, `m3`, rope lengths `l`, `l'`, movable
    /// pulley mass `m_p` and gravity `g`.
    pub fn new;
    derived {
        description: Description = Description {
            coordinates: vec![Coordinate::length("x"), Coordinate::length("x'")],
            bodies: vec![Body::point("mass 1", mass_1), Body::point("mass 2", mass_2), Body::point("mass 3", mass_3), Body::point("movable pulley", lower_pulley_mass)],
            gravity,
            constant_mass_matrix: true,
            ..Description::default()
        },
    }
}

impl DoubleAtwood {
    /// The constant mass matrix `M = [[m1 + m2 + m3 + m_p, m3 − m2], [m3 − m2, m2 + m3]]`, from
    /// `T = ½ m1 ẋ² + ½ m2 (ẋ' − ẋ)² + ½ m3 (ẋ + ẋ')² + ½ m_p ẋ²` (docs/scenes.md#double_atwood plus the pulley).
    pub fn mass_matrix(&self) -> [[f64; 2]; 2] {
        let (m1, m2, m3, mp) = (self.mass_1, self.mass_2, self.mass_3, self.lower_pulley_mass);
        [[m1 + m2 + m3 + mp, m3 - m2], [m3 - m2, m2 + m3]]
    }

    /// The constant generalized gravity force `F = −∂V/∂q = g (m1 − m2 − m3 − m_p, m2 − m3)`, from
    /// `V = −g (m1 x₁ + m2 x₂ + m3 x₃ + m_p x_p)` (docs/scenes.md#double_atwood plus the pulley).
    pub fn applied_force(&self) -> [f64; 2] {
        let (m1, m2, m3, mp, g) = (self.mass_1, self.mass_2, self.mass_3, self.lower_pulley_mass, self.gravity);
        [g * (m1 - m2 - m3 - mp), g * (m2 - m3)]
    }

    /// The constant `(ẍ, ẍ')`. With a massless pulley, docs/scenes.md#double_atwood's closed forms
    /// `ẍ = g (m1 (m2 + m3) − 4 m2 m3) / (m1 (m2 + m3) + 4 m2 m3)`,
    /// `ẍ' = 2 m1 (m2 − m3) g / (m1 (m2 + m3) + 4 m2 m3)`; otherwise `M q̈ = F`
    /// ([`mass_matrix`](Self::mass_matrix), [`applied_force`](Self::applied_force)) by Cramer's rule.
    pub fn acceleration(&self) -> [f64; 2] {
        let (m1, m2, m3, g) = (self.mass_1, self.mass_2, self.mass_3, self.gravity);
        if self.lower_pulley_mass == 0.0 {
            let denominator = m1 * (m2 + m3) + 4.0 * m2 * m3;
            return [g * (m1 * (m2 + m3) - 4.0 * m2 * m3) / denominator, 2.0 * m1 * (m2 - m3) * g / denominator];
        }
        let [[a, b], [c, d]] = self.mass_matrix();
        let [f1, f2] = self.applied_force();
        let determinant = a * d - b * c;
        [(f1 * d - b * f2) / determinant, (a * f2 - c * f1) / determinant]
    }

    /// The rope tensions `(upper, lower) = (m1 (g − ẍ₁), m2 (g − ẍ₂))` (N), with the downward
    /// accelerations `ẍ₁ = ẍ`, `ẍ₂ = −ẍ + ẍ'` (docs/scenes.md#double_atwood, "Absolute accelerations").
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn tensions(&self, q: &[f64], qdot: &[f64]) -> (f64, f64) {
        let _: ([f64; 2], [f64; 2]) = (fixed(q, "q"), fixed(qdot, "q̇"));
        let [x_ddot, x_prime_ddot] = self.acceleration();
        let g = self.gravity;
        (self.mass_1 * (g - x_ddot), self.mass_2 * (g - (x_prime_ddot - x_ddot)))
    }
}

impl Mechanism for DoubleAtwood {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (x, x_prime) = (q[0], q[1]);
        // Depths below the upper pulley: m1, the movable pulley, and the masses below it.
        let pulley_depth = -x + self.rope_length;
        let depths = [x, pulley_depth + x_prime, pulley_depth - x_prime + self.lower_rope_length, pulley_depth];
        hang_at_depths(world_from_body, depths);
    }

    /// Every rope segment keeps a non-negative length (radii neglected): the upper rope's `x`
    /// to `m1` and `l − x` to the movable pulley, the lower rope's `x'` to `m2` and `l' − x'` to
    /// `m3` (no mass passes through a pulley).
    fn admissible(&self, _t: f64, q: &[f64], _qdot: &[f64], bounds: &mut Bounds) -> bool {
        let (x, x_prime) = (q[0], q[1]);
        bounds.at_least("upper rope to m1, x", x, 0.0);
        bounds.at_least("upper rope to the pulley, l − x", self.rope_length - x, 0.0);
        bounds.at_least("lower rope to m2, x'", x_prime, 0.0);
        bounds.at_least("lower rope to m3, l' − x'", self.lower_rope_length - x_prime, 0.0);
        true
    }
}

impl ConstantForce<2> for DoubleAtwood {
    fn qddot(&self) -> [f64; 2] {
        self.acceleration()
    }

    /// [`mass_matrix`](Self::mass_matrix), [`applied_force`](Self::applied_force) and
    /// `V₀ = −g ((m2 + m3 + m_p) l + m3 l')`.
    fn constant_terms(&self) -> ([[f64; 2]; 2], [f64; 2], f64) {
        let (m2, m3, mp) = (self.mass_2, self.mass_3, self.lower_pulley_mass);
        let potential_at_zero = -self.gravity * ((m2 + m3 + mp) * self.rope_length + m3 * self.lower_rope_length);
        (self.mass_matrix(), self.applied_force(), potential_at_zero)
    }
}

impl SceneType for DoubleAtwood {
    const ID: &'static str = "double_atwood";
    const TITLE: &'static str = "Double Atwood machine";
    const REFERENCE: &'static str = "docs/scenes.md#double_atwood; the lecture (docs/scenes.md#the-lecture), example: double Atwood machine (massive pulley beyond the lecture)";
    param_table!();

    /// `x = 2.5`, `x' = 0.5`, `ẋ = 0.5`, `ẋ' = 1.2`: `m1` nearly balances the lower pulley
    /// (`ẍ = 0.027`, so `x ≤ 8.9`), and the lower rope is set moving against its acceleration
    /// (`ẍ' = −0.24`), so that it turns back near `t = 5` s (`x' ≤ 3.5`): every rope segment
    /// stays positive for the report's 10 s, also with the 0.5 kg movable pulley of the rapier
    /// multibody build (`ẍ = −0.091`, `2.5 ≤ x ≤ 3.9`).
    fn default_state(&self) -> State {
        State::new(0.0, [2.5, 0.5], [0.5, 1.2])
    }

    constant_force_scene!();

    /// Vertical slides below the upper pulley for `m1` (`x`) and the movable pulley (coupled:
    /// `l − x`), and below the movable pulley for `m2` (`x'`) and `m3` (coupled: `l' − x'`).
    fn joint_graph(&self) -> Option<JointGraph> {
        let (o, down) = ([0.0, 0.0], [0.0, -1.0]);
        Some(
            crate::scene::graph_of(Self::ID, self)
                .with_joint(GraphJoint::prismatic("x", GROUND, o, "mass 1", o, down))
                .with_joint(GraphJoint::prismatic("x'", "movable pulley", o, "mass 2", o, down))
                .with_joint(GraphJoint::prismatic("upper rope", GROUND, o, "movable pulley", o, down))
                .with_joint(GraphJoint::prismatic("lower rope", "movable pulley", o, "mass 3", o, down))
                .with_coupling("upper rope", "x", -1.0, self.rope_length)
                .with_coupling("lower rope", "x'", -1.0, self.lower_rope_length),
        )
    }

    /// A massless movable pulley makes rapier's multibody mass matrix singular
    /// (docs/rapier.md#couplings), so the multibody build gives it mass.
    fn rapier_deviations(multibody: bool) -> &'static [crate::RapierDeviation] {
        if multibody { &[("lower_pulley_mass", "", "")] } else { &[] }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_of;
    use crate::testing::{
        ENGINE_VS_CLOSED_FORM, PLANAR_ROWS, assert_close, assert_engine_matches_closed_form_along,
        assert_exact_solution_consistent,
    };
    use lagrange::{Buffered, Model, System};

    #[test]
    fn engine_matches_closed_form_with_massless_and_massive_pulley() {
        assert_engine_matches_closed_form_along::<DoubleAtwood, 2>(
            &PLANAR_ROWS,
            &[("m_p", 0.7), ("m1", 0.5), ("m3", 4.0), ("m_p", 0.0)],
        );
    }

    /// Cramer's rule on `M q̈ = F` reproduces docs/scenes.md#double_atwood's closed forms at `m_p = 0` (the
    /// two branches of `acceleration` agree), and the massive-pulley `M`, `F` are the engine's.
    #[test]
    fn cramer_branch_agrees_with_the_lecture_closed_form_and_the_engine() {
        let massless = DoubleAtwood::new(3.0, 1.0, 1.5, 5.0, 2.0, 0.0, 9.81).unwrap();
        let nearly = DoubleAtwood::new(3.0, 1.0, 1.5, 5.0, 2.0, 1e-300, 9.81).unwrap();
        assert_close("m_p → 0", &massless.acceleration(), &nearly.acceleration(), 1e-14);
        let scene = DoubleAtwood::new(3.0, 1.0, 1.5, 5.0, 2.0, 0.8, 9.81).unwrap();
        let model = Model::new(scene.clone()).unwrap();
        let mut ws = model.workspace();
        let mass_matrix = lagrange::mass_matrix(&model, &mut ws, 0.0, &[2.0, 1.0], &[0.0, 0.0]).unwrap().to_vec();
        let expected: Vec<f64> = scene.mass_matrix().concat();
        assert_close("M", &expected, &mass_matrix, ENGINE_VS_CLOSED_FORM * 6.0);
        let qddot = lagrange::accelerations(&model, &mut ws, 0.0, &[2.0, 1.0], &[0.0, 0.0]).unwrap().to_vec();
        let force: Vec<f64> = (0..2).map(|i| (0..2).map(|j| expected[2 * i + j] * qddot[j]).sum()).collect();
        assert_close("F = M q̈", &scene.applied_force(), &force, ENGINE_VS_CLOSED_FORM * 60.0);
    }

    #[test]
    fn exact_solution_is_consistent() {
        let mut params = scene_of::<DoubleAtwood>().default_params();
        for m_p in [0.0, 0.4] {
            params.set("m_p", m_p).unwrap();
            for initial in [State::new(0.0, [2.0, 1.0], [0.0, 0.0]), State::new(1.0, [1.0, 0.5], [0.3, -0.2])] {
                assert_exact_solution_consistent(scene_of::<DoubleAtwood>(), &params, &initial, &[0.5, 2.0]);
            }
        }
    }

    /// The engine's reaction forces on `m1` and `m2` are the rope tensions; docs/scenes.md#double_atwood's
    /// tension check: with a massless pulley the lower masses act like `μ = 4 m2 m3/(m2 + m3)`.
    #[test]
    fn tensions_match_the_engine_and_the_effective_mass() {
        let scene = DoubleAtwood::new(3.0, 1.0, 1.5, 5.0, 2.0, 0.0, 9.81).unwrap();
        let mut system = Buffered::new(Model::new(scene.clone()).unwrap());
        let (q, qdot) = ([2.0, 1.0], [0.1, 0.2]);
        let (upper, lower) = scene.tensions(&q, &qdot);
        let reactions = system.reaction_forces(0.0, &q, &qdot).unwrap().unwrap().to_vec();
        let tolerance = ENGINE_VS_CLOSED_FORM * scene.mass_1 * scene.gravity;
        assert_close("vertical reactions on m1, m2", &[upper, lower], &[reactions[1], reactions[4]], tolerance);
        // Massless pulley: the upper rope carries twice the lower tension.
        assert_close("upper = 2 lower", &[upper], &[2.0 * lower], tolerance);
        let mu = 4.0 * scene.mass_2 * scene.mass_3 / (scene.mass_2 + scene.mass_3);
        let x_ddot = scene.gravity * (scene.mass_1 - mu) / (scene.mass_1 + mu);
        assert_close("ẍ = g (m1 − μ)/(m1 + μ)", &[x_ddot], &scene.acceleration()[..1], 1e-14);
    }

    #[test]
    fn equilibrium_iff_equal_lower_masses_and_m1_twice() {
        let balanced = DoubleAtwood::new(2.0, 1.0, 1.0, 5.0, 2.0, 0.0, 9.81).unwrap();
        assert_eq!(balanced.acceleration(), [0.0, 0.0]);
    }
}
