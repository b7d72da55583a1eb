//! Pendulum on a movable support: a cart on a frictionless rail with a pendulum hanging from it
//! (docs/scenes.md#cart_pendulum; the lecture (docs/scenes.md#the-lecture), the first example).

use crate::checks::fixed;
use crate::params::{GRAVITY, param_table, scene_params};
use crate::scene::body_scene;
use crate::{Conserved, Domain, Invariant, SceneType};
use lagrange::graph::{GROUND, GraphJoint, JointGraph};
use lagrange::tree::{Joint, Parent, Tree};
use lagrange::{Body, Coordinate, Description, Error, Mechanism, Pose, Scalar, State};

scene_params! {
    /// A cart of mass `M` at `(X, 0)` on a horizontal rail, and a bob of mass `m` on a massless rod
    /// of length `r` at `(X + r sinθ, −r cosθ)`; `q = (X, θ)`, `θ` from the downward vertical,
    /// counter-clockwise (docs/scenes.md#cart_pendulum). The bob may have a moment of inertia `I_b` about its
    /// centre (a compound bob fixed to the rod, turning with it: its angle is `θ`); the lecture's
    /// point bob is `I_b = 0`. Rigid-body engines whose revolute joints cannot hold a point bob
    /// are compared against this model with `I_b > 0`.
    ///
    /// It describes itself as a kinematic [`Tree`] ([`Mechanism::tree`]): the cart on a prismatic
    /// joint along x from the ground, the bob on a revolute joint at the cart's centre with the
    /// absolute angle `θ` ([`AngleReference::World`](lagrange::tree::AngleReference); the cart never
    /// turns, so it is also the angle relative to the cart), `(0, r)` in the bob's frame; so
    /// [`Model::new`](lagrange::Model::new) computes `q̈` with the articulated-body algorithm.
    pub struct CartPendulum {
        /// Cart mass `M` (kg).
        pub cart_mass: f64 = ["M", "kg", 2.0, Domain::Positive, "mass of the cart"],
        /// Bob mass `m` (kg).
        pub bob_mass: f64 = ["m", "kg", 1.0, Domain::Positive, "mass of the pendulum bob"],
        /// Rod length `r` (m).
        pub rod_length: f64 = ["r", "m", 1.0, Domain::Positive, "length of the massless rod"],
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
        /// Moment of inertia of the bob about its centre `I_b` (kg m²); 0 for a point bob.
        pub bob_inertia: f64 = [
            "I_b",
            "kg m²",
            0.0,
            Domain::NonNegative,
            "moment of inertia of the bob about its centre (0: point bob; > 0: a compound bob fixed to the rod)"
        ],
    }
    /// As [`new`](Self::new), with a compound bob of inertia `I_b` about its centre.
    pub fn with_bob_inertia;
    derived {
        description: Description = Description {
            coordinates: vec![Coordinate::length("X"), Coordinate::angle("θ")],
            bodies: vec![Body::point("cart", cart_mass), Body::rigid("bob", bob_mass, bob_inertia)],
            gravity,
            ..Description::default()
        },
        // The cart slides along the rail; the bob hangs a rod length below the cart's centre.
        tree: Tree = {
            let joints = vec![
                Joint::prismatic("X", Parent::Ground, [0.0, 0.0], [1.0, 0.0], [0.0, 0.0]),
                Joint::absolute_revolute("θ", Parent::Body(0), [0.0, 0.0], [0.0, rod_length]),
            ];
            Tree::new(joints, description.bodies.clone(), gravity)?
        },
    }
}

impl CartPendulum {
    /// A cart pendulum with cart mass `M`, a point bob of mass `m`, rod length `r` and gravity `g`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first parameter outside its domain ([`PARAMS`]):
    /// masses and the rod length must be positive and finite, `g` non-negative.
    pub fn new(cart_mass: f64, bob_mass: f64, rod_length: f64, gravity: f64) -> Result<Self, Error> {
        Self::with_bob_inertia(cart_mass, bob_mass, rod_length, gravity, 0.0)
    }

    /// `(Ẍ, θ̈)` in closed form (docs/scenes.md#cart_pendulum, "Closed form (exact, any amplitude)"):
    /// `Ẍ = m sinθ (r θ̇² + g cosθ) / (M + m sin²θ)`,
    /// `θ̈ = −((M + m) g sinθ + m r θ̇² sinθ cosθ) / (r (M + m sin²θ))`.
    /// With a compound bob (`I_b > 0`) Lagrange's equations become
    /// `(M + m) Ẍ + m r cosθ θ̈ = m r θ̇² sinθ` and `m r cosθ Ẍ + (m r² + I_b) θ̈ = −m g r sinθ`,
    /// solved by Cramer's rule with determinant `(M + m)(m r² + I_b) − m² r² cos²θ`; at
    /// `I_b = 0` this is the lecture's form (used verbatim there).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn closed_form_accelerations(&self, q: &[f64], qdot: &[f64]) -> [f64; 2] {
        let [_, theta] = fixed(q, "q");
        let [_, theta_dot] = fixed(qdot, "q̇");
        let (cart, bob, r, g, inertia) =
            (self.cart_mass, self.bob_mass, self.rod_length, self.gravity, self.bob_inertia);
        let (sin, cos) = theta.sin_cos();
        if inertia == 0.0 {
            let denominator = cart + bob * sin * sin;
            let cart_acceleration = bob * sin * (r * theta_dot * theta_dot + g * cos) / denominator;
            let angular_acceleration =
                -((cart + bob) * g * sin + bob * r * theta_dot * theta_dot * sin * cos) / (r * denominator);
            return [cart_acceleration, angular_acceleration];
        }
        let (a11, a12, a22) = (cart + bob, bob * r * cos, bob * r * r + inertia);
        let (f1, f2) = (bob * r * theta_dot * theta_dot * sin, -bob * g * r * sin);
        let determinant = a11 * a22 - a12 * a12;
        [(f1 * a22 - a12 * f2) / determinant, (a11 * f2 - a12 * f1) / determinant]
    }

    /// The conserved horizontal momentum `p_X = (M + m) Ẋ + m r θ̇ cosθ` (docs/scenes.md#cart_pendulum; unchanged by `I_b`;
    /// "Conserved quantities": `X` is cyclic).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn horizontal_momentum(&self, q: &[f64], qdot: &[f64]) -> f64 {
        let [_, theta] = fixed(q, "q");
        let [cart_velocity, theta_dot] = fixed(qdot, "q̇");
        (self.cart_mass + self.bob_mass) * cart_velocity + self.bob_mass * self.rod_length * theta_dot * theta.cos()
    }

    /// The non-zero normal-mode frequency about `θ = 0`, `ω = √(g (M + m) / (M r))` (docs/scenes.md#cart_pendulum,
    /// "Small oscillations"; the other mode, free translation, has `ω = 0`). With a compound bob,
    /// `det(K − ω² M₀) = 0` with `M₀ = [[M + m, m r], [m r, m r² + I_b]]`, `K = diag(0, m g r)`
    /// gives `ω² = m g r (M + m) / ((M + m)(m r² + I_b) − m² r²)`, which is the same at `I_b = 0`.
    pub fn small_oscillation_frequency(&self) -> f64 {
        let (cart, bob, r, g, inertia) =
            (self.cart_mass, self.bob_mass, self.rod_length, self.gravity, self.bob_inertia);
        if inertia == 0.0 {
            return (g * (cart + bob) / (cart * r)).sqrt();
        }
        (bob * g * r * (cart + bob) / ((cart + bob) * (bob * r * r + inertia) - bob * bob * r * r)).sqrt()
    }

    /// The rod tension `T = m (g cosθ + r θ̇² − Ẍ sinθ)` (N), with `Ẍ` from the closed form (for
    /// the compound bob, `I_b > 0`, this is the force along the rod; the pin also carries a
    /// transverse force `I_b θ̈ / r`): the
    /// rod pulls the bob towards the pivot, along `(−sinθ, cosθ)`, with this magnitude
    /// (Newton's law for the bob projected on the rod, from docs/scenes.md#cart_pendulum's bob acceleration).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn rod_tension(&self, q: &[f64], qdot: &[f64]) -> f64 {
        let [cart_acceleration, _] = self.closed_form_accelerations(q, qdot);
        let [_, theta] = fixed(q, "q");
        let [_, theta_dot] = fixed(qdot, "q̇");
        let (sin, cos) = theta.sin_cos();
        self.bob_mass * (self.gravity * cos + self.rod_length * theta_dot * theta_dot - cart_acceleration * sin)
    }
}

impl Mechanism for CartPendulum {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (cart_x, theta) = (q[0], q[1]);
        // Cart on the rail; bob at the end of the rod.
        world_from_body[0] = Pose::point(cart_x, S::zero());
        let (sin, cos) = theta.sin_cos();
        // A compound bob turns with the rod (its angle is irrelevant for a point bob).
        world_from_body[1] = Pose::new(cart_x + sin * self.rod_length, -cos * self.rod_length, theta);
    }

    fn tree(&self) -> Option<&Tree> {
        Some(&self.tree)
    }
}

impl SceneType for CartPendulum {
    const ID: &'static str = "cart_pendulum";
    const TITLE: &'static str = "Pendulum on a movable support (cart)";
    const REFERENCE: &'static str = "docs/scenes.md#cart_pendulum; the lecture (docs/scenes.md#the-lecture), example: pendulum attached to a movable support";
    param_table!();

    /// `X = 0`, `θ = 0.5`, at rest.
    fn default_state(&self) -> State {
        State::new(0.0, [0.0, 0.5], [0.0, 0.0])
    }

    /// `E = ½ (M + m) Ẋ² + m r Ẋ θ̇ cosθ + ½ (m r² + I_b) θ̇² − m g r cosθ` and
    /// [`p_X`](CartPendulum::horizontal_momentum) (docs/scenes.md#cart_pendulum).
    fn conserves_energy(&self) -> Vec<Conserved> {
        let energy = Conserved::energy(self, |s, q, qdot| {
            let ([_, theta], [v, w]) = (fixed(q, "q"), fixed(qdot, "q̇"));
            let (cart, bob, r, cos) = (s.cart_mass, s.bob_mass, s.rod_length, theta.cos());
            let rotation = bob * r * r + s.bob_inertia;
            0.5 * (cart + bob) * v * v + bob * r * v * w * cos + 0.5 * rotation * w * w - bob * s.gravity * r * cos
        });
        let momentum = |s: &Self, _, q: &[f64], qdot: &[f64]| s.horizontal_momentum(q, qdot);
        vec![energy, Conserved::new(self, "p_X", "X is cyclic", Invariant::CyclicMomentum(0), momentum)]
    }

    body_scene!();

    /// The cart on a prismatic joint along x, the bob on a revolute joint at the cart's centre,
    /// its angle `θ` absolute (from the downward vertical: the rod's end `(0, r)` in the bob's
    /// frame).
    fn joint_graph(&self) -> Option<JointGraph> {
        Some(
            crate::scene::graph_of(Self::ID, self)
                .with_joint(GraphJoint::prismatic("X", GROUND, [0.0, 0.0], "cart", [0.0, 0.0], [1.0, 0.0]))
                .with_joint(GraphJoint::revolute("θ", "cart", [0.0, 0.0], "bob", [0.0, self.rod_length]).absolute()),
        )
    }

    /// The bob is a point: an impulse revolute joint freezes it, so rapier's impulse build
    /// gives it a compound bob's inertia.
    fn rapier_deviations(multibody: bool) -> &'static [crate::RapierDeviation] {
        if multibody { &[] } else { &[("bob_inertia", "bob_mass", "rod_length")] }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_of;
    use crate::testing::{ENGINE_VS_CLOSED_FORM, assert_close, assert_engine_matches_closed_form};
    use lagrange::{Buffered, Model, System};

    fn states() -> Vec<State> {
        vec![
            State::new(0.0, [0.0, 0.5], [0.0, 0.0]),
            State::new(0.3, [1.2, -0.7], [0.4, 1.3]),
            State::new(1.0, [-2.0, 2.5], [-1.0, -2.2]),
            State::new(2.0, [0.5, 1.4], [0.3, 0.1]),
            State::new(5.0, [3.0, -2.9], [2.0, 4.0]),
        ]
    }

    #[test]
    fn engine_matches_closed_form() {
        let mut params = scene_of::<CartPendulum>().default_params();
        assert_engine_matches_closed_form(scene_of::<CartPendulum>(), &params, &states());
        params.set("M", 0.3).unwrap();
        params.set("r", 1.7).unwrap();
        params.set("g", 3.0).unwrap();
        assert_engine_matches_closed_form(scene_of::<CartPendulum>(), &params, &states());
    }

    /// The engine's reaction force on the bob is the rod tension along `(−sinθ, cosθ)`, and the
    /// engine's `p_X` is the closed-form horizontal momentum.
    #[test]
    fn rod_tension_and_momentum_match_the_engine() {
        let scene = CartPendulum::new(2.0, 1.0, 1.3, 9.81).unwrap();
        let mut system = scene_of::<CartPendulum>().build(&scene_of::<CartPendulum>().default_params()).unwrap();
        let mut system_r = Buffered::new(Model::new(scene.clone()).unwrap());
        for state in states() {
            let tension = scene.rod_tension(&state.q, &state.qdot);
            let reactions = system_r.reaction_forces(state.t, &state.q, &state.qdot).unwrap().unwrap().to_vec();
            let (sin, cos) = state.q[1].sin_cos();
            let tolerance = ENGINE_VS_CLOSED_FORM * tension.abs().max(scene.bob_mass * scene.gravity);
            assert_close("reaction on the bob", &[-tension * sin, tension * cos], &reactions[3..5], tolerance);
            let momenta = system_r.momenta(state.t, &state.q, &state.qdot).unwrap();
            let expected = scene.horizontal_momentum(&state.q, &state.qdot);
            assert_close("p_X", &[expected], &momenta[..1], ENGINE_VS_CLOSED_FORM * expected.abs().max(1.0));
        }
        assert_eq!(system.cyclic_coordinates(), &[true, false], "X is cyclic");
        assert!(system.accelerations(0.0, &[0.0, 0.5], &[0.0, 0.0]).is_ok());
    }

    /// `det(K₀ − ω² M₀) = 0` at the closed-form frequency (docs/scenes.md#cart_pendulum's `M₀`, `K₀`).
    #[test]
    fn small_oscillation_frequency_solves_the_characteristic_equation() {
        let scene = CartPendulum::new(2.0, 0.7, 1.3, 9.81).unwrap();
        let omega2 = scene.small_oscillation_frequency().powi(2);
        let (cart, bob, r, g) = (scene.cart_mass, scene.bob_mass, scene.rod_length, scene.gravity);
        let m0 = [[cart + bob, bob * r], [bob * r, bob * r * r]];
        let k0 = [[0.0, 0.0], [0.0, bob * g * r]];
        let a = |i: usize, j: usize| k0[i][j] - omega2 * m0[i][j];
        let determinant = a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0);
        let scale = (omega2 * m0[0][0]) * (bob * g * r);
        assert!(determinant.abs() <= 1e-14 * scale, "det = {determinant:e}, scale {scale:e}");
        // M → ∞ gives the simple pendulum.
        let heavy = CartPendulum::new(1e12, 1.0, 2.0, 9.81).unwrap();
        assert!((heavy.small_oscillation_frequency() - (9.81_f64 / 2.0).sqrt()).abs() < 1e-9);
    }

    #[test]
    fn zero_length_rod_and_bad_masses_are_rejected_with_the_parameter_named() {
        let cases = [
            (CartPendulum::new(2.0, 1.0, 0.0, 9.81), "rod_length"),
            (CartPendulum::new(f64::NAN, 1.0, 1.0, 9.81), "cart_mass"),
            (CartPendulum::new(2.0, -1.0, 1.0, 9.81), "bob_mass"),
            (CartPendulum::new(0.0, 1.0, 1.0, 9.81), "cart_mass"),
            (CartPendulum::new(2.0, 1.0, 1.0, -1.0), "gravity"),
        ];
        for (result, expected) in cases {
            assert!(
                matches!(result, Err(Error::InvalidParameter { ref name, .. }) if name == expected),
                "expected {expected} rejected, got {result:?}"
            );
        }
    }
}
