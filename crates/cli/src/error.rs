//! The command line's one error type, [`CliError`], and the exit code of each kind.
//!
//! Two kinds of error: a bad argument value (the user asked for something that cannot be done:
//! exit [`USAGE`], 2, as for clap's own errors) and a runtime failure (the engine, the file
//! system or a validation run failed on a valid request: exit [`FAILURE`], 1).

use crate::output::compact;
use lagrange_maximal::{BuildError, Engine};
use std::path::PathBuf;

/// Exit code of a bad argument value (and of clap's own usage errors).
pub const USAGE: u8 = 2;

/// Exit code of a runtime failure.
pub const FAILURE: u8 = 1;

/// Everything a command of `lagrange` can fail with. Its message is one line, naming what is
/// wrong (the flag and the value for a bad argument, the path for a file).
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    // Bad argument values (exit 2).
    /// A scene file that cannot be read or is not a valid scene (drawn on its text by
    /// [`FileError::render`](lagrange_file::FileError::render)).
    #[error("{0}")]
    File(lagrange_file::FileError),
    /// `scenes --export` of a scene that is not a joint graph.
    #[error(
        "`{0}` is not a joint graph: only joint-graph scenes export to a file (coordinates-form files of built-in scenes are in examples/scenes)"
    )]
    NotAGraph(String),
    /// `eom` of a built-in scene written in Rust (not a joint graph).
    #[error(
        "`{0}` is written in Rust, not as a joint graph: print the equations of its coordinates-form file (examples/scenes/{0}.toml)"
    )]
    NotAFile(String),
    /// A `--param` that is not `NAME=VALUE`.
    #[error("--param `{0}` is not of the form NAME=VALUE")]
    ParamForm(String),
    /// A value that does not parse as a number.
    #[error("{flag}: `{value}` is not a number")]
    NotANumber {
        /// The flag, with the parameter's name for `--param`.
        flag: String,
        /// The text given.
        value: String,
    },
    /// A decimal beyond the range of `f64` (about ±1.8e308), which would read as infinity.
    #[error("{flag}: `{value}` is beyond the range of f64 (largest about 1.8e308)")]
    OutOfRange {
        /// The flag, with the parameter's name for `--param`.
        flag: String,
        /// The text given.
        value: String,
    },
    /// A coordinate list (`--q`, `--qdot`) with the wrong number of values.
    #[error("{flag} needs {} values ({}), got {got}", .coordinates.len(), .coordinates.join(", "))]
    Arity {
        /// The flag.
        flag: &'static str,
        /// The scene's coordinates, by name.
        coordinates: Vec<String>,
        /// How many values were given.
        got: usize,
    },
    /// `--hold` naming a coordinate the scene does not have, or given for a scene without
    /// constraints among its coordinates.
    #[error("--hold: {why}")]
    Hold {
        /// What is wrong.
        why: String,
    },
    /// A value that is NaN or infinite.
    #[error("{flag}: {} is not finite", compact(*.value))]
    NotFinite {
        /// The flag.
        flag: &'static str,
        /// The value.
        value: f64,
    },
    /// A duration, step or interval that is not positive and finite.
    #[error("{flag} must be positive and finite, got {}", compact(*.value))]
    NotPositive {
        /// The flag.
        flag: &'static str,
        /// The value.
        value: f64,
    },
    /// A rapier step longer than the run: no sample after the first would fall on a step.
    #[error("--dt {} is longer than the run (--t-end {}): rapier would not take one step inside it", compact(*.dt), compact(*.t_end))]
    StepBeyondRun {
        /// The step.
        dt: f64,
        /// The simulated time.
        t_end: f64,
    },
    /// A step too small to advance the time over the run: `t + dt` rounds back to `t`.
    #[error(
        "{flag} {} is below the resolution of the time at t = {} (the spacing of f64 there is {}): \
         a step would not advance the time",
        compact(*.value), compact(*.t), compact(*.spacing)
    )]
    StepBelowResolution {
        /// The flag.
        flag: &'static str,
        /// The step.
        value: f64,
        /// The latest time of the run.
        t: f64,
        /// The spacing of the `f64` values at `t`.
        spacing: f64,
    },
    /// The same parameter given twice (by its name, symbol or ASCII spelling).
    #[error("--param {name} is given twice (`{first}`, then `{second}`); give each parameter once")]
    RepeatedParam {
        /// The parameter's name.
        name: &'static str,
        /// The first `--param`.
        first: String,
        /// The repeated `--param`.
        second: String,
    },
    /// A setting the chosen integrator does not take (`--dt` for an error-controlled one,
    /// `--tol` for a fixed-step one).
    #[error("{flag} does not apply to the {integrator} integrator: it applies to {applies_to}; use {instead}")]
    NotForIntegrator {
        /// The flag given.
        flag: &'static str,
        /// The integrator chosen.
        integrator: &'static str,
        /// The integrators that take the flag.
        applies_to: &'static str,
        /// The flag the chosen integrator takes instead.
        instead: &'static str,
    },
    /// An `--engine` that is not one of the maximal engines or `all`.
    #[error("unknown engine `{0}`; expected one of {names}, all", names = engine_names())]
    UnknownEngine(String),
    /// An empty `--out`.
    #[error("--out: the output directory must not be empty")]
    EmptyOut,
    /// A `--param` value the scene rejects: an unknown name, or a value outside the parameter's
    /// domain.
    #[error("--param: {0}")]
    Param(#[source] lagrange::Error),
    /// An argument the validation library rejects: an unknown scene, a report horizon off the
    /// sample grid.
    #[error(transparent)]
    Argument(lagrange_validation::Error),
    /// A request whose estimated cost (wall time or output size) is beyond the documented limit
    /// (`commands::long_work`); `--force` runs it anyway.
    #[error("{estimate}, beyond the limit of {limit}: change {flag}, or pass --force to run it anyway")]
    TooCostly {
        /// The estimate and what it is made of.
        estimate: String,
        /// The limit, in words.
        limit: &'static str,
        /// The flag to change.
        flag: &'static str,
    },
    /// `simulate --t-end` not after `--start`.
    #[error("--t-end ({t_end}) must be after --start ({start})")]
    EndBeforeStart {
        /// The initial time.
        start: f64,
        /// The end time.
        t_end: f64,
    },

    // Runtime failures (exit 1, except where the engine rejects a value the user gave: see
    // [`CliError::exit_code`]).
    /// The engine failed: a singular mass matrix, a non-finite value, a diverging or stiff
    /// integration; or it rejected a setting (`invalid step`, `invalid tolerance`).
    #[error(transparent)]
    Engine(#[from] lagrange::Error),
    /// A maximal engine, or the reduced reference run it is compared with, failed in
    /// `lagrange compare`.
    #[error("{}", compare_message(*.engine, .source))]
    Compare {
        /// The engine.
        engine: Engine,
        /// What failed.
        source: lagrange_validation::Error,
    },
    /// The engine failed with a non-finite value at a state or with parameters of which some
    /// lie at the edge of `f64`'s range (see [`crate::args::extreme_inputs`]), named.
    #[error("{source}; inputs at the edge of f64's range: {extremes}")]
    Extreme {
        /// The engine's error.
        source: lagrange::Error,
        /// The extreme inputs, as `--param mass = 1e-320, --qdot x = 1e200`.
        extremes: String,
    },
    /// `lagrange accel --check`: the engine's `q̈` and the scene's closed form differ beyond the
    /// round-off bound of two exact formulas.
    #[error(
        "the engine's q̈ differs from the closed form by {} (relative to its largest |q̈_i|), beyond the \
         round-off bound {} = max(1e-12, 64 ε κ(M)) at κ(M) = {}",
        compact(*.difference), compact(*.bound), compact(*.condition_number)
    )]
    Disagreement {
        /// `max_i |q̈_i − closed_i| / max_i |closed_i|` (absolute when the closed form is 0).
        difference: f64,
        /// The bound it exceeds.
        bound: f64,
        /// The condition number of the mass matrix at the state.
        condition_number: f64,
    },
    /// A run that did not keep what its scene declares (a constant of the motion, the
    /// constraints) to the error its method and setting allow.
    #[error(
        "the run of {scene} with {method} did not keep what the scene declares: {findings}; the result is \
         not to be trusted (expected relative error {expected:.2e}): use a smaller {flag}, or --allow-drift to keep \
         it anyway"
    )]
    Unhealthy {
        /// The scene's id.
        scene: String,
        /// The method and its setting (`rk4 at dt = 1e-3`).
        method: String,
        /// What drifted, joined.
        findings: String,
        /// The run's expected relative error.
        expected: f64,
        /// The flag that sets the accuracy: `--dt` or `--tol`.
        flag: &'static str,
    },
    /// A run that failed after it had diverged: the failure is a consequence, the divergence
    /// the cause.
    #[error(
        "the run of {scene} with {method} diverged ({findings}) before it stopped with: {source}; \
         use a smaller {flag}"
    )]
    DivergedFirst {
        /// The scene's id.
        scene: String,
        /// The method and its setting.
        method: String,
        /// What drifted, joined.
        findings: String,
        /// The error the run stopped with.
        source: Box<lagrange::Error>,
        /// The flag that sets the accuracy.
        flag: &'static str,
    },
    /// A run whose step size collapsed where the motion is not stiff: the stiffness test's
    /// verdict refuted by the Jacobian.
    #[error(
        "the run of {scene} with {method} stopped at t = {} with the step at h = {}, far below the explicit \
         method's stability limit there (about 3.3 / ω = {} for the fastest rate ω = {} 1/s): not stiffness; \
         the motion is not resolved there (a singular configuration, a discontinuity, or a tolerance too loose \
         for the motion: {source})",
        compact(*.t), compact(*.h), compact(3.3 / *.rate), compact(*.rate)
    )]
    NotStiff {
        /// The scene's id.
        scene: String,
        /// The method and its setting.
        method: String,
        /// Where it stopped.
        t: f64,
        /// The last step.
        h: f64,
        /// The fastest rate of the motion there.
        rate: f64,
        /// The error the run stopped with.
        source: Box<lagrange::Error>,
    },
    /// A run stopped by `--max-seconds`, with what it had by then.
    #[error("{what} stopped after {:.2} s of wall time ({limit}): {why}; what it had is written", .elapsed)]
    OutOfTime {
        /// What was stopped, and how far it got.
        what: String,
        /// Wall time when it stopped (s).
        elapsed: f64,
        /// The limit: `--max-seconds S`, or the default watch of a request estimated within
        /// the time limit.
        limit: String,
        /// Why (the deadline, or the projected time).
        why: String,
    },
    /// The operating system refused the report's worker threads.
    #[error("cannot start the report's threads: {0}")]
    Threads(String),
    /// The validation library failed: a reference, a sweep or a stability case could not run.
    #[error(transparent)]
    Validation(#[from] lagrange_validation::Error),
    /// A file could not be written.
    #[error("cannot write {}: {source}", .path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The report's output directory (`--out`) cannot be created or written into.
    #[error("--out {}: {what}: {source}", .path.display())]
    OutputDirectory {
        /// The directory.
        path: PathBuf,
        /// What failed: `cannot create the output directory`, `cannot write into it`.
        what: &'static str,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// Standard output could not be written.
    #[error("cannot write to standard output: {0}")]
    Stdout(#[source] std::io::Error),
    /// A result could not be serialized as JSON.
    #[error("cannot serialize the output as JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// A plot could not be drawn or written.
    #[error("cannot draw {}: {source}", .path.display())]
    Plot {
        /// The SVG file.
        path: PathBuf,
        /// What went wrong drawing it.
        source: lagrange_validation::render::plots::PlotError,
    },
}

/// The maximal engines' names, comma-separated.
fn engine_names() -> String {
    Engine::ALL.iter().map(|e| e.name()).collect::<Vec<_>>().join(", ")
}

/// The message of [`CliError::Compare`]: the engine and its failure, or that the reduced
/// reference run failed (the engine is then not to blame).
fn compare_message(engine: Engine, source: &lagrange_validation::Error) -> String {
    match source {
        lagrange_validation::Error::Reference { scene, source } => {
            format!("{scene}: the reduced reference run (to compare {engine} with) failed: {source}")
        }
        source => format!("{engine}: {source}"),
    }
}

/// Whether the engine rejected a value out of its domain (a parameter, a step, a tolerance, an
/// output time): a value the user gave, so a bad argument rather than a failure.
fn rejects_a_value(error: &lagrange::Error) -> bool {
    matches!(error, lagrange::Error::InvalidParameter { .. } | lagrange::Error::InvalidSetting { .. })
}

impl CliError {
    /// The process exit code: [`USAGE`] (2) for a bad argument value, including a value the
    /// engine rejects as outside its domain (`--tol 0`, an `--every` off the step grid, a rapier
    /// `--dt 0`); [`FAILURE`] (1) for everything that fails at run time.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::ParamForm(_)
            | CliError::File(_)
            | CliError::NotAGraph(_)
            | CliError::NotAFile(_)
            | CliError::NotANumber { .. }
            | CliError::OutOfRange { .. }
            | CliError::Arity { .. }
            | CliError::Hold { .. }
            | CliError::NotFinite { .. }
            | CliError::NotPositive { .. }
            | CliError::StepBelowResolution { .. }
            | CliError::StepBeyondRun { .. }
            | CliError::RepeatedParam { .. }
            | CliError::NotForIntegrator { .. }
            | CliError::UnknownEngine(_)
            | CliError::EmptyOut
            | CliError::Param(_)
            | CliError::Argument(_)
            | CliError::TooCostly { .. }
            | CliError::EndBeforeStart { .. } => USAGE,
            CliError::Engine(e)
            | CliError::Compare {
                source:
                    lagrange_validation::Error::Engine(e)
                    | lagrange_validation::Error::Reference { source: e, .. }
                    | lagrange_validation::Error::Build(BuildError::Invalid(e)),
                ..
            } if rejects_a_value(e) => USAGE,
            CliError::Engine(_)
            | CliError::Compare { .. }
            | CliError::Extreme { .. }
            | CliError::Disagreement { .. }
            | CliError::Unhealthy { .. }
            | CliError::DivergedFirst { .. }
            | CliError::NotStiff { .. }
            | CliError::OutOfTime { .. }
            | CliError::Validation(_)
            | CliError::Io { .. }
            | CliError::OutputDirectory { .. }
            | CliError::Stdout(_)
            | CliError::Json(_)
            | CliError::Plot { .. }
            | CliError::Threads(_) => FAILURE,
        }
    }
}
