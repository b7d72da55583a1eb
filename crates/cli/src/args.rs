//! Argument parsing shared by the commands: scenes, parameters, state vectors.

use lagrange::State;
use lagrange_scenes::{Params, Scene};

/// Find a scene by id (the validation library's one lookup), or say which exist.
pub fn scene(id: &str) -> Result<&'static dyn Scene, String> {
    lagrange_validation::scene(id).map_err(|e| e.to_string())
}

/// The scene's parameters with `NAME=VALUE` overrides (name or symbol).
pub fn params(scene: &dyn Scene, overrides: &[String]) -> Result<Params, String> {
    let mut params = scene.default_params();
    for item in overrides {
        let (key, value) =
            item.split_once('=').ok_or_else(|| format!("--param `{item}` is not of the form NAME=VALUE"))?;
        let value: f64 = value.trim().parse().map_err(|_| format!("--param {key}: `{value}` is not a number"))?;
        params.set(key.trim(), value).map_err(|e| e.to_string())?;
    }
    Ok(params)
}

/// A comma-separated list of numbers with the scene's arity.
pub fn vector(flag: &str, text: &str, coordinates: &[lagrange::Coordinate]) -> Result<Vec<f64>, String> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| v.trim().parse::<f64>().map_err(|_| format!("{flag}: `{}` is not a number", v.trim())))
        .collect::<Result<_, _>>()?;
    if values.len() != coordinates.len() {
        let names: Vec<&str> = coordinates.iter().map(|c| c.name.as_str()).collect();
        return Err(format!("{flag} needs {} values ({}), got {}", coordinates.len(), names.join(", "), values.len()));
    }
    if let Some(bad) = values.iter().find(|v| !v.is_finite()) {
        return Err(format!("{flag}: {bad} is not finite"));
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
) -> Result<State, String> {
    let coordinates = scene.coordinates(params).map_err(|e| e.to_string())?;
    let mut state = scene.default_state(params).map_err(|e| e.to_string())?;
    if let Some(q) = q {
        state.q = vector("--q", q, &coordinates)?;
    }
    if let Some(qdot) = qdot {
        state.qdot = vector("--qdot", qdot, &coordinates)?;
    }
    if let Some(t) = t {
        if !t.is_finite() {
            return Err(format!("--t: {t} is not finite"));
        }
        state.t = t;
    }
    Ok(state)
}
