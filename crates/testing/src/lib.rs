//! # lagrange-testing — the numeric helpers every check shares
//!
//! The engine's and the scenes' unit tests, the maximal builds' tests, the integration tests
//! and the validation library all measure with the same few functions: one seeded random
//! generator, the NaN-aware maxima of vectors, a closeness assertion and the condition number
//! of a symmetric matrix. They take plain `f64` slices and depend on no crate of the
//! workspace, so any crate's unit tests can use them without building a second copy of the
//! crate under test (or rapier).
//!
//! ```
//! use lagrange_testing::{assert_close, max_abs, max_abs_diff};
//!
//! assert_eq!(max_abs(&[1.0, -3.0, 2.0]), 3.0);
//! assert!(max_abs_diff(&[1.0, f64::NAN], &[1.0, 2.0]).is_nan());
//! assert_close("sum", &[0.3], &[0.1 + 0.2], 1e-15);
//! ```
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// The random generator of every check: reproducible, from a fixed seed.
pub type Rng = ChaCha8Rng;

/// A reproducible random generator: every random input of every check comes from a fixed seed.
pub fn rng(seed: u64) -> Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// `max(a, b)` that propagates a NaN (`f64::max` returns the other operand and hides it).
pub fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() { f64::NAN } else { a.max(b) }
}

/// `max_i |a_i|` (0 for an empty slice); NaN if any entry is NaN.
pub fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, x| nan_max(m, x.abs()))
}

/// `max_i |a_i − b_i|` (0 when both are empty); NaN if any difference is NaN or the lengths
/// differ, so that neither a NaN on either side nor a missing entry is hidden behind a finite
/// maximum.
pub fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    if a.len() != b.len() {
        return f64::NAN;
    }
    a.iter().zip(b).fold(0.0, |m, (x, y)| nan_max(m, (x - y).abs()))
}

/// Assert `|got_i − expected_i| ≤ tolerance` for every entry (and equal lengths), printing
/// expected, got and the residual on failure; returns the largest residual. A NaN anywhere
/// fails.
///
/// # Panics
/// When the lengths differ or a residual exceeds `tolerance` or is NaN.
pub fn assert_close(what: &str, expected: &[f64], got: &[f64], tolerance: f64) -> f64 {
    assert_eq!(expected.len(), got.len(), "{what}: expected {expected:?}, got {got:?} (lengths differ)");
    let worst = max_abs_diff(expected, got);
    assert!(
        worst <= tolerance,
        "{what}:\n  expected {expected:?}\n  got      {got:?}\n  max residual {worst:e} > tolerance {tolerance:e}"
    );
    worst
}

/// Spectral condition number `λ_max / λ_min` of a symmetric positive definite matrix
/// (`n × n`, row-major), from nalgebra's symmetric eigenvalues (absolute values, so that a
/// round-off-negative smallest eigenvalue of a nearly singular matrix gives a large, positive
/// condition number).
pub fn condition_number(n: usize, m: &[f64]) -> f64 {
    let eigen = nalgebra::DMatrix::from_row_slice(n, n, m).symmetric_eigenvalues();
    let (low, high) = eigen.iter().fold((f64::INFINITY, 0.0_f64), |(l, h), &e| (l.min(e.abs()), h.max(e.abs())));
    high / low
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maxima_propagate_nan() {
        assert_eq!(max_abs(&[1.0, -3.0, 2.0]), 3.0);
        assert_eq!(max_abs_diff(&[1.0, 2.0], &[1.5, -1.0]), 3.0);
        assert!(max_abs(&[1.0, f64::NAN, 2.0]).is_nan());
        assert!(max_abs_diff(&[f64::NAN, 2.0], &[1.0, 2.0]).is_nan());
        assert!(max_abs_diff(&[1.0, 2.0], &[1.0, f64::NAN]).is_nan());
    }

    #[test]
    #[should_panic(expected = "max residual NaN")]
    fn assert_close_fails_on_nan() {
        assert_close("nan", &[1.0], &[f64::NAN], 1.0);
    }

    #[test]
    fn condition_numbers_of_known_matrices() {
        // diag(1, 4) turned by 30°.
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let m = [c * c + 4.0 * s * s, 3.0 * c * s, 3.0 * c * s, s * s + 4.0 * c * c];
        assert!((condition_number(2, &m) - 4.0).abs() < 1e-12);
        let mut d = [0.0; 16];
        for (i, v) in [2.0, 1e-3, 5.0, 1.0].into_iter().enumerate() {
            d[i * 4 + i] = v;
        }
        assert!((condition_number(4, &d) / 5e3 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn the_generator_is_reproducible() {
        use rand::Rng as _;
        let (mut a, mut b) = (rng(7), rng(7));
        assert_eq!(a.random::<u64>(), b.random::<u64>());
    }
}
