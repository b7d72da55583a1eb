//! # lagrange-python — the engine from Python
//!
//! The extension module `lagrange._lagrange`, wrapped by the Python package `lagrange`
//! (`python/lagrange`): a scene (built-in, file or joint graph), its exact equations of motion
//! `M(q) q̈ = f(q, q̇, t)` (with the constraints' multipliers `M q̈ + Gᵀλ = f`, `G q̈ = γ` where
//! it has loops) evaluated and integrated by the same code as the command line, numpy arrays in
//! and out, the same checks (every run against what its scene declares) and the same messages.
//! The GIL is released while the engine runs, so Python threads run scenes in parallel.
//!
//! Built with maturin (`pip install ./crates/python`); from Python:
//!
//! ```python
//! import lagrange
//! pendulum = lagrange.scene("double_pendulum")
//! run = pendulum.simulate(t_end=5.0, method="dop853", tol=1e-12)
//! run.q[-1], run.energy.max() - run.energy.min()
//! ```
//!
//! Every function takes the scene's parameters as `(name, value)` pairs and a state as
//! optional lists; the Python side turns dicts and arrays into them and the JSON results
//! (compare, modes, equations, report) into Python objects. docs/python.md is the user's guide.

mod error;
mod scene;

use error::{Failure, Result};
use lagrange::integrate::MethodKind;
use lagrange::{Method, Output, State, System};
use lagrange_scenes::Params;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use scene::Spec;

/// A scene: what to simulate, with everything the engine derives from it.
#[pyclass(frozen, module = "lagrange._lagrange")]
struct Scene {
    scene: &'static dyn lagrange_scenes::Scene,
    spec: Spec,
}

/// Parameters given as `(name, value)` pairs over the scene's defaults: a name, a symbol or the
/// symbol in ASCII (`alpha` for `α`), each parameter at most once.
fn params(scene: &dyn lagrange_scenes::Scene, given: &[(String, f64)]) -> Result<Params> {
    let mut params = scene.default_params();
    let mut seen: Vec<(&'static str, &str)> = Vec::new();
    for (key, value) in given {
        params.set(key, *value).map_err(|e| Failure::argument(format!("params: {e}")))?;
        if let Some(spec) = params.spec(key) {
            if let Some((_, first)) = seen.iter().find(|(name, _)| *name == spec.name) {
                return Err(Failure::argument(format!(
                    "params: {} is given twice (`{first}`, then `{key}`); give each parameter once",
                    spec.name
                )));
            }
            seen.push((spec.name, key));
        }
    }
    Ok(params)
}

/// A state vector with the scene's arity, every value finite.
fn vector(what: &str, values: Vec<f64>, names: &[String]) -> Result<Vec<f64>> {
    if values.len() != names.len() {
        return Err(Failure::argument(format!(
            "{what} needs {} values ({}), got {}",
            names.len(),
            names.join(", "),
            values.len()
        )));
    }
    if let Some(v) = values.iter().find(|v| !v.is_finite()) {
        return Err(Failure::argument(format!("{what}: {v} is not finite")));
    }
    Ok(values)
}

/// A value that must be finite.
fn finite(what: &str, value: f64) -> Result<f64> {
    if value.is_finite() { Ok(value) } else { Err(Failure::argument(format!("{what}: {value} is not finite"))) }
}

/// A value that must be positive and finite.
fn positive(what: &str, value: f64) -> Result<f64> {
    if value > 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(Failure::argument(format!("{what} must be positive and finite, got {value}")))
    }
}

/// Where a call starts: the parameters, and the scene's default state with the given overrides.
struct Start {
    params: Params,
    state: State,
    names: Vec<String>,
}

impl Scene {
    fn start(
        &self,
        given: &[(String, f64)],
        t: Option<f64>,
        q: Option<Vec<f64>>,
        qdot: Option<Vec<f64>>,
    ) -> Result<Start> {
        let params = params(self.scene, given)?;
        let names: Vec<String> = self.scene.coordinates(&params)?.iter().map(|c| c.name.clone()).collect();
        let mut state = self.scene.default_state(&params)?;
        if let Some(q) = q {
            state.q = vector("q", q, &names)?;
        }
        if let Some(qdot) = qdot {
            state.qdot = vector("qdot", qdot, &names)?;
        }
        if let Some(t) = t {
            state.t = finite("t", t)?;
        }
        Ok(Start { params, state, names })
    }

    fn build(&self, params: &Params) -> Result<Box<dyn System>> {
        Ok(self.scene.build(params)?)
    }

    /// `query` on the system built with the given parameters at the given state (the scene's
    /// initial state where not given), without the GIL; with the number of coordinates.
    #[allow(clippy::too_many_arguments)]
    fn at_state<T: Send>(
        &self,
        py: Python<'_>,
        params: &[(String, f64)],
        t: Option<f64>,
        q: Option<Vec<f64>>,
        qdot: Option<Vec<f64>>,
        query: impl FnOnce(&mut dyn System, &State) -> std::result::Result<T, lagrange::Error> + Send,
    ) -> Result<(T, usize)> {
        let start = self.start(params, t, q, qdot)?;
        let n = start.state.q.len();
        let value = py.detach(|| -> Result<T> { Ok(query(self.build(&start.params)?.as_mut(), &start.state)?) })?;
        Ok((value, n))
    }
}

/// A row-major matrix as a 2-D array.
fn matrix<'py>(py: Python<'py>, rows: usize, values: Vec<f64>) -> Bound<'py, PyArray2<f64>> {
    let columns = values.len().checked_div(rows).unwrap_or(0);
    Array2::from_shape_vec((rows, columns), values)
        .map_or_else(|_| Array2::zeros((0, 0)).into_pyarray(py), |array| array.into_pyarray(py))
}

/// The method a name and a setting ask for: `tol` for the error-controlled methods, `dt` for
/// the fixed-step ones, each defaulting as the command line does.
fn method(name: &str, dt: Option<f64>, tol: Option<f64>) -> Result<Method> {
    let kind = MethodKind::ALL
        .into_iter()
        .find(|k| k.name() == name)
        .or_else(|| MethodKind::FORMER_NAMES.iter().find(|(n, _)| *n == name).map(|(_, k)| *k))
        .ok_or_else(|| {
            let names: Vec<&str> = MethodKind::ALL.iter().map(|k| k.name()).collect();
            Failure::argument(format!("unknown method `{name}`; expected one of {}", names.join(", ")))
        })?;
    match (kind.is_fixed_step(), dt, tol) {
        (true, _, Some(_)) => Err(Failure::argument(format!(
            "tol does not apply to the {} method: it applies to the error-controlled methods (dopri5, dop853, \
             sdirk4); use dt",
            kind.name()
        ))),
        (false, Some(_), _) => Err(Failure::argument(format!(
            "dt does not apply to the {} method: it applies to the fixed-step methods (rk4, variational, gauss4); \
             use tol",
            kind.name()
        ))),
        (true, Some(dt), None) => Ok(kind.with(positive("dt", dt)?)),
        (false, None, Some(tol)) => Ok(kind.with(positive("tol", tol)?)),
        _ => Ok(kind.default_method()),
    }
}

/// A trajectory that, every tenth of a second of wall time, asks Python whether a signal
/// arrived (Ctrl-C): the run goes on without the GIL, so Python's own handler cannot run until
/// it returns. An interrupt stops the run ([`lagrange::Error::Stopped`]) and is raised as
/// Python's `KeyboardInterrupt`.
struct Interruptible {
    trajectory: lagrange::Trajectory,
    last_check: std::time::Instant,
    interrupt: Option<PyErr>,
}

impl lagrange::integrate::Sink for Interruptible {
    fn wants_energy(&self) -> bool {
        self.trajectory.wants_energy()
    }

    fn wants_violation(&self) -> bool {
        self.trajectory.wants_violation()
    }

    fn record(&mut self, sample: lagrange::integrate::Sample<'_>) {
        self.trajectory.record(sample);
    }

    fn finish(&mut self, stats: lagrange::integrate::Stats) {
        self.trajectory.finish(stats);
    }

    fn keep_going(&mut self, _t: f64) -> bool {
        if self.last_check.elapsed().as_secs_f64() < 0.1 {
            return true;
        }
        self.last_check = std::time::Instant::now();
        self.interrupt = Python::attach(|py| py.check_signals().err());
        self.interrupt.is_none()
    }
}

/// Why a run returned early: a failure, or the user's interrupt (raised as it came).
enum RunError {
    Failed(Failure),
    Interrupted(PyErr),
}

impl<E: Into<Failure>> From<E> for RunError {
    fn from(error: E) -> Self {
        RunError::Failed(error.into())
    }
}

impl From<RunError> for PyErr {
    fn from(error: RunError) -> PyErr {
        match error {
            RunError::Failed(failure) => failure.into(),
            RunError::Interrupted(interrupt) => interrupt,
        }
    }
}

/// What [`Scene::simulate`] hands back before it becomes Python objects.
struct Run {
    trajectory: lagrange::Trajectory,
    health: lagrange_validation::health::Health,
    method: Method,
    /// Wall time of the engine's part (build, run, check), what the same run costs from Rust.
    seconds: f64,
}

#[pymethods]
impl Scene {
    /// The scene a spec (JSON, as [`Scene::spec`] gives it) describes: `{"builtin": id}`,
    /// `{"file": {"path", "text"}}` or `{"graph": {"graph", "t", "q", "qdot"}}`.
    #[staticmethod]
    fn from_spec(spec: &str) -> PyResult<Self> {
        let spec: Spec =
            serde_json::from_str(spec).map_err(|e| Failure::argument(format!("not a scene description: {e}")))?;
        Ok(Self { scene: scene::resolve(&spec)?, spec })
    }

    /// The description this scene is rebuilt from in another process (JSON).
    fn spec(&self) -> PyResult<String> {
        Ok(serde_json::to_string(&self.spec).map_err(Failure::from)?)
    }

    /// The scene's id.
    #[getter]
    fn id(&self) -> &'static str {
        self.scene.id()
    }

    /// One line on the scene.
    #[getter]
    fn title(&self) -> &'static str {
        self.scene.title()
    }

    /// Where the scene and its closed form come from.
    #[getter]
    fn reference(&self) -> &'static str {
        self.scene.reference()
    }

    /// The span the report runs it over (s), if it declares one.
    #[getter]
    fn horizon(&self) -> Option<f64> {
        self.scene.horizon()
    }

    /// The parameters: `(name, symbol, unit, default, description)` each.
    fn parameters(&self) -> Vec<(&'static str, &'static str, &'static str, f64, &'static str)> {
        self.scene.params().iter().map(|p| (p.name, p.symbol, p.unit, p.default, p.description)).collect()
    }

    /// The coordinates with `params`: `(name, unit)` each.
    fn coordinates(&self, params: Vec<(String, f64)>) -> PyResult<Vec<(String, String)>> {
        let params = self::params(self.scene, &params)?;
        let coordinates = self.scene.coordinates(&params).map_err(Failure::from)?;
        Ok(coordinates.iter().map(|c| (c.name.clone(), c.unit().to_string())).collect())
    }

    /// The initial state with `params`: `(t, q, qdot)`.
    fn default_state(&self, params: Vec<(String, f64)>) -> PyResult<(f64, Vec<f64>, Vec<f64>)> {
        let params = self::params(self.scene, &params)?;
        let state = self.scene.default_state(&params).map_err(Failure::from)?;
        Ok((state.t, state.q, state.qdot))
    }

    /// The state `(t, q, q̇)` brought onto the constraints, keeping the coordinates named in
    /// `hold` and their rates (a state given without `hold` must be on them already).
    #[pyo3(signature = (params, t=None, q=None, qdot=None, hold=None))]
    fn initial_state(
        &self,
        params: Vec<(String, f64)>,
        t: Option<f64>,
        q: Option<Vec<f64>>,
        qdot: Option<Vec<f64>>,
        hold: Option<Vec<String>>,
    ) -> PyResult<(f64, Vec<f64>, Vec<f64>)> {
        let start = self.start(&params, t, q, qdot)?;
        let state = self.held(&start, hold.as_deref())?;
        Ok((state.t, state.q, state.qdot))
    }

    /// Integrate from the given state (default: the scene's) to `t_end` and check the run
    /// against every constant of the motion the scene declares and against its constraints.
    /// Returns a dict: `t`, `q`, `qdot`, `energy`, `violation` (or None), the run's `stats`,
    /// its `health` (`expected` error, `checked`, `findings`), the `method` described and
    /// `engine_seconds`, the wall time of the engine's part (build, run, check).
    /// Output at `times` (increasing, within the run), or every `every` seconds, or by default
    /// at 200 intervals.
    #[pyo3(signature = (params, t_end, method="dopri5", dt=None, tol=None, t=None, q=None, qdot=None, hold=None, times=None, every=None))]
    #[allow(clippy::too_many_arguments)]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        params: Vec<(String, f64)>,
        t_end: f64,
        method: &str,
        dt: Option<f64>,
        tol: Option<f64>,
        t: Option<f64>,
        q: Option<Vec<f64>>,
        qdot: Option<Vec<f64>>,
        hold: Option<Vec<String>>,
        times: Option<Vec<f64>>,
        every: Option<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let start = self.start(&params, t, q, qdot)?;
        let method = self::method(method, dt, tol)?;
        let t_end = finite("t_end", t_end)?;
        if t_end <= start.state.t {
            return Err(
                Failure::argument(format!("t_end ({t_end}) must be after the start ({})", start.state.t)).into()
            );
        }
        let span = t_end - start.state.t;
        let output = match (times, every) {
            (Some(_), Some(_)) => return Err(Failure::argument("give times or every, not both").into()),
            (Some(times), None) => {
                if let Some(v) = times.iter().find(|v| !v.is_finite()) {
                    return Err(Failure::argument(format!("times: {v} is not finite")).into());
                }
                Output::Times(times)
            }
            (None, Some(every)) => Output::Every(positive("every", every)?),
            (None, None) => Output::Every(match method {
                Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss4 { dt } => {
                    dt * (span / 200.0 / dt).round().max(1.0)
                }
                _ => span / 200.0,
            }),
        };
        let held = hold.as_deref();
        let run = py.detach(|| self.run(&start, held, t_end, method, &output))?;
        let out = PyDict::new(py);
        let trajectory = run.trajectory;
        let rows = trajectory.len();
        out.set_item("coordinates", start.names)?;
        out.set_item("t", trajectory.t.into_pyarray(py))?;
        out.set_item("q", matrix(py, rows, trajectory.q))?;
        out.set_item("qdot", matrix(py, rows, trajectory.qdot))?;
        out.set_item("energy", trajectory.energy.into_pyarray(py))?;
        if trajectory.violation.is_empty() {
            out.set_item("violation", py.None())?;
        } else {
            out.set_item("violation", matrix(py, rows, trajectory.violation.concat()))?;
        }
        let stats = PyDict::new(py);
        let s = &trajectory.stats;
        stats.set_item("steps", s.steps)?;
        stats.set_item("rejected", s.rejected)?;
        stats.set_item("evaluations", s.evaluations)?;
        stats.set_item("newton_iterations", s.newton_iterations)?;
        stats.set_item("jacobians", s.jacobians)?;
        stats.set_item("factorizations", s.factorizations)?;
        stats.set_item("stiffness", s.stiffness)?;
        stats.set_item("fallbacks", s.fallbacks)?;
        out.set_item("stats", stats)?;
        let health = PyDict::new(py);
        health.set_item("expected", run.health.expected)?;
        health.set_item("checked", run.health.checked)?;
        let findings: Vec<(String, f64, f64, f64)> =
            run.health.findings.iter().map(|f| (f.quantity.clone(), f.drift, f.bound, f.since)).collect();
        health.set_item("findings", findings)?;
        out.set_item("health", health)?;
        out.set_item("method", run.method.describe())?;
        out.set_item("engine_seconds", run.seconds)?;
        Ok(out)
    }

    /// The message of an unhealthy run, as the command line prints it (`None` for a healthy
    /// one): raised by the Python side unless it is told to keep drifting runs.
    #[staticmethod]
    fn unhealthy_message(
        scene: &str,
        method: &str,
        findings: Vec<(String, f64, f64, f64)>,
        expected: f64,
        fixed_step: bool,
    ) -> Option<String> {
        if findings.is_empty() {
            return None;
        }
        let findings: Vec<String> = findings
            .into_iter()
            .map(|(quantity, drift, bound, since)| {
                lagrange_validation::health::Finding { quantity, drift, bound, since }.to_string()
            })
            .collect();
        Some(format!(
            "the run of {scene} with {method} did not keep what the scene declares: {}; the result is not to be \
             trusted (expected relative error {expected:.2e}): use a smaller {}, or allow_drift=True to keep it \
             anyway",
            findings.join("; "),
            if fixed_step { "dt" } else { "tol" }
        ))
    }

    /// Generalized accelerations `q̈` at a state (default: the scene's initial state).
    #[pyo3(signature = (params, t=None, q=None, qdot=None))]
    fn accelerations<'py>(
        &self,
        py: Python<'py>,
        params: Vec<(String, f64)>,
        t: Option<f64>,
        q: Option<Vec<f64>>,
        qdot: Option<Vec<f64>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (qddot, _) =
            self.at_state(py, &params, t, q, qdot, |system, s| Ok(system.accelerations(s.t, &s.q, &s.qdot)?.to_vec()))?;
        Ok(qddot.into_pyarray(py))
    }

    /// The scene's closed-form `q̈` at a state, where it has one (`None` otherwise).
    #[pyo3(signature = (params, t=None, q=None, qdot=None))]
    fn closed_form_accelerations<'py>(
        &self,
        py: Python<'py>,
        params: Vec<(String, f64)>,
        t: Option<f64>,
        q: Option<Vec<f64>>,
        qdot: Option<Vec<f64>>,
    ) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
        let start = self.start(&params, t, q, qdot)?;
        let s = &start.state;
        let closed = self.scene.closed_form_accelerations(&start.params, s.t, &s.q, &s.qdot).map_err(Failure::from)?;
        Ok(closed.map(|v| v.into_pyarray(py)))
    }

    /// The mass matrix `M(q)` (n × n) at a configuration.
    #[pyo3(signature = (params, t=None, q=None))]
    fn mass_matrix<'py>(
        &self,
        py: Python<'py>,
        params: Vec<(String, f64)>,
        t: Option<f64>,
        q: Option<Vec<f64>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (m, n) =
            self.at_state(py, &params, t, q, None, |system, s| Ok(system.mass_matrix(s.t, &s.q, &s.qdot)?.to_vec()))?;
        Ok(matrix(py, n, m))
    }

    /// The energy function `h = q̇ · ∂L/∂q̇ − L` at a state.
    #[pyo3(signature = (params, t=None, q=None, qdot=None))]
    fn energy(
        &self,
        py: Python<'_>,
        params: Vec<(String, f64)>,
        t: Option<f64>,
        q: Option<Vec<f64>>,
        qdot: Option<Vec<f64>>,
    ) -> PyResult<f64> {
        Ok(self.at_state(py, &params, t, q, qdot, |system, s| system.energy_function(s.t, &s.q, &s.qdot))?.0)
    }

    /// The constraint multipliers `λ` (`M q̈ + Gᵀλ = f`) at a state; `None` for a scene without
    /// constraints among its coordinates.
    #[pyo3(signature = (params, t=None, q=None, qdot=None))]
    fn multipliers<'py>(
        &self,
        py: Python<'py>,
        params: Vec<(String, f64)>,
        t: Option<f64>,
        q: Option<Vec<f64>>,
        qdot: Option<Vec<f64>>,
    ) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
        let (lambda, _) = self.at_state(py, &params, t, q, qdot, |system, s| {
            Ok(system.constraint_multipliers(s.t, &s.q, &s.qdot)?.map(<[f64]>::to_vec))
        })?;
        Ok(lambda.map(|v| v.into_pyarray(py)))
    }

    /// How far the equations determine the multipliers at a state: `(rows, determined,
    /// conditioning)`; `None` for a scene without constraints among its coordinates.
    #[pyo3(signature = (params, t=None, q=None, qdot=None))]
    fn multiplier_rank(
        &self,
        py: Python<'_>,
        params: Vec<(String, f64)>,
        t: Option<f64>,
        q: Option<Vec<f64>>,
        qdot: Option<Vec<f64>>,
    ) -> PyResult<Option<(usize, usize, f64)>> {
        let (rank, _) =
            self.at_state(py, &params, t, q, qdot, |system, s| system.multiplier_rank(s.t, &s.q, &s.qdot))?;
        Ok(rank.map(|r| (r.rows, r.determined, r.conditioning)))
    }

    /// The constraint forces on the bodies at a state: one row `(Fx, Fy, τ)` per body; `None`
    /// for a scene without bodies.
    #[pyo3(signature = (params, t=None, q=None, qdot=None))]
    fn reactions<'py>(
        &self,
        py: Python<'py>,
        params: Vec<(String, f64)>,
        t: Option<f64>,
        q: Option<Vec<f64>>,
        qdot: Option<Vec<f64>>,
    ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        let (forces, _) = self.at_state(py, &params, t, q, qdot, |system, s| {
            Ok(system.reaction_forces(s.t, &s.q, &s.qdot)?.map(<[f64]>::to_vec))
        })?;
        Ok(forces.map(|f| matrix(py, f.len() / 3, f)))
    }

    /// The body names, in the order of [`reactions`](Self::reactions).
    fn bodies(&self, params: Vec<(String, f64)>) -> PyResult<Vec<String>> {
        let params = self::params(self.scene, &params)?;
        Ok(self.build(&params)?.bodies().iter().map(|b| b.name.to_string()).collect())
    }

    /// The scene beside maximal-coordinate engines (`cartesian`, `rapier-impulse`,
    /// `rapier-multibody`, their `-f32` builds): a JSON list, one object per engine — its
    /// errors over time against the scene's closed form or the reduced solution, drifts,
    /// constraint violation and force error, cost — or the reason it cannot build the scene.
    #[pyo3(signature = (params, engines, t_end, dt, substeps, tol, t=None, q=None, qdot=None, hold=None))]
    #[allow(clippy::too_many_arguments)]
    fn compare(
        &self,
        py: Python<'_>,
        params: Vec<(String, f64)>,
        engines: Vec<String>,
        t_end: f64,
        dt: f64,
        substeps: usize,
        tol: f64,
        t: Option<f64>,
        q: Option<Vec<f64>>,
        qdot: Option<Vec<f64>>,
        hold: Option<Vec<String>>,
    ) -> PyResult<String> {
        use lagrange_maximal::{BuildError, Engine, Settings};
        let engines: Vec<Engine> = engines
            .iter()
            .map(|name| {
                Engine::from_name(name).ok_or_else(|| {
                    let names: Vec<&str> = Engine::ALL.iter().map(|e| e.name()).collect();
                    Failure::argument(format!("unknown engine `{name}`; expected one of {}", names.join(", ")))
                })
            })
            .collect::<Result<_>>()?;
        let start = self.start(&params, t, q, qdot)?;
        let t_end = positive("t_end", t_end)?;
        let settings = Settings { dt: positive("dt", dt)?, substeps, tolerance: positive("tol", tol)? };
        if substeps == 0 {
            return Err(Failure::argument("substeps must be positive, got 0").into());
        }
        if settings.dt > t_end {
            return Err(Failure::argument(format!(
                "dt {dt} is longer than the run (t_end {t_end}): rapier would not take one step inside it"
            ))
            .into());
        }
        let initial = self.held(&start, hold.as_deref())?;
        let every = lagrange_validation::compare::sample_interval(t_end, settings.dt);
        let rows = py.detach(|| {
            use rayon::prelude::*;
            engines
                .par_iter()
                .map(|&engine| {
                    let result = lagrange_validation::compare::compare(
                        engine,
                        self.scene,
                        &start.params,
                        &initial,
                        &settings,
                        initial.t + t_end,
                        every,
                    );
                    match result {
                        Ok(c) => Ok(serde_json::json!({
                            "engine": engine.name(),
                            "deviations": c.deviations,
                            "reference": c.reference.name(),
                            "times": c.times,
                            "errors": c.errors,
                            "max_error": c.max_error,
                            "final_error": c.final_error,
                            "energy_drift": c.energy_drift,
                            "reference_energy_drift": c.reference_energy_drift,
                            "momentum_drift": c.momentum_drift,
                            "constraint_violation": c.constraint_violation,
                            "force_error": c.force_error,
                            "steps": c.steps,
                            "seconds_per_step": c.seconds_per_step,
                        })),
                        Err(lagrange_validation::Error::Build(BuildError::Unbuildable { reason, .. })) => {
                            Ok(serde_json::json!({ "engine": engine.name(), "unbuildable": reason }))
                        }
                        Err(error) => Err(Failure::from(error)),
                    }
                })
                .collect::<Result<Vec<_>>>()
        })?;
        Ok(serde_json::to_string(&rows).map_err(Failure::from)?)
    }

    /// The equilibrium nearest a configuration and the normal modes about it (JSON): the
    /// equilibrium, the mass and stiffness matrices there, and each mode's kind, ω², ω,
    /// frequency, period and shape.
    #[pyo3(signature = (params, t=None, q=None))]
    fn modes(
        &self,
        py: Python<'_>,
        params: Vec<(String, f64)>,
        t: Option<f64>,
        q: Option<Vec<f64>>,
    ) -> PyResult<String> {
        use lagrange::modes::ModeKind;
        let start = self.start(&params, t, q, None)?;
        let s = &start.state;
        let modes = py.detach(|| -> Result<lagrange::modes::Modes> {
            Ok(lagrange::modes::normal_modes(self.build(&start.params)?.as_mut(), s.t, &s.q)?)
        })?;
        let tau = std::f64::consts::TAU;
        let list: Vec<serde_json::Value> = modes
            .modes
            .iter()
            .map(|m| {
                let oscillating = m.kind == ModeKind::Oscillating;
                serde_json::json!({
                    "kind": match m.kind {
                        ModeKind::Oscillating => "oscillating",
                        ModeKind::Zero => "zero",
                        ModeKind::Unstable => "unstable",
                    },
                    "omega_squared": m.omega_squared,
                    "omega": m.omega(),
                    "frequency": oscillating.then(|| m.omega() / tau),
                    "period": oscillating.then(|| tau / m.omega()),
                    "shape": m.shape,
                })
            })
            .collect();
        let out = serde_json::json!({
            "scene": self.scene.id(),
            "t": s.t,
            "coordinates": start.names,
            "equilibrium": modes.equilibrium,
            "mass_matrix": modes.mass,
            "stiffness_matrix": modes.stiffness,
            "damped": modes.damped,
            "asymmetry": modes.asymmetry,
            "modes": list,
        });
        Ok(serde_json::to_string(&out).map_err(Failure::from)?)
    }

    /// The equations of motion derived symbolically (JSON: `T`, `V`, `L`, Lagrange's equations,
    /// constraints, constants of the motion, each formula in Unicode, LaTeX and the scene-file
    /// language), then the same as Unicode text as a textbook prints them and as LaTeX: for a
    /// scene file, or a joint graph (built-in or given).
    fn eom(&self) -> PyResult<(String, String, String)> {
        let equations = match &self.spec {
            Spec::File { path, text } => lagrange_file::eom_source(path, text).map_err(Failure::from)?,
            _ => lagrange_file::scene_equations(self.scene, &self.scene.default_params())
                .map_err(Failure::from)?
                .ok_or_else(|| {
                    Failure::argument(format!(
                        "`{0}` is written in Rust, not as a joint graph: its equations are those of its \
                         coordinates-form file (examples/scenes/{0}.toml)",
                        self.scene.id()
                    ))
                })?,
        };
        let title = match &self.spec {
            Spec::File { path, .. } => path.as_str(),
            _ => self.scene.id(),
        };
        use lagrange_file::symbolic::text;
        let json = serde_json::to_string(&equations).map_err(Failure::from)?;
        Ok((json, text::unicode(title, &equations), text::latex(&equations)))
    }
}

impl Scene {
    /// The start brought onto the constraints as `hold` says.
    fn held(&self, start: &Start, hold: Option<&[String]>) -> Result<State> {
        let mut system = self.build(&start.params)?;
        let names: Option<Vec<&str>> = hold.map(|h| h.iter().map(String::as_str).collect());
        Ok(lagrange_validation::start::hold(system.as_mut(), start.state.clone(), names.as_deref(), |name| {
            format!("hold=['{name}']")
        })?)
    }

    /// The run and its health, without the GIL.
    fn run(
        &self,
        start: &Start,
        hold: Option<&[String]>,
        t_end: f64,
        method: Method,
        output: &Output,
    ) -> std::result::Result<Run, RunError> {
        let started = std::time::Instant::now();
        let mut system = self.build(&start.params)?;
        let names: Option<Vec<&str>> = hold.map(|h| h.iter().map(String::as_str).collect());
        let initial =
            lagrange_validation::start::hold(system.as_mut(), start.state.clone(), names.as_deref(), |name| {
                format!("hold=['{name}']")
            })?;
        // Into a trajectory that keeps the samples recorded before a failure, for its diagnosis.
        let mut sink = Interruptible {
            trajectory: lagrange::Trajectory::with_capacity(initial.q.len(), 0),
            last_check: std::time::Instant::now(),
            interrupt: None,
        };
        let result = system.simulate_into(&initial, t_end, method, output, &mut sink);
        if let Some(interrupt) = sink.interrupt {
            return Err(RunError::Interrupted(interrupt));
        }
        let trajectory = sink.trajectory;
        if let Err(error) = result {
            return Err(self.diagnosed(start, system.as_mut(), method, &trajectory, error).into());
        }
        let health =
            lagrange_validation::health::check(self.scene, &start.params, system.as_mut(), method, &trajectory)?;
        Ok(Run { trajectory, health, method, seconds: started.elapsed().as_secs_f64() })
    }

    /// A failed run's error with the evidence of its samples, as the command line words it.
    fn diagnosed(
        &self,
        start: &Start,
        system: &mut dyn System,
        method: Method,
        partial: &lagrange::Trajectory,
        error: lagrange::Error,
    ) -> Failure {
        use lagrange_validation::health::{self, Cause};
        let class = error::Failure::from(error.clone()).class;
        let flag = if method.kind().is_fixed_step() { "dt" } else { "tol" };
        let message = match health::diagnose(self.scene, &start.params, system, method, partial, &error) {
            None => error.to_string(),
            Some(Cause::DivergedFirst { findings }) => {
                let findings: Vec<String> = findings.iter().map(ToString::to_string).collect();
                format!(
                    "the run of {} with {} diverged ({}) before it stopped with: {error}; use a smaller {flag}",
                    self.scene.id(),
                    method.describe(),
                    findings.join("; ")
                )
            }
            Some(Cause::NotStiff { t, h, rate, .. }) => format!(
                "the run of {} with {} stopped at t = {t} with the step at h = {h:e}, far below the explicit \
                 method's stability limit there (about 3.3 / ω = {:e} for the fastest rate ω = {rate} 1/s): not \
                 stiffness; the motion is not resolved there (a singular configuration, a discontinuity, or a \
                 tolerance too loose for the motion: {error})",
                self.scene.id(),
                method.describe(),
                3.3 / rate
            ),
        };
        Failure { class, message }
    }
}

/// Every built-in scene's id, in the registry's order.
#[pyfunction]
fn scene_ids() -> Vec<&'static str> {
    lagrange_scenes::all().iter().map(|s| s.id()).collect()
}

/// The validation report (JSON, the schema of `report.json`): the given scenes (specs; all
/// built-in scenes when empty) by every method over the plan's sweeps against their
/// references, then the stability suite of those scenes, on `jobs` threads. With `out`, writes
/// `report.json`, `report.md` and each scene's plots there too.
#[pyfunction]
#[pyo3(signature = (scenes, quick, t_end=None, jobs=None, out=None))]
fn report(
    py: Python<'_>,
    scenes: Vec<String>,
    quick: bool,
    t_end: Option<f64>,
    jobs: Option<usize>,
    out: Option<std::path::PathBuf>,
) -> PyResult<String> {
    use lagrange_validation::render::{markdown, plots};
    use lagrange_validation::runs::{ScenePlan, SceneRuns};
    use lagrange_validation::schema::Plots;
    use rayon::prelude::*;
    let started = std::time::Instant::now();
    let plan = lagrange_validation::plan::Plan::new(quick, t_end).map_err(Failure::from)?;
    let asked: Vec<&'static dyn lagrange_scenes::Scene> = scenes
        .iter()
        .map(|spec| {
            let spec: Spec =
                serde_json::from_str(spec).map_err(|e| Failure::argument(format!("not a scene description: {e}")))?;
            scene::resolve(&spec)
        })
        .collect::<Result<_>>()?;
    let all = asked.is_empty();
    let chosen: Vec<&'static dyn lagrange_scenes::Scene> = if all { lagrange_scenes::all().to_vec() } else { asked };
    let jobs = match jobs {
        Some(0) => return Err(Failure::argument("jobs must be positive, got 0").into()),
        Some(jobs) => jobs,
        None => std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get),
    };
    if let Some(out) = &out {
        std::fs::create_dir_all(out).map_err(|e| {
            Failure::argument(format!("out {}: cannot create the output directory: {e}", out.display()))
        })?;
    }
    let write = |path: std::path::PathBuf, text: &str| {
        std::fs::write(&path, text).map_err(|e| Failure::argument(format!("cannot write {}: {e}", path.display())))
    };
    let json = py.detach(|| -> Result<String> {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(jobs).build().map_err(|e| Failure {
            class: "EngineError",
            message: format!("cannot start the report's threads: {e}"),
        })?;
        let scene_reports = pool.install(|| {
            chosen
                .par_iter()
                .map(|&scene| -> Result<_> {
                    let scene_start = std::time::Instant::now();
                    let scene_plan = ScenePlan::new(scene, &plan)?;
                    let runs = SceneRuns::execute(&scene_plan, |_| {})?;
                    let id = scene.id();
                    let names = Plots {
                        work_precision: format!("{id}_work_precision.svg"),
                        error: format!("{id}_error.svg"),
                        animation: None,
                    };
                    if let Some(out) = &out {
                        let own = &scene_plan.plan;
                        let svg = |svg: std::result::Result<String, plots::PlotError>| {
                            svg.map_err(|e| Failure {
                                class: "EngineError",
                                message: format!("cannot draw a plot: {e}"),
                            })
                        };
                        write(out.join(&names.work_precision), &svg(plots::work_precision(&runs, own.horizon))?)?;
                        write(out.join(&names.error), &svg(plots::errors_over_time(&runs, &own.times))?)?;
                    }
                    Ok(lagrange_validation::assemble::scene_report(&runs, names, scene_start.elapsed().as_secs_f64()))
                })
                .collect::<Result<Vec<_>>>()
        })?;
        let ids: Vec<&str> = if all { Vec::new() } else { chosen.iter().map(|s| s.id()).collect() };
        let effort = if plan.quick {
            lagrange_validation::stability::Effort::Quick
        } else {
            lagrange_validation::stability::Effort::Full
        };
        let stability = lagrange_validation::stability::run(effort, &ids, jobs, |_| {})?;
        let generator = format!("lagrange-python {}", env!("CARGO_PKG_VERSION"));
        let report = lagrange_validation::assemble::report(
            &plan,
            scene_reports,
            stability,
            generator,
            started.elapsed().as_secs_f64(),
        );
        let json = serde_json::to_string_pretty(&report)?;
        if let Some(out) = &out {
            write(out.join("report.json"), &json)?;
            write(out.join("report.md"), &markdown::render(&report))?;
        }
        Ok(json)
    })?;
    Ok(json)
}

/// The extension module.
#[pymodule]
fn _lagrange(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Scene>()?;
    m.add_function(wrap_pyfunction!(scene_ids, m)?)?;
    m.add_function(wrap_pyfunction!(report, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
