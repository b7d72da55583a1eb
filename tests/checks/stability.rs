//! Stability: which methods stay stable and accurate, at what cost, against theory where
//! theory exists — stiff springs and strong damping at fixed steps (stability limits against
//! the stability functions of the methods), extreme parameters against closed forms and
//! conservation laws, a nearly parabolic Kepler orbit over 100 periods, chaos (how long two
//! tolerances agree), near-singular configurations, and long runs.

mod chaos;
mod extreme;
mod kepler;
mod long_run;
mod singular;
mod stiff;

use lagrange::System;
use lagrange_scenes::{Params, Scene, find};
use lagrange_validation::fixtures::{phase, relative_energy_error};

fn scene(id: &str) -> &'static dyn Scene {
    find(id).unwrap_or_else(|| panic!("scene {id} is registered"))
}

/// The scene's defaults with `changes` applied (by parameter name).
fn params(id: &str, changes: &[(&str, f64)]) -> Params {
    let mut params = scene(id).default_params();
    for &(name, value) in changes {
        params.set(name, value).unwrap_or_else(|e| panic!("{id}: {name} = {value}: {e}"));
    }
    params
}

/// The scene's simulation with these parameters.
fn build(id: &str, params: &Params) -> Box<dyn System> {
    scene(id).build(params).unwrap_or_else(|e| panic!("{id}: {e}"))
}
