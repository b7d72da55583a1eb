//! Harmonic oscillator, optionally with linear damping (docs/scenes.md#harmonic_oscillator; the lecture (docs/scenes.md#the-lecture)).

use crate::checks::fixed;
use crate::params::{param_table, scene_params};
use crate::scene::body_scene;
use crate::{Conserved, Domain, SceneType};
use lagrange::graph::{ForceElement, GROUND, GraphJoint, JointGraph};
use lagrange::{Body, Coordinate, Description, Mechanism, Pose, Scalar, State};

scene_params! {
    /// A mass `m` at `(x, 0)` on a spring of stiffness `k`, `V = ½ k x²`, with an optional
    /// damping force `−c ẋ` (a generalized force); `q = (x)`, the displacement from the spring's
    /// rest position (docs/scenes.md#harmonic_oscillator). No gravity.
    pub struct HarmonicOscillator {
        /// Mass `m` (kg).
        pub mass: f64 = ["m", "kg", 1.0, Domain::Positive, "mass on the spring"],
        /// Spring constant `k` (N/m).
        pub stiffness: f64 = ["k", "N/m", 10.0, Domain::Positive, "spring constant"],
        /// Damping coefficient `c` (kg/s); 0 for the lecture's undamped oscillator.
        pub damping: f64 = ["c", "kg/s", 0.0, Domain::NonNegative, "linear damping coefficient (force −c ẋ)"],
    }
    /// An oscillator with mass `m`, stiffness `k` and damping `c`.
    pub fn new;
    derived {
        description: Description = Description {
            coordinates: vec![Coordinate::length("x")],
            bodies: vec![Body::point("mass", mass)],
            constant_mass_matrix: true,
            ..Description::default()
        },
    }
}

impl HarmonicOscillator {
    /// `ẍ = −(k x + c ẋ)/m` (docs/scenes.md#harmonic_oscillator with the damping force added).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 1 entry.
    pub fn closed_form_accelerations(&self, q: &[f64], qdot: &[f64]) -> [f64; 1] {
        let [x] = fixed(q, "q");
        let [velocity] = fixed(qdot, "q̇");
        [-(self.stiffness * x + self.damping * velocity) / self.mass]
    }

    /// The natural (undamped) angular frequency `ω₀ = √(k/m)` (docs/scenes.md#harmonic_oscillator).
    pub fn natural_frequency(&self) -> f64 {
        (self.stiffness / self.mass).sqrt()
    }

    /// `(x, ẋ)` a time `tau` after `(x₀, v₀)`: the exact solution of `ẍ + 2γ ẋ + ω₀² x = 0`,
    /// `γ = c/(2m)`, `ω₀² = k/m` (any textbook, e.g. Taylor, *Classical Mechanics*, §5.4):
    /// `x = e^{−γτ} [x₀ C(τ) + (v₀ + γ x₀) S(τ)]`, `ẋ = e^{−γτ} [v₀ C(τ) − (ω₀² x₀ + γ v₀) S(τ)]`
    /// with `C = cos ω_d τ`, `S = sin(ω_d τ)/ω_d` (under-damped, `ω_d² = ω₀² − γ² > 0`; the
    /// undamped `x₀ cos ω₀τ + v₀/ω₀ sin ω₀τ` at `γ = 0`), `C = 1`, `S = τ` (critical), and
    /// `C = cosh sτ`, `S = sinh(sτ)/s` (over-damped, `s² = γ² − ω₀²`).
    pub fn motion(&self, x0: f64, v0: f64, tau: f64) -> (f64, f64) {
        let gamma = self.damping / (2.0 * self.mass);
        let omega0_sq = self.stiffness / self.mass;
        let discriminant = omega0_sq - gamma * gamma;
        // e^{−γτ} C(τ) and e^{−γτ} S(τ) for the three regimes.
        let (decay_c, decay_s) = if discriminant > 0.0 {
            let omega_d = discriminant.sqrt();
            let decay = (-gamma * tau).exp();
            let (sin, cos) = (omega_d * tau).sin_cos();
            (decay * cos, decay * sin / omega_d)
        } else if discriminant == 0.0 {
            let decay = (-gamma * tau).exp();
            (decay, decay * tau)
        } else {
            let s = (-discriminant).sqrt();
            if (s * tau).abs() < 1.0 {
                // sinh(sτ)/s without cancellation for small sτ.
                let decay = (-gamma * tau).exp();
                (decay * (s * tau).cosh(), decay * (s * tau).sinh() / s)
            } else {
                // e^{−γτ}(e^{sτ} ± e^{−sτ})/2 with the slow rate s − γ = −ω₀²/(γ + s) formed
                // without cancellation, so that large γτ neither overflows nor loses digits.
                let slow = (-omega0_sq / (gamma + s) * tau).exp();
                let fast = (-(gamma + s) * tau).exp();
                (0.5 * (slow + fast), 0.5 * (slow - fast) / s)
            }
        };
        let x = x0 * decay_c + (v0 + gamma * x0) * decay_s;
        let v = v0 * decay_c - (omega0_sq * x0 + gamma * v0) * decay_s;
        (x, v)
    }
}

impl Mechanism for HarmonicOscillator {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        world_from_body[0] = Pose::point(q[0], S::zero());
    }

    /// `V = ½ k x²`, through the body's position so that the spring force is applied to it.
    fn potential<S: Scalar>(&self, _t: S, _q: &[S], world_from_body: &[Pose<S>]) -> Option<S> {
        let x = world_from_body[0].x;
        Some(x * x * (0.5 * self.stiffness))
    }

    /// `Q = −c ẋ`; none when `c = 0` (the answer depends only on the parameters).
    fn generalized_force<S: Scalar>(&self, _t: S, _q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        if self.damping == 0.0 {
            return false;
        }
        force[0] -= qdot[0] * self.damping;
        true
    }
}

impl SceneType for HarmonicOscillator {
    const ID: &'static str = "harmonic_oscillator";
    const TITLE: &'static str = "Harmonic oscillator (optionally damped)";
    const REFERENCE: &'static str = "docs/scenes.md#harmonic_oscillator; the lecture (docs/scenes.md#the-lecture), example: harmonic oscillator (damping beyond the lecture)";
    param_table!();

    /// `x = 0.1`, at rest.
    fn default_state(&self) -> State {
        State::new(0.0, [0.1], [0.0])
    }

    /// See [`HarmonicOscillator::motion`].
    fn exact_solution(&self, initial: &State, t: f64) -> Option<State> {
        let (x, v) = self.motion(initial.q[0], initial.qdot[0], t - initial.t);
        Some(State::new(t, [x], [v]))
    }

    /// Undamped: `E = ½ m ẋ² + ½ k x²`; damped: none (`dE/dt = −c ẋ²`).
    fn conserves_energy(&self) -> Vec<Conserved> {
        let energy = |s: &Self, q: &[f64], qdot: &[f64]| 0.5 * (s.mass * qdot[0] * qdot[0] + s.stiffness * q[0] * q[0]);
        if self.damping == 0.0 { vec![Conserved::energy(self, energy)] } else { Vec::new() }
    }

    body_scene!();

    /// A prismatic joint along x with a spring `½ k x²` on it and, when `c > 0`, a damper.
    fn joint_graph(&self) -> Option<JointGraph> {
        let mut graph = crate::scene::graph_of(Self::ID, self)
            .with_joint(GraphJoint::prismatic("x", GROUND, [0.0, 0.0], "mass", [0.0, 0.0], [1.0, 0.0]))
            .with_force(ForceElement::JointSpring { joint: "x".into(), stiffness: self.stiffness, rest: 0.0 });
        if self.damping != 0.0 {
            graph = graph.with_force(ForceElement::JointDamper { joint: "x".into(), coefficient: self.damping });
        }
        Some(graph)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_of;
    use crate::testing::{assert_close, assert_engine_matches_closed_form_along, assert_exact_solution_consistent};

    /// Damping `c` for each regime at `m = 1`, `k = 10` (critical: `c = 2√(km)`).
    fn damping_cases() -> [f64; 4] {
        [0.0, 1.5, 2.0 * 10.0_f64.sqrt(), 25.0]
    }

    #[test]
    fn engine_matches_closed_form_with_and_without_damping() {
        let rows = [(0.5, [-0.4], [1.2]), (1.0, [2.0], [-3.0]), (3.0, [0.0], [0.7]), (7.0, [-1.5], [-0.2])];
        let changes = damping_cases().map(|c| ("c", c));
        assert_engine_matches_closed_form_along::<HarmonicOscillator, 1>(&rows, &changes);
        for (key, c) in changes {
            let mut params = scene_of::<HarmonicOscillator>().default_params();
            params.set(key, c).unwrap();
            let system = scene_of::<HarmonicOscillator>().build(&params).unwrap();
            assert_eq!(system.conserves_energy(), c == 0.0, "c = {c}");
        }
    }

    #[test]
    fn exact_solution_in_every_damping_regime() {
        for c in damping_cases() {
            let mut params = scene_of::<HarmonicOscillator>().default_params();
            params.set("c", c).unwrap();
            for initial in [State::new(0.0, [0.1], [0.0]), State::new(0.4, [-0.3], [1.1])] {
                assert_exact_solution_consistent(scene_of::<HarmonicOscillator>(), &params, &initial, &[0.3, 1.7, 4.0]);
            }
        }
    }

    #[test]
    fn undamped_solution_is_the_lecture_cosine() {
        let scene = HarmonicOscillator::new(2.0, 8.0, 0.0).unwrap();
        let omega = scene.natural_frequency();
        assert_eq!(omega, 2.0);
        let (x, v) = scene.motion(0.3, 0.5, 1.1);
        let expected = [0.3 * (2.2_f64).cos() + 0.25 * (2.2_f64).sin(), -0.6 * (2.2_f64).sin() + 0.5 * (2.2_f64).cos()];
        assert_close("x, ẋ", &expected, &[x, v], 1e-15);
    }

    /// Heavy over-damping over a long time neither overflows nor loses the slow mode.
    #[test]
    fn heavily_overdamped_motion_decays_on_the_slow_rate() {
        let scene = HarmonicOscillator::new(1.0, 1.0, 2000.0).unwrap();
        let (x, v) = scene.motion(1.0, 0.0, 1000.0);
        // Slow rate ≈ −ω₀²/(2γ) = −1/2000 per second: x ≈ e^{−0.5}.
        assert!(x.is_finite() && v.is_finite(), "x = {x}, v = {v}");
        assert!((x - (-0.5_f64).exp()).abs() < 1e-3, "x = {x}");
    }
}
