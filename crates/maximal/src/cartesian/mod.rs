//! Cartesian coordinates with holonomic constraints and Lagrange multipliers.
//! (Being written: see `build`.)

use crate::{BuildError, Built, Engine, Settings};
use lagrange::State;
use lagrange_scenes::Params;

/// Build the Cartesian + multiplier simulation of `scene`.
///
/// # Errors
/// As [`crate::build`].
pub fn build(scene: &str, params: &Params, initial: &State, settings: &Settings) -> Result<Built, BuildError> {
    let _ = (params, initial, settings);
    Err(BuildError::Unbuildable { engine: Engine::Cartesian, scene: scene.into(), reason: "not implemented yet".into() })
}
