//! Atwood machine with a massive pulley (docs/scenes.md#atwood; the lecture (docs/scenes.md#the-lecture)).

use crate::checks::fixed;
use crate::params::{GRAVITY, param_table, scene_params};
use crate::uniform_acceleration::{ConstantForce, constant_force_scene};
use crate::{Domain, SceneType};
use lagrange::graph::{GROUND, GraphJoint, JointGraph};
use lagrange::{Body, Bounds, Coordinate, Description, Mechanism, Pose, Scalar, State};
use std::f64::consts::PI;

scene_params! {
    /// Masses `m1` at `(−a, −x)` and `m2` at `(a, −(l − πa − x))` on a rope over a pulley of radius
    /// `a` and inertia `I` at the origin, turning by `x/a` (no slip); `q = (x)`, the depth of `m1`
    /// below the axle, measured downward (docs/scenes.md#atwood).
    pub struct Atwood {
        /// Mass `m₁` (kg) on the left, at depth `x`.
        pub mass_1: f64 = ["m1", "kg", 1.1, Domain::Positive, "mass on the left end of the rope"],
        /// Mass `m₂` (kg) on the right, at depth `l − πa − x`.
        pub mass_2: f64 = ["m2", "kg", 1.0, Domain::Positive, "mass on the right end of the rope"],
        /// Pulley moment of inertia `I` (kg m²); 0 for the ideal machine.
        pub pulley_inertia: f64 = ["I", "kg m²", 0.1, Domain::NonNegative, "moment of inertia of the pulley"],
        /// Pulley radius `a` (m).
        pub pulley_radius: f64 = ["a", "m", 0.5, Domain::Positive, "radius of the pulley"],
        /// Rope length `l` (m), including the `πa` around the pulley. Any `l > 0` is accepted (it
        /// shifts `m2`'s height only), but the rope reaches both masses only for
        /// `0 ≤ x ≤ l − πa`, the admissible region.
        pub rope_length: f64 = ["l", "m", 10.0, Domain::Positive, "length of the rope"],
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
    }
    /// An Atwood machine with masses `m1`, `m2`, pulley inertia `I`, pulley radius `a`, rope
    /// length `l` and gravity `g`.
    pub fn new;
    derived {
        description: Description = Description {
            coordinates: vec![Coordinate::length("x")],
            bodies: vec![
                Body::point("mass 1", mass_1),
                Body::point("mass 2", mass_2),
                Body::rigid("pulley", 0.0, pulley_inertia),
            ],
            gravity,
            constant_mass_matrix: true,
            ..Description::default()
        },
    }
}

impl Atwood {
    /// The constant `ẍ = (m1 − m2) g / (m1 + m2 + I/a²)` (docs/scenes.md#atwood, "Closed form"; the
    /// lecture's result). Positive when `m1` descends.
    pub fn acceleration(&self) -> f64 {
        let a = self.pulley_radius;
        (self.mass_1 - self.mass_2) * self.gravity / (self.mass_1 + self.mass_2 + self.pulley_inertia / (a * a))
    }

    /// The rope tensions `(T1, T2) = (m1 (g − ẍ), m2 (g + ẍ))` (N) on `m1` and `m2`
    /// (docs/scenes.md#atwood; `(T1 − T2) a = I ẍ / a`). Constant: the state does not enter.
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 1 entry.
    pub fn tensions(&self, q: &[f64], qdot: &[f64]) -> (f64, f64) {
        let _: ([f64; 1], [f64; 1]) = (fixed(q, "q"), fixed(qdot, "q̇"));
        let acceleration = self.acceleration();
        (self.mass_1 * (self.gravity - acceleration), self.mass_2 * (self.gravity + acceleration))
    }
}

impl Mechanism for Atwood {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (x, a) = (q[0], self.pulley_radius);
        // m1 at depth x on the left, m2 at depth l − πa − x on the right, pulley turning x/a.
        world_from_body[0] = Pose::point(S::from(-a), -x);
        world_from_body[1] = Pose::point(S::from(a), x - (self.rope_length - PI * a));
        world_from_body[2] = Pose::new(S::zero(), S::zero(), x * (1.0 / a));
    }

    /// Both rope segments keep a non-negative length: `x` from the pulley to `m1` and
    /// `l − πa − x` to `m2` (the masses cannot pass through the pulley).
    fn admissible(&self, _t: f64, q: &[f64], _qdot: &[f64], bounds: &mut Bounds) -> bool {
        bounds.at_least("rope to m1, x", q[0], 0.0);
        bounds.at_least("rope to m2, l − πa − x", self.rope_length - PI * self.pulley_radius - q[0], 0.0);
        true
    }
}

impl ConstantForce<1> for Atwood {
    fn qddot(&self) -> [f64; 1] {
        [self.acceleration()]
    }

    /// `M = m1 + m2 + I/a²`, `F = (m1 − m2) g`, `V₀ = −m2 g (l − πa)` (docs/scenes.md#atwood).
    fn constant_terms(&self) -> ([[f64; 1]; 1], [f64; 1], f64) {
        let (a, g) = (self.pulley_radius, self.gravity);
        let mass = self.mass_1 + self.mass_2 + self.pulley_inertia / (a * a);
        ([[mass]], [(self.mass_1 - self.mass_2) * g], -self.mass_2 * g * (self.rope_length - PI * a))
    }
}

impl SceneType for Atwood {
    const ID: &'static str = "atwood";
    const TITLE: &'static str = "Atwood machine with a massive pulley";
    const REFERENCE: &'static str =
        "docs/scenes.md#atwood; the lecture (docs/scenes.md#the-lecture), example: Atwood machine";
    param_table!();

    /// `x = 6`, `ẋ = −2`: `m1` thrown upward. With the default parameters (`ẍ = 0.39`) it rises
    /// to `x = 0.90` at `t = 5.1` s and is back at `x = 5.6` at 10 s, inside
    /// `0 ≤ x ≤ l − πa = 8.43` throughout.
    fn default_state(&self) -> State {
        State::new(0.0, [6.0], [-2.0])
    }

    constant_force_scene!();

    /// The masses on vertical slides below the pulley's rims (`x` the depth of `m1`), the rope
    /// as a coupling of the second slide to the first (`x₂ = l − πa − x`), the pulley on a pin
    /// turning with the rope (`φ = x/a`).
    fn joint_graph(&self) -> Option<JointGraph> {
        let (a, down) = (self.pulley_radius, [0.0, -1.0]);
        Some(
            crate::scene::graph_of(Self::ID, self)
                .with_joint(GraphJoint::prismatic("x", GROUND, [-a, 0.0], "mass 1", [0.0, 0.0], down))
                .with_joint(GraphJoint::prismatic("rope to m2", GROUND, [a, 0.0], "mass 2", [0.0, 0.0], down))
                .with_joint(GraphJoint::revolute("pulley turn", GROUND, [0.0, 0.0], "pulley", [0.0, 0.0]))
                .with_coupling("rope to m2", "x", -1.0, self.rope_length - PI * a)
                .with_coupling("pulley turn", "x", 1.0 / a, 0.0),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_of;
    use crate::testing::{
        ENGINE_VS_CLOSED_FORM, assert_close, assert_engine_matches_closed_form_along, assert_exact_solution_consistent,
    };
    use lagrange::{Buffered, Model, System};

    #[test]
    fn engine_matches_closed_form() {
        assert_engine_matches_closed_form_along::<Atwood, 1>(
            &[(0.5, [-0.4], [1.2]), (1.0, [2.0], [-3.0]), (3.0, [7.5], [0.7]), (7.0, [-1.5], [-0.2])],
            &[("I", 0.0), ("m2", 3.5), ("a", 0.2), ("g", 1.6)],
        );
    }

    #[test]
    fn exact_solution_is_consistent() {
        let params = scene_of::<Atwood>().default_params();
        for initial in [State::new(0.0, [1.0], [0.0]), State::new(2.0, [-0.5], [0.8])] {
            assert_exact_solution_consistent(scene_of::<Atwood>(), &params, &initial, &[0.5, 3.0]);
        }
    }

    /// The engine's reaction forces on the masses are the rope tensions (vertical), and the
    /// net rope torque on the pulley is `I φ̈`.
    #[test]
    fn tensions_match_the_engine_reactions() {
        let scene = Atwood::new(2.0, 1.0, 0.1, 0.5, 10.0, 9.81).unwrap();
        let mut system = Buffered::new(Model::new(scene.clone()).unwrap());
        let (q, qdot) = ([1.0], [0.3]);
        let (t1, t2) = scene.tensions(&q, &qdot);
        let reactions = system.reaction_forces(0.0, &q, &qdot).unwrap().unwrap().to_vec();
        let tolerance = ENGINE_VS_CLOSED_FORM * scene.mass_1 * scene.gravity;
        assert_close("reactions on m1, m2", &[0.0, t1, 0.0, 0.0, t2, 0.0], &reactions[..6], tolerance);
        let a = scene.pulley_radius;
        assert_close("torque on the pulley", &[(t1 - t2) * a], &reactions[8..9], tolerance);
        assert_close(
            "(T1 − T2) a = I ẍ/a",
            &[(t1 - t2) * a],
            &[scene.pulley_inertia * scene.acceleration() / a],
            tolerance,
        );
    }

    #[test]
    fn limits_of_the_lecture_result() {
        let ideal = Atwood::new(3.0, 1.0, 0.0, 0.5, 10.0, 10.0).unwrap();
        assert_eq!(ideal.acceleration(), 5.0, "I = 0: (m1 − m2) g / (m1 + m2)");
        let balanced = Atwood::new(1.5, 1.5, 0.3, 0.5, 10.0, 9.81).unwrap();
        assert_eq!(balanced.acceleration(), 0.0);
    }
}
