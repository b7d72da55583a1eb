//! `lagrange report` from start to end: validate the arguments, probe every scene, run every
//! sweep under a progress bar, and write report.json, report.md, the plots and the summary.

use super::options::{Args, Options};
use crate::error::CliError;
use crate::output::{out, outln};
use lagrange_maximal::{Engine, Settings};
use lagrange_validation::animation::animate;
use lagrange_validation::assemble::{self, scene_report};
use lagrange_validation::plan::Plan;
use lagrange_validation::render::animation;
use lagrange_validation::render::{index, markdown, plots, terminal};
use lagrange_validation::runs::{ScenePlan, SceneRuns};
use lagrange_validation::schema::{Plots, SceneReport};
use rayon::prelude::*;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use crate::commands::{files, long_work};
use indicatif::ProgressBar;
use lagrange_validation::stability::{self, Effort};
use std::path::Path;
use std::time::Instant;

/// Write a file whole or not at all (an interrupted report leaves no partial file).
fn write(path: &Path, contents: &str) -> Result<(), CliError> {
    files::write(path, contents.as_bytes())
}

/// A progress bar over `total` runs on standard error with the time left (drawn only on a
/// terminal).
fn progress_bar(total: usize) -> ProgressBar {
    long_work::progress_bar(total as u64)
}

/// The scene's animation (`<scene>.html`): the reduced solution and every maximal engine over
/// the scene's span, rapier's step scaled with the span as the sweeps' are (`scale`). An
/// animation that cannot be made (an engine failing along the run) is left out with the reason
/// on standard error: the report's own runs record that failure.
///
/// # Errors
/// The page cannot be written.
fn animation(scene_plan: &ScenePlan, scale: f64, out: &Path) -> Result<Option<String>, CliError> {
    let settings = Settings { dt: Settings::default().dt * scale, ..Settings::default() };
    let (scene, initial) = (scene_plan.scene, &scene_plan.initial);
    let t_end = initial.t + scene_plan.plan.horizon;
    match animate(scene, &scene_plan.params, initial, &Engine::ALL, &settings, t_end) {
        Ok(animation) => {
            let name = format!("{}.html", scene.id());
            files::write(&out.join(&name), animation::page(&animation).as_bytes())?;
            Ok(Some(name))
        }
        Err(error) => {
            crate::output::warn(&format!("{}: no animation: {error}", scene.id()));
            Ok(None)
        }
    }
}

/// One scene: its runs, plots and animation, and its part of the report.
///
/// # Errors
/// A failing reference, or a file that cannot be written.
fn run_scene(scene_plan: &ScenePlan, plan: &Plan, out: &Path, bar: &ProgressBar) -> Result<SceneReport, CliError> {
    let scene_start = Instant::now();
    let runs = SceneRuns::execute(scene_plan, |label| {
        bar.set_message(label.to_string());
        bar.inc(1);
    })?;
    let id = scene_plan.scene.id();
    let own = &scene_plan.plan;
    let animation = animation(scene_plan, own.horizon / plan.horizon, out)?;
    let names =
        Plots { work_precision: format!("{id}_work_precision.svg"), error: format!("{id}_error.svg"), animation };
    let plot = |name: &String, svg: Result<String, plots::PlotError>| {
        let path = out.join(name);
        let svg = svg.map_err(|source| CliError::Plot { path: path.clone(), source })?;
        files::write(&path, svg.as_bytes())
    };
    plot(&names.work_precision, plots::work_precision(&runs, own.horizon))?;
    plot(&names.error, plots::errors_over_time(&runs, &own.times))?;
    Ok(scene_report(&runs, names, scene_start.elapsed().as_secs_f64()))
}

/// Run the report.
///
/// # Errors
/// A bad argument, an output that cannot be written, or a scene whose reference fails.
pub fn run(args: &Args) -> Result<(), CliError> {
    let start = Instant::now();
    let options = Options::new(args)?;
    let plan = &options.plan;
    let scene_plans: Vec<ScenePlan> =
        options.scenes.iter().map(|&scene| ScenePlan::new(scene, plan)).collect::<Result<_, _>>()?;
    let out_of_time = || options.max_seconds.is_some_and(|limit| start.elapsed().as_secs_f64() > limit);
    let bar = progress_bar(scene_plans.iter().map(ScenePlan::runs).sum());
    // Scenes on --jobs threads; results in the plan's order. Past --max-seconds no scene starts.
    let stopped = AtomicBool::new(false);
    let done = AtomicUsize::new(0);
    let ticker = Mutex::new(long_work::ticker());
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.jobs)
        .build()
        .map_err(|e| CliError::Threads(e.to_string()))?;
    let outcomes: Vec<Result<Option<SceneReport>, CliError>> = pool.install(|| {
        scene_plans
            .par_iter()
            .map(|scene_plan| {
                if stopped.load(Ordering::Relaxed) || out_of_time() {
                    stopped.store(true, Ordering::Relaxed);
                    return Ok(None);
                }
                if let Ok(mut ticker) = ticker.lock() {
                    let finished = done.load(Ordering::Relaxed);
                    ticker.tick(|| format!("report: {finished} of {} scenes done", scene_plans.len()));
                }
                let report = run_scene(scene_plan, plan, &options.out, &bar)?;
                done.fetch_add(1, Ordering::Relaxed);
                Ok(Some(report))
            })
            .collect()
    });
    let mut scenes = Vec::with_capacity(scene_plans.len());
    let mut left_out: Vec<&str> = Vec::new();
    for (scene_plan, outcome) in scene_plans.iter().zip(outcomes) {
        match outcome? {
            Some(report) => scenes.push(report),
            None => left_out.push(scene_plan.scene.id()),
        }
    }
    let files = 2 * scenes.len();
    bar.finish_and_clear();
    // The stability cases of the requested scenes (all of them by default).
    let ids: Vec<&str> =
        if options.all_scenes() { Vec::new() } else { options.scenes.iter().map(|s| s.id()).collect() };
    let effort = if plan.quick { Effort::Quick } else { Effort::Full };
    let stability = if left_out.is_empty() && !out_of_time() {
        let bar = progress_bar(stability::case_count(&ids));
        let stability = stability::run(effort, &ids, options.jobs, |id| {
            bar.set_message(format!("stability: {id}"));
            bar.inc(1);
        })?;
        bar.finish_and_clear();
        stability
    } else {
        left_out.push("the stability suite");
        stability::StabilityReport::default_for(effort)
    };
    let generator = format!("lagrange-cli {}", env!("CARGO_PKG_VERSION"));
    let report = assemble::report(plan, scenes, stability, generator, start.elapsed().as_secs_f64());
    let json = serde_json::to_string_pretty(&report)?;
    write(&options.out.join("report.json"), &json)?;
    write(&options.out.join("report.md"), &markdown::render(&report))?;
    write(&options.out.join("index.html"), &index::page(&report))?;
    if options.json {
        outln!("{json}")?;
    } else {
        out!("{}", terminal::render(&report, &options.out, files))?;
    }
    if left_out.is_empty() {
        return Ok(());
    }
    Err(CliError::OutOfTime {
        what: format!("the report ({} of {} scenes done)", report.scenes.len(), scene_plans.len()),
        elapsed: start.elapsed().as_secs_f64(),
        limit: format!("--max-seconds {}", options.max_seconds.unwrap_or(0.0)),
        why: format!("left out: {}", left_out.join(", ")),
    })
}
