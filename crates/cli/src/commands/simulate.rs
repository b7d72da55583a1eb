//! `lagrange simulate`: integrate a scene and write `t, q, q̇, h` as CSV, with units in the
//! header; warn when a conserved energy drifts beyond what the method's tolerance or step
//! allows; refuse a request whose estimated cost is absurd (`--force` runs it anyway); write
//! `--out` whole or not at all.

use super::files::Pending;
use super::long_work::{self, Run};
use crate::args;
use crate::error::CliError;
use indicatif::ProgressBar;
use lagrange::integrate::{MethodKind, Sample, Sink, Stats};
use lagrange::{Coordinate, Method, Output, State, System, Trajectory};
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
        Some(clap::builder::PossibleValue::new(self.0.name()).help(self.0.summary()))
    }
}

/// Arguments of `lagrange simulate`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene id (see `lagrange scenes`).
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
    #[arg(long, value_enum, default_value_t = Integrator(MethodKind::Adaptive))]
    integrator: Integrator,
    /// Step of the fixed-step integrators: rk4, variational, gauss (default 1e-3).
    #[arg(long, allow_negative_numbers = true)]
    dt: Option<f64>,
    /// Tolerance (relative and absolute) of the error-controlled integrators: adaptive, implicit
    /// (default 1e-10 for adaptive, 1e-8 for implicit).
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
}

/// The method and output interval the arguments ask for, over `span` simulated seconds.
fn method_and_every(args: &Args, span: f64) -> Result<(Method, f64), CliError> {
    let Integrator(kind) = args.integrator;
    let method = match kind.default_method() {
        default @ (Method::Adaptive { .. } | Method::Dop853 { .. } | Method::Implicit { .. }) => {
            if args.dt.is_some() {
                return Err(CliError::NotForIntegrator {
                    flag: "--dt",
                    integrator: kind.name(),
                    applies_to: "the fixed-step integrators (rk4, variational, gauss)",
                    instead: "--tol",
                });
            }
            args.tol.map_or(default, |tol| kind.with(tol))
        }
        Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss { dt } => {
            if args.tol.is_some() {
                return Err(CliError::NotForIntegrator {
                    flag: "--tol",
                    integrator: kind.name(),
                    applies_to: "the error-controlled integrators (adaptive, dop853, implicit)",
                    instead: "--dt",
                });
            }
            kind.with(args::step("--dt", args.dt.unwrap_or(dt), args.t_end)?)
        }
    };
    let every = match (args.every, method) {
        (Some(every), _) => every,
        (None, Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss { dt }) => {
            dt * (span / 200.0 / dt).round().max(1.0)
        }
        (None, Method::Adaptive { .. } | Method::Dop853 { .. } | Method::Implicit { .. }) => span / 200.0,
    };
    if !(every > 0.0 && every.is_finite()) {
        return Err(CliError::NotPositive { flag: "--every", value: every });
    }
    Ok((method, every))
}

/// `rk4 at dt = 1e-3`, `adaptive at tol = 1e-10`.
fn describe(method: Method) -> String {
    match method {
        Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss { dt } => {
            format!("{} at dt = {dt:e}", method.name())
        }
        Method::Adaptive { tol } | Method::Dop853 { tol } | Method::Implicit { tol } => {
            format!("{} at tol = {:e}", method.name(), tol.rtol)
        }
    }
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

/// Write the trajectory as CSV.
fn write_csv(out: &mut dyn Write, coordinates: &[Coordinate], trajectory: &Trajectory) -> std::io::Result<()> {
    let constrained = !trajectory.violation.is_empty();
    writeln!(out, "{}", header(coordinates, constrained))?;
    for k in 0..trajectory.len() {
        let mut row = vec![trajectory.t[k].to_string()];
        row.extend(trajectory.q(k).iter().map(f64::to_string));
        row.extend(trajectory.qdot(k).iter().map(f64::to_string));
        row.push(trajectory.energy[k].to_string());
        if let Some(violation) = trajectory.violation.get(k) {
            row.extend(violation.iter().map(f64::to_string));
        }
        writeln!(out, "{}", row.join(","))?;
    }
    Ok(())
}

/// The fastest rate of the motion at the state `(t, q, q̇)`, `ω` (1/s): from the acceleration
/// Jacobian, `√‖∂q̈/∂q‖∞ + ‖∂q̈/∂q̇‖∞` — the row-sum norms bound the spectral radii, so this
/// bounds the frequency of the stiffest linearized mode plus its damping rate. `None` where the
/// Jacobian cannot be evaluated.
fn fastest_rate(system: &mut dyn System, t: f64, q: &[f64], qdot: &[f64]) -> Option<f64> {
    let n = q.len();
    let jacobian = system.acceleration_jacobian(t, q, qdot).ok()?;
    let row_sum = |columns: std::ops::Range<usize>| {
        (0..n).map(|i| columns.clone().map(|j| jacobian[i * 2 * n + j].abs()).sum::<f64>()).fold(0.0, f64::max)
    };
    let rate = row_sum(0..n).sqrt() + row_sum(n..2 * n);
    rate.is_finite().then_some(rate)
}

/// The relative drift of the energy function `h` that a run of `method` over `steps` steps can
/// be expected to stay below, on a scene that conserves `h`; `rate` is
/// [`fastest_rate`] at the initial state. Beyond it, the run is not resolving the motion (a
/// tolerance too loose, a step too large, an instability) and `simulate` warns.
///
/// - Error-controlled methods (adaptive, implicit) keep each step's local error below `tol`
///   relative to the state; `h` is quadratic in the velocities, so a relative state error `δ`
///   moves `h` by about `2δ`, and in the worst case these add up over the steps: `2 N tol`.
///   The threshold `10 N tol` leaves a factor 5 for the dense output between steps and for
///   states of order one, where the absolute part of the tolerance counts as much.
/// - Fixed steps: an order-`p` method's local error is `O((ω dt)^{p+1})`. RK4 is not
///   symplectic: its energy error accumulates step after step, `≲ N (ω dt)⁵`. The variational
///   (order 2) and Gauss (order 4) integrators are symplectic: their energy error stays bounded,
///   `≲ (ω dt)^p`, however long the run (docs/method.md). The threshold is 10 times that, plus
///   `10 N ε` for round-off adding up over the steps.
///
/// Whatever these allow, a drift beyond [`MAX_DRIFT`] is warned about: the estimates lose their
/// meaning once `ω dt` approaches 1 or `N tol` a percent, and a run that moves a conserved
/// energy by a tenth does not resolve the motion.
fn drift_threshold(method: Method, steps: usize, rate: Option<f64>) -> Option<f64> {
    let n = steps.max(1) as f64;
    let round_off = 10.0 * n * f64::EPSILON;
    let threshold = match method {
        Method::Adaptive { tol } | Method::Dop853 { tol } | Method::Implicit { tol } => {
            10.0 * n * tol.rtol.max(tol.atol)
        }
        Method::Rk4 { dt } => 10.0 * n * (rate? * dt).powi(5) + round_off,
        Method::Variational { dt } => 10.0 * (rate? * dt).powi(2) + round_off,
        Method::Gauss { dt } => 10.0 * (rate? * dt).powi(4) + round_off,
    };
    Some(threshold.min(MAX_DRIFT))
}

/// The largest relative energy drift `simulate` accepts without a warning, whatever the method.
const MAX_DRIFT: f64 = 0.1;

/// The largest drift of `h` over the samples relative to `|h(t0)|`; `None` for a run without
/// samples or starting at `h = 0`, where a relative drift is undefined.
fn energy_drift(trajectory: &Trajectory) -> Option<f64> {
    let h0 = *trajectory.energy.first()?;
    let drift = trajectory.energy.iter().map(|h| (h - h0).abs()).fold(0.0, f64::max);
    (h0 != 0.0).then(|| drift / h0.abs())
}

/// A [`Trajectory`] that also sets a progress bar to the fraction of the horizon each sample
/// reaches (in thousandths).
struct Progress<'a> {
    trajectory: Trajectory,
    bar: &'a ProgressBar,
    t0: f64,
    span: f64,
}

impl Sink for Progress<'_> {
    fn wants_energy(&self) -> bool {
        self.trajectory.wants_energy()
    }

    fn wants_violation(&self) -> bool {
        self.trajectory.wants_violation()
    }

    fn record(&mut self, sample: Sample<'_>) {
        self.bar.set_position(((sample.t - self.t0) / self.span * 1e3) as u64);
        self.trajectory.record(sample);
    }

    fn finish(&mut self, stats: Stats) {
        self.trajectory.finish(stats);
    }
}

/// The run, with a progress bar and the time left when standard error is a terminal: the same
/// run as [`System::simulate`], into a sink that moves the bar as it records.
fn simulate(
    scene: &dyn lagrange_scenes::Scene,
    system: &dyn System,
    initial: &State,
    t_end: f64,
    method: Method,
    output: &Output,
) -> Result<Trajectory, CliError> {
    if !long_work::shows_progress() {
        return Ok(system.simulate(initial, t_end, method, output)?);
    }
    let bar = long_work::progress_bar(1000);
    bar.set_message(scene.id());
    let trajectory = Trajectory::with_capacity(initial.q.len(), 0);
    let mut progress = Progress { trajectory, bar: &bar, t0: initial.t, span: t_end - initial.t };
    system.simulate_into(initial, t_end, method, output, &mut progress)?;
    bar.finish_and_clear();
    Ok(progress.trajectory)
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
    let mut system = scene.build(&params)?;
    let initial = args::hold(system.as_mut(), given, args.hold.as_deref())?;
    let coordinates = system.coordinates().to_vec();
    // Refuse an absurd request before running it: the output's size first (known exactly),
    // then the wall time, measured on the run's own beginning.
    let rows = (span / every).floor() + 2.0;
    let violation_columns = if system.constraint_counts() == (0, 0) { 0 } else { 2 };
    long_work::check_output(rows, 2 * coordinates.len() + 2 + violation_columns, args.force, "--every")?;
    let (first, flag) = match method {
        Method::Rk4 { dt } | Method::Variational { dt } | Method::Gauss { dt } => (dt, "--t-end or --dt"),
        Method::Adaptive { .. } | Method::Dop853 { .. } | Method::Implicit { .. } => (0.0, "--t-end or --tol"),
    };
    if !args.force {
        // The reduced solver's steps are short: its calibration runs to its end.
        let estimate = long_work::wall_time(span, first, |tau, _| {
            match system.simulate(&initial, initial.t + tau, method, &Output::Ends) {
                Ok(_) => Run::Done,
                Err(_) => Run::Failed,
            }
        });
        let what = format!("simulating {span:e} s of {} with {}", scene.id(), describe(method));
        long_work::check_time(estimate, args.force, &what, flag)?;
    }
    let trajectory = simulate(scene, system.as_ref(), &initial, args.t_end, method, &Output::Every(every))?;
    if let Some(t) = trajectory.stats.stiffness {
        crate::output::warn(&format!("warning: the problem looks stiff from t = {t}; try --integrator implicit"));
    }
    if system.conserves_energy() {
        let rate = fastest_rate(system.as_mut(), initial.t, &initial.q, &initial.qdot);
        if let (Some(drift), Some(threshold)) =
            (energy_drift(&trajectory), drift_threshold(method, trajectory.stats.steps, rate))
            && drift > threshold
        {
            crate::output::warn(&format!(
                "warning: the energy h of this conservative scene drifted by {drift:.2e} (relative) over the run, \
                 beyond the {threshold:.1e} that {} over {} steps allows: the result is not to be trusted; \
                 use a smaller {}",
                describe(method),
                trajectory.stats.steps,
                if method.kind().is_fixed_step() { "--dt" } else { "--tol" }
            ));
        }
    }
    match &args.out {
        Some(path) => {
            let mut file = Pending::create(path)?;
            write_csv(file.writer(), &coordinates, &trajectory).map_err(|e| file.error(e))?;
            file.commit()?;
            crate::output::warn(&format!(
                "{}: {} samples to {} ({} steps, {} rejected)",
                scene.id(),
                trajectory.len(),
                path.display(),
                trajectory.stats.steps,
                trajectory.stats.rejected
            ));
        }
        None => {
            let stdout = std::io::stdout();
            write_csv(&mut stdout.lock(), &coordinates, &trajectory).map_err(CliError::Stdout)?;
        }
    }
    Ok(())
}
