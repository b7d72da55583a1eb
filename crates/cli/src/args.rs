//! Argument parsing shared by the commands: scenes, parameters, state vectors.

use crate::error::CliError;
use crate::output::compact;
use lagrange::State;
use lagrange_scenes::{Params, Scene};

/// Find a scene by id (the validation library's one lookup), or say which exist; a path to a
/// scene file (`*.toml`, or any file that exists) is read and registered under its id, once.
pub fn scene(id: &str) -> Result<&'static dyn Scene, CliError> {
    if is_scene_file(id) {
        return scene_file(id);
    }
    lagrange_validation::scene(id).map_err(CliError::Argument)
}

/// Whether a scene argument names a file rather than a built-in scene.
fn is_scene_file(argument: &str) -> bool {
    argument.ends_with(".toml") || std::path::Path::new(argument).is_file()
}

/// The scene of the file at `path`, registered the first time it is asked for (a command may
/// resolve its scene more than once).
fn scene_file(path: &str) -> Result<&'static dyn Scene, CliError> {
    static LOADED: std::sync::Mutex<Vec<(String, &'static dyn Scene)>> = std::sync::Mutex::new(Vec::new());
    let mut loaded = LOADED.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some((_, scene)) = loaded.iter().find(|(p, _)| p == path) {
        return Ok(*scene);
    }
    let scene = lagrange_file::register(path).map_err(CliError::File)?;
    loaded.push((path.to_string(), scene));
    Ok(scene)
}

/// The scene's parameters with `NAME=VALUE` overrides (name, symbol, or the symbol in ASCII:
/// `alpha` for `α`), each parameter at most once.
pub fn params(scene: &dyn Scene, overrides: &[String]) -> Result<Params, CliError> {
    let mut params = scene.default_params();
    let mut given: Vec<(&'static str, &String)> = Vec::new();
    for item in overrides {
        let (key, value) = item.split_once('=').ok_or_else(|| CliError::ParamForm(item.clone()))?;
        let value = number(&format!("--param {}", key.trim()), value.trim())?;
        params.set(key.trim(), value).map_err(CliError::Param)?;
        // `set` accepted the key, so it names a parameter.
        if let Some(spec) = params.spec(key.trim()) {
            if let Some((_, first)) = given.iter().find(|(name, _)| *name == spec.name) {
                return Err(CliError::RepeatedParam { name: spec.name, first: (*first).clone(), second: item.clone() });
            }
            given.push((spec.name, item));
        }
    }
    Ok(params)
}

/// A fixed step `dt` (flag `flag`) for a run ending at `t_end`: positive, finite, and large
/// enough to advance the time at `t_end` (a step below the spacing of `f64` there, such as
/// 1e-320, would leave `t + dt == t`).
///
/// # Errors
/// [`CliError::NotPositive`] or [`CliError::StepBelowResolution`], naming the flag.
pub fn step(flag: &'static str, dt: f64, t_end: f64) -> Result<f64, CliError> {
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(CliError::NotPositive { flag, value: dt });
    }
    let t = t_end.abs();
    if t + dt == t {
        // The gap from `t` to the next f64 above it.
        let spacing = f64::from_bits(t.to_bits() + 1) - t;
        return Err(CliError::StepBelowResolution { flag, value: dt, t: t_end, spacing });
    }
    Ok(dt)
}

/// Inputs at the edge of `f64`'s range: a nonzero magnitude above 1e150 or below 1e-150, whose
/// square (or the square of its reciprocal) overflows `f64` (largest ≈ 1.8e308), the usual way an
/// acceleration becomes infinite or NaN at an otherwise valid state. Named as the user gives them:
/// `--param mass = 1e-320`, `--qdot x = 1e200`, `--q θ = 1e300`, `--t = 1e200`.
pub fn extreme_inputs(params: &Params, names: &[String], state: &State) -> Vec<String> {
    let extreme = |v: f64| v != 0.0 && !(1e-150..=1e150).contains(&v.abs());
    let mut found: Vec<String> = params
        .iter()
        .filter(|(_, v)| extreme(*v))
        .map(|(spec, v)| format!("--param {} = {}", spec.name, compact(v)))
        .collect();
    for (flag, values) in [("--q", &state.q), ("--qdot", &state.qdot)] {
        for (name, &v) in names.iter().zip(values.iter()) {
            if extreme(v) {
                found.push(format!("{flag} {name} = {}", compact(v)));
            }
        }
    }
    if extreme(state.t) {
        found.push(format!("--t = {}", compact(state.t)));
    }
    found
}

/// An engine error at a state, with the extreme inputs named when the engine met a non-finite
/// value ([`extreme_inputs`]): "non-finite accelerations" alone does not say which input to
/// change.
pub fn explain(error: lagrange::Error, params: &Params, names: &[String], state: &State) -> CliError {
    // A quantity derived from the parameters that overflowed (`inertia of disc` = ½ m R² = inf
    // at R = 1e300) is named with the inputs it came from.
    let derived_overflow = matches!(error, lagrange::Error::InvalidParameter { value, .. } if !value.is_finite());
    if matches!(error, lagrange::Error::NonFinite { .. }) || derived_overflow {
        let extremes = extreme_inputs(params, names, state);
        if !extremes.is_empty() {
            return CliError::Extreme { source: error, extremes: extremes.join(", ") };
        }
    }
    CliError::Engine(error)
}

/// `text` as a number for `flag`: a decimal beyond `f64`'s range (`1e400`) is named as such,
/// not read as the infinity it rounds to.
///
/// # Errors
/// [`CliError::NotANumber`], [`CliError::OutOfRange`].
pub fn number(flag: &str, text: &str) -> Result<f64, CliError> {
    let value: f64 =
        text.parse().map_err(|_| CliError::NotANumber { flag: flag.to_string(), value: text.to_string() })?;
    if value.is_infinite() && !text.to_ascii_lowercase().contains("inf") {
        return Err(CliError::OutOfRange { flag: flag.to_string(), value: text.to_string() });
    }
    Ok(value)
}

/// The scene's system with `params`, a failure explained as [`explain`] does (at the given
/// state, for the extreme inputs it names).
///
/// # Errors
/// The scene's, explained.
pub fn build(scene: &dyn Scene, params: &Params, state: &State) -> Result<Box<dyn lagrange::System>, CliError> {
    scene.build(params).map_err(|error| {
        let names: Vec<String> =
            scene.coordinates(params).map(|c| c.iter().map(|c| c.name.clone()).collect()).unwrap_or_default();
        explain(error, params, &names, state)
    })
}

/// A comma-separated list of numbers with the scene's arity.
pub fn vector(flag: &'static str, text: &str, coordinates: &[lagrange::Coordinate]) -> Result<Vec<f64>, CliError> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| {
            let v = v.trim();
            number(flag, v)
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

/// The state `initial` brought onto the scene's constraints among its coordinates, keeping the
/// coordinates named in `hold` (comma-separated names, e.g. `θ2`) and their rates
/// ([`lagrange_validation::start::hold`]); `initial` itself without `--hold`, if it is already
/// on them.
///
/// # Errors
/// [`CliError::Hold`] for an unknown name, a scene without constraints, or an inconsistent
/// state without `--hold`; the engine's
/// [`lagrange::Error::AssemblyFailed`] when the links cannot close from there.
pub fn hold(system: &mut dyn lagrange::System, initial: State, hold: Option<&str>) -> Result<State, CliError> {
    use lagrange_validation::start::{self, HoldError};
    let names: Option<Vec<&str>> = hold.map(|h| h.split(',').map(str::trim).collect());
    start::hold(system, initial, names.as_deref(), |name| format!("--hold {name}")).map_err(|error| match error {
        HoldError::Refused(why) => CliError::Hold { why },
        HoldError::Engine(error) => CliError::Engine(error),
    })
}

/// `--jobs`: the threads a command runs its independent work on (the report's scenes,
/// `compare`'s engines), by default the number of cores.
///
/// # Errors
/// [`CliError::NotPositive`] for 0.
pub fn jobs(jobs: Option<usize>) -> Result<usize, CliError> {
    match jobs {
        Some(0) => Err(CliError::NotPositive { flag: "--jobs", value: 0.0 }),
        Some(jobs) => Ok(jobs),
        None => Ok(std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)),
    }
}

/// The scene and the state a run starts from, as `compare` and `animate` take them.
#[derive(clap::Args, Debug)]
pub struct Start {
    /// Scene id (see `lagrange scenes`) or scene file (`*.toml`, docs/files.md).
    pub scene: String,
    /// Parameter override NAME=VALUE (name or symbol), repeatable.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
    /// Initial coordinates (default: the scene's initial state); with `animate --mode`, where
    /// to start looking for the equilibrium.
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    pub q: Option<String>,
    /// Initial velocities (default: the scene's initial state).
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    pub qdot: Option<String>,
    /// For a mechanism with constraints among its coordinates (a four-bar): bring the initial
    /// state onto them, keeping these coordinates and their rates (comma-separated names, e.g.
    /// `θ2`); the others move as little as possible. Without it, a given state must already
    /// satisfy the constraints.
    #[arg(long, value_name = "NAME,..")]
    pub hold: Option<String>,
}

impl Start {
    /// The scene, its parameters and the given state (not yet brought onto the constraints).
    ///
    /// # Errors
    /// An unknown scene, a bad parameter or a bad state vector.
    pub fn resolve(&self) -> Result<(&'static dyn Scene, Params, State), CliError> {
        let scene = scene(&self.scene)?;
        let params = params(scene, &self.params)?;
        let given = state(scene, &params, self.q.as_deref(), self.qdot.as_deref(), None)?;
        Ok((scene, params, given))
    }

    /// [`resolve`](Self::resolve), the state brought onto the constraints as `--hold` says.
    ///
    /// # Errors
    /// As `resolve`, and a state that cannot be held.
    pub fn initial(&self) -> Result<(&'static dyn Scene, Params, State), CliError> {
        let (scene, params, given) = self.resolve()?;
        let initial = hold(build(scene, &params, &given)?.as_mut(), given, self.hold.as_deref())?;
        Ok((scene, params, initial))
    }
}

/// The maximal engines' numerical settings, as `compare` and `animate` take them.
#[derive(clap::Args, Debug)]
pub struct EngineSettings {
    /// rapier step (s) [default: 1/240].
    #[arg(long, default_value_t = 1.0 / 240.0, hide_default_value = true, allow_negative_numbers = true)]
    pub dt: f64,
    /// rapier substeps per step.
    #[arg(long, default_value_t = 4)]
    pub substeps: usize,
    /// Tolerance of the Cartesian engine's integrator.
    #[arg(long, default_value = "1e-12", allow_negative_numbers = true)]
    pub tol: f64,
}

impl EngineSettings {
    /// As the engines take them.
    pub fn settings(&self) -> lagrange_maximal::Settings {
        lagrange_maximal::Settings { dt: self.dt, substeps: self.substeps, tolerance: self.tol }
    }
}
