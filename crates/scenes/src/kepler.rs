//! Central force with the Kepler potential `V = −k/r` (docs/scenes.md#kepler; the lecture (docs/scenes.md#the-lecture)).

use crate::checks::fixed;
use crate::params::{param_table, scene_params};
use crate::scene::body_scene;
use crate::{Conserved, Domain, Invariant, SceneType};
use lagrange::{Body, Bounds, Coordinate, Description, Mechanism, Pose, Scalar, State};
use std::f64::consts::{PI, TAU};

scene_params! {
    /// A particle of mass `m` at `(r cosθ, r sinθ)` attracted to the origin by `V = −k/r`;
    /// `q = (r, θ)`, plane polar coordinates (docs/scenes.md#kepler). No gravity. The closed forms assume
    /// `r > 0`.
    pub struct Kepler {
        /// Mass `m` (kg).
        pub mass: f64 = ["m", "kg", 1.0, Domain::Positive, "mass of the particle"],
        /// Strength `k` of the potential `V = −k/r` (N m²).
        pub strength: f64 = ["k", "N m²", 1.0, Domain::Positive, "strength of the attraction (V = −k/r)"],
    }
    /// A Kepler problem with mass `m` and strength `k`.
    pub fn new;
    derived {
        description: Description = Description {
            coordinates: vec![Coordinate::length("r"), Coordinate::angle("θ")],
            bodies: vec![Body::point("particle", mass)],
            ..Description::default()
        },
    }
}

/// The orbit through a state: its constants of motion and conic elements (docs/scenes.md#kepler,
/// "Orbit": `r(θ) = p / (1 + e cos(θ − θ₀))`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    /// Energy `E = ½ m (ṙ² + r² θ̇²) − k/r` (J).
    pub energy: f64,
    /// Angular momentum `ℓ = m r² θ̇` (kg m²/s), positive for counter-clockwise motion.
    pub angular_momentum: f64,
    /// Eccentricity `e = √(1 + 2 E ℓ² / (m k²))`: 0 circle, < 1 ellipse, 1 parabola, > 1 hyperbola.
    pub eccentricity: f64,
    /// Semi-latus rectum `p = ℓ² / (m k)` (m).
    pub semi_latus_rectum: f64,
    /// Semi-major axis `a = −k / (2E)` (m), for bound orbits (`E < 0`) only.
    pub semi_major_axis: Option<f64>,
    /// Period `P = 2π √(m a³ / k)` (s), for bound orbits (`E < 0`) only.
    pub period: Option<f64>,
}

impl Kepler {
    /// `r̈ = r θ̇² − k/(m r²)`, `θ̈ = −2 ṙ θ̇ / r` (docs/scenes.md#kepler, "Equations").
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn closed_form_accelerations(&self, q: &[f64], qdot: &[f64]) -> [f64; 2] {
        let [r, _] = fixed(q, "q");
        let [r_dot, theta_dot] = fixed(qdot, "q̇");
        [r * theta_dot * theta_dot - self.strength / (self.mass * r * r), -2.0 * r_dot * theta_dot / r]
    }

    /// The angular momentum `ℓ = p_θ = m r² θ̇` (docs/scenes.md#kepler, conserved: `θ` is cyclic).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn angular_momentum(&self, q: &[f64], qdot: &[f64]) -> f64 {
        let [r, _] = fixed(q, "q");
        let [_, theta_dot] = fixed(qdot, "q̇");
        self.mass * r * r * theta_dot
    }

    /// The energy `E = ½ m (ṙ² + r² θ̇²) − k/r` (docs/scenes.md#kepler).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn energy(&self, q: &[f64], qdot: &[f64]) -> f64 {
        let [r, _] = fixed(q, "q");
        let [r_dot, theta_dot] = fixed(qdot, "q̇");
        0.5 * self.mass * (r_dot * r_dot + r * r * theta_dot * theta_dot) - self.strength / r
    }

    /// The Runge–Lenz vector `A = p × L − m k r̂ = (ℓ²/r − m k) r̂ − m ṙ ℓ θ̂` in Cartesian
    /// components (docs/scenes.md#kepler): conserved for `V ∝ 1/r` only, it points to the
    /// periapsis with length `m k e`.
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn runge_lenz(&self, q: &[f64], qdot: &[f64]) -> [f64; 2] {
        let ([r, theta], [r_dot, _]) = (fixed(q, "q"), fixed(qdot, "q̇"));
        let l = self.angular_momentum(q, qdot);
        let (radial, transverse) = (l * l / r - self.mass * self.strength, -self.mass * r_dot * l);
        let (sin, cos) = theta.sin_cos();
        [radial * cos - transverse * sin, radial * sin + transverse * cos]
    }

    /// Time to fall from rest at `r₀ > 0` to the centre (`ℓ = 0`, the degenerate ellipse of
    /// semi-major axis `r₀/2`, half its period): `t = (π/2) √(m r₀³ / 2k)`.
    pub fn radial_infall_time(&self, r0: f64) -> f64 {
        std::f64::consts::FRAC_PI_2 * (self.mass * r0 * r0 * r0 / (2.0 * self.strength)).sqrt()
    }

    /// The orbit through `(q, q̇)` (docs/scenes.md#kepler, "Orbit").
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn orbit(&self, q: &[f64], qdot: &[f64]) -> Orbit {
        let (m, k) = (self.mass, self.strength);
        let energy = self.energy(q, qdot);
        let angular_momentum = self.angular_momentum(q, qdot);
        // e² can round to slightly below 0 on a circular orbit.
        let eccentricity = (1.0 + 2.0 * energy * angular_momentum * angular_momentum / (m * k * k)).max(0.0).sqrt();
        let semi_latus_rectum = angular_momentum * angular_momentum / (m * k);
        let semi_major_axis = (energy < 0.0).then(|| -k / (2.0 * energy));
        let period = semi_major_axis.map(|a| TAU * (m * a * a * a / k).sqrt());
        Orbit { energy, angular_momentum, eccentricity, semi_latus_rectum, semi_major_axis, period }
    }

    /// The state `(r, θ, ṙ, θ̇)` a time `tau` after `(q, q̇)` on a bound orbit, by Kepler's
    /// equation; `None` for unbound (`E ≥ 0`) or radial (`ℓ = 0`) orbits, or `r ≤ 0`.
    ///
    /// With `μ = k/m`, `a = −k/(2E)`, mean motion `n = √(μ/a³)` and the eccentric anomaly `E`
    /// (Goldstein, *Classical Mechanics*, §3.8; Danby, *Fundamentals of Celestial Mechanics*, ch. 6):
    /// `e cos E₀ = 1 − r₀/a`, `e sin E₀ = r₀ ṙ₀ / √(μ a)`; Kepler's equation
    /// `E − e sin E = E₀ − e sin E₀ + n τ` is solved by safeguarded Newton iteration; then
    /// `r = a (1 − e cos E)`, `ṙ = √(μ a) e sin E / r`, `θ̇ = ℓ / (m r²)`, and `θ` advances by the
    /// true anomaly's increase `ν(E) − ν(E₀)` (signed by `ℓ`), with the form
    /// `ν = E + 2 atan(β sin E / (1 − β cos E))`, `β = e / (1 + √(1 − e²))` (Broucke & Cefola,
    /// Celestial Mechanics 7, 388 (1973)), which is continuous in `E`, so that `θ` is continuous
    /// (no wrap to `(−π, π]`).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 2 entries.
    pub fn motion(&self, q: &[f64], qdot: &[f64], tau: f64) -> Option<([f64; 2], [f64; 2])> {
        let [r0, theta0] = fixed(q, "q");
        let [r_dot0, theta_dot0] = fixed(qdot, "q̇");
        let orbit = self.orbit(q, qdot);
        let a = orbit.semi_major_axis?;
        if r0 <= 0.0 || orbit.angular_momentum == 0.0 {
            return None;
        }
        let mu = self.strength / self.mass;
        let n = (mu / (a * a * a)).sqrt();
        // e cos E₀ and e sin E₀ from the state (well defined also for e = 0).
        let e_cos0 = 1.0 - r0 / a;
        let e_sin0 = r0 * r_dot0 / (mu * a).sqrt();
        let e = e_cos0.hypot(e_sin0);
        if e >= 1.0 {
            return None;
        }
        let anomaly0 = e_sin0.atan2(e_cos0);
        // Mean anomaly at τ, split into whole turns and a remainder in [−π, π].
        let mean = anomaly0 - e_sin0 + n * tau;
        let turns = (mean / TAU).round();
        let anomaly = turns * TAU + solve_kepler_equation(e, mean - turns * TAU);
        let (sin, cos) = anomaly.sin_cos();
        let (e_cos, e_sin) = (e * cos, e * sin);
        let r = a * (1.0 - e_cos);
        let r_dot = (mu * a).sqrt() * e_sin / r;
        let h = r0 * r0 * theta_dot0;
        // True anomaly minus eccentric anomaly, continuous in E: 2 atan(β sin E / (1 − β cos E)),
        // written with e sin E and e cos E and b = β/e = 1/(1 + √(1 − e²)) (finite at e = 0).
        let b = 1.0 / (1.0 + (1.0 - e * e).sqrt());
        let excess = |e_sin: f64, e_cos: f64| 2.0 * (b * e_sin / (1.0 - b * e_cos)).atan();
        let true_anomaly_advance = (anomaly - anomaly0) + excess(e_sin, e_cos) - excess(e_sin0, e_cos0);
        let theta = theta0 + true_anomaly_advance.copysign(h);
        Some(([r, theta], [r_dot, h / (r * r)]))
    }
}

/// Solve Kepler's equation `E − e sin E = M` for `M ∈ [−π, π]`, `0 ≤ e < 1`.
///
/// `f(E) = E − e sin E − M` is increasing (`f' = 1 − e cos E ≥ 1 − e > 0`) with `f(−π) ≤ 0 ≤ f(π)`,
/// so Newton's iteration is safeguarded by bisection on that bracket: it converges for every
/// `e < 1` (tested to `e = 0.999`), quadratically once close. Start: Danby's `E = M + 0.85 e sgn(sin M)`.
fn solve_kepler_equation(e: f64, mean: f64) -> f64 {
    let (mut low, mut high) = (-PI, PI);
    let mut anomaly = (mean + 0.85 * e * mean.sin().signum()).clamp(low, high);
    for _ in 0..100 {
        let residual = anomaly - e * anomaly.sin() - mean;
        // Keep the bracket around the root.
        if residual > 0.0 {
            high = anomaly;
        } else {
            low = anomaly;
        }
        let newton = anomaly - residual / (1.0 - e * anomaly.cos());
        // Newton step if it stays in the bracket, bisection otherwise.
        let next = if newton > low && newton < high { newton } else { 0.5 * (low + high) };
        if (next - anomaly).abs() <= 4.0 * f64::EPSILON * PI {
            return next;
        }
        anomaly = next;
    }
    anomaly
}

impl Mechanism for Kepler {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (r, theta) = (q[0], q[1]);
        let (sin, cos) = theta.sin_cos();
        world_from_body[0] = Pose::point(r * cos, r * sin);
    }

    /// `V = −k/|x|`, through the particle's position so that the force is applied to it.
    fn potential<S: Scalar>(&self, _t: S, _q: &[S], world_from_body: &[Pose<S>]) -> Option<S> {
        let Pose { x, y, .. } = world_from_body[0];
        Some(-(x * x + y * y).sqrt().recip() * self.strength)
    }

    /// Plane polar coordinates describe the particle for `r > 0` only (at `r = 0` the
    /// potential is singular and `θ` moves no mass; past it `(r, θ)` and `(−r, θ + π)` are one
    /// point).
    fn admissible(&self, _t: f64, q: &[f64], _qdot: &[f64], bounds: &mut Bounds) -> bool {
        bounds.above("r", q[0], 0.0);
        true
    }
}

impl SceneType for Kepler {
    const ID: &'static str = "kepler";
    const TITLE: &'static str = "Central force: Kepler problem (V = −k/r)";
    const REFERENCE: &'static str =
        "docs/scenes.md#kepler; the lecture (docs/scenes.md#the-lecture), example: central force";
    param_table!();

    /// `r = 1`, `θ = 0`, `ṙ = 0`, `θ̇ = 1.2`: an ellipse with period ≈ 14.99 at the defaults.
    fn default_state(&self) -> State {
        State::new(0.0, [1.0, 0.0], [0.0, 1.2])
    }

    /// Bound orbits only; see [`Kepler::motion`].
    fn exact_solution(&self, initial: &State, t: f64) -> Option<State> {
        let motion = self.motion(&initial.q, &initial.qdot, t - initial.t);
        motion.map(|(q, qdot)| State::new(t, q, qdot))
    }

    /// [`E`](Kepler::energy), [`ℓ`](Kepler::angular_momentum) and the
    /// [Runge–Lenz vector](Kepler::runge_lenz).
    fn conserves_energy(&self) -> Vec<Conserved> {
        let (why, other) = ("Runge–Lenz vector: V ∝ 1/r", Invariant::Other);
        vec![
            Conserved::energy(self, Self::energy),
            Conserved::new(self, "ℓ", "θ is cyclic", Invariant::CyclicMomentum(1), |s, _, q, v| {
                s.angular_momentum(q, v)
            }),
            Conserved::new(self, "A_x", why, other, |s, _, q, qdot| s.runge_lenz(q, qdot)[0]),
            Conserved::new(self, "A_y", why, other, |s, _, q, qdot| s.runge_lenz(q, qdot)[1]),
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
        assert_engine_matches_closed_form_along::<Kepler, 2>(&POLAR_ROWS, &[("m", 2.5), ("k", 0.3)]);
    }

    #[test]
    fn default_orbit_has_the_documented_period() {
        let scene = Kepler::new(1.0, 1.0).unwrap();
        let orbit = scene.orbit(&[1.0, 0.0], &[0.0, 1.2]);
        // E = 0.72 − 1 = −0.28, a = 1/0.56, P = 2π a^{3/2}.
        assert_eq!(orbit.energy, 0.72 - 1.0);
        let a = 1.0 / 0.56;
        assert_close("a", &[a], &[orbit.semi_major_axis.unwrap()], 1e-15);
        assert_close("P", &[TAU * a.powf(1.5)], &[orbit.period.unwrap()], 1e-13);
        assert!((orbit.period.unwrap() - 14.99).abs() < 0.01);
        // Periapsis at r = 1 = p/(1 + e): p = 1.44, e = 0.44.
        assert_close("p, e", &[1.44, 0.44], &[orbit.semi_latus_rectum, orbit.eccentricity], 1e-15);
        // The Runge–Lenz vector points to the periapsis (θ = 0) with length m k e.
        assert_close("A", &[0.44, 0.0], &scene.runge_lenz(&[1.0, 0.0], &[0.0, 1.2]), 1e-15);
    }

    #[test]
    fn exact_solution_is_consistent_on_ellipses_of_every_eccentricity() {
        let params = scene_of::<Kepler>().default_params();
        let initials = [
            State::new(0.0, [1.0, 0.0], [0.0, 1.2]),
            State::new(0.3, [1.0, 2.0], [0.0, 1.0]),   // circular, e = 0
            State::new(0.0, [0.8, -1.0], [0.5, -1.1]), // clockwise
            State::new(1.0, [1.5, 4.0], [-0.3, 0.5]),
        ];
        for initial in &initials {
            assert_exact_solution_consistent(scene_of::<Kepler>(), &params, initial, &[0.4, 3.0, 11.0, 40.0]);
        }
    }

    /// After exactly one period the state returns to the start, with `θ` advanced by ±2π
    /// (the motion is continuous), for eccentricities up to 0.999.
    #[test]
    fn one_period_returns_to_the_start() {
        let scene = Kepler::new(1.3, 0.7).unwrap();
        let mut params = scene_of::<Kepler>().default_params();
        params.set("m", 1.3).unwrap();
        params.set("k", 0.7).unwrap();
        for (r_dot, theta_dot) in [(0.0, 0.6), (0.3, 0.2), (0.0, 0.0139), (-0.2, -0.8), (0.1, 0.01)] {
            let initial = State::new(0.5, [1.1, 0.4], [r_dot, theta_dot]);
            let orbit = scene.orbit(&initial.q, &initial.qdot);
            let period = orbit.period.unwrap();
            let after = scene_of::<Kepler>().exact_solution(&params, &initial, initial.t + period).unwrap().unwrap();
            let turn = TAU.copysign(theta_dot);
            let expected = [initial.q[0], initial.q[1] + turn, initial.qdot[0], initial.qdot[1]];
            let got = [after.q[0], after.q[1], after.qdot[0], after.qdot[1]];
            // Round-off of n·P = 2π and of the Newton solve, amplified by dr/dE near periapsis.
            assert_close(&format!("one period at e = {}", orbit.eccentricity), &expected, &got, 1e-9);
        }
        let nearly_parabolic = scene.orbit(&[1.1, 0.4], &[0.0, 0.0139]);
        assert!(nearly_parabolic.eccentricity > 0.999, "e = {}", nearly_parabolic.eccentricity);
    }

    #[test]
    fn kepler_equation_converges_up_to_high_eccentricity() {
        for e in [0.0, 0.1, 0.5, 0.9, 0.99, 0.999] {
            for k in 0..=40 {
                let mean = -PI + TAU * f64::from(k) / 40.0;
                let anomaly = solve_kepler_equation(e, mean);
                let residual = anomaly - e * anomaly.sin() - mean;
                assert!(residual.abs() <= 1e-14, "e = {e}, M = {mean}: E = {anomaly}, residual {residual:e}");
            }
        }
    }

    #[test]
    fn unbound_orbits_have_no_elliptic_solution() {
        let params = scene_of::<Kepler>().default_params();
        for qdot in [[0.0, 1.5], [1.0, 1.0], [0.0, 2.0_f64.sqrt()]] {
            let initial = State::new(0.0, [1.0, 0.0], qdot);
            assert_eq!(scene_of::<Kepler>().exact_solution(&params, &initial, 3.0), Ok(None), "q̇ = {qdot:?}");
        }
        let hyperbola = Kepler::new(1.0, 1.0).unwrap().orbit(&[1.0, 0.0], &[0.0, 1.5]);
        assert!(hyperbola.eccentricity > 1.0 && hyperbola.period.is_none() && hyperbola.semi_major_axis.is_none());
    }
}
