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

use lagrange::{State, System};
use lagrange_scenes::{Params, Scene, find};

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

/// `max_k |E_k − E_0| / |E_0|`.
fn relative_energy_error(energy: &[f64]) -> f64 {
    let e0 = energy[0];
    energy.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max) / e0.abs()
}

/// `(q, q̇)` of a state, concatenated.
fn phase(state: &State) -> Vec<f64> {
    [state.q.as_slice(), state.qdot.as_slice()].concat()
}
