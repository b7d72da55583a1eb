//! `lagrange compare`: the reduced solver and the maximal-coordinate engines side by side.
//! Each engine's run is estimated before any runs, and a request estimated beyond
//! [`long_work::TIME_LIMIT_S`] is refused (`--force` runs it anyway); a progress bar with the
//! time left is drawn on a terminal.

use super::long_work;
use crate::args;
use crate::error::CliError;
use crate::output::outln;
use lagrange_maximal::{Engine, Settings};
use lagrange_validation::compare::{Row, Table, compare, sample_interval};
use lagrange_validation::cost::compare_wall_time;
use lagrange_validation::render::terminal;

/// Arguments of `lagrange compare`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    start: args::Start,
    /// Engine: cartesian, rapier-impulse, rapier-multibody, rapier-impulse-f32,
    /// rapier-multibody-f32, or all.
    #[arg(long, default_value = "all")]
    engine: String,
    #[command(flatten)]
    engine_settings: args::EngineSettings,
    /// Simulated time (s).
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    t_end: f64,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
    /// Run a request whose estimated wall time is beyond the limit (2 minutes).
    #[arg(long)]
    force: bool,
    /// Engines run at once, each on its own thread [default: the number of cores]; `--jobs 1`
    /// times each engine's steps alone.
    #[arg(long, value_name = "N")]
    jobs: Option<usize>,
    /// Wall-time limit (s): an engine still running then is abandoned, the rows of the engines
    /// done are printed, and the command exits 1 naming the engines left out. With it, the
    /// cost is not estimated up front; without it (and without --force) a request estimated
    /// within 2 minutes runs under a 4-minute limit.
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    max_seconds: Option<f64>,
}

/// What each engine will cost, estimated before any runs (none with `--force` or
/// `--max-seconds`); a request estimated beyond the time limit is refused.
///
/// # Errors
/// [`CliError::TooCostly`].
pub(super) fn estimates(
    (force, t_end): (bool, f64),
    scene: &'static dyn lagrange_scenes::Scene,
    (params, initial): (&lagrange_scenes::Params, &lagrange::State),
    settings: &Settings,
    engines: &[Engine],
) -> Result<Vec<Option<long_work::Estimate>>, CliError> {
    let estimates: Vec<Option<long_work::Estimate>> = if force {
        vec![None; engines.len()]
    } else {
        engines.iter().map(|&engine| compare_wall_time(engine, scene, params, initial, settings, t_end)).collect()
    };
    let total = long_work::Estimate {
        seconds: estimates.iter().flatten().map(|e| e.seconds).sum(),
        at_least: estimates.iter().flatten().any(|e| e.at_least),
    };
    if estimates.iter().any(Option::is_some) {
        let what = format!(
            "comparing {} over {} s in {} engine{} (rapier dt = {:e}, {} substeps)",
            scene.id(),
            t_end,
            engines.len(),
            if engines.len() == 1 { "" } else { "s" },
            settings.dt,
            settings.substeps
        );
        long_work::check_time(Some(total), force, &what, "--t-end, --dt or --substeps")?;
    }
    Ok(estimates)
}

/// Run the comparison.
pub fn run(args: &Args) -> Result<(), CliError> {
    let (scene, params, initial) = args.start.initial()?;
    let engines: Vec<Engine> = if args.engine == "all" {
        Engine::ALL.to_vec()
    } else {
        vec![Engine::from_name(&args.engine).ok_or_else(|| CliError::UnknownEngine(args.engine.clone()))?]
    };
    let jobs = args::jobs(args.jobs)?;
    if !(args.t_end.is_finite() && args.t_end > 0.0) {
        return Err(CliError::NotPositive { flag: "--t-end", value: args.t_end });
    }
    let settings = args.engine_settings.settings();
    args::step("--dt", settings.dt, args.t_end)?;
    if settings.dt > args.t_end {
        return Err(CliError::StepBeyondRun { dt: settings.dt, t_end: args.t_end });
    }
    let every = sample_interval(args.t_end, settings.dt);
    let limit = long_work::max_seconds(args.max_seconds, args.force)?;
    let max_seconds = limit.as_ref().map(|(seconds, _)| *seconds);
    let started = std::time::Instant::now();
    let estimates = estimates(
        (args.force || args.max_seconds.is_some(), args.t_end),
        scene,
        (&params, &initial),
        &settings,
        &engines,
    )?;
    // Progress in estimated milliseconds (one unit per engine without estimates).
    let units = |estimate: Option<long_work::Estimate>| estimate.map_or(1, |e| (e.seconds * 1e3).ceil() as u64 + 1);
    let bar = long_work::progress_bar(estimates.iter().map(|&e| units(e)).sum());
    let mut rows = Vec::new();
    let mut left_out: Vec<&'static str> = Vec::new();
    let mut ticker = long_work::ticker();
    let runs: Vec<(Engine, Option<long_work::Estimate>)> = engines.into_iter().zip(estimates).collect();
    // --jobs engines at once, each on its own thread (so that one still running at
    // --max-seconds can be abandoned); rows in the order asked.
    for batch in runs.chunks(jobs) {
        let remaining = max_seconds.map(|limit| limit - started.elapsed().as_secs_f64());
        if !left_out.is_empty() || remaining.is_some_and(|r| r <= 0.0) {
            left_out.extend(batch.iter().map(|(engine, _)| engine.name()));
            continue;
        }
        let receivers: Vec<_> = batch
            .iter()
            .map(|&(engine, _)| {
                let (send, receive) = std::sync::mpsc::channel();
                let (p, i) = (params.clone(), initial.clone());
                let t_end = args.t_end;
                std::thread::spawn(move || {
                    let _ = send.send(compare(engine, scene, &p, &i, &settings, t_end, every));
                });
                receive
            })
            .collect();
        let names: Vec<&str> = batch.iter().map(|(engine, _)| engine.name()).collect();
        bar.set_message(names.join(", "));
        for (&(engine, estimate), receive) in batch.iter().zip(receivers) {
            ticker.tick(|| format!("compare {}: {} rows done, running {}", scene.id(), rows.len(), names.join(", ")));
            let remaining = max_seconds.map(|limit| limit - started.elapsed().as_secs_f64());
            let result = match remaining {
                Some(r) if r <= 0.0 => None,
                Some(r) => receive.recv_timeout(std::time::Duration::from_secs_f64(r)).ok(),
                None => receive.recv().ok(),
            };
            bar.inc(units(estimate));
            match result {
                Some(result) => {
                    rows.push(Row::new(engine, result).map_err(|source| CliError::Compare { engine, source })?);
                }
                None => left_out.push(engine.name()),
            }
        }
    }
    bar.finish_and_clear();
    let stopped = (!left_out.is_empty()).then(|| CliError::OutOfTime {
        what: format!("comparing {} ({} of {} engines done)", scene.id(), rows.len(), rows.len() + left_out.len()),
        elapsed: started.elapsed().as_secs_f64(),
        limit: limit.map_or_else(String::new, |(_, said)| said),
        why: format!("left out: {}", left_out.join(", ")),
    });
    let table = Table::new(scene, &params, &initial, &settings, (args.t_end, every), rows);
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&table)?)?;
    } else {
        crate::output::print(&terminal::comparison(&table))?;
    }
    stopped.map_or(Ok(()), Err)
}
