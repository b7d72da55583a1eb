//! `lagrange simulate`: integrate a scene and write `t, q, q̇, h` as CSV, with units in the
//! header; check the run against every constant of the motion its scene declares and against
//! its constraints, to the error its method's tolerance or step allows
//! ([`lagrange_validation::health`]: exit 1 beyond it, after writing, unless `--allow-drift`);
//! tell a divergence from stiffness when a run fails; refuse a request whose estimated cost is absurd (`--force` runs it anyway); write
//! `--out` whole or not at all.

use super::files::Pending;
use super::long_work::{self, Run};
use crate::args;
use crate::error::CliError;
use indicatif::ProgressBar;
use lagrange::integrate::{MethodKind, Sample, Sink, Stats};
use lagrange::{Coordinate, Method, Output, State, System, Trajectory};
use lagrange_validation::health;
use std::io::Write;

/// Which integrator: a [`MethodKind`], spelled and described as the solver names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Integrator(MethodKind);

/// Every integrator, in [`MethodKind::ALL`] order.
const INTEGRATORS: [Integrator; MethodKind::ALL.len()] = {
    let mut all = [Integrator(MethodKind::Rk4); MethodKind::ALL.len()];
    let mut i = 0;
    while i < all.len() {
        all[i] = Integrator(MethodKind::ALL[i]);
        i += 1;
    }
    all
};

impl clap::ValueEnum for Integrator {
    fn value_variants<'a>() -> &'a [Self] {
        &INTEGRATORS
    }

    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        let former = MethodKind::FORMER_NAMES.iter().filter(|(_, kind)| *kind == self.0).map(|(name, _)| *name);
        Some(clap::builder::PossibleValue::new(self.0.name()).help(self.0.summary()).aliases(former))
    }
}

/// Arguments of `lagrange simulate`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene id (see `lagrange scenes`) or scene file (`*.toml`, docs/files.md).
    scene: String,
    /// Parameter override NAME=VALUE (name or symbol), repeatable.
    #[arg(long = "param", value_name = "NAME=VALUE")]
    params: Vec<String>,
    /// Initial coordinates, comma-separated (default: the scene's initial state).
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    q: Option<String>,
    /// Initial velocities, comma-separated (default: the scene's initial state).
    #[arg(long, value_name = "a,b,..", allow_hyphen_values = true)]
    qdot: Option<String>,
    /// For a mechanism with constraints among its coordinates (a four-bar): bring the initial
    /// state onto them, keeping these coordinates and their rates (comma-separated names, e.g.
    /// `θ2`); the others move as little as possible. Without it, a given state must already
    /// satisfy the constraints.
    #[arg(long, value_name = "NAME,..")]
    hold: Option<String>,
    /// End time (s).
    #[arg(long, allow_negative_numbers = true)]
    t_end: f64,
    /// Initial time (s), default 0: where a driven or time-dependent scene starts its motion.
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    start: Option<f64>,
    /// Integrator.
    #[arg(long, value_enum, default_value_t = Integrator(MethodKind::Dopri5))]
    integrator: Integrator,
    /// Step of the fixed-step integrators: rk4, variational, gauss4 (default 1e-3).
    #[arg(long, allow_negative_numbers = true)]
    dt: Option<f64>,
    /// Tolerance (relative and absolute) of the error-controlled integrators: dopri5, dop853,
    /// sdirk4 (default 1e-10 for dopri5, 1e-12 for dop853, 1e-8 for sdirk4).
    #[arg(long, allow_negative_numbers = true)]
    tol: Option<f64>,
    /// Output interval (default: 200 samples; a multiple of --dt for fixed steps).
    #[arg(long, allow_negative_numbers = true)]
    every: Option<f64>,
    /// CSV file to write (default: standard output); written whole or not at all.
    #[arg(long)]
    out: Option<std::path::PathBuf>,
    /// Run a request whose estimated wall time or output size is beyond the limits (2 minutes,
    /// 1 GB).
    #[arg(long)]
    force: bool,
    /// Wall-time limit (s): the run stops there — or earlier, once its measured progress
    /// projects it beyond three times the limit — writes the samples it has, and exits 1
    /// saying how far it got. With it, the cost is not estimated up front; without it (and
    /// without --force) a request estimated within 2 minutes runs under a 4-minute limit.
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    max_seconds: Option<f64>,
    /// Exit 0 (with a warning) when the run drifts from a constant of the motion or from its
    /// constraints beyond what its method and setting allow; without it such a run exits 1
    /// (after writing its output).
    #[arg(long)]
    allow_drift: bool,
}

/// The method and output interval the arguments ask for, over `span` simulated seconds.
fn method_and_every(args: &Args, span: f64) -> Result<(Method, f64), CliError> {
    let Integrator(kind) = args.integrator;
    let method = match kind.default_method() {
        default @ (Method::Dopri5 { .. } | Method::Dop853 { .. } | Method::Sdirk4 { .. }) => {
            if args.dt.is_some() {
                return Err(CliError::NotForIntegrator {
                    flag: "--dt",
                    integrator: kind.name(),
                    applies_to: "the fixed-step integrators (rk4, variational, gauss4)",
                    instead: "--tol",
                });
            }
            args.tol.map_or(default, |tol| kind.with(tol))
        }
        Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss4 { dt } => {
            if args.tol.is_some() {
                return Err(CliError::NotForIntegrator {
                    flag: "--tol",
                    integrator: kind.name(),
                    applies_to: "the error-controlled integrators (dopri5, dop853, sdirk4)",
                    instead: "--dt",
                });
            }
            kind.with(args::step("--dt", args.dt.unwrap_or(dt), args.t_end)?)
        }
    };
    let every = match (args.every, method) {
        (Some(every), _) => every,
        (None, Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss4 { dt }) => {
            dt * (span / 200.0 / dt).round().max(1.0)
        }
        (None, Method::Dopri5 { .. } | Method::Dop853 { .. } | Method::Sdirk4 { .. }) => span / 200.0,
    };
    if !(every > 0.0 && every.is_finite()) {
        return Err(CliError::NotPositive { flag: "--every", value: every });
    }
    Ok((method, every))
}

/// The CSV header: `t [s]`, each coordinate and its velocity (`_dot`) with their SI units, the
/// energy function `h [J]` and, for a mechanism with constraints among its coordinates, the
/// largest constraint residuals of each sample: `max|Phi|` (positions) and `max|Phi_dot|`
/// (velocities, the velocity constraints included), in the units of the constraints as
/// written.
fn header(coordinates: &[Coordinate], constrained: bool) -> String {
    let mut header = vec!["t [s]".to_string()];
    header.extend(coordinates.iter().map(|c| format!("{} [{}]", c.name, c.unit())));
    header.extend(coordinates.iter().map(|c| format!("{}_dot [{}/s]", c.name, c.unit())));
    header.push("h [J]".into());
    if constrained {
        header.extend(["max|Phi|".into(), "max|Phi_dot|".into()]);
    }
    header.join(",")
}

/// Write the trajectory as CSV: every number in its shortest form that reads back to the same
/// `f64` (scientific outside 1e-4 … 1e6, never 17 leading zeros), the time to 15 digits.
fn write_csv(out: &mut dyn Write, coordinates: &[Coordinate], trajectory: &Trajectory) -> std::io::Result<()> {
    let constrained = !trajectory.violation.is_empty();
    writeln!(out, "{}", header(coordinates, constrained))?;
    for k in 0..trajectory.len() {
        let number = |v: &f64| crate::output::compact(*v).to_string();
        // The time to 15 significant digits: a sample time `t0 + k · every` carries the rounding
        // of the product (`0.8999999999999999` for 0.9), which is not a time anyone asked for.
        let t: f64 = format!("{:.14e}", trajectory.t[k]).parse().unwrap_or(trajectory.t[k]);
        let mut row = vec![number(&t)];
        row.extend(trajectory.q(k).iter().map(number));
        row.extend(trajectory.qdot(k).iter().map(number));
        row.push(number(&trajectory.energy[k]));
        if let Some(violation) = trajectory.violation.get(k) {
            row.extend(violation.iter().map(number));
        }
        writeln!(out, "{}", row.join(","))?;
    }
    Ok(())
}

/// A [`Trajectory`] that also sets a progress bar (when there is one) to the fraction of the
/// horizon each sample reaches (in thousandths).
struct Progress {
    trajectory: Trajectory,
    bar: Option<ProgressBar>,
    t0: f64,
    span: f64,
    watch: long_work::Watch,
}

impl Sink for Progress {
    fn wants_energy(&self) -> bool {
        self.trajectory.wants_energy()
    }

    fn wants_violation(&self) -> bool {
        self.trajectory.wants_violation()
    }

    fn record(&mut self, sample: Sample<'_>) {
        if let Some(bar) = &self.bar {
            bar.set_position(((sample.t - self.t0) / self.span * 1e3) as u64);
        }
        self.trajectory.record(sample);
    }

    fn finish(&mut self, stats: Stats) {
        self.trajectory.finish(stats);
    }

    fn keep_going(&mut self, t: f64) -> bool {
        self.watch.keep_going(t)
    }
}

/// The run, with a progress bar and the time left when standard error is a terminal (a line
/// every 10 s otherwise), stopped by `max_seconds`: the same run as [`System::simulate`], into a
/// sink that keeps the samples recorded before a failure or a stop.
fn simulate(
    scene: &dyn lagrange_scenes::Scene,
    system: &dyn System,
    initial: &State,
    (t_end, max_seconds): (f64, Option<f64>),
    method: Method,
    output: &Output,
) -> (Trajectory, Result<Stats, lagrange::Error>, long_work::Watch) {
    let bar = long_work::shows_progress().then(|| {
        let bar = long_work::progress_bar(1000);
        bar.set_message(scene.id());
        bar
    });
    let trajectory = Trajectory::with_capacity(initial.q.len(), 0);
    let label = format!("simulate {}", scene.id());
    let watch = long_work::Watch::new(&label, initial.t, t_end, max_seconds, long_work::ticker());
    let mut progress = Progress { trajectory, bar, t0: initial.t, span: t_end - initial.t, watch };
    let result = system.simulate_into(initial, t_end, method, output, &mut progress);
    if let Some(bar) = &progress.bar {
        bar.finish_and_clear();
    }
    (progress.trajectory, result, progress.watch)
}

/// The flag that sets a method's accuracy.
fn accuracy_flag(method: Method) -> &'static str {
    if method.kind().is_fixed_step() { "--dt" } else { "--tol" }
}

/// The error of a failed run, with the evidence of its samples ([`health::diagnose`]).
fn diagnose(
    scene: &dyn lagrange_scenes::Scene,
    params: &lagrange_scenes::Params,
    system: &mut dyn System,
    method: Method,
    partial: &Trajectory,
    error: lagrange::Error,
) -> CliError {
    let cause = health::diagnose(scene, params, system, method, partial, &error);
    let (scene, source) = (scene.id().to_string(), Box::new(error));
    match cause {
        None => CliError::Engine(*source),
        Some(health::Cause::DivergedFirst { findings }) => CliError::DivergedFirst {
            scene,
            method: method.describe(),
            findings: joined(&findings),
            source,
            flag: accuracy_flag(method),
        },
        Some(health::Cause::NotStiff { t, h, rate }) => {
            CliError::NotStiff { scene, method: method.describe(), t, h, rate, source }
        }
    }
}

/// The findings, one sentence.
fn joined(findings: &[health::Finding]) -> String {
    findings.iter().map(ToString::to_string).collect::<Vec<_>>().join("; ")
}

/// Write the samples as CSV to `--out` (whole or not at all; a pipe or device directly) or to
/// standard output.
fn write_output(args: &Args, id: &str, coordinates: &[Coordinate], trajectory: &Trajectory) -> Result<(), CliError> {
    match &args.out {
        Some(path) => {
            let mut file = Pending::create(path)?;
            write_csv(file.writer(), coordinates, trajectory).map_err(|e| file.error(e))?;
            file.commit()?;
            crate::output::warn(&format!(
                "{}: {} samples to {} ({} steps, {} rejected)",
                id,
                trajectory.len(),
                path.display(),
                trajectory.stats.steps,
                trajectory.stats.rejected
            ));
        }
        None => {
            let stdout = std::io::stdout();
            write_csv(&mut stdout.lock(), coordinates, trajectory).map_err(CliError::Stdout)?;
        }
    }
    Ok(())
}

/// Integrate and write.
pub fn run(args: &Args) -> Result<(), CliError> {
    let scene = args::scene(&args.scene)?;
    let params = args::params(scene, &args.params)?;
    if let Some(start) = args.start.filter(|s| !s.is_finite()) {
        return Err(CliError::NotFinite { flag: "--start", value: start });
    }
    let given = args::state(scene, &params, args.q.as_deref(), args.qdot.as_deref(), args.start)?;
    if !args.t_end.is_finite() || (args.start.is_none() && args.t_end <= given.t) {
        return Err(CliError::NotPositive { flag: "--t-end", value: args.t_end });
    }
    if args.t_end <= given.t {
        return Err(CliError::EndBeforeStart { start: given.t, t_end: args.t_end });
    }
    let span = args.t_end - given.t;
    let (method, every) = method_and_every(args, span)?;
    let mut system = args::build(scene, &params, &given)?;
    let initial = args::hold(system.as_mut(), given, args.hold.as_deref())?;
    let coordinates = system.coordinates().to_vec();
    // Refuse an absurd request before running it: the output's size first (known exactly),
    // then the wall time, measured on the run's own beginning.
    let rows = (span / every).floor() + 2.0;
    let violation_columns = if system.constraint_counts() == (0, 0) { 0 } else { 2 };
    long_work::check_output(rows, 2 * coordinates.len() + 2 + violation_columns, args.force, "--every")?;
    let (first, flag) = match method {
        Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss4 { dt } => (dt, "--t-end or --dt"),
        Method::Dopri5 { .. } | Method::Dop853 { .. } | Method::Sdirk4 { .. } => (0.0, "--t-end or --tol"),
    };
    if !args.force && args.max_seconds.is_none() {
        // The reduced solver's steps are short: its calibration runs to its end.
        let estimate = long_work::wall_time(span, first, |tau, _| {
            match system.simulate(&initial, initial.t + tau, method, &Output::Ends) {
                Ok(_) => Run::Done,
                Err(_) => Run::Failed,
            }
        });
        let what = format!("simulating {span:e} s of {} with {}", scene.id(), method.describe());
        long_work::check_time(estimate, args.force, &what, flag)?;
    }
    let limit = long_work::max_seconds(args.max_seconds, args.force)?;
    let max_seconds = limit.as_ref().map(|(seconds, _)| *seconds);
    let (trajectory, result, watch) =
        simulate(scene, system.as_ref(), &initial, (args.t_end, max_seconds), method, &Output::Every(every));
    match result {
        Err(lagrange::Error::Stopped { t, .. }) => {
            // What it has, then why it stopped.
            write_output(args, scene.id(), &coordinates, &trajectory)?;
            let why = match watch.stopped {
                Some(long_work::Stop::WillNotFinish { seconds }) => {
                    format!("at its measured rate the whole run would take about {}", long_work::duration(seconds))
                }
                _ => "the time ran out".to_string(),
            };
            return Err(CliError::OutOfTime {
                what: format!("simulating {} (t = {t:.6} of {} s reached)", scene.id(), args.t_end),
                elapsed: watch.elapsed(),
                limit: limit.map_or_else(String::new, |(_, said)| said),
                why,
            });
        }
        Err(error) => return Err(diagnose(scene, &params, system.as_mut(), method, &trajectory, error)),
        Ok(_) => {}
    }
    // The run checks itself against what the scene declares (docs/cli.md); the output is
    // written either way, and a run that failed its checks exits 1 after it.
    let health = health::check(scene, &params, system.as_mut(), method, &trajectory)?;
    let unhealthy = (!health.is_healthy()).then(|| CliError::Unhealthy {
        scene: scene.id().to_string(),
        method: method.describe(),
        findings: joined(&health.findings),
        expected: health.expected,
        flag: accuracy_flag(method),
    });
    if let (Some(t), None) = (trajectory.stats.stiffness, &unhealthy) {
        crate::output::warn(&format!("warning: the problem looks stiff from t = {t}; try --integrator sdirk4"));
    }
    write_output(args, scene.id(), &coordinates, &trajectory)?;
    match unhealthy {
        Some(error) if args.allow_drift => {
            crate::output::warn(&format!("warning: {error} (kept: --allow-drift)"));
            Ok(())
        }
        Some(error) => Err(error),
        None => Ok(()),
    }
}
