//! `lagrange compare`: the reduced solver and the maximal-coordinate engines side by side.
//! Each engine's run is estimated before any runs, and a request estimated beyond
//! [`long_work::TIME_LIMIT_S`] is refused (`--force` runs it anyway); a progress bar with the
//! time left is drawn on a terminal.

use super::long_work::{self, Run};
use crate::args;
use crate::error::CliError;
use crate::output::outln;
use lagrange::State;
use lagrange_maximal::{BuildError, Engine, Settings};
use lagrange_scenes::{Params, Scene};
use lagrange_validation::Error;
use lagrange_validation::compare::{Comparison, compare};
use lagrange_validation::plan::REFERENCE_TOLERANCE;
use lagrange_validation::reference::ReferenceKind;
use serde::Serialize;
use std::collections::BTreeMap;

/// Arguments of `lagrange compare`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene id (see `lagrange scenes`).
    scene: String,
    /// Parameter override NAME=VALUE (name or symbol), repeatable.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Initial coordinates (default: the scene's initial state).
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    q: Option<String>,
    /// Initial velocities (default: the scene's initial state).
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    qdot: Option<String>,
    /// For a mechanism with constraints among its coordinates (a four-bar): bring the initial
    /// state onto them, keeping these coordinates and their rates (comma-separated names, e.g.
    /// `θ2`); the others move as little as possible. Without it, a given state must already
    /// satisfy the constraints.
    #[arg(long, value_name = "NAME,..")]
    hold: Option<String>,
    /// Engine: cartesian, rapier-impulse, rapier-multibody, rapier-impulse-f32,
    /// rapier-multibody-f32, or all.
    #[arg(long, default_value = "all")]
    engine: String,
    /// rapier step (s) [default: 1/240].
    #[arg(long, default_value_t = 1.0 / 240.0, hide_default_value = true, allow_negative_numbers = true)]
    dt: f64,
    /// rapier substeps per step.
    #[arg(long, default_value_t = 4)]
    substeps: usize,
    /// Tolerance of the Cartesian engine's integrator.
    #[arg(long, default_value = "1e-12", allow_negative_numbers = true)]
    tol: f64,
    /// Simulated time (s).
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    t_end: f64,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
    /// Run a request whose estimated wall time is beyond the limit (2 minutes).
    #[arg(long)]
    force: bool,
    /// Wall-time limit (s): an engine still running then is abandoned, the rows of the engines
    /// done are printed, and the command exits 1 naming the engines left out. With it, the
    /// cost is not estimated up front; without it (and without --force) a request estimated
    /// within 2 minutes runs under a 4-minute limit.
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    max_seconds: Option<f64>,
}

/// Substeps of a rapier engine's calibration run: a rapier step costs its substeps, so a run
/// with more is estimated from one with this many, scaled by the ratio.
const CALIBRATION_SUBSTEPS: usize = 16;

/// Estimated wall time of `compare` for `engine` (its reference run included): the same
/// comparison over the first `τ, 2τ, …` of the horizon from one rapier step on
/// ([`long_work::wall_time`]), each calibration run on its own thread so that one whose steps
/// are too slow is abandoned once it proves the request beyond the limit. Zero for an engine
/// that cannot build the scene; `None` when a calibration run fails (the real one will say
/// why).
fn estimate(
    engine: Engine,
    scene: &'static dyn Scene,
    params: &Params,
    initial: &State,
    settings: &Settings,
    span: f64,
) -> Option<long_work::Estimate> {
    let (calibration, scale) = if engine.is_rapier() && settings.substeps > CALIBRATION_SUBSTEPS {
        let calibration = Settings { substeps: CALIBRATION_SUBSTEPS, ..*settings };
        (calibration, settings.substeps as f64 / CALIBRATION_SUBSTEPS as f64)
    } else {
        (*settings, 1.0)
    };
    let mut unbuildable = false;
    let wall = long_work::wall_time(span, settings.dt, |tau, budget| {
        let (params, initial) = (params.clone(), initial.clone());
        let (send, receive) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let run = compare(engine, scene, &params, &initial, &calibration, initial.t + tau, tau);
            let _ = send.send(match run {
                Ok(_) => Some(true),
                Err(Error::Build(BuildError::Unbuildable { .. })) => None,
                Err(_) => Some(false),
            });
        });
        // A substep count scaled down runs `scale` times faster than the real one.
        match receive.recv_timeout(std::time::Duration::from_secs_f64(budget / scale)) {
            Ok(Some(true)) => Run::Done,
            Ok(Some(false)) | Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => Run::Failed,
            Ok(None) => {
                unbuildable = true;
                Run::Failed
            }
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => Run::Exceeded,
        }
    });
    if unbuildable {
        return Some(long_work::Estimate { seconds: 0.0, at_least: false });
    }
    wall.map(|w| long_work::Estimate { seconds: w.seconds * scale, ..w })
}

/// `compare --json`: what was compared, under which settings, and one row per engine
/// (documented field by field in docs/cli-json.md).
#[derive(Serialize)]
struct Document {
    scene: &'static str,
    /// Every parameter by name, overrides applied.
    parameters: BTreeMap<&'static str, f64>,
    /// The initial state.
    t0: f64,
    q0: Vec<f64>,
    qdot0: Vec<f64>,
    /// rapier's step and substeps, the Cartesian engine's tolerance.
    dt: f64,
    substeps: usize,
    tol: f64,
    t_end: f64,
    /// Interval of the times where errors are measured.
    every: f64,
    /// Tolerance of the reduced solution the engines are measured against; `None` when every
    /// row is measured against the scene's closed form.
    reference_tol: Option<f64>,
    rows: Vec<Row>,
}

/// One engine's row.
#[derive(Serialize)]
struct Row {
    engine: &'static str,
    /// Present when the engine cannot build the scene.
    unbuildable: Option<String>,
    deviations: Vec<String>,
    /// `closed_form` or `reduced_dop853`: what the errors are measured against.
    reference: Option<&'static str>,
    max_error: Option<f64>,
    final_error: Option<f64>,
    energy_drift: Option<f64>,
    reference_energy_drift: Option<f64>,
    momentum_drift: Option<f64>,
    constraint_violation: Option<f64>,
    force_error: Option<f64>,
    steps: Option<usize>,
    microseconds_per_step: Option<f64>,
}

impl Row {
    fn from(engine: Engine, result: Result<Comparison, Error>) -> Result<Row, CliError> {
        let empty = |reason: Option<String>| Row {
            engine: engine.name(),
            unbuildable: reason,
            deviations: Vec::new(),
            reference: None,
            max_error: None,
            final_error: None,
            energy_drift: None,
            reference_energy_drift: None,
            momentum_drift: None,
            constraint_violation: None,
            force_error: None,
            steps: None,
            microseconds_per_step: None,
        };
        match result {
            Err(Error::Build(BuildError::Unbuildable { reason, .. })) => Ok(empty(Some(reason))),
            Err(source) => Err(CliError::Compare { engine, source }),
            Ok(c) => Ok(Row {
                deviations: c.deviations,
                reference: Some(c.reference.name()),
                max_error: Some(c.max_error),
                final_error: Some(c.final_error),
                energy_drift: c.energy_drift,
                reference_energy_drift: c.reference_energy_drift,
                momentum_drift: c.momentum_drift,
                constraint_violation: c.constraint_violation,
                force_error: c.force_error,
                steps: Some(c.steps),
                microseconds_per_step: Some(c.seconds_per_step * 1e6),
                ..empty(None)
            }),
        }
    }
}

fn cell(value: Option<f64>) -> String {
    value.map_or_else(|| "—".to_string(), |v| format!("{v:.2e}"))
}

/// Run the comparison.
pub fn run(args: &Args) -> Result<(), CliError> {
    let scene = args::scene(&args.scene)?;
    let params = args::params(scene, &args.params)?;
    let given = args::state(scene, &params, args.q.as_deref(), args.qdot.as_deref(), None)?;
    let initial = args::hold(args::build(scene, &params, &given)?.as_mut(), given, args.hold.as_deref())?;
    let engines: Vec<Engine> = if args.engine == "all" {
        Engine::ALL.to_vec()
    } else {
        vec![Engine::from_name(&args.engine).ok_or_else(|| CliError::UnknownEngine(args.engine.clone()))?]
    };
    if !(args.t_end.is_finite() && args.t_end > 0.0) {
        return Err(CliError::NotPositive { flag: "--t-end", value: args.t_end });
    }
    args::step("--dt", args.dt, args.t_end)?;
    let settings = Settings { dt: args.dt, substeps: args.substeps, tolerance: args.tol };
    if args.dt > args.t_end {
        return Err(CliError::StepBeyondRun { dt: args.dt, t_end: args.t_end });
    }
    // A hundred samples; with a rapier step longer than that, one sample per step (a sample
    // between two steps would measure the rounding of its time, not the engine).
    let every = (args.t_end / 100.0).max(args.dt);
    // What each engine will cost, before any runs (skipped with --force).
    let limit = long_work::max_seconds(args.max_seconds, args.force)?;
    let max_seconds = limit.as_ref().map(|(seconds, _)| *seconds);
    let started = std::time::Instant::now();
    let estimates: Vec<Option<long_work::Estimate>> = if args.force || args.max_seconds.is_some() {
        vec![None; engines.len()]
    } else {
        engines.iter().map(|&engine| estimate(engine, scene, &params, &initial, &settings, args.t_end)).collect()
    };
    let total = long_work::Estimate {
        seconds: estimates.iter().flatten().map(|e| e.seconds).sum(),
        at_least: estimates.iter().flatten().any(|e| e.at_least),
    };
    if estimates.iter().any(Option::is_some) {
        let what = format!(
            "comparing {} over {} s in {} engine{} (rapier dt = {:e}, {} substeps)",
            scene.id(),
            args.t_end,
            engines.len(),
            if engines.len() == 1 { "" } else { "s" },
            args.dt,
            args.substeps
        );
        long_work::check_time(Some(total), args.force, &what, "--t-end, --dt or --substeps")?;
    }
    // Progress in estimated milliseconds (one unit per engine without estimates).
    let units = |estimate: Option<long_work::Estimate>| estimate.map_or(1, |e| (e.seconds * 1e3).ceil() as u64 + 1);
    let bar = long_work::progress_bar(estimates.iter().map(|&e| units(e)).sum());
    let mut rows = Vec::new();
    let mut left_out: Vec<&'static str> = Vec::new();
    let mut ticker = long_work::Ticker::new();
    for (engine, estimate) in engines.into_iter().zip(estimates) {
        bar.set_message(engine.name());
        ticker.tick(|| format!("compare {}: {} rows done, running {}", scene.id(), rows.len(), engine.name()));
        let remaining = max_seconds.map(|limit| limit - started.elapsed().as_secs_f64());
        if !left_out.is_empty() || remaining.is_some_and(|r| r <= 0.0) {
            left_out.push(engine.name());
            continue;
        }
        // On its own thread, so that one still running at --max-seconds can be abandoned.
        let (send, receive) = std::sync::mpsc::channel();
        let (p, i) = (params.clone(), initial.clone());
        let t_end = args.t_end;
        std::thread::spawn(move || {
            let _ = send.send(compare(engine, scene, &p, &i, &settings, t_end, every));
        });
        let result = match remaining {
            Some(r) => receive.recv_timeout(std::time::Duration::from_secs_f64(r)).ok(),
            None => receive.recv().ok(),
        };
        bar.inc(units(estimate));
        match result {
            Some(result) => rows.push(Row::from(engine, result)?),
            None => left_out.push(engine.name()),
        }
    }
    bar.finish_and_clear();
    let stopped = (!left_out.is_empty()).then(|| CliError::OutOfTime {
        what: format!("comparing {} ({} of {} engines done)", scene.id(), rows.len(), rows.len() + left_out.len()),
        elapsed: started.elapsed().as_secs_f64(),
        limit: limit.map_or_else(String::new, |(_, said)| said),
        why: format!("left out: {}", left_out.join(", ")),
    });
    // Rows measured against a computed reference (no closed form, or not for every row).
    let computed = rows.iter().any(|r| r.reference == Some(ReferenceKind::Reduced.name()));
    if args.json {
        let document = Document {
            scene: scene.id(),
            parameters: params.iter().map(|(spec, value)| (spec.name, value)).collect(),
            t0: initial.t,
            q0: initial.q.clone(),
            qdot0: initial.qdot.clone(),
            dt: args.dt,
            substeps: args.substeps,
            tol: args.tol,
            t_end: args.t_end,
            every,
            reference_tol: computed.then_some(REFERENCE_TOLERANCE),
            rows,
        };
        outln!("{}", serde_json::to_string_pretty(&document)?)?;
        return stopped.map_or(Ok(()), Err);
    }
    let against = if computed {
        format!("the reduced solution (dop853) at tol {REFERENCE_TOLERANCE:e}")
    } else {
        "the scene's closed form".to_string()
    };
    outln!(
        "{} over {} s (rapier dt = {:.3e}, {} substeps; Cartesian tol = {:e}); errors against {against}",
        scene.id(),
        args.t_end,
        args.dt,
        args.substeps,
        args.tol,
    )?;
    outln!(
        "{:<21} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>9}",
        "engine",
        "max err",
        "final err",
        "energy",
        "(ours)",
        "momentum",
        "violation",
        "force err",
        "µs/step"
    )?;
    for row in &rows {
        if let Some(reason) = &row.unbuildable {
            outln!("{:<21} not buildable: {reason}", row.engine)?;
            continue;
        }
        outln!(
            "{:<21} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>9.2}",
            row.engine,
            cell(row.max_error),
            cell(row.final_error),
            cell(row.energy_drift),
            cell(row.reference_energy_drift),
            cell(row.momentum_drift),
            cell(row.constraint_violation),
            cell(row.force_error),
            row.microseconds_per_step.unwrap_or(0.0)
        )?;
        for deviation in &row.deviations {
            outln!("{:<21}   deviation: {deviation}", "")?;
        }
    }
    stopped.map_or(Ok(()), Err)
}
