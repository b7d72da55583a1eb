//! rapier builds of the scenes (impulse and multibody joints, f64 and f32).
//! (Being written: see `build`.)

use crate::{BuildError, Built, Engine, Settings};
use lagrange::State;
use lagrange_scenes::Params;

/// Build the rapier simulation of `scene` in `engine` (one of the four rapier engines).
///
/// # Errors
/// As [`crate::build`].
pub fn build(engine: Engine, scene: &str, params: &Params, initial: &State, settings: &Settings) -> Result<Built, BuildError> {
    let _ = (params, initial, settings);
    Err(BuildError::Unbuildable { engine, scene: scene.into(), reason: "not implemented yet".into() })
}
