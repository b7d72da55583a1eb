//! Double pendulum: two point masses on massless rods (beyond the lecture).

use crate::checks::fixed;
use crate::params::{GRAVITY, param_table, scene_params};
use crate::scene::body_scene;
use crate::{Conserved, Domain, SceneType};
use lagrange::graph::{GROUND, GraphJoint, JointGraph};
use lagrange::tree::{Joint, Parent, Tree};
use lagrange::{Body, Coordinate, Description, Error, Mechanism, Pose, Scalar, State};

scene_params! {
    /// Bob 1 (mass `m1`) at `(l1 sinθ₁, −l1 cosθ₁)` on a massless rod from the origin, bob 2 (mass
    /// `m2`) at bob 1 + `(l2 sinθ₂, −l2 cosθ₂)`; `q = (θ₁, θ₂)`, absolute angles from the downward
    /// vertical, counter-clockwise. Each bob may have a moment of inertia about its centre (a
    /// compound bob fixed to its rod, turning with it); the point bobs of the usual double pendulum
    /// have `I1 = I2 = 0`. Rigid-body engines whose revolute joints cannot hold point bobs are
    /// compared against this model with inertias.
    ///
    /// `T = ½ (m1 + m2) l1² θ̇₁² + ½ m2 l2² θ̇₂² + m2 l1 l2 θ̇₁ θ̇₂ cos(θ₁ − θ₂)`,
    /// `V = −(m1 + m2) g l1 cosθ₁ − m2 g l2 cosθ₂` (derived here from the Cartesian maps, as the
    /// lecture does; the system is treated in Taylor, *Classical Mechanics*, §11.4).
    ///
    /// It describes itself as a kinematic [`Tree`] ([`Mechanism::tree`]): bob 1 hangs from the
    /// origin, bob 2 from bob 1's centre, each by a revolute joint with the absolute angle `θ_i`
    /// ([`AngleReference::World`](lagrange::tree::AngleReference)) at `(0, l_i)` in the bob's frame;
    /// so [`Model::new`](lagrange::Model::new) computes `q̈` with the articulated-body algorithm.
    pub struct DoublePendulum {
        /// Upper bob mass `m₁` (kg).
        pub mass_1: f64 = ["m1", "kg", 1.0, Domain::Positive, "mass of the upper bob"],
        /// Lower bob mass `m₂` (kg).
        pub mass_2: f64 = ["m2", "kg", 1.0, Domain::Positive, "mass of the lower bob"],
        /// Upper rod length `l₁` (m).
        pub length_1: f64 = ["l1", "m", 1.0, Domain::Positive, "length of the upper rod"],
        /// Lower rod length `l₂` (m).
        pub length_2: f64 = ["l2", "m", 1.0, Domain::Positive, "length of the lower rod"],
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
        /// Moment of inertia of bob 1 about its centre `I1` (kg m²); 0 for a point bob.
        pub inertia_1: f64 = [
            "I1",
            "kg m²",
            0.0,
            Domain::NonNegative,
            "moment of inertia of bob 1 about its centre (0: point bob)"
        ],
        /// Moment of inertia of bob 2 about its centre `I2` (kg m²); 0 for a point bob.
        pub inertia_2: f64 = [
            "I2",
            "kg m²",
            0.0,
            Domain::NonNegative,
            "moment of inertia of bob 2 about its centre (0: point bob)"
        ],
    }
    /// As [`new`](Self::new), with compound bobs of inertias `I1`, `I2` about their centres.
    pub fn with_inertia;
    derived {
        description: Description = Description {
            coordinates: vec![Coordinate::angle("θ1"), Coordinate::angle("θ2")],
            bodies: vec![Body::rigid("bob 1", mass_1, inertia_1), Body::rigid("bob 2", mass_2, inertia_2)],
            gravity,
            ..Description::default()
        },
        // Each bob a rod length below its pivot: the origin, then bob 1's centre.
        tree: Tree = {
            let joints = vec![
                Joint::absolute_revolute("θ1", Parent::Ground, [0.0, 0.0], [0.0, length_1]),
                Joint::absolute_revolute("θ2", Parent::Body(0), [0.0, 0.0], [0.0, length_2]),
            ];
            Tree::new(joints, description.bodies.clone(), gravity)?
        },
    }
}

impl DoublePendulum {
    /// A double pendulum with point bobs: masses `m1`, `m2`, rod lengths `l1`, `l2` and gravity `g`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first parameter outside its domain ([`PARAMS`]).
    pub fn new(mass_1: f64, mass_2: f64, length_1: f64, length_2: f64, gravity: f64) -> Result<Self, Error> {
        Self::with_inertia(mass_1, mass_2, length_1, length_2, gravity, 0.0, 0.0)
    }

    /// `(θ̈₁, θ̈₂)` in closed form. Lagrange's equations (divided by `l1` and `m2 l2`), with
    /// `Δ = θ₁ − θ₂`, `s = sinΔ`, `c = cosΔ`:
    /// `(m1 + m2) l1 θ̈₁ + m2 l2 c θ̈₂ = −m2 l2 θ̇₂² s − (m1 + m2) g sinθ₁`,
    /// `l1 c θ̈₁ + l2 θ̈₂ = l1 θ̇₁² s − g sinθ₂`;
    /// solved by Cramer's rule (determinant `l1 l2 (m1 + m2 s²)`):
    /// `θ̈₁ = (−m2 s (l2 θ̇₂² + l1 θ̇₁² c) − (m1 + m2) g sinθ₁ + m2 g c sinθ₂) / (l1 (m1 + m2 s²))`,
    /// `θ̈₂ = ((m1 + m2)(l1 θ̇₁² s − g sinθ₂ + g c sinθ₁) + m2 l2 θ̇₂² s c) / (l2 (m1 + m2 s²))`.
    /// The same as the usual textbook form with denominator `2 m1 + m2 − m2 cos 2Δ`
    /// (e.g. myPhysicsLab's double pendulum), since `2 m1 + m2 − m2 cos 2Δ = 2 (m1 + m2 s²)`.
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    ///
    /// With compound bobs (`I1`, `I2` > 0) the equations are
    /// `((m1 + m2) l1² + I1) θ̈₁ + m2 l1 l2 c θ̈₂ = −m2 l1 l2 s θ̇₂² − (m1 + m2) g l1 sinθ₁`,
    /// `m2 l1 l2 c θ̈₁ + (m2 l2² + I2) θ̈₂ = m2 l1 l2 s θ̇₁² − m2 g l2 sinθ₂`, solved by Cramer's rule.
    pub fn closed_form_accelerations(&self, q: &[f64], qdot: &[f64]) -> [f64; 2] {
        let [theta_1, theta_2] = fixed(q, "q");
        let [omega_1, omega_2] = fixed(qdot, "q̇");
        let (m1, m2, l1, l2, g) = (self.mass_1, self.mass_2, self.length_1, self.length_2, self.gravity);
        if (self.inertia_1, self.inertia_2) != (0.0, 0.0) {
            let (s, c) = (theta_1 - theta_2).sin_cos();
            let a11 = (m1 + m2) * l1 * l1 + self.inertia_1;
            let (a12, a22) = (m2 * l1 * l2 * c, m2 * l2 * l2 + self.inertia_2);
            let f1 = -m2 * l1 * l2 * s * omega_2 * omega_2 - (m1 + m2) * g * l1 * theta_1.sin();
            let f2 = m2 * l1 * l2 * s * omega_1 * omega_1 - m2 * g * l2 * theta_2.sin();
            let determinant = a11 * a22 - a12 * a12;
            return [(f1 * a22 - a12 * f2) / determinant, (a11 * f2 - a12 * f1) / determinant];
        }
        let (s, c) = (theta_1 - theta_2).sin_cos();
        let (sin_1, sin_2) = (theta_1.sin(), theta_2.sin());
        let (w1_sq, w2_sq) = (omega_1 * omega_1, omega_2 * omega_2);
        let reduced = m1 + m2 * s * s;
        let alpha_1 =
            (-m2 * s * (l2 * w2_sq + l1 * w1_sq * c) - (m1 + m2) * g * sin_1 + m2 * g * c * sin_2) / (l1 * reduced);
        let alpha_2 =
            ((m1 + m2) * (l1 * w1_sq * s - g * sin_2 + g * c * sin_1) + m2 * l2 * w2_sq * s * c) / (l2 * reduced);
        [alpha_1, alpha_2]
    }

    /// The two normal-mode angular frequencies `(ω_slow, ω_fast)` about the hanging equilibrium.
    ///
    /// `det(K − ω² M) = 0` with `M = [[(m1 + m2) l1², m2 l1 l2], [m2 l1 l2, m2 l2²]]`,
    /// `K = diag((m1 + m2) g l1, m2 g l2)` gives
    /// `m1 l1 l2 ω⁴ − (m1 + m2) g (l1 + l2) ω² + (m1 + m2) g² = 0`, i.e.
    /// `ω² = g / (2 m1 l1 l2) [(m1 + m2)(l1 + l2) ∓ √((m1 + m2)² (l1 + l2)² − 4 m1 (m1 + m2) l1 l2)]`
    /// (derived here; Taylor §11.4 gives the equal-mass, equal-length case `ω² = (2 ∓ √2) g/l`).
    /// The slow root is computed as `(m1 + m2) g² / (m1 l1 l2 ω_fast²)` to avoid cancellation.
    ///
    /// With compound bobs: `det(K − ω² M) = 0` with `M = [[(m1 + m2) l1² + I1, m2 l1 l2],
    /// [m2 l1 l2, m2 l2² + I2]]`, i.e. `det M ω⁴ − (K₁₁ M₂₂ + K₂₂ M₁₁) ω² + K₁₁ K₂₂ = 0`.
    pub fn small_oscillation_frequencies(&self) -> (f64, f64) {
        let (m1, m2, l1, l2, g) = (self.mass_1, self.mass_2, self.length_1, self.length_2, self.gravity);
        if (self.inertia_1, self.inertia_2) != (0.0, 0.0) {
            let (a11, a12, a22) = ((m1 + m2) * l1 * l1 + self.inertia_1, m2 * l1 * l2, m2 * l2 * l2 + self.inertia_2);
            let (k1, k2) = ((m1 + m2) * g * l1, m2 * g * l2);
            let (a, b, c) = (a11 * a22 - a12 * a12, k1 * a22 + k2 * a11, k1 * k2);
            let fast_sq = (b + (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
            if fast_sq == 0.0 {
                return (0.0, 0.0);
            }
            return ((c / (a * fast_sq)).sqrt(), fast_sq.sqrt());
        }
        let (total, lengths) = (m1 + m2, l1 + l2);
        let root = (total * total * lengths * lengths - 4.0 * m1 * total * l1 * l2).sqrt();
        let fast_sq = g / (2.0 * m1 * l1 * l2) * (total * lengths + root);
        if fast_sq == 0.0 {
            return (0.0, 0.0);
        }
        let slow_sq = total * g * g / (m1 * l1 * l2 * fast_sq);
        (slow_sq.sqrt(), fast_sq.sqrt())
    }
}

impl Mechanism for DoublePendulum {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (theta_1, theta_2) = (q[0], q[1]);
        // Bob 1 at the end of rod 1; bob 2 at the end of rod 2, hung from bob 1.
        let ((sin_1, cos_1), (sin_2, cos_2)) = (theta_1.sin_cos(), theta_2.sin_cos());
        let (x1, y1) = (sin_1 * self.length_1, -cos_1 * self.length_1);
        // Compound bobs turn with their rods (the angles are irrelevant for point bobs).
        world_from_body[0] = Pose::new(x1, y1, theta_1);
        world_from_body[1] = Pose::new(x1 + sin_2 * self.length_2, y1 - cos_2 * self.length_2, theta_2);
    }

    fn tree(&self) -> Option<&Tree> {
        Some(&self.tree)
    }
}

impl SceneType for DoublePendulum {
    const ID: &'static str = "double_pendulum";
    const TITLE: &'static str = "Double pendulum";
    const REFERENCE: &'static str =
        "beyond the lecture; closed forms derived in double_pendulum.rs (cf. Taylor, Classical Mechanics, §11.4)";
    param_table!();

    /// `θ₁ = θ₂ = 0.5`, at rest.
    fn default_state(&self) -> State {
        State::new(0.0, [0.5, 0.5], [0.0, 0.0])
    }

    /// The energy `T + V` (`T`, `V` above, with the bobs' rotation `½ I_i θ̇_i²`).
    fn conserves_energy(&self) -> Vec<Conserved> {
        vec![Conserved::energy(self, |s, q, qdot| {
            let ([theta_1, theta_2], [w1, w2]) = (fixed(q, "q"), fixed(qdot, "q̇"));
            let (m1, m2, l1, l2, g) = (s.mass_1, s.mass_2, s.length_1, s.length_2, s.gravity);
            let rotations = ((m1 + m2) * l1 * l1 + s.inertia_1) * w1 * w1 + (m2 * l2 * l2 + s.inertia_2) * w2 * w2;
            let kinetic = 0.5 * rotations + m2 * l1 * l2 * w1 * w2 * (theta_1 - theta_2).cos();
            kinetic - (m1 + m2) * g * l1 * theta_1.cos() - m2 * g * l2 * theta_2.cos()
        })]
    }

    body_scene!();

    /// Revolute joints at the origin and at bob 1's centre, absolute angles from the downward
    /// vertical (each rod's end `(0, l_i)` in its bob's frame).
    fn joint_graph(&self) -> Option<JointGraph> {
        Some(
            crate::scene::graph_of(Self::ID, self)
                .with_joint(GraphJoint::revolute("θ1", GROUND, [0.0, 0.0], "bob 1", [0.0, self.length_1]).absolute())
                .with_joint(GraphJoint::revolute("θ2", "bob 1", [0.0, 0.0], "bob 2", [0.0, self.length_2]).absolute()),
        )
    }

    /// The bob is a point: an impulse revolute joint freezes it, so rapier's impulse build
    /// gives it a compound bob's inertia.
    fn rapier_deviations(multibody: bool) -> &'static [crate::RapierDeviation] {
        if multibody { &[] } else { &[("inertia_1", "mass_1", "length_1"), ("inertia_2", "mass_2", "length_2")] }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::assert_engine_matches_closed_form_along;

    #[test]
    fn engine_matches_closed_form() {
        assert_engine_matches_closed_form_along::<DoublePendulum, 2>(
            &[
                (0.5, [-0.4, 1.3], [1.2, -0.5]),
                (1.0, [2.0, -2.9], [-3.0, 2.0]),
                (3.0, [3.0, 0.1], [0.7, 4.1]),
                (7.0, [-1.5, 2.5], [-0.2, -1.1]),
            ],
            &[("m1", 0.3), ("l2", 1.7), ("m2", 2.5), ("l1", 0.6)],
        );
    }

    /// Both frequencies solve `det(K − ω² M) = 0`, and equal masses and lengths give the
    /// textbook `ω² = (2 ∓ √2) g/l`.
    #[test]
    fn small_oscillation_frequencies_solve_the_characteristic_equation() {
        for (m1, m2, l1, l2) in [(1.0, 1.0, 1.0, 1.0), (0.3, 2.5, 0.6, 1.7), (10.0, 0.01, 1.0, 2.0)] {
            let scene = DoublePendulum::new(m1, m2, l1, l2, 9.81).unwrap();
            let (slow, fast) = scene.small_oscillation_frequencies();
            assert!(0.0 < slow && slow < fast, "{slow}, {fast}");
            let g = scene.gravity;
            let mass = [[(m1 + m2) * l1 * l1, m2 * l1 * l2], [m2 * l1 * l2, m2 * l2 * l2]];
            let stiffness = [[(m1 + m2) * g * l1, 0.0], [0.0, m2 * g * l2]];
            for omega in [slow, fast] {
                let a = |i: usize, j: usize| stiffness[i][j] - omega * omega * mass[i][j];
                let determinant = a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0);
                let scale = stiffness[0][0] * stiffness[1][1] + (omega * omega).powi(2) * mass[0][0] * mass[1][1];
                assert!(determinant.abs() <= 1e-13 * scale, "ω = {omega}: det = {determinant:e}, scale {scale:e}");
            }
        }
        let (slow, fast) = DoublePendulum::new(1.0, 1.0, 1.0, 1.0, 9.81).unwrap().small_oscillation_frequencies();
        let expected = [((2.0 - 2.0_f64.sqrt()) * 9.81).sqrt(), ((2.0 + 2.0_f64.sqrt()) * 9.81).sqrt()];
        crate::testing::assert_close("ω for equal masses and lengths", &expected, &[slow, fast], 1e-14);
    }
}
