//! Argument parsing shared by the commands: scenes, parameters, state vectors.

use crate::error::CliError;
use lagrange::State;
use lagrange_scenes::{Params, Scene};

/// Find a scene by id (the validation library's one lookup), or say which exist.
pub fn scene(id: &str) -> Result<&'static dyn Scene, CliError> {
    lagrange_validation::scene(id).map_err(CliError::Argument)
}

/// The scene's parameters with `NAME=VALUE` overrides (name or symbol).
pub fn params(scene: &dyn Scene, overrides: &[String]) -> Result<Params, CliError> {
    let mut params = scene.default_params();
    for item in overrides {
        let (key, value) = item.split_once('=').ok_or_else(|| CliError::ParamForm(item.clone()))?;
        let value: f64 = value
            .trim()
            .parse()
            .map_err(|_| CliError::NotANumber { flag: format!("--param {key}"), value: value.to_string() })?;
        params.set(key.trim(), value).map_err(CliError::Param)?;
    }
    Ok(params)
}

/// A comma-separated list of numbers with the scene's arity.
pub fn vector(flag: &'static str, text: &str, coordinates: &[lagrange::Coordinate]) -> Result<Vec<f64>, CliError> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| {
            let v = v.trim();
            v.parse::<f64>().map_err(|_| CliError::NotANumber { flag: flag.to_string(), value: v.to_string() })
        })
        .collect::<Result<_, _>>()?;
    if values.len() != coordinates.len() {
        let coordinates = coordinates.iter().map(|c| c.name.clone()).collect();
        return Err(CliError::Arity { flag, coordinates, got: values.len() });
    }
    if let Some(&value) = values.iter().find(|v| !v.is_finite()) {
        return Err(CliError::NotFinite { flag, value });
    }
    Ok(values)
}

/// The scene's default state with optional overrides of `q`, `q̇` and `t`.
pub fn state(
    scene: &dyn Scene,
    params: &Params,
    q: Option<&str>,
    qdot: Option<&str>,
    t: Option<f64>,
) -> Result<State, CliError> {
    let coordinates = scene.coordinates(params)?;
    let mut state = scene.default_state(params)?;
    if let Some(q) = q {
        state.q = vector("--q", q, &coordinates)?;
    }
    if let Some(qdot) = qdot {
        state.qdot = vector("--qdot", qdot, &coordinates)?;
    }
    if let Some(t) = t {
        if !t.is_finite() {
            return Err(CliError::NotFinite { flag: "--t", value: t });
        }
        state.t = t;
    }
    Ok(state)
}
