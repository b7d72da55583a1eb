//! A charged particle in a uniform magnetic field: a velocity-dependent potential, given as a
//! raw Lagrangian (beyond the lecture).

use crate::checks::fixed;
use crate::params::{param_table, scene_params};
use crate::scene::raw_scene;
use crate::{Conserved, Domain, Invariant, SceneType};
use lagrange::{Coordinate, Lagrangian, Scalar, State};

scene_params! {
    /// A particle of mass `m` and charge `e` in the plane, in a uniform magnetic field `B` along
    /// `+z`, with the symmetric-gauge vector potential `A = (B/2)(−y, x)`:
    /// `L = ½ m (ẋ² + ẏ²) + (e B / 2)(x ẏ − y ẋ)`; `q = (x, y)`. A velocity-dependent potential, so
    /// it is given as a raw [`Lagrangian`] rather than as bodies (Goldstein, *Classical Mechanics*,
    /// §1.5, `L = T − qφ + q A·v`).
    pub struct ChargedParticle {
        /// Mass `m` (kg).
        pub mass: f64 = ["m", "kg", 1.0, Domain::Positive, "mass of the particle"],
        /// Charge `e` (C); any sign.
        pub charge: f64 = ["e", "C", 1.0, Domain::Finite, "charge of the particle"],
        /// Field `B` along `+z` (T); any sign.
        pub field: f64 = ["B", "T", 1.0, Domain::Finite, "uniform magnetic field along +z"],
    }
    /// A particle of mass `m` and charge `e` in the field `B`.
    pub fn new;
    derived {
        coordinates: [Coordinate; 2] = [Coordinate::length("x"), Coordinate::length("y")],
    }
}

impl ChargedParticle {
    /// The cyclotron (signed angular) frequency `ω_c = e B / m` (rad/s).
    pub fn cyclotron_frequency(&self) -> f64 {
        self.charge * self.field / self.mass
    }

    /// `ẍ = (e B/m) ẏ`, `ÿ = −(e B/m) ẋ`: Lagrange's equations of `L`
    /// (`d/dt(m ẋ − e B y/2) = e B ẏ/2` and `d/dt(m ẏ + e B x/2) = −e B ẋ/2`), i.e. the Lorentz
    /// force `e v × B`.
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn closed_form_accelerations(&self, q: &[f64], qdot: &[f64]) -> [f64; 2] {
        let _: [f64; 2] = fixed(q, "q");
        let [vx, vy] = fixed(qdot, "q̇");
        let omega = self.cyclotron_frequency();
        [omega * vy, -omega * vx]
    }

    /// `(q, q̇)` a time `tau` after `(q₀, q̇₀)`: the velocity turns clockwise at `ω_c` (for
    /// `ω_c > 0`), `v(τ) = R(−ω_c τ) v₀`, and the position follows the circle
    /// `x = x₀ + (ẋ₀ sin ω_cτ + ẏ₀ (1 − cos ω_cτ))/ω_c`, `y = y₀ + (ẏ₀ sin ω_cτ − ẋ₀ (1 − cos ω_cτ))/ω_c`
    /// (uniform circular motion, radius `|v|/|ω_c|`); a straight line when `ω_c = 0` (`B = 0` or
    /// `e = 0`). `1 − cos` is written `2 sin²(ω_cτ/2)` so that small `ω_c` loses no digits.
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn motion(&self, q: &[f64], qdot: &[f64], tau: f64) -> ([f64; 2], [f64; 2]) {
        let [x0, y0] = fixed(q, "q");
        let [vx0, vy0] = fixed(qdot, "q̇");
        let omega = self.cyclotron_frequency();
        if omega == 0.0 {
            return ([x0 + vx0 * tau, y0 + vy0 * tau], [vx0, vy0]);
        }
        let (sin, cos) = (omega * tau).sin_cos();
        let half_sin = (0.5 * omega * tau).sin();
        let one_minus_cos = 2.0 * half_sin * half_sin;
        let x = x0 + (vx0 * sin + vy0 * one_minus_cos) / omega;
        let y = y0 + (vy0 * sin - vx0 * one_minus_cos) / omega;
        ([x, y], [vx0 * cos + vy0 * sin, -vx0 * sin + vy0 * cos])
    }
}

impl Lagrangian for ChargedParticle {
    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }

    fn lagrangian<S: Scalar>(&self, _t: S, q: &[S], qdot: &[S]) -> S {
        let (x, y, vx, vy) = (q[0], q[1], qdot[0], qdot[1]);
        // Kinetic energy plus e A·v with A = (B/2)(−y, x).
        (vx * vx + vy * vy) * (0.5 * self.mass) + (x * vy - y * vx) * (0.5 * self.charge * self.field)
    }
}

impl SceneType for ChargedParticle {
    const ID: &'static str = "charged_particle";
    const TITLE: &'static str = "Charged particle in a uniform magnetic field";
    const REFERENCE: &'static str =
        "beyond the lecture (velocity-dependent potential, raw Lagrangian); Goldstein, Classical Mechanics, §1.5";
    param_table!();

    /// `x = 1`, `y = 0`, `ẋ = 0`, `ẏ = 1`.
    fn default_state(&self) -> State {
        State::new(0.0, [1.0, 0.0], [0.0, 1.0])
    }

    /// Uniform circular motion; see [`ChargedParticle::motion`].
    fn exact_solution(&self, initial: &State, t: f64) -> Option<State> {
        let (q, qdot) = self.motion(&initial.q, &initial.qdot, t - initial.t);
        Some(State::new(t, q, qdot))
    }

    /// The energy `E = h = ½ m |v|²`; the canonical angular momentum
    /// `p_φ = m (x ẏ − y ẋ) + (e B/2)(x² + y²)` (`L` is invariant under rotations about the
    /// origin); and `K = (m ẋ − e B y, m ẏ + e B x)`, `e B` times the guiding centre turned by
    /// −90° (a translation changes `L` by a total time derivative).
    fn conserves_energy(&self) -> Vec<Conserved> {
        let (why, other) = ("translations change L by a total derivative", Invariant::Other);
        vec![
            Conserved::energy(self, |s, _, v| 0.5 * s.mass * (v[0] * v[0] + v[1] * v[1])),
            Conserved::new(self, "p_φ", "L is invariant under rotations", other, |s, _, q, v| {
                s.mass * (q[0] * v[1] - q[1] * v[0]) + 0.5 * s.charge * s.field * (q[0] * q[0] + q[1] * q[1])
            }),
            Conserved::new(self, "K_x", why, other, |s, _, q, v| s.mass * v[0] - s.charge * s.field * q[1]),
            Conserved::new(self, "K_y", why, other, |s, _, q, v| s.mass * v[1] + s.charge * s.field * q[0]),
        ]
    }

    raw_scene!();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_of;
    use crate::testing::{
        PLANAR_ROWS, assert_close, assert_engine_matches_closed_form_along, assert_exact_solution_consistent,
    };
    use std::f64::consts::TAU;

    #[test]
    fn engine_matches_closed_form() {
        assert_engine_matches_closed_form_along::<ChargedParticle, 2>(
            &PLANAR_ROWS,
            &[("B", -2.5), ("e", 0.3), ("m", 4.0)],
        );
    }

    #[test]
    fn exact_solution_is_consistent_for_both_signs_and_zero_field() {
        for field in [1.0, -2.0, 0.0, 1e-9] {
            let mut params = scene_of::<ChargedParticle>().default_params();
            params.set("B", field).unwrap();
            for initial in [State::new(0.0, [1.0, 0.0], [0.0, 1.0]), State::new(0.7, [-0.5, 2.0], [0.4, -1.3])] {
                assert_exact_solution_consistent(scene_of::<ChargedParticle>(), &params, &initial, &[0.3, 2.0, 9.0]);
            }
        }
    }

    /// The default state circles the centre `(2, 0)` with radius 1 and period `2π/ω_c`.
    #[test]
    fn default_orbit_is_a_unit_circle() {
        let scene = ChargedParticle::new(1.0, 1.0, 1.0).unwrap();
        for k in 0..8 {
            let (q, _) = scene.motion(&[1.0, 0.0], &[0.0, 1.0], f64::from(k) * 0.4);
            assert!(((q[0] - 2.0).hypot(q[1]) - 1.0).abs() < 1e-15, "{q:?}");
        }
        let (q, qdot) = scene.motion(&[1.0, 0.0], &[0.0, 1.0], TAU);
        assert_close("one cyclotron period", &[1.0, 0.0, 0.0, 1.0], &[q[0], q[1], qdot[0], qdot[1]], 1e-14);
    }
}
