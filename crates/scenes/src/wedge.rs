//! Block sliding on a movable frictionless wedge (docs/scenes.md#wedge; the lecture (docs/scenes.md#the-lecture)).

use crate::params::{GRAVITY, param_table, scene_params};
use crate::uniform_acceleration::{ConstantForce, constant_force_scene};
use crate::{Domain, SceneType};
use lagrange::graph::{GROUND, GraphJoint, JointGraph};
use lagrange::{Body, Bounds, Coordinate, Description, Mechanism, Pose, Scalar, State};
use std::f64::consts::FRAC_PI_2;

scene_params! {
    /// A wedge of mass `M` sliding on a frictionless floor, its top corner at `(x, 0)`, and a block
    /// of mass `m` on its frictionless incline (angle `α`, length `L`, descending towards `+x`) at
    /// `(x + x' cosα, (L − x') sinα)`; `q = (x, x')`, `x'` measured down the slope from the top
    /// corner (docs/scenes.md#wedge). The wedge only translates.
    pub struct Wedge {
        /// Wedge mass `M` (kg).
        pub wedge_mass: f64 = ["M", "kg", 3.0, Domain::Positive, "mass of the wedge"],
        /// Block mass `m` (kg).
        pub block_mass: f64 = ["m", "kg", 1.0, Domain::Positive, "mass of the block"],
        /// Incline angle `α` (rad), `0 < α < π/2`.
        pub angle: f64 = ["α", "rad", 0.05, Domain::OpenInterval(0.0, FRAC_PI_2), "angle of the incline"],
        /// Incline length `L` (m).
        pub incline_length: f64 = ["L", "m", 10.0, Domain::Positive, "length of the incline"],
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
    }
    /// A wedge of mass `M` with a block of mass `m`, incline angle `α`, incline length `L` and
    /// gravity `g`.
    pub fn new;
    derived {
        description: Description = Description {
            coordinates: vec![Coordinate::length("x"), Coordinate::length("x'")],
            bodies: vec![Body::point("wedge", wedge_mass), Body::point("block", block_mass)],
            gravity,
            constant_mass_matrix: true,
            ..Description::default()
        },
    }
}

impl Wedge {
    /// The constant `(ẍ, ẍ')` (docs/scenes.md#wedge, "Closed forms"; the lecture's results):
    /// `ẍ = −m g sinα cosα / (M + m sin²α)` (the wedge recoils towards −x),
    /// `ẍ' = (M + m) g sinα / (M + m sin²α)`.
    pub fn acceleration(&self) -> [f64; 2] {
        let (wedge, block, g) = (self.wedge_mass, self.block_mass, self.gravity);
        let (sin, cos) = self.angle.sin_cos();
        let denominator = wedge + block * sin * sin;
        [-block * g * sin * cos / denominator, (wedge + block) * g * sin / denominator]
    }

    /// The normal force of the incline on the block, `N = M m g cosα / (M + m sin²α)` (N),
    /// along the incline's outward normal `(sinα, cosα)` (docs/scenes.md#wedge).
    pub fn normal_force(&self) -> f64 {
        let (wedge, block) = (self.wedge_mass, self.block_mass);
        let (sin, cos) = self.angle.sin_cos();
        wedge * block * self.gravity * cos / (wedge + block * sin * sin)
    }
}

impl Mechanism for Wedge {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (x, x_prime) = (q[0], q[1]);
        let (sin, cos) = self.angle.sin_cos();
        // Wedge corner on the floor; block at x' down the slope.
        world_from_body[0] = Pose::point(x, S::zero());
        world_from_body[1] = Pose::point(x + x_prime * cos, (-x_prime + self.incline_length) * sin);
    }

    /// The block stays on the incline, between its top corner (`x' = 0`) and its foot on the
    /// floor (`x' = L`); past either end the block would slide on a slope that is not there.
    /// The floor is unbounded: the wedge's `x` is free.
    fn admissible(&self, _t: f64, q: &[f64], _qdot: &[f64], bounds: &mut Bounds) -> bool {
        bounds.at_least("block on the incline x'", q[1], 0.0);
        bounds.at_most("block on the incline x'", q[1], self.incline_length);
        true
    }
}

impl ConstantForce<2> for Wedge {
    /// `x` is cyclic: the horizontal momentum `p_x = (M + m) ẋ + m cosα ẋ'` is conserved.
    const CYCLIC: &'static [usize] = &[0];

    fn qddot(&self) -> [f64; 2] {
        self.acceleration()
    }

    /// `M = [[M + m, m cosα], [m cosα, m]]`, `F = (0, m g sinα)`, `V₀ = m g L sinα`
    /// (docs/scenes.md#wedge).
    fn constant_terms(&self) -> ([[f64; 2]; 2], [f64; 2], f64) {
        let (block, (sin, cos)) = (self.block_mass, self.angle.sin_cos());
        let weight = block * self.gravity * sin;
        ([[self.wedge_mass + block, block * cos], [block * cos, block]], [0.0, weight], weight * self.incline_length)
    }
}

impl SceneType for Wedge {
    const ID: &'static str = "wedge";
    const TITLE: &'static str = "Block on a movable frictionless wedge";
    const REFERENCE: &'static str =
        "docs/scenes.md#wedge; the lecture (docs/scenes.md#the-lecture), example: block on a movable wedge";
    param_table!();

    /// `x = 0`, `x' = 9` (block 1 m from the foot), `ẋ = 0.8`, `ẋ' = −3.2`: the block pushed up
    /// the incline. With the default parameters (`ẍ' = 0.65`) it turns back at `x' = 1.2` near
    /// `t = 4.9` s and is at `x' = 9.6` at 10 s, on the incline throughout.
    fn default_state(&self) -> State {
        State::new(0.0, [0.0, 9.0], [0.8, -3.2])
    }

    constant_force_scene!();

    /// The wedge on a prismatic joint along x; the block on a prismatic joint of the wedge along
    /// the slope `(cos α, −sin α)` from the top corner `(0, L sin α)`.
    fn joint_graph(&self) -> Option<JointGraph> {
        let (sin, cos) = self.angle.sin_cos();
        Some(
            crate::scene::graph_of(Self::ID, self)
                .with_joint(GraphJoint::prismatic("x", GROUND, [0.0, 0.0], "wedge", [0.0, 0.0], [1.0, 0.0]))
                .with_joint(GraphJoint::prismatic(
                    "x'",
                    "wedge",
                    [0.0, self.incline_length * sin],
                    "block",
                    [0.0, 0.0],
                    [cos, -sin],
                )),
        )
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
    fn engine_matches_closed_form() {
        assert_engine_matches_closed_form_along::<Wedge, 2>(
            &PLANAR_ROWS,
            &[("α", 1.2), ("M", 0.2), ("m", 5.0), ("α", 0.05)],
        );
    }

    #[test]
    fn exact_solution_is_consistent() {
        let params = scene_of::<Wedge>().default_params();
        for initial in [State::new(0.0, [0.0, 0.0], [0.0, 0.0]), State::new(1.0, [0.3, 0.5], [-0.1, 0.4])] {
            assert_exact_solution_consistent(scene_of::<Wedge>(), &params, &initial, &[0.5, 2.0]);
        }
    }

    /// The engine's reaction force on the block is the normal force `N (sinα, cosα)`; the
    /// engine's `p_x` is the closed-form horizontal momentum.
    #[test]
    fn normal_force_and_momentum_match_the_engine() {
        let scene = Wedge::new(3.0, 1.0, 0.4, 2.0, 9.81).unwrap();
        let mut system = Buffered::new(Model::new(scene.clone()).unwrap());
        let (q, qdot) = ([0.2, 0.7], [-0.3, 0.9]);
        let reactions = system.reaction_forces(0.0, &q, &qdot).unwrap().unwrap().to_vec();
        let normal = scene.normal_force();
        let (sin, cos) = scene.angle.sin_cos();
        let tolerance = ENGINE_VS_CLOSED_FORM * normal;
        assert_close("reaction on the block", &[normal * sin, normal * cos], &reactions[3..5], tolerance);
        let momenta = system.momenta(0.0, &q, &qdot).unwrap();
        let horizontal_momentum = scene.conserves_energy()[1].value(0.0, &q, &qdot).unwrap();
        assert_close("p_x", &[horizontal_momentum], &momenta[..1], 1e-14);
    }

    #[test]
    fn limits_of_the_lecture_result() {
        // M → ∞: ẍ' = g sinα; M → 0: ẍ' = g / sinα, ẍ = −g cotα.
        let heavy = Wedge::new(1e15, 1.0, 0.5, 2.0, 9.81).unwrap();
        assert_close("M → ∞", &[0.0, 9.81 * 0.5_f64.sin()], &heavy.acceleration(), 1e-12);
        let light = Wedge::new(1e-15, 1.0, 0.5, 2.0, 9.81).unwrap();
        let expected = [-9.81 / 0.5_f64.tan(), 9.81 / 0.5_f64.sin()];
        assert_close("M → 0", &expected, &light.acceleration(), 1e-12);
    }
}
