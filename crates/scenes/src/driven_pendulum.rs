//! Pendulum whose support is driven horizontally: a rheonomic constraint (beyond the lecture).

use crate::checks::fixed;
use crate::params::{GRAVITY, param_table, scene_params};
use crate::scene::body_scene;
use crate::{Conserved, Domain, SceneType};
use lagrange::{Body, Coordinate, Description, Mechanism, Pose, Scalar, State};

scene_params! {
    /// A bob of mass `m` on a massless rod of length `l` whose support moves as `(A sin ωt, 0)`:
    /// bob at `(A sin ωt + l sinθ, −l cosθ)`; `q = (θ)`, from the downward vertical,
    /// counter-clockwise. The pose depends on time (rheonomic), so energy is not conserved.
    pub struct DrivenPendulum {
        /// Bob mass `m` (kg).
        pub mass: f64 = ["m", "kg", 1.0, Domain::Positive, "mass of the bob"],
        /// Rod length `l` (m).
        pub length: f64 = ["l", "m", 1.0, Domain::Positive, "length of the massless rod"],
        /// Drive amplitude `A` (m).
        pub amplitude: f64 = ["A", "m", 0.1, Domain::Finite, "amplitude of the support's horizontal motion"],
        /// Drive angular frequency `ω` (rad/s).
        pub drive_frequency: f64 = ["ω", "rad/s", 3.0, Domain::NonNegative, "angular frequency of the drive"],
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
    }
    /// A driven pendulum with mass `m`, length `l`, drive amplitude `A`, drive frequency `ω` and
    /// gravity `g`.
    pub fn new;
    derived {
        description: Description = Description {
            coordinates: vec![Coordinate::angle("θ")],
            bodies: vec![Body::point("bob", mass)],
            gravity,
            ..Description::default()
        },
    }
}

impl DrivenPendulum {
    /// `θ̈ = −(g/l) sinθ + (A ω² sin ωt / l) cosθ`: from
    /// `L = ½ m (A² ω² cos² ωt + 2 A ω cos ωt l θ̇ cosθ + l² θ̇²) + m g l cosθ`, the support's
    /// acceleration `−A ω² sin ωt` acts on the bob as the inertial force `m A ω² sin ωt` along x
    /// (derived as docs/scenes.md#cart_pendulum with the cart's motion prescribed).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 1 entry.
    pub fn closed_form_accelerations(&self, t: f64, q: &[f64], qdot: &[f64]) -> [f64; 1] {
        let [theta] = fixed(q, "q");
        let _: [f64; 1] = fixed(qdot, "q̇");
        let (l, a, omega) = (self.length, self.amplitude, self.drive_frequency);
        let drive = a * omega * omega * (omega * t).sin() / l;
        [-(self.gravity / l) * theta.sin() + drive * theta.cos()]
    }
}

impl Mechanism for DrivenPendulum {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let theta = q[0];
        // Support at (A sin ωt, 0); bob at the end of the rod.
        let support = (t * self.drive_frequency).sin() * self.amplitude;
        let (sin, cos) = theta.sin_cos();
        world_from_body[0] = Pose::point(support + sin * self.length, -cos * self.length);
    }
}

impl SceneType for DrivenPendulum {
    const ID: &'static str = "driven_pendulum";
    const TITLE: &'static str = "Pendulum with a horizontally driven support";
    const REFERENCE: &'static str =
        "beyond the lecture (rheonomic constraint); closed form derived in driven_pendulum.rs";
    param_table!();

    fn closed_form(&self, t: f64, q: &[f64], qdot: &[f64], qddot: &mut [f64]) {
        qddot.copy_from_slice(&self.closed_form_accelerations(t, q, qdot));
    }

    /// `θ = 0.2`, at rest.
    fn default_state(&self) -> State {
        State::new(0.0, [0.2], [0.0])
    }

    /// Driven: none (`∂L/∂t ≠ 0`). Without a drive (`A = 0` or `ω = 0`) the energy
    /// `E = ½ m l² θ̇² − m g l cosθ`.
    fn conserves_energy(&self) -> Vec<Conserved> {
        if self.amplitude != 0.0 && self.drive_frequency != 0.0 {
            return Vec::new();
        }
        let energy = |s: &Self, q: &[f64], v: &[f64]| {
            s.mass * s.length * (0.5 * s.length * v[0] * v[0] - s.gravity * q[0].cos())
        };
        vec![Conserved::energy(self, energy)]
    }

    body_scene!(engine);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_of;
    use crate::testing::assert_engine_matches_closed_form_along;

    #[test]
    fn engine_matches_closed_form() {
        assert_engine_matches_closed_form_along::<DrivenPendulum, 1>(
            &[(0.37, [-0.4], [1.2]), (1.1, [2.0], [-3.0]), (3.9, [3.0], [0.7]), (7.3, [-1.5], [-0.2])],
            &[("A", -0.5), ("ω", 7.0), ("l", 0.3), ("ω", 0.0)],
        );
    }

    #[test]
    fn the_drive_makes_the_system_non_autonomous() {
        let system = scene_of::<DrivenPendulum>().build(&scene_of::<DrivenPendulum>().default_params()).unwrap();
        assert!(!system.conserves_energy());
        let mut still = scene_of::<DrivenPendulum>().default_params();
        still.set("A", 0.0).unwrap();
        assert!(scene_of::<DrivenPendulum>().build(&still).unwrap().conserves_energy());
    }
}
