//! The rapier2d (f32) build: `world.rs` compiled with `Real = f32`.

use rapier2d as rapier;

/// f64 into rapier's `Real`, rounded to the nearest f32.
fn real(x: f64) -> rapier::math::Real {
    x as f32
}

/// rapier's `Real` into f64 (exact).
fn wide(x: rapier::math::Real) -> f64 {
    f64::from(x)
}

#[allow(clippy::duplicate_mod, reason = "the same source is also compiled against rapier2d-f64 in `double`")]
#[path = "world.rs"]
pub(super) mod world;
