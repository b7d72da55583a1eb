//! The Newton iterations of the implicit integrators: a value that stops being finite inside
//! one is a divergence that names it, never a Newton failure with a residual of NaN.

use super::*;
use crate::{Coordinate, Lagrangian, RawModel, Scalar, State};

/// `L = ½ ẋ² − 1/x`: an attraction whose potential is infinite at `x = 0`.
struct InverseDistance {
    coordinates: [Coordinate; 1],
}

impl Lagrangian for InverseDistance {
    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }
    fn lagrangian<S: Scalar>(&self, _t: S, q: &[S], v: &[S]) -> S {
        v[0] * v[0] * 0.5 - q[0].recip()
    }
}

/// From `x = 1` at `ẋ = −10` with `dt = 0.2`, the predictor of the first step puts the midpoint
/// at `x = 1 − 10 · 0.1 = 0` exactly, where `∂L/∂x = 1/x²` is infinite: the error names it
/// and the Newton iteration.
#[test]
fn a_non_finite_derivative_inside_variational_newton_is_named() {
    let raw = RawModel::new(InverseDistance { coordinates: [Coordinate::length("x")] }).unwrap();
    let initial = State::new(0.0, [1.0], [-10.0]);
    let result = simulate(&raw, &initial, 1.0, Method::Variational { dt: 0.2 }, &Output::Ends);
    match result {
        Err(Error::Diverged { t, step, quantity }) => {
            assert_eq!((t, step), (0.0, 0));
            assert_eq!(quantity, "∂L/∂q[x] = inf in Newton iteration 1 of the variational integrator");
        }
        other => panic!("{other:?}"),
    }
}

/// `L = ½ ((c + ẋ g(x))² + (ẋ s(x))²) − ½ x²` with `g = 1 − x²/2`, `s = x − x³/6`: a pendulum-like
/// oscillator whose support moves at the constant speed `c` (cosine and sine replaced by their
/// Taylor polynomials, so that every operation is IEEE arithmetic and the rounding below is the
/// same on every platform). Its momentum `p = (c + ẋ g) g + ẋ s²` carries `c g` ≈ 0.28 whatever
/// the velocity, as the driven pendulum's carries its drive.
struct MovingSupport {
    coordinates: [Coordinate; 1],
}

/// The support's speed `c`.
const C: f64 = 0.3 + 1e-3 * std::f64::consts::SQRT_2;

impl Lagrangian for MovingSupport {
    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }
    fn lagrangian<S: Scalar>(&self, _t: S, q: &[S], v: &[S]) -> S {
        let x = q[0];
        let g = -(x * x) * 0.5 + 1.0;
        let s = x - x * x * x * (1.0 / 6.0);
        let (vx, vy) = (v[0] * g + C, v[0] * s);
        (vx * vx + vy * vy) * 0.5 - x * x * 0.5
    }
}

/// The integrator on [`MovingSupport`] started at `x = 0.4`, `ẋ = v0`.
fn moving_support(v0: f64) -> (RawModel<MovingSupport>, Variational<RawModel<MovingSupport>>) {
    let raw = RawModel::new(MovingSupport { coordinates: [Coordinate::length("x")] }).unwrap();
    let mut integrator = Variational::new(&raw);
    integrator.start(&raw, 0.0, &[0.4], &[v0]).unwrap();
    (raw, integrator)
}

/// From `ẋ₀` = 2.50451e-3 the step of 0.0125 has `Δq` ≈ −6.9e-9 (midpoint velocity −5.5e-7):
/// Newton's update of `Δq` cannot fall below the rounding of the residual, whose terms are
/// ≈ 0.28 (5.6e-17 · h ≈ 7e-19 in `Δq`, 1.0e-10 of `|Δq|`), so the test relative to `|Δq|`
/// alone (1e-10) alternated between two neighbouring values for 50 iterations and failed. It
/// stops at that plateau, with the residual at the rounding of the momenta (measured 5.6e-17,
/// one unit in the last place of 0.28; the bound is two roundings of `c`).
#[test]
fn variational_step_converges_where_the_midpoint_velocity_nearly_vanishes() {
    let (raw, mut integrator) = moving_support(2.50451e-3);
    integrator.step(&raw, 0.0125).unwrap();
    assert!(integrator.stats().newton_iterations <= 5, "{:?}", integrator.stats());
    assert!(integrator.max_residual <= 2.0 * f64::EPSILON * C, "{:e}", integrator.max_residual);
}

/// From `ẋ₀` = 4.90002e-3 the step of 0.0125 ends at `ẋ₁` ≈ −1.1e-4: Newton on the Legendre map
/// cannot bring its update below the rounding of `p₁` ≈ 0.28 (5.6e-17 in `ẋ`, 5e-13 of `|ẋ₁|`),
/// so the test relative to `|ẋ|` alone alternated for 50 iterations and failed (as the driven
/// pendulum's read at dt = 0.0125, t = 4.15 did). It stops at that plateau, at the closed-form
/// inverse `ẋ = (p − c g)/(g² + s²)` to within the roundings of both (measured 2.7e-17; bound
/// four roundings of `c`).
#[test]
fn legendre_inversion_converges_near_a_turning_point() {
    let (raw, mut integrator) = moving_support(4.90002e-3);
    integrator.step(&raw, 0.0125).unwrap();
    let stepped = integrator.stats();
    let mut qdot = [f64::NAN];
    integrator.velocities(&raw, &mut qdot).unwrap();
    let (x, p) = (integrator.q()[0], integrator.momenta()[0]);
    let (g, s) = (1.0 - x * x / 2.0, x - x * x * x / 6.0);
    let exact = (p - C * g) / (g * g + s * s);
    assert!(integrator.stats().newton_iterations - stepped.newton_iterations <= 5, "{:?}", integrator.stats());
    assert!((qdot[0] - exact).abs() <= 4.0 * f64::EPSILON * C, "{} vs {exact}", qdot[0]);
}
