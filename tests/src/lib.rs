//! Support for the integration tests: seeded random inputs, tolerances with their reasons,
//! and sampling of scene parameters and states.

pub mod sampling;
pub mod tolerance;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// A reproducible random generator: every random input of every test comes from a fixed seed.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// `max_i |a_i − b_i|`.
pub fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len(), "length mismatch");
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// `max_i |a_i|`.
pub fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// Spectral condition number of a symmetric positive definite matrix (n × n, row-major).
pub fn condition_number(n: usize, m: &[f64]) -> f64 {
    let matrix = nalgebra::DMatrix::from_row_slice(n, n, m);
    let eigen = matrix.symmetric_eigenvalues();
    eigen.max() / eigen.min()
}
