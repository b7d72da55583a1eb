//! The rapier2d-f64 build: `world.rs` compiled with `Real = f64`.

use rapier2d_f64 as rapier;

/// f64 into rapier's `Real` (the identity here).
fn real(x: f64) -> rapier::math::Real {
    x
}

/// rapier's `Real` into f64 (the identity here).
fn wide(x: rapier::math::Real) -> f64 {
    x
}

#[allow(clippy::duplicate_mod, reason = "the same source is also compiled against rapier2d (f32) in `single`")]
#[path = "world.rs"]
pub(super) mod world;
