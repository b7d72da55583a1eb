//! The exact motion of the plane pendulum `ψ̈ = −ω² sin ψ` (`ψ` from the downward vertical) in
//! Jacobi elliptic functions, for the mechanisms whose parallelogram branch is one pendulum
//! (`parallelogram_chain`, `redundant_parallelogram`; docs/scenes.md#parallelogram_chain).
//!
//! With `C = ψ̇² + 4ω² sin²(ψ/2)` (twice the energy per unit `I`, from the bottom) the motion
//! rotates when `C > 4ω²` and librates when `C < 4ω²` (e.g. Lawden, *Elliptic Functions and
//! Applications*, §5.2; Whittaker, *Analytical Dynamics*, §44):
//!
//! * rotation, `m = 4ω²/C`: `u = ψ/2` obeys `u̇² = (C/4)(1 − m sin² u)`, so
//!   `ψ/2 = am(σ (√C/2) t + F(ψ₀/2 | m) | m)` and `ψ̇ = σ √C dn(…)`, `σ` the sign of `ψ̇₀`;
//! * libration, `m = κ² = C/(4ω²)`: `sin(ψ/2) = κ sn(ω t + w₀ | m)`, `ψ̇ = 2κω cn(ω t + w₀ | m)`,
//!   with `am(w₀) = atan2(sin(ψ₀/2), ψ̇₀/(2ω))` (so that `sn(w₀)`, `cn(w₀)` give the initial
//!   angle and rate) about the nearest bottom `2πj`;
//! * the separatrix `C = 4ω²`: `ψ/2 = gd(σ ω t + gd⁻¹(ψ₀/2))`, `gd` the Gudermannian.

use crate::elliptic::{amplitude, incomplete_first_kind};
use lagrange::State;
use std::f64::consts::{FRAC_PI_2, PI};

/// How far a state may be from the parallelogram branch and still count as on it, relative to
/// `1 + max |q|` for the angles and `1 + max |q̇|` for the rates. States on the branch are on
/// it to round-off (the exact solution, ~1e-15 of that scale) — except near the flat position:
/// there the loop residuals grow only quadratically off the branch, so a state consistent to
/// round-off (`|Φ|` ~ ε) may be `√ε` ≈ 1.5e-8 away, and projections onto the constraints, which
/// converge only linearly there, stop further out (1.7e-7 measured for an assembled state).
/// A consistent state off the branch is O(1) away, except near that crossing of the branches;
/// there its rates still differ by O(|q̇|), since the branches cross at an angle. 1e-6 leaves
/// a margin over the first and stays far below the second.
const ON_BRANCH: f64 = 1e-6;

/// The parallelogram branch of a linkage of parallel unit cranks on ground pivots, joined by
/// couplers whose angles are measured from their crank: on it every crank has the same angle
/// `θ` (absolute, from +x) and every coupler keeps its ground-parallel orientation (relative
/// angle `−θ`, mod 2π), so the whole linkage is one pendulum in `ψ = θ + π/2`:
/// `T = ½ I θ̇²`, `V = W sin θ` give `ψ̈ = −ω² sin ψ` with `ω² = W/I`, which each scene
/// derives for its links.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ParallelBranch {
    /// Indices in `q` of the cranks' absolute angles.
    pub(crate) cranks: Vec<usize>,
    /// Indices in `q` of the couplers' angles relative to their cranks.
    pub(crate) couplers: Vec<usize>,
    /// `ω²` (1/s²).
    pub(crate) omega_squared: f64,
}

/// `x` reduced to `[−π, π]` by whole turns.
fn wrapped(x: f64) -> f64 {
    x - 2.0 * PI * (x / (2.0 * PI)).round()
}

impl ParallelBranch {
    /// Whether `(q, q̇)` lies on the branch ([`ON_BRANCH`]): every crank at the first crank's
    /// angle and rate, every coupler at minus them (angles mod 2π).
    pub(crate) fn contains(&self, q: &[f64], qdot: &[f64]) -> bool {
        let (theta, rate) = (q[self.cranks[0]], qdot[self.cranks[0]]);
        let angle_scale = ON_BRANCH * (1.0 + q.iter().fold(0.0_f64, |m, v| m.max(v.abs())));
        let rate_scale = ON_BRANCH * (1.0 + qdot.iter().fold(0.0_f64, |m, v| m.max(v.abs())));
        let cranks = self
            .cranks
            .iter()
            .all(|&i| wrapped(q[i] - theta).abs() <= angle_scale && (qdot[i] - rate).abs() <= rate_scale);
        let couplers = self
            .couplers
            .iter()
            .all(|&i| wrapped(q[i] + theta).abs() <= angle_scale && (qdot[i] + rate).abs() <= rate_scale);
        cranks && couplers
    }

    /// `q̈` on the branch: `θ̈ = −ω² cos θ` for every crank (`ψ̈ = −ω² sin ψ` with
    /// `ψ = θ + π/2`), `−θ̈` for every coupler; no velocity term, since `T = ½ I θ̇²` with `I`
    /// constant.
    pub(crate) fn accelerations(&self, q: &[f64], qddot: &mut [f64]) {
        let alpha = -self.omega_squared * q[self.cranks[0]].cos();
        for &i in &self.cranks {
            qddot[i] = alpha;
        }
        for &i in &self.couplers {
            qddot[i] = -alpha;
        }
    }

    /// The exact state at `t` from `initial` on the branch ([`pendulum`] in `ψ = θ + π/2`), each
    /// coordinate moved by the same turn `±Δθ` (so each keeps its own multiple of 2π); `None`
    /// for an initial state off the branch.
    pub(crate) fn exact(&self, initial: &State, t: f64) -> Option<State> {
        if !self.contains(&initial.q, &initial.qdot) {
            return None;
        }
        let (theta, rate) = (initial.q[self.cranks[0]], initial.qdot[self.cranks[0]]);
        let (psi, psi_rate) = pendulum(self.omega_squared, theta + FRAC_PI_2, rate, t - initial.t);
        let turn = psi - FRAC_PI_2 - theta;
        let (mut q, mut qdot) = (initial.q.clone(), initial.qdot.clone());
        for &i in &self.cranks {
            q[i] += turn;
            qdot[i] = psi_rate;
        }
        for &i in &self.couplers {
            q[i] -= turn;
            qdot[i] = -psi_rate;
        }
        Some(State::new(t, q, qdot))
    }
}

/// `(ψ, ψ̇)` at time `t` of `ψ̈ = −ω² sin ψ` from `(ψ₀, ψ̇₀)` at time 0, for `ω² ≥ 0`.
pub(crate) fn pendulum(omega_squared: f64, psi: f64, rate: f64, t: f64) -> (f64, f64) {
    let omega = omega_squared.sqrt();
    let half_sin = (0.5 * psi).sin();
    let c = rate * rate + 4.0 * omega_squared * half_sin * half_sin;
    let sign = if rate < 0.0 { -1.0 } else { 1.0 };
    if omega_squared == 0.0 || c == 0.0 {
        // No gravity (free turning), or at rest at a bottom.
        return (psi + rate * t, rate);
    }
    let separatrix = 4.0 * omega_squared;
    if c > separatrix {
        // Rotation: ψ/2 = am(σ (√C/2) t + F(ψ₀/2)).
        let m = separatrix / c;
        let w = sign * 0.5 * c.sqrt() * t + incomplete_first_kind(0.5 * psi, m);
        let half = amplitude(w, m);
        let s = half.sin();
        (2.0 * half, sign * c.sqrt() * (1.0 - m * s * s).sqrt())
    } else if c < separatrix {
        // Libration about the nearest bottom 2πj: sin(ψ/2) = κ sn(ω t + w₀), cos(ψ/2) = dn.
        let bottom = 2.0 * PI * (psi / (2.0 * PI)).round();
        let m = c / separatrix;
        let kappa = m.sqrt();
        let start = (0.5 * (psi - bottom)).sin().atan2(rate / (2.0 * omega));
        let phase = amplitude(omega * t + incomplete_first_kind(start, m), m);
        let (sn, cn) = phase.sin_cos();
        let dn = (1.0 - m * sn * sn).sqrt();
        (bottom + 2.0 * (kappa * sn).atan2(dn), 2.0 * kappa * omega * cn)
    } else {
        // The separatrix: ψ/2 − jπ = gd(σ ω t + gd⁻¹(ψ₀/2 − jπ)), gd(x) = atan(sinh x).
        let turns = (0.5 * psi / PI).round();
        let half = 0.5 * psi - turns * PI;
        if rate == 0.0 {
            // At rest at the top.
            return (psi, 0.0);
        }
        let x = sign * omega * t + half.tan().asinh();
        (2.0 * (turns * PI + x.sinh().atan()), sign * 2.0 * omega / x.cosh())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::assert_close;
    use lagrange::{Description, Mechanism, Method, Model, Output, Pose, Scalar, State, Tolerances, simulate};

    /// A point bob on a massless rod of length 1 under gravity `ω²`: `ψ̈ = −ω² sin ψ`.
    struct Bob {
        description: Description,
    }

    impl Bob {
        /// The bob (1 kg) at angle `ψ` under gravity `ω²`.
        fn new(omega_squared: f64) -> Self {
            Bob { description: Description::new().angle("ψ").point("bob", 1.0).gravity(omega_squared) }
        }
    }

    impl Mechanism for Bob {
        fn description(&self) -> &Description {
            &self.description
        }

        fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
            world_from_body[0] = Pose::point(q[0].sin(), -q[0].cos());
        }
    }

    /// Rotating, librating (also about the bottom 2π, and with a large amplitude), and close to
    /// the separatrix from both sides, at the gravity of `parallelogram_chain`'s default
    /// `ω² = 3 g (3N + 1)/(2 (4N + 1))`, N = 4.
    fn cases() -> Vec<(f64, f64, f64)> {
        let omega_squared: f64 = 3.0 * 9.81 * 13.0 / (2.0 * 17.0);
        let separatrix = 2.0 * omega_squared.sqrt();
        vec![
            (omega_squared, 0.0, 8.0),
            (omega_squared, 1.0, -0.5),
            (omega_squared, 2.0 * PI - 0.3, 2.0),
            (omega_squared, 3.0, 0.0),
            (omega_squared, -0.2, -9.5),
            (omega_squared, 0.0, separatrix * (1.0 + 1e-6)),
            (omega_squared, 0.0, separatrix * (1.0 - 1e-6)),
        ]
    }

    /// Values by mpmath 1.3.0 (`odefun`, a Taylor integrator, at 30 digits, from the exact
    /// double inputs) of `ψ̈ = −ω² sin ψ`, `ω² = 3 · 9.81 · 13/34`: the exact solution
    /// reproduces them to `1e-13` (absolute, rad and rad/s). Its error is that of the elliptic
    /// functions (a few ε, see `elliptic.rs`) times the growth of errors along the motion: a
    /// relative error `δ` of the argument `w ≈ (√C/2) t` (up to ~40 at t = 10) moves `ψ` by up
    /// to `2 δ w`, ~80 ε ≈ 2e-14.
    #[test]
    fn values_match_a_high_precision_integration() {
        let omega_squared: f64 = 3.0 * 9.81 * 13.0 / (2.0 * 17.0);
        let separatrix = 2.0 * omega_squared.sqrt();
        let rows: [(f64, f64, f64, f64, f64); 6] = [
            (0.0, 8.0, 0.7, 3.972619494786211, 5.13064221490721),
            (0.0, 8.0, 10.0, 60.2218150234894, 4.7004988532712675),
            (1.0, -0.5, 3.1, -0.9051437862130358, 1.410314988098783),
            (3.0, 0.0, 10.0, 2.8784401714735197, -0.7413021607393832),
            (0.0, separatrix * (1.0 + 1e-6), 4.0, 3.476792714297287, 1.1192108991299163),
            (0.0, separatrix * (1.0 - 1e-6), 4.0, 2.8063849148844597, -1.1191558593499398),
        ];
        for (psi, rate, t, expected_psi, expected_rate) in rows {
            let (got_psi, got_rate) = pendulum(omega_squared, psi, rate, t);
            let what = format!("ψ₀ = {psi}, ψ̇₀ = {rate}, t = {t}");
            // Near the separatrix the problem itself is ill-conditioned in doubles: `C` and
            // `4ω²` are known to ε relative, so `1 − m` only to `ε/|1 − m|` relative (1e-10 at
            // the rows 1e-6 from it, where 3.2e-11 was measured), and `K`, the phase and `ψ`
            // move by about that much.
            let c = rate * rate + 4.0 * omega_squared * (0.5 * psi).sin().powi(2);
            let conditioning = f64::EPSILON / (1.0 - 4.0 * omega_squared / c).abs();
            assert_close(&what, &[expected_psi, expected_rate], &[got_psi, got_rate], 1e-13 + conditioning);
        }
    }

    /// Against the project's own Dop853 at `rtol = atol = 1e-14` over 20 s, sampled every
    /// 0.5 s. The integrator's global error is the bound: its local errors are held to 1e-14
    /// of `1 + |y|` (|ψ| up to ~150 rad after 20 s of turning) over some 10⁴ steps and add up
    /// with the flow's linear growth of phase errors, so up to ~1e-9 rad at 20 s (measured at
    /// most 4.3e-11, from rest near the top); the elliptic solution itself is good to ~1e-13
    /// (the test above). A wrong sign or period would differ by O(1) within a second. The two
    /// motions 1e-6 from the separatrix are left out: each pass near the top multiplies the
    /// integrator's error by ~e^(ω Δt), so the comparison measures the integrator (2.5e-8
    /// there); the 30-digit references above cover them.
    #[test]
    fn matches_a_tight_numerical_integration_over_20_seconds() {
        for (omega_squared, psi, rate) in cases().into_iter().take(5) {
            let model = Model::new(Bob::new(omega_squared)).unwrap();
            let method = Method::Dop853 { tol: Tolerances::uniform(1e-14) };
            let run = simulate(&model, &State::new(0.0, [psi], [rate]), 20.0, method, &Output::Every(0.5)).unwrap();
            let mut worst: f64 = 0.0;
            for k in 0..run.len() {
                let (exact_psi, exact_rate) = pendulum(omega_squared, psi, rate, run.t[k]);
                worst = worst.max((exact_psi - run.q(k)[0]).abs()).max((exact_rate - run.qdot(k)[0]).abs());
            }
            eprintln!("ψ₀ = {psi}, ψ̇₀ = {rate}: exact vs Dop853 over 20 s, worst {worst:e}");
            assert!(worst <= 1e-9, "ψ₀ = {psi}, ψ̇₀ = {rate}: exact vs Dop853 differ by {worst:e}");
        }
    }

    /// `½ ψ̇² − ω² cos ψ` is the same at 200 times over 20 s, to 1e-12 of `C`: the energy of
    /// the exact solution is exact up to the elliptic functions' round-off (a few ε relative in
    /// `sn`, `dn`) and the growth of the argument (see above).
    #[test]
    fn conserves_energy() {
        for (omega_squared, psi, rate) in cases() {
            let energy = |psi: f64, rate: f64| 0.5 * rate * rate - omega_squared * psi.cos();
            let start = energy(psi, rate);
            let scale = rate * rate + 4.0 * omega_squared;
            for k in 0..=200 {
                let (p, r) = pendulum(omega_squared, psi, rate, 0.1 * f64::from(k));
                let drift = (energy(p, r) - start).abs();
                assert!(drift <= 1e-12 * scale, "ψ₀ = {psi}, ψ̇₀ = {rate}, t = {}: drift {drift:e}", 0.1 * k as f64);
            }
        }
    }

    /// At `t = 0` the solution is the initial state, to a few ε (the round trip `am(F(φ))`).
    #[test]
    fn starts_at_the_initial_state() {
        for (omega_squared, psi, rate) in cases() {
            let (p, r) = pendulum(omega_squared, psi, rate, 0.0);
            assert_close(&format!("ψ₀ = {psi}, ψ̇₀ = {rate}"), &[psi, rate], &[p, r], 1e-14 * (1.0 + rate.abs()));
        }
    }

    /// The branch test: whole turns of any coordinate and round-off are on the branch; an angle
    /// or a rate 1e-4 off it is not (far above [`ON_BRANCH`]), nor the folded window of
    /// `parallelogram_chain` (coupler at `π` from its crank, the next crank pointing back).
    #[test]
    fn the_branch_is_told_apart_from_its_neighbours() {
        let branch = ParallelBranch { cranks: vec![0, 2], couplers: vec![1], omega_squared: 10.0 };
        let (theta, rate) = (-0.7, 3.0);
        let on = |q: [f64; 3], qdot: [f64; 3]| branch.contains(&q, &qdot);
        assert!(on([theta, -theta, theta], [rate, -rate, rate]));
        assert!(on([theta + 2.0 * PI, -theta - 4.0 * PI, theta], [rate, -rate, rate * (1.0 + f64::EPSILON)]));
        assert!(!on([theta, -theta, theta + 1e-4], [rate, -rate, rate]));
        assert!(!on([theta, -theta, theta], [rate, -rate + 1e-4, rate]));
        assert!(!on([theta, PI, PI], [rate, 0.0, 0.0]));
        let mut qddot = [0.0; 3];
        branch.accelerations(&[theta, -theta, theta], &mut qddot);
        let alpha = -10.0 * theta.cos();
        assert_eq!(qddot, [alpha, -alpha, alpha]);
    }

    /// Exactly on the separatrix the pendulum creeps to the top: `ψ → π` as `t → ∞`, with
    /// `ψ̇ = 2ω cos(ψ/2)` (energy exactly `ω²`); after `ω t = 12`, `π − ψ ≈ 4 e⁻¹² ≈ 2.5e-5`.
    /// At rest at the top or the bottom it stays.
    #[test]
    fn separatrix_and_rest() {
        let omega_squared = 4.0;
        let (p, r) = pendulum(omega_squared, 0.0, 4.0, 6.0);
        assert!((PI - p) < 1e-4 && r > 0.0, "ψ = {p}, ψ̇ = {r}");
        // ψ/2 ≈ π/2 carries its rounding, ~2.2e-16, into cos(ψ/2), times 2ω = 4.
        assert!((r - 4.0 * (0.5 * p).cos()).abs() <= 4e-15, "ψ̇ = {r} vs 2ω cos(ψ/2)");
        assert_eq!(pendulum(omega_squared, PI, 0.0, 2.0), (PI, 0.0));
        assert_eq!(pendulum(omega_squared, 0.0, 0.0, 2.0), (0.0, 0.0));
    }
}
