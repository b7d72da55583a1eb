//! A pendulum written in the bob's Cartesian coordinates with one holonomic constraint
//! (docs/scenes.md#nonminimal_pendulum).

use crate::checks::fixed;
use crate::params::{GRAVITY, param_table, scene_params};
use crate::scene::body_scene;
use crate::{Conserved, Domain, SceneType};
use lagrange::{Body, Coordinate, Description, Mechanism, Pose, Scalar, State};

scene_params! {
    /// A bob of mass `m` at `(x, y)`, the coordinates themselves, held on the circle of radius
    /// `l` about the origin by the holonomic constraint `Φ = x² + y² − l² = 0` (a massless rod
    /// written as a constraint instead of being eliminated); gravity `g` along −y. The same
    /// system as the pendulum in its angle `θ = atan2(x, −y)`, in two coordinates and one
    /// constraint (docs/scenes.md#nonminimal_pendulum).
    pub struct NonminimalPendulum {
        /// Bob mass `m` (kg).
        pub mass: f64 = ["m", "kg", 1.0, Domain::Positive, "mass of the bob"],
        /// Rod length `l` (m).
        pub length: f64 = ["l", "m", 1.0, Domain::Positive, "length of the rod (radius of the constraint circle)"],
        /// Gravitational acceleration `g` (m/s²).
        pub gravity: f64 = [GRAVITY],
    }
    /// A Cartesian pendulum with mass `m`, rod length `l` and gravity `g`.
    pub fn new;
    derived {
        description: Description = Description {
            coordinates: vec![Coordinate::length("x"), Coordinate::length("y")],
            bodies: vec![Body::point("bob", mass)],
            gravity,
            constraints: vec!["rod: x² + y² = l²".into()],
            ..Description::default()
        },
    }
}

impl NonminimalPendulum {
    /// `(ẍ, ÿ)` and the multiplier `λ` solving `m q̈ + Gᵀ λ = (0, −m g)`, `G q̈ = −γ` with
    /// `G = 2 (x, y)` and `γ = 2 (ẋ² + ẏ²)`, at any state (on the circle or not):
    /// `q̈ = (0, −g) − (2λ/m) q` dotted with `q` gives `q·q̈ = −g y − 2λ r²/m = −|q̇|²`, so
    /// `λ = m (|q̇|² − g y) / (2 r²)`, `r² = x² + y²`. On the circle with a tangent velocity
    /// (`x = l sinθ`, `y = −l cosθ`, `|q̇| = l |θ̇|`) this is `λ = T/(2l)`, `T = m (g cosθ + l θ̇²)`
    /// the rod tension, and `q̈ = l (cosθ θ̈ − sinθ θ̇², sinθ θ̈ + cosθ θ̇²)` with
    /// `θ̈ = −(g/l) sinθ` (docs/scenes.md#nonminimal_pendulum).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn accelerations_and_multiplier(&self, q: &[f64], qdot: &[f64]) -> ([f64; 2], f64) {
        let [x, y] = fixed(q, "q");
        let [vx, vy] = fixed(qdot, "q̇");
        let (m, g) = (self.mass, self.gravity);
        // k = 2λ/m.
        let k = (vx * vx + vy * vy - g * y) / (x * x + y * y);
        ([-k * x, -g - k * y], 0.5 * m * k)
    }

    /// `(ẍ, ÿ)` in closed form; see [`accelerations_and_multiplier`](Self::accelerations_and_multiplier).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn closed_form_accelerations(&self, q: &[f64], qdot: &[f64]) -> [f64; 2] {
        self.accelerations_and_multiplier(q, qdot).0
    }

    /// The multiplier `λ = T / (2l)` of the constraint, `T` the rod tension (positive when the
    /// rod pulls the bob towards the pivot: the constraint force `−Gᵀλ = −2λ (x, y)`).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn multiplier(&self, q: &[f64], qdot: &[f64]) -> f64 {
        self.accelerations_and_multiplier(q, qdot).1
    }

    /// The state `(x, y, ẋ, ẏ)` of the bob at angle `θ` from the downward vertical turning at
    /// `θ̇`: `(l sinθ, −l cosθ)`, `(l cosθ θ̇, l sinθ θ̇)`.
    pub fn state_at_angle(&self, t: f64, theta: f64, theta_dot: f64) -> State {
        let (s, c) = theta.sin_cos();
        let l = self.length;
        State::new(t, [l * s, -l * c], [l * c * theta_dot, l * s * theta_dot])
    }
}

impl Mechanism for NonminimalPendulum {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        world_from_body[0] = Pose::point(q[0], q[1]);
    }

    /// `Φ = x² + y² − l²`.
    fn constraints<S: Scalar>(&self, _t: S, q: &[S], phi: &mut [S]) {
        phi[0] = q[0] * q[0] + q[1] * q[1] - self.length * self.length;
    }
}

impl SceneType for NonminimalPendulum {
    const ID: &'static str = "nonminimal_pendulum";
    const TITLE: &'static str = "Pendulum in Cartesian coordinates (one holonomic constraint)";
    const REFERENCE: &'static str = "docs/scenes.md#nonminimal_pendulum; closed forms derived there";
    param_table!();

    /// `x = l sin 0.5`, `y = −l cos 0.5`, at rest.
    fn default_state(&self) -> State {
        self.state_at_angle(0.0, 0.5, 0.0)
    }

    /// The energy `E = ½ m (ẋ² + ẏ²) + m g y`.
    fn conserves_energy(&self) -> Vec<Conserved> {
        vec![Conserved::energy(self, |s, q, v| s.mass * (0.5 * (v[0] * v[0] + v[1] * v[1]) + s.gravity * q[1]))]
    }

    body_scene!();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{assert_close, assert_engine_matches_closed_form};
    use crate::{DrivenPendulum, scene_of};
    use lagrange::{Method, Model, Output, System, Tolerances};

    /// Generic states on the circle, from `(θ, θ̇)`.
    const ANGLES: [(f64, f64); 5] = [(0.5, 0.0), (-1.2, 2.5), (2.9, -0.7), (3.1, 4.0), (-2.0, -6.0)];

    /// The engine's `q̈` and `λ` against the closed form (any state, also off the circle) and
    /// against the pendulum in its angle carried to `(x, y)`, `θ̈ = −(g/l) sinθ`, with
    /// `λ = T/(2l)`. Both are exact formulas: round-off only (a dozen operations; the engine's
    /// 3 × 3 Schur solve), bound [`crate::testing::ENGINE_VS_CLOSED_FORM`].
    #[test]
    fn engine_matches_the_pendulum_in_its_angle() {
        let scene = scene_of::<NonminimalPendulum>();
        for changes in [&[][..], &[("m", 1.3), ("l", 0.7), ("g", 3.0)][..]] {
            let mut params = scene.default_params();
            for &(key, value) in changes {
                params.set(key, value).unwrap();
            }
            let pendulum = NonminimalPendulum::from_params(&params).unwrap();
            let (l, g, m) = (pendulum.length, pendulum.gravity, pendulum.mass);
            let mut states: Vec<State> = ANGLES.iter().map(|&(a, w)| pendulum.state_at_angle(0.3, a, w)).collect();
            // Off the circle, the closed form is still the engine's KKT solution.
            states.push(State::new(0.0, [0.3, -0.2], [1.1, -0.4]));
            assert_engine_matches_closed_form(scene, &params, &states);
            let mut system = scene.build(&params).unwrap();
            // The angle pendulum: the undriven driven pendulum of the same bob.
            let angle = DrivenPendulum::new(m, l, 0.0, 0.0, g).unwrap();
            for &(theta, theta_dot) in &ANGLES {
                let state = pendulum.state_at_angle(0.0, theta, theta_dot);
                let theta_ddot = angle.closed_form_accelerations(0.0, &[theta], &[theta_dot])[0];
                let (s, c) = theta.sin_cos();
                let expected = [
                    l * (c * theta_ddot - s * theta_dot * theta_dot),
                    l * (s * theta_ddot + c * theta_dot * theta_dot),
                ];
                let got = system.accelerations(0.0, &state.q, &state.qdot).unwrap().to_vec();
                let scale = expected.iter().fold(1.0_f64, |w, v| w.max(v.abs()));
                assert_close(&format!("q̈ at θ = {theta}"), &expected, &got, 1e-13 * scale);
                let lambda = system.constraint_multipliers(0.0, &state.q, &state.qdot).unwrap().unwrap()[0];
                let tension = m * (g * c + l * theta_dot * theta_dot);
                let closed = pendulum.multiplier(&state.q, &state.qdot);
                assert_close(
                    &format!("λ at θ = {theta}"),
                    &[tension / (2.0 * l)],
                    &[lambda],
                    1e-13 * tension.abs().max(1.0),
                );
                assert_close(&format!("closed λ at θ = {theta}"), &[lambda], &[closed], 1e-13 * tension.abs().max(1.0));
            }
        }
    }

    /// The Cartesian run against the angle pendulum run the same way (adaptive at tol 1e-12),
    /// over 5 s: positions agree to the two runs' own global errors (a few 1e-11 measured;
    /// bound 1e-9), and the bob stays on the circle to round-off after every projection.
    #[test]
    fn trajectory_matches_the_angle_pendulum() {
        let pendulum = NonminimalPendulum::new(1.0, 1.0, 9.81).unwrap();
        let initial = pendulum.default_state();
        let method = Method::Dopri5 { tol: Tolerances::uniform(1e-12) };
        let output = Output::Every(0.1);
        let mut system = Box::new(lagrange::Buffered::new(Model::new(pendulum.clone()).unwrap()));
        let run = system.simulate(&initial, 5.0, method, &output).unwrap();
        let angle = DrivenPendulum::new(1.0, 1.0, 0.0, 0.0, 9.81).unwrap();
        let reference =
            angle.into_system().unwrap().simulate(&State::new(0.0, [0.5], [0.0]), 5.0, method, &output).unwrap();
        assert_eq!(run.len(), reference.len());
        let mut worst: f64 = 0.0;
        for k in 0..run.len() {
            let expected = pendulum.state_at_angle(run.t[k], reference.q(k)[0], reference.qdot(k)[0]);
            worst = worst.max(assert_close(&format!("q at {}", run.t[k]), &expected.q, run.q(k), 1e-9));
            assert_close(&format!("q̇ at {}", run.t[k]), &expected.qdot, run.qdot(k), 1e-8);
            let [position, velocity] = system.constraint_violation(run.t[k], run.q(k), run.qdot(k)).unwrap().unwrap();
            assert!(position <= 1e-14 && velocity <= 1e-13, "violation {position:e}, {velocity:e} at {}", run.t[k]);
        }
        eprintln!("nonminimal pendulum vs angle pendulum over 5 s: largest position difference {worst:.1e}");
    }
}
