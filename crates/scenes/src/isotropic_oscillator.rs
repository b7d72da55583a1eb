//! Central force with the isotropic-oscillator potential `V = ½ k r²` (docs/scenes.md#isotropic_oscillator;
//! the lecture (docs/scenes.md#the-lecture)).

use crate::checks::fixed;
use crate::params::{param_table, scene_params};
use crate::scene::body_scene;
use crate::{Conserved, Domain, Invariant, SceneType};
use lagrange::{Body, Bounds, Coordinate, Description, Mechanism, Pose, Scalar, State};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

scene_params! {
    /// A particle of mass `m` at `(r cosθ, r sinθ)` bound to the origin by `V = ½ k r²`;
    /// `q = (r, θ)`, plane polar coordinates (docs/scenes.md#isotropic_oscillator). No gravity.
    pub struct IsotropicOscillator {
        /// Mass `m` (kg).
        pub mass: f64 = ["m", "kg", 1.0, Domain::Positive, "mass of the particle"],
        /// Spring constant `k` (N/m).
        pub stiffness: f64 = ["k", "N/m", 1.0, Domain::Positive, "spring constant of the central force"],
    }
    /// An isotropic oscillator with mass `m` and stiffness `k`.
    pub fn new;
    derived {
        description: Description = Description {
            coordinates: vec![Coordinate::length("r"), Coordinate::angle("θ")],
            bodies: vec![Body::point("particle", mass)],
            ..Description::default()
        },
    }
}

impl IsotropicOscillator {
    /// `r̈ = r θ̇² − (k/m) r`, `θ̈ = −2 ṙ θ̇ / r` (docs/scenes.md#isotropic_oscillator, "Equations").
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn closed_form_accelerations(&self, q: &[f64], qdot: &[f64]) -> [f64; 2] {
        let [r, _] = fixed(q, "q");
        let [r_dot, theta_dot] = fixed(qdot, "q̇");
        [r * theta_dot * theta_dot - self.stiffness / self.mass * r, -2.0 * r_dot * theta_dot / r]
    }

    /// The angular frequency `ω = √(k/m)` of the Cartesian motion (docs/scenes.md#isotropic_oscillator).
    pub fn frequency(&self) -> f64 {
        (self.stiffness / self.mass).sqrt()
    }

    /// The state `(r, θ, ṙ, θ̇)` a time `tau` after `(q, q̇)`, from the Cartesian solution
    /// `x(t) = x₀ cos ωτ + (ẋ₀/ω) sin ωτ` (same for `y`; docs/scenes.md#isotropic_oscillator) converted back to polar
    /// coordinates with `θ` continuous: the position turns by exactly `π` (with the sign of the
    /// angular momentum) every half period `π/ω`, and by less than `π` in the remainder.
    /// The sign of `r` is kept (a negative `r₀` stays negative); with zero angular momentum the
    /// motion is along a line through the origin, `θ` constant and `r` changing sign.
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn motion(&self, q: &[f64], qdot: &[f64], tau: f64) -> ([f64; 2], [f64; 2]) {
        let [r0, theta0] = fixed(q, "q");
        let [r_dot0, theta_dot0] = fixed(qdot, "q̇");
        let omega = self.frequency();
        let h = r0 * r0 * theta_dot0;
        if h == 0.0 {
            // Radial motion: r itself is a one-dimensional oscillator.
            let (sin, cos) = (omega * tau).sin_cos();
            let r = r0 * cos + r_dot0 / omega * sin;
            let r_dot = -r0 * omega * sin + r_dot0 * cos;
            return ([r, theta0], [r_dot, 0.0]);
        }
        // Cartesian initial state (with the signed r₀).
        let (position0, velocity0) = cartesian(q, qdot);
        // Whole half periods, then the remainder τ_r ∈ [0, π/ω).
        let half_periods = (omega * tau / PI).floor();
        let remainder = tau - half_periods * PI / omega;
        let (sin, cos) = (omega * remainder).sin_cos();
        let at = |i: usize| position0[i] * cos + velocity0[i] / omega * sin;
        let speed = |i: usize| -position0[i] * omega * sin + velocity0[i] * cos;
        let (position_r, velocity_r) = ([at(0), at(1)], [speed(0), speed(1)]);
        // Angle swept in the remainder: in [0, π) for h > 0, (−π, 0] for h < 0; atan2 may land
        // on the other side of ±π or 0 by round-off, which the sign of h resolves.
        let cross = position0[0] * position_r[1] - position0[1] * position_r[0];
        let dot = position0[0] * position_r[0] + position0[1] * position_r[1];
        let mut swept = cross.atan2(dot);
        if h > 0.0 && swept < -FRAC_PI_2 {
            swept += TAU;
        } else if h < 0.0 && swept > FRAC_PI_2 {
            swept -= TAU;
        }
        let theta = theta0 + (half_periods * PI).copysign(h) + swept;
        // After an odd number of half periods the position is −position_r; r, ṙ, θ̇ are even.
        let distance = position_r[0].hypot(position_r[1]);
        let r = distance.copysign(r0);
        let r_dot = (position_r[0] * velocity_r[0] + position_r[1] * velocity_r[1]) / distance.copysign(r0);
        let theta_dot = (position_r[0] * velocity_r[1] - position_r[1] * velocity_r[0]) / (distance * distance);
        ([r, theta], [r_dot, theta_dot])
    }
}

/// The Cartesian position and velocity of the polar state `(r, θ, ṙ, θ̇)`.
fn cartesian(q: &[f64], qdot: &[f64]) -> ([f64; 2], [f64; 2]) {
    let ([r, theta], [r_dot, theta_dot]) = (fixed(q, "q"), fixed(qdot, "q̇"));
    let (sin, cos) = theta.sin_cos();
    ([r * cos, r * sin], [r_dot * cos - r * theta_dot * sin, r_dot * sin + r * theta_dot * cos])
}

impl Mechanism for IsotropicOscillator {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (r, theta) = (q[0], q[1]);
        let (sin, cos) = theta.sin_cos();
        world_from_body[0] = Pose::point(r * cos, r * sin);
    }

    /// `V = ½ k |x|²`, through the particle's position so that the force is applied to it.
    fn potential<S: Scalar>(&self, _t: S, _q: &[S], world_from_body: &[Pose<S>]) -> Option<S> {
        let Pose { x, y, .. } = world_from_body[0];
        Some((x * x + y * y) * (0.5 * self.stiffness))
    }

    /// Plane polar coordinates describe the particle for `r > 0` only (at `r = 0` `θ` moves no
    /// mass; past it `(r, θ)` and `(−r, θ + π)` are one point).
    fn admissible(&self, _t: f64, q: &[f64], _qdot: &[f64], bounds: &mut Bounds) -> bool {
        bounds.above("r", q[0], 0.0);
        true
    }
}

impl SceneType for IsotropicOscillator {
    const ID: &'static str = "isotropic_oscillator";
    const TITLE: &'static str = "Central force: isotropic oscillator (V = k r²/2)";
    const REFERENCE: &'static str =
        "docs/scenes.md#isotropic_oscillator; the lecture (docs/scenes.md#the-lecture), example: central force";
    param_table!();

    /// `r = 1`, `θ = 0`, `ṙ = 0`, `θ̇ = 0.5`.
    fn default_state(&self) -> State {
        State::new(0.0, [1.0, 0.0], [0.0, 0.5])
    }

    /// See [`IsotropicOscillator::motion`].
    fn exact_solution(&self, initial: &State, t: f64) -> Option<State> {
        let (q, qdot) = self.motion(&initial.q, &initial.qdot, t - initial.t);
        Some(State::new(t, q, qdot))
    }

    /// `E = ½ m (ṙ² + r² θ̇²) + ½ k r²`, `ℓ = m r² θ̇`, and the Fradkin tensor
    /// `A_ij = p_i p_j / m + k x_i x_j` (docs/scenes.md#isotropic_oscillator) by its components
    /// `E_x = A_xx / 2`, the energy of the x motion, and `A_xy`.
    fn conserves_energy(&self) -> Vec<Conserved> {
        let (why, other) = ("Fradkin tensor: V ∝ r²", Invariant::Other);
        let energy = |s: &Self, q: &[f64], v: &[f64]| {
            0.5 * (s.mass * (v[0] * v[0] + q[0] * q[0] * v[1] * v[1]) + s.stiffness * q[0] * q[0])
        };
        let angular_momentum = |s: &Self, _, q: &[f64], v: &[f64]| s.mass * q[0] * q[0] * v[1];
        let energy_x = |s: &Self, _, q: &[f64], qdot: &[f64]| {
            let ([x, _], [vx, _]) = cartesian(q, qdot);
            0.5 * (s.mass * vx * vx + s.stiffness * x * x)
        };
        let fradkin_xy = |s: &Self, _, q: &[f64], qdot: &[f64]| {
            let ([x, y], [vx, vy]) = cartesian(q, qdot);
            s.mass * vx * vy + s.stiffness * x * y
        };
        vec![
            Conserved::energy(self, energy),
            Conserved::new(self, "ℓ", "θ is cyclic", Invariant::CyclicMomentum(1), angular_momentum),
            Conserved::new(self, "E_x", why, other, energy_x),
            Conserved::new(self, "A_xy", why, other, fradkin_xy),
        ]
    }

    body_scene!();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_of;
    use crate::testing::{
        POLAR_ROWS, assert_close, assert_engine_matches_closed_form_along, assert_exact_solution_consistent,
    };

    #[test]
    fn engine_matches_closed_form() {
        assert_engine_matches_closed_form_along::<IsotropicOscillator, 2>(&POLAR_ROWS, &[("m", 0.4), ("k", 3.0)]);
    }

    #[test]
    fn exact_solution_is_consistent_including_negative_r_and_radial_motion() {
        let mut params = scene_of::<IsotropicOscillator>().default_params();
        params.set("k", 2.0).unwrap();
        let initials = [
            State::new(0.0, [1.0, 0.0], [0.0, 0.5]),
            State::new(0.2, [0.6, 2.0], [0.9, -1.7]),
            State::new(0.0, [-0.8, 0.3], [0.2, 0.6]),
            State::new(0.0, [0.5, 1.0], [1.0, 0.0]),
        ];
        for initial in &initials {
            assert_exact_solution_consistent(
                scene_of::<IsotropicOscillator>(),
                &params,
                initial,
                &[0.3, 1.1, 2.2, 9.0, 31.0],
            );
        }
    }

    /// Over one period `2π/ω` the orbit closes and `θ` advances by exactly 2π.
    #[test]
    fn one_period_closes_the_ellipse() {
        let scene = IsotropicOscillator::new(1.0, 4.0).unwrap();
        let period = TAU / scene.frequency();
        for (q, qdot) in [([1.0, 0.3], [0.2, 0.5]), ([2.0, -1.0], [-1.0, -0.1])] {
            let (q1, qdot1) = scene.motion(&q, &qdot, period);
            let turn = TAU.copysign(qdot[1]);
            assert_close(
                "after one period",
                &[q[0], q[1] + turn, qdot[0], qdot[1]],
                &[q1[0], q1[1], qdot1[0], qdot1[1]],
                1e-12,
            );
        }
    }
}
