//! Support for the integration tests: sampling of scene parameters and states. The shared
//! numeric helpers (seeded generator, maxima, closeness, condition number) are
//! `lagrange-testing`'s and the tolerances with their reasons the validation library's, both
//! re-exported here.

pub mod sampling;

pub use lagrange_testing::{condition_number, max_abs, max_abs_diff, rng};
pub use lagrange_validation::tolerance;

use lagrange_scenes::Scene;

/// The registered scene `id` (through the validation library's one lookup); panics on an
/// unknown id, which in a test is a bug of the test.
pub fn scene(id: &str) -> &'static dyn Scene {
    lagrange_validation::scene(id).unwrap_or_else(|e| panic!("{e}"))
}
