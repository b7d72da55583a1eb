//! The report's stability section: for each case, which methods stay stable and accurate, at
//! what cost, against theory where theory exists. One file per group of cases: `stiff.rs`
//! (stiff springs, strong damping), `extreme.rs` (extreme parameters), `orbit.rs` (Kepler at
//! `e = 0.99`), `chaos.rs` (double pendulum), `singular.rs` (near-singular configurations),
//! `constrained.rs` (closed loops and redundant constraints), `long_run.rs` (10⁷ steps),
//! `bad_input.rs` (random and invalid input); the stability functions behind the theory values
//! are in [`theory`], the serialized types are here, and report.md's section and the terminal
//! lines are rendered by [`crate::render::stability`].
//!
//! Every measurement is one row: what was run (scene, parameters, method, settings), what was
//! measured (a quantity and its value, or the run's failure), the theory value and the bound
//! it is checked against where one exists, pass or fail, and the cost (steps, evaluations,
//! Jacobians, factorizations, wall time).

use crate::Error;
use crate::scene as find;
mod bad_input;
mod branch;
mod chaos;
mod constrained;
mod extreme;
mod long_run;
mod orbit;
mod singular;
mod stiff;
pub mod theory;

use crate::measure::relative_energy_error;
use lagrange::integrate::Stats;
use lagrange::{Method, Output, State, System, Trajectory};
use lagrange_scenes::{Params, Scene};
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::Instant;

/// How much runs: the full report or `--quick`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effort {
    /// The full report.
    Full,
    /// `--quick`: fewer parameters, shorter horizons, fewer long-run steps.
    Quick,
}

impl Effort {
    /// `full` or `quick` value.
    fn pick<T>(self, full: T, quick: T) -> T {
        match self {
            Effort::Full => full,
            Effort::Quick => quick,
        }
    }
}

/// The `stability` object of report.json.
#[derive(Clone, Debug, Serialize)]
pub struct StabilityReport {
    /// `full` or `quick`.
    pub mode: &'static str,
    /// One entry per case, in the order of `CASES`.
    pub cases: Vec<Case>,
    /// Measurements that passed their check.
    pub passed: usize,
    /// Measurements that failed their check.
    pub failed: usize,
    /// Measurements reported without a check (no theory or bound applies).
    pub unchecked: usize,
    /// Wall time of the whole section (s).
    pub wall_time_s: f64,
}

impl StabilityReport {
    /// The report of no case at `effort` (a run stopped before the suite).
    pub fn default_for(effort: Effort) -> StabilityReport {
        StabilityReport {
            mode: effort.pick("full", "quick"),
            cases: Vec::new(),
            passed: 0,
            failed: 0,
            unchecked: 0,
            wall_time_s: 0.0,
        }
    }
}

/// One case.
#[derive(Clone, Debug, Serialize)]
pub struct Case {
    /// Identifier (`stiff_spring`, …).
    pub id: &'static str,
    /// One-line title.
    pub title: &'static str,
    /// The scenes it runs (scene ids; a local mechanism is named after the scene it varies).
    pub scenes: Vec<&'static str>,
    /// What was run, in words.
    pub setup: String,
    /// The theory the measurements are checked against, in words (with its source).
    pub theory: &'static str,
    /// The measurements.
    pub measurements: Vec<Measurement>,
    /// Whether every checked measurement passed (null when none is checked).
    pub pass: Option<bool>,
    /// Wall time of the case (s).
    pub wall_time_s: f64,
}

/// How a measurement's value is checked.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Check {
    /// `|value / theory − 1| ≤ bound`.
    RelativeToTheory,
    /// `|value − theory| ≤ bound`.
    AbsoluteToTheory,
    /// `max(value/theory, theory/value) ≤ bound` (both positive).
    WithinFactor,
    /// `value ≤ bound`.
    AtMost,
    /// `value ≥ bound`.
    AtLeast,
    /// `value == theory` exactly.
    Exact,
    /// The run must end in the engine's error of the expected variant (`expected_error`): any
    /// other error, or a value, fails.
    TypedError,
    /// A finite value (`status` = `ok`, `value` not null).
    Finite,
    /// A finite value or a typed error — never a non-finite value returned as a value.
    FiniteOrTypedError,
    /// Reported only.
    None,
}

/// The variant of an engine error (`lagrange::Error`), as recorded and as expected by a
/// [`Check::TypedError`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ErrorKind {
    /// `InvalidParameter`.
    InvalidParameter,
    /// `DimensionMismatch`.
    DimensionMismatch,
    /// `SingularMassMatrix`.
    SingularMassMatrix,
    /// `NonFinite`.
    NonFinite,
    /// `Diverged`.
    Diverged,
    /// `InvalidSetting`.
    InvalidSetting,
    /// `Inadmissible`: the state left the scene's admissible region.
    Inadmissible,
    /// `InconsistentConstraints`: dependent constraint rows that contradict each other.
    InconsistentConstraints,
    /// `AssemblyFailed`: the constraints cannot be met from the given positions.
    AssemblyFailed,
    /// Any other variant (a failing integration: step-size underflow, too many steps, …).
    Other,
}

impl ErrorKind {
    /// The variant of `error`.
    pub fn of(error: &lagrange::Error) -> ErrorKind {
        use lagrange::Error as E;
        match error {
            E::InvalidParameter { .. } => ErrorKind::InvalidParameter,
            E::DimensionMismatch { .. } => ErrorKind::DimensionMismatch,
            E::SingularMassMatrix { .. } => ErrorKind::SingularMassMatrix,
            E::NonFinite { .. } => ErrorKind::NonFinite,
            E::Diverged { .. } => ErrorKind::Diverged,
            E::InvalidSetting { .. } => ErrorKind::InvalidSetting,
            E::Inadmissible { .. } => ErrorKind::Inadmissible,
            E::InconsistentConstraints { .. } => ErrorKind::InconsistentConstraints,
            E::AssemblyFailed { .. } => ErrorKind::AssemblyFailed,
            _ => ErrorKind::Other,
        }
    }
}

/// The settings of a measurement's run (null where they do not apply).
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct RunSettings {
    /// Fixed step, or rapier step (s).
    pub dt: Option<f64>,
    /// Tolerance of an adaptive method (relative = absolute unless said).
    pub tolerance: Option<f64>,
    /// rapier substeps.
    pub substeps: Option<usize>,
    /// Simulated time (s).
    pub horizon_s: Option<f64>,
}

/// The cost of a measurement's run (null where not counted).
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Cost {
    /// Steps (accepted steps for adaptive methods; rapier steps; for a bisection, the total).
    pub steps: Option<usize>,
    /// Evaluations of `q̈`.
    pub evaluations: Option<usize>,
    /// Evaluations of the acceleration Jacobian (implicit Runge–Kutta methods).
    pub jacobians: Option<usize>,
    /// LU factorizations of a Newton matrix.
    pub factorizations: Option<usize>,
    /// Steps taken by RK4 substeps where Gauss's Newton iteration did not converge (see
    /// `lagrange::integrate::Stats::fallbacks`).
    pub fallbacks: Option<usize>,
    /// Wall time (s).
    pub wall_time_s: f64,
}

impl Cost {
    fn of(stats: &Stats, wall_time: f64) -> Cost {
        let some = |n: usize| (n > 0).then_some(n);
        Cost {
            steps: Some(stats.steps),
            evaluations: some(stats.evaluations),
            jacobians: some(stats.jacobians),
            factorizations: some(stats.factorizations),
            fallbacks: some(stats.fallbacks),
            wall_time_s: wall_time,
        }
    }
}

/// One measurement.
#[derive(Clone, Debug, Serialize)]
pub struct Measurement {
    /// Short label within the case (`k/m = 1e6`).
    pub label: String,
    /// Scene id (with `local:` for a mechanism built for the case).
    pub scene: String,
    /// Parameters that differ from the scene's defaults, and those the case varies.
    pub parameters: BTreeMap<String, f64>,
    /// `rk4`, `adaptive`, `variational`, `implicit`, `gauss`, `rapier-impulse`,
    /// `rapier-multibody`, `cartesian`, or `engine` for direct evaluations.
    pub method: &'static str,
    /// The run's settings.
    pub settings: RunSettings,
    /// What is measured, with its unit.
    pub quantity: String,
    /// The value (null when the run failed before it could be measured, or it is not finite).
    pub value: Option<f64>,
    /// The theory value, where one exists.
    pub theory: Option<f64>,
    /// How the value is checked.
    pub check: Check,
    /// The bound of the check.
    pub bound: Option<f64>,
    /// Whether the check passed (null for `check: none`).
    pub pass: Option<bool>,
    /// `ok`, or `failed` when the run ended in an error.
    pub status: &'static str,
    /// The error of a failed run, or a remark.
    pub note: Option<String>,
    /// The variant of the engine error the run ended in, where it ended in one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<ErrorKind>,
    /// The variant a [`Check::TypedError`] expects.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expected_error: Option<ErrorKind>,
    /// What the run cost.
    pub cost: Cost,
}

impl Measurement {
    /// A measurement of `quantity` on `scene` with `method`, not yet valued or checked.
    fn new(label: impl Into<String>, scene: &str, method: &'static str, quantity: &str) -> Measurement {
        Measurement {
            label: label.into(),
            scene: scene.to_string(),
            parameters: BTreeMap::new(),
            method,
            settings: RunSettings::default(),
            quantity: quantity.to_string(),
            value: None,
            theory: None,
            check: Check::None,
            bound: None,
            pass: None,
            status: "ok",
            note: None,
            error: None,
            expected_error: None,
            cost: Cost::default(),
        }
    }

    fn params(mut self, parameters: &[(&str, f64)]) -> Self {
        self.parameters.extend(parameters.iter().map(|&(k, v)| (k.to_string(), v)));
        self
    }

    fn method_settings(mut self, method: Method, horizon: f64) -> Self {
        self.settings = match method {
            Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss4 { dt } => {
                RunSettings { dt: Some(dt), horizon_s: Some(horizon), ..RunSettings::default() }
            }
            Method::Dopri5 { tol } | Method::Dop853 { tol } | Method::Sdirk4 { tol } => {
                RunSettings { tolerance: Some(tol.rtol), horizon_s: Some(horizon), ..RunSettings::default() }
            }
        };
        self
    }

    fn settings(mut self, settings: RunSettings) -> Self {
        self.settings = settings;
        self
    }

    fn cost(mut self, cost: Cost) -> Self {
        self.cost = cost;
        self
    }

    fn note(mut self, note: impl Into<String>) -> Self {
        self.note = Some(note.into());
        self
    }

    /// The measured value (a non-finite value is recorded as null with a note).
    fn value(mut self, value: f64) -> Self {
        if value.is_finite() {
            self.value = Some(value);
        } else {
            self.value = None;
            let remark = format!("the measured value is {value}");
            self.note = Some(match self.note.take() {
                Some(note) => format!("{note}; {remark}"),
                None => remark,
            });
        }
        self
    }

    /// The run failed: its error, and no value.
    fn failed(mut self, error: impl std::fmt::Display) -> Self {
        self.status = "failed";
        self.value = None;
        self.note = Some(error.to_string());
        self
    }

    /// A failure by the engine's `error`, its variant recorded (for [`Check::TypedError`]).
    fn failed_with(self, error: &lagrange::Error) -> Self {
        let mut m = self.failed(error);
        m.error = Some(ErrorKind::of(error));
        m
    }

    /// How a timed run ended: its last time and its cost, or its error (variant recorded) and
    /// its wall time.
    fn ended(self, run: Result<Trajectory, lagrange::Error>, wall: f64) -> Self {
        match run {
            Ok(t) => self.value(t.t[t.len() - 1]).cost(Cost::of(&t.stats, wall)),
            Err(e) => {
                let mut m = self.failed_with(&e);
                m.cost.wall_time_s = wall;
                m
            }
        }
    }

    /// Check that the run ended in the engine's error `kind` ([`Check::TypedError`]).
    fn expect_error(mut self, kind: ErrorKind) -> Self {
        self.expected_error = Some(kind);
        self.check(Check::TypedError, None, None)
    }

    /// Check against `theory` with `check` and `bound`, and record whether it passed.
    fn check(mut self, check: Check, theory: Option<f64>, bound: Option<f64>) -> Self {
        self.check = check;
        self.theory = theory;
        self.bound = bound;
        self.pass = match (check, self.value, theory, bound) {
            (Check::None, ..) => None,
            (Check::TypedError, ..) => {
                Some(self.status == "failed" && self.error.is_some() && self.error == self.expected_error)
            }
            (Check::Finite, ..) => Some(self.status == "ok" && self.value.is_some()),
            (Check::FiniteOrTypedError, ..) => Some(self.status == "failed" || self.value.is_some()),
            (_, None, ..) => Some(false),
            (Check::RelativeToTheory, Some(v), Some(t), Some(b)) => Some((v / t - 1.0).abs() <= b),
            (Check::AbsoluteToTheory, Some(v), Some(t), Some(b)) => Some((v - t).abs() <= b),
            (Check::WithinFactor, Some(v), Some(t), Some(b)) => Some(v > 0.0 && t > 0.0 && (v / t).max(t / v) <= b),
            (Check::AtMost, Some(v), _, Some(b)) => Some(v <= b),
            (Check::AtLeast, Some(v), _, Some(b)) => Some(v >= b),
            (Check::Exact, Some(v), Some(t), _) => Some(v == t),
            _ => Some(false),
        };
        self
    }
}

/// A simulation, timed: the trajectory or the error, and the wall time.
fn timed_simulate(
    system: &dyn System,
    initial: &State,
    t_end: f64,
    method: Method,
    output: &Output,
) -> (Result<Trajectory, lagrange::Error>, f64) {
    let start = Instant::now();
    let result = system.simulate(initial, t_end, method, output);
    (result, start.elapsed().as_secs_f64())
}

/// The scene's defaults with `changes` (parameter names; the values are valid by construction).
fn scene_params(scene: &dyn Scene, changes: &[(&str, f64)]) -> Result<Params, Error> {
    let mut params = scene.default_params();
    for &(name, value) in changes {
        params.set(name, value).map_err(|e| Error::scene(scene.id(), e))?;
    }
    Ok(params)
}

/// A case under construction.
struct CaseBuilder {
    id: &'static str,
    title: &'static str,
    scenes: Vec<&'static str>,
    theory: &'static str,
    setup: String,
    measurements: Vec<Measurement>,
}

impl CaseBuilder {
    fn push(&mut self, measurement: Measurement) {
        self.measurements.push(measurement);
    }

    fn finish(self, wall_time: f64) -> Case {
        let checked: Vec<bool> = self.measurements.iter().filter_map(|m| m.pass).collect();
        Case {
            id: self.id,
            title: self.title,
            scenes: self.scenes,
            setup: self.setup,
            theory: self.theory,
            pass: (!checked.is_empty()).then(|| checked.iter().all(|&p| p)),
            measurements: self.measurements,
            wall_time_s: wall_time,
        }
    }
}

/// A stability case: its identity and the function that runs it.
struct CaseSpec {
    id: &'static str,
    title: &'static str,
    /// The scenes the case runs on; empty for every registered scene.
    scenes: &'static [&'static str],
    theory: &'static str,
    run: fn(&mut CaseBuilder, Effort) -> Result<(), Error>,
}

/// Every case, in report order.
const CASES: [CaseSpec; 11] = [
    stiff::STIFF_SPRING,
    stiff::STIFF_DAMPED,
    extreme::EXTREME,
    orbit::KEPLER,
    chaos::CHAOS,
    singular::SINGULAR,
    branch::BRANCH,
    constrained::CONSTRAINED,
    long_run::LONG_RUN,
    long_run::RAPIER_LONG_RUN,
    bad_input::BAD_INPUT,
];

/// The ids of every case, in report order.
pub fn case_ids() -> impl Iterator<Item = &'static str> {
    CASES.iter().map(|c| c.id)
}

/// Run the one case `id` (the tests run each case of the quick set this way).
///
/// # Errors
/// [`Error::Missing`] for an unknown case id; a case that cannot be set up.
pub fn run_case(id: &str, effort: Effort) -> Result<Case, Error> {
    let spec = CASES.iter().find(|c| c.id == id).ok_or(Error::Missing("no such stability case"))?;
    run_spec(spec, effort)
}

fn run_spec(spec: &CaseSpec, effort: Effort) -> Result<Case, Error> {
    let case_start = Instant::now();
    let mut case = CaseBuilder {
        id: spec.id,
        title: spec.title,
        scenes: spec.scenes(),
        theory: spec.theory,
        setup: String::new(),
        measurements: Vec::new(),
    };
    (spec.run)(&mut case, effort).map_err(|e| Error::Case { case: spec.id, source: Box::new(e) })?;
    Ok(case.finish(case_start.elapsed().as_secs_f64()))
}

/// The ids of the cases that run on any of `scenes` (all when `scenes` is empty).
pub fn case_count(scenes: &[&str]) -> usize {
    CASES.iter().filter(|c| selected(c, scenes)).count()
}

fn selected(case: &CaseSpec, scenes: &[&str]) -> bool {
    scenes.is_empty() || case.scenes().iter().any(|s| scenes.contains(s))
}

impl CaseSpec {
    /// The scenes the case runs on: its own list, or every registered scene.
    fn scenes(&self) -> Vec<&'static str> {
        if self.scenes.is_empty() { lagrange_scenes::ids() } else { self.scenes.to_vec() }
    }
}

/// Run every case that involves one of `scenes` (every case when empty), `jobs` at a time (at
/// least one), calling `progress` with each case's id before it runs; the report lists them in
/// their order. A case's reported seconds are its wall time while up to `jobs − 1` other cases
/// run beside it.
///
/// # Errors
/// A case that cannot be set up (a bug in the case: its scenes and parameters are fixed).
pub fn run(
    effort: Effort,
    scenes: &[&str],
    jobs: usize,
    progress: impl FnMut(&str) + Send,
) -> Result<StabilityReport, Error> {
    let start = Instant::now();
    let specs: Vec<&CaseSpec> = CASES.iter().filter(|c| selected(c, scenes)).collect();
    // The cases are independent and check theory, not speed (their seconds are reported costs),
    // so they run `jobs` at a time; the report keeps the cases' order.
    let next = std::sync::atomic::AtomicUsize::new(0);
    let progress = std::sync::Mutex::new(progress);
    let results: Vec<std::sync::Mutex<Option<Result<Case, Error>>>> =
        specs.iter().map(|_| std::sync::Mutex::new(None)).collect();
    std::thread::scope(|scope| {
        for _ in 0..jobs.max(1) {
            scope.spawn(|| {
                loop {
                    let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let Some(spec) = specs.get(k) else { break };
                    if let Ok(mut progress) = progress.lock() {
                        progress(spec.id);
                    }
                    let outcome = run_spec(spec, effort);
                    if let Ok(mut slot) = results[k].lock() {
                        *slot = Some(outcome);
                    }
                }
            });
        }
    });
    let mut cases = Vec::with_capacity(specs.len());
    for slot in results {
        let outcome = slot.into_inner().ok().flatten();
        cases.push(outcome.unwrap_or(Err(Error::Missing("a stability case did not finish")))?);
    }
    let all = cases.iter().flat_map(|c| &c.measurements);
    let (mut passed, mut failed, mut unchecked) = (0, 0, 0);
    for m in all {
        match m.pass {
            Some(true) => passed += 1,
            Some(false) => failed += 1,
            None => unchecked += 1,
        }
    }
    Ok(StabilityReport {
        mode: effort.pick("full", "quick"),
        cases,
        passed,
        failed,
        unchecked,
        wall_time_s: start.elapsed().as_secs_f64(),
    })
}
