//! Elastic (spring) pendulum: a bob on a spring swinging under gravity (beyond the lecture).

use crate::checks::fixed;
use crate::params::{GRAVITY, param_table, scene_params};
use crate::scene::body_scene;
use crate::{Conserved, Domain, SceneType};
use lagrange::{Body, Bounds, Coordinate, Description, Mechanism, Pose, Scalar, State};

scene_params! {
    /// A bob of mass `m` at `(r sinθ, −r cosθ)` on a massless spring (stiffness `k`, rest length
    /// `L0`) hung from the origin, `V_spring = ½ k (|x| − L0)²`; `q = (r, θ)`, `θ` from the downward
    /// vertical, counter-clockwise. The closed forms assume `r > 0`.
    pub struct SpringPendulum {
        /// Bob mass `m` (kg).
        pub mass: f64 = ["m", "kg", 1.0, Domain::Positive, "mass of the bob"],
        /// Spring constant `k` (N/m).
        pub stiffness: f64 = ["k", "N/m", 100.0, Domain::Positive, "spring constant"],
        /// Rest length `L₀` (m).
        pub rest_length: f64 = ["L0", "m", 1.0, Domain::Positive, "unstretched length of the spring"],
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
    }
    /// A spring pendulum with mass `m`, stiffness `k`, rest length `L0` and gravity `g`.
    pub fn new;
    derived {
        description: Description = Description {
            coordinates: vec![Coordinate::length("r"), Coordinate::angle("θ")],
            bodies: vec![Body::point("bob", mass)],
            gravity,
            ..Description::default()
        },
    }
}

impl SpringPendulum {
    /// `r̈ = r θ̇² + g cosθ − (k/m)(r − L0)`, `θ̈ = −(g sinθ + 2 ṙ θ̇)/r`, from
    /// `L = ½ m (ṙ² + r² θ̇²) + m g r cosθ − ½ k (r − L0)²` (derived as in docs/scenes.md#kepler, with
    /// the gravity term of §1).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn closed_form_accelerations(&self, q: &[f64], qdot: &[f64]) -> [f64; 2] {
        let [r, theta] = fixed(q, "q");
        let [r_dot, theta_dot] = fixed(qdot, "q̇");
        let (sin, cos) = theta.sin_cos();
        let g = self.gravity;
        let radial = r * theta_dot * theta_dot + g * cos - self.stiffness / self.mass * (r - self.rest_length);
        [radial, -(g * sin + 2.0 * r_dot * theta_dot) / r]
    }
}

impl Mechanism for SpringPendulum {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (r, theta) = (q[0], q[1]);
        let (sin, cos) = theta.sin_cos();
        world_from_body[0] = Pose::point(r * sin, -r * cos);
    }

    /// `V = ½ k (|x| − L0)²`, through the bob's position so that the spring force is applied to it.
    fn potential<S: Scalar>(&self, _t: S, _q: &[S], world_from_body: &[Pose<S>]) -> Option<S> {
        let Pose { x, y, .. } = world_from_body[0];
        let stretch = (x * x + y * y).sqrt() - self.rest_length;
        Some(stretch * stretch * (0.5 * self.stiffness))
    }

    /// `r` is the spring's length, which must stay positive (at `r = 0` `θ` moves no mass and
    /// the spring's direction is undefined).
    fn admissible(&self, _t: f64, q: &[f64], _qdot: &[f64], bounds: &mut Bounds) -> bool {
        bounds.above("spring length r", q[0], 0.0);
        true
    }
}

impl SceneType for SpringPendulum {
    const ID: &'static str = "spring_pendulum";
    const TITLE: &'static str = "Elastic (spring) pendulum";
    const REFERENCE: &'static str = "beyond the lecture; closed form derived in spring_pendulum.rs";
    param_table!();

    /// `r = 1.1`, `θ = 0.5`, at rest.
    fn default_state(&self) -> State {
        State::new(0.0, [1.1, 0.5], [0.0, 0.0])
    }

    /// The energy `E = ½ m (ṙ² + r² θ̇²) − m g r cosθ + ½ k (r − L0)²`.
    fn conserves_energy(&self) -> Vec<Conserved> {
        vec![Conserved::energy(self, |s, q, qdot| {
            let ([r, theta], [r_dot, theta_dot]) = (fixed(q, "q"), fixed(qdot, "q̇"));
            let stretch = r - s.rest_length;
            let kinetic = 0.5 * s.mass * (r_dot * r_dot + r * r * theta_dot * theta_dot);
            kinetic - s.mass * s.gravity * r * theta.cos() + 0.5 * s.stiffness * stretch * stretch
        })]
    }

    body_scene!();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::assert_engine_matches_closed_form_along;

    #[test]
    fn engine_matches_closed_form() {
        assert_engine_matches_closed_form_along::<SpringPendulum, 2>(
            &[
                (0.5, [0.7, -1.3], [0.4, -2.0]),
                (1.0, [2.3, 3.0], [-0.6, 0.3]),
                (2.0, [0.4, 7.0], [1.5, 4.0]),
                (4.0, [1.0, 0.2], [0.1, 0.05]),
            ],
            &[("k", 3.0), ("L0", 0.6), ("m", 0.2), ("g", 0.0)],
        );
    }

    /// Hanging at rest at the stretched length `L0 + m g/k` is an equilibrium.
    #[test]
    fn static_stretch_is_an_equilibrium() {
        let scene = SpringPendulum::new(2.0, 50.0, 1.0, 9.81).unwrap();
        let stretched = 1.0 + 2.0 * 9.81 / 50.0;
        let [radial, angular] = scene.closed_form_accelerations(&[stretched, 0.0], &[0.0, 0.0]);
        assert!(radial.abs() < 1e-14 && angular == 0.0, "{radial}, {angular}");
    }
}
