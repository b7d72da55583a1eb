//! What a run costs, for any front end: its wall time estimated before it runs
//! ([`wall_time`], [`compare_wall_time`]), and watched while it runs ([`Watch`]: progress lines,
//! a wall-time limit, and an early stop when the measured progress projects the run far beyond
//! it). Refusing a request, and how to say so, is the front end's.
//!
//! The wall time is estimated by running the request itself over the first `τ, 2τ, 4τ, …` of
//! its horizon until one calibration run takes [`CALIBRATION_S`] or covers the whole horizon,
//! then extrapolating along the last two runs to the whole horizon ([`wall_time`]): the cost of
//! a run is a set-up plus steps at a rate that the calibration measures, so the estimate is of
//! the right order (the first steps of an adaptive run are its smallest, which errs on the
//! high side). A calibration run that alone proves the request beyond [`TIME_LIMIT_S`] is
//! abandoned there. The calibration costs about two [`CALIBRATION_S`] runs for a long request,
//! and about the request itself once more for a short one (its last calibration run is the
//! whole horizon).

use crate::Error;
use crate::compare::compare;
use lagrange::State;
use lagrange_maximal::{BuildError, Engine, Settings};
use lagrange_scenes::{Params, Scene};
use std::time::Instant;

/// Estimated wall time beyond which a front end refuses a request unless told to run it
/// anyway (s): two minutes, longer than any interactive use of `simulate` or `compare` with
/// the defaults (the slowest, `compare chain` at its default `N`, takes seconds) and short
/// enough that a mistyped horizon or step is caught before it runs for hours.
pub const TIME_LIMIT_S: f64 = 120.0;

/// Wall time of the calibration run from which an estimate is scaled (s).
pub const CALIBRATION_S: f64 = 0.05;

/// The least wall time (s) a calibration run is given before it may be abandoned.
pub const BUDGET_FLOOR_S: f64 = 2.0;

/// Bytes of one CSV number with its separator: `f64`'s shortest round-trip decimal form, as
/// measured on `simulate --every 1e-4` runs of harmonic_oscillator, double_pendulum and kepler
/// (17.9 to 18.2 bytes a number).
pub const BYTES_PER_NUMBER: f64 = 18.0;

/// How one calibration run went.
pub enum Run {
    /// It ran to its end.
    Done,
    /// It failed (the real run will say why).
    Failed,
    /// It was still running when its budget ran out (it is abandoned).
    Exceeded,
}

/// An estimated wall time.
#[derive(Clone, Copy, Debug)]
pub struct Estimate {
    /// Seconds.
    pub seconds: f64,
    /// Whether `seconds` is only a lower bound (a calibration run exceeded its budget).
    pub at_least: bool,
}

/// Estimated wall time of a run over `span` simulated seconds, from `calibrate(τ, budget)` —
/// the same run over the first `τ` of the horizon — for `τ = first, 2 first, …` up to `span`
/// (from `span / 2⁴⁰` at least). `budget` is the wall time (s) beyond which the calibration run
/// proves the whole run beyond [`TIME_LIMIT_S`] (and at least [`BUDGET_FLOOR_S`]): a caller that can abandon a run stops waiting
/// then and says [`Run::Exceeded`], and the estimate is that lower bound. `None` when a
/// calibration run fails. A run that reaches [`CALIBRATION_S`] is timed twice and the shorter
/// time kept: a pause of the process (another program on the cores) only ever lengthens a run.
pub fn wall_time(span: f64, first: f64, mut calibrate: impl FnMut(f64, f64) -> Run) -> Option<Estimate> {
    let mut timed = |tau: f64| {
        let start = Instant::now();
        // Never less than BUDGET_FLOOR_S: a run's fixed set-up must not pass for its cost.
        let run = calibrate(tau, (TIME_LIMIT_S * tau / span).max(BUDGET_FLOOR_S));
        let wall = start.elapsed().as_secs_f64();
        match run {
            Run::Done => Some(Ok(wall)),
            Run::Failed => None,
            Run::Exceeded => Some(Err(Estimate { seconds: wall * span / tau, at_least: true })),
        }
    };
    // At most 40 doublings: a horizon of more than 2⁴⁰ calibration runs' worth is absurd at
    // any cost per run.
    let mut tau = first.max(span * 2f64.powi(-40)).min(span);
    let mut previous: Option<(f64, f64)> = None;
    loop {
        let mut wall = match timed(tau)? {
            Ok(wall) => wall,
            Err(bound) => return Some(bound),
        };
        if tau >= span {
            return Some(Estimate { seconds: wall, at_least: false });
        }
        if wall >= CALIBRATION_S {
            wall = match timed(tau)? {
                Ok(again) => wall.min(again),
                Err(bound) => return Some(bound),
            };
            if wall >= CALIBRATION_S {
                // Extrapolate along the last two runs — cost = set-up + rate × τ — so a fixed
                // set-up is not scaled with the horizon; from the origin without a previous run.
                let seconds = match previous {
                    Some((tau0, wall0)) if wall > wall0 => wall + (wall - wall0) / (tau - tau0) * (span - tau),
                    _ => wall * span / tau,
                };
                return Some(Estimate { seconds, at_least: false });
            }
        }
        previous = Some((tau, wall));
        tau = (2.0 * tau).min(span);
    }
}

/// `12 s`, `3.4 min`, `5.6 h`, `7.8e3 days`.
pub fn duration(seconds: f64) -> String {
    match seconds {
        s if s < 120.0 => format!("{s:.0} s"),
        s if s < 7200.0 => format!("{:.1} min", s / 60.0),
        s if s < 172_800.0 => format!("{:.1} h", s / 3600.0),
        s => format!("{:.2e} days", s / 86400.0),
    }
}

/// `850 MB`, `3.1 GB`, `1.1e292 GB`.
pub fn size(bytes: f64) -> String {
    match bytes {
        b if b < 1e9 => format!("{:.0} MB", b / 1e6),
        b if b < 1e13 => format!("{:.1} GB", b / 1e9),
        b => format!("{:.1e} GB", b / 1e9),
    }
}

/// Substeps of a rapier engine's calibration run: a rapier step costs its substeps, so a run
/// with more is estimated from one with this many, scaled by the ratio.
const CALIBRATION_SUBSTEPS: usize = 16;

/// Estimated wall time of [`compare`] for `engine` over `span` simulated seconds (its reference
/// run included): the same comparison over the first `τ, 2τ, …` of the horizon from one rapier
/// step on ([`wall_time`]), each calibration run on its own thread so that one whose steps are
/// too slow is abandoned once it proves the request beyond [`TIME_LIMIT_S`]. Zero for an
/// engine that cannot build the scene; `None` when a calibration run fails (the real one will
/// say why).
pub fn compare_wall_time(
    engine: Engine,
    scene: &'static dyn Scene,
    params: &Params,
    initial: &State,
    settings: &Settings,
    span: f64,
) -> Option<Estimate> {
    let (calibration, scale) = if engine.is_rapier() && settings.substeps > CALIBRATION_SUBSTEPS {
        let calibration = Settings { substeps: CALIBRATION_SUBSTEPS, ..*settings };
        (calibration, settings.substeps as f64 / CALIBRATION_SUBSTEPS as f64)
    } else {
        (*settings, 1.0)
    };
    let mut unbuildable = false;
    let wall = wall_time(span, settings.dt, |tau, budget| {
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
        return Some(Estimate { seconds: 0.0, at_least: false });
    }
    wall.map(|w| Estimate { seconds: w.seconds * scale, ..w })
}

/// Seconds between two progress lines (to a log file, a CI job): the run says where it is
/// without flooding the log.
pub const PROGRESS_LINE_S: f64 = 10.0;

/// A progress line every [`PROGRESS_LINE_S`], handed to the front end's `say` (a log line on
/// a standard error that is not a terminal, say); silent without one (where a progress bar is
/// drawn instead).
pub struct Ticker {
    last: Instant,
    say: Option<fn(&str)>,
}

impl Ticker {
    /// A ticker whose first line comes [`PROGRESS_LINE_S`] from now, said through `say`.
    pub fn new(say: Option<fn(&str)>) -> Ticker {
        Ticker { last: Instant::now(), say }
    }

    /// Say `line()` if the interval has passed since the last one.
    pub fn tick(&mut self, line: impl FnOnce() -> String) {
        if let Some(say) = self.say
            && self.last.elapsed().as_secs_f64() >= PROGRESS_LINE_S
        {
            self.last = Instant::now();
            say(&line());
        }
    }
}

/// The least share of the wall-time limit a run is watched for before its measured progress may
/// stop it early.
const PREDICT_AFTER: f64 = 0.1;

/// A run projected to need more than this many times the wall-time limit is stopped early: the
/// projection follows the measured rate and its trend, which can still change (a motion that
/// slows down), so only a clear excess is acted on.
const PREDICT_FACTOR: f64 = 3.0;

/// Why a watched run was stopped.
#[derive(Clone, Copy, Debug)]
pub enum Stop {
    /// The wall-time limit passed.
    Deadline,
    /// The measured progress projected the run to need `seconds` in all.
    WillNotFinish {
        /// The projected wall time of the whole run (s).
        seconds: f64,
    },
}

/// Progress of a run over simulated time, measured: the simulated seconds per wall second over
/// the recent part of the run, its trend, the time left, and the wall-time limit.
pub struct Watch {
    start: Instant,
    t0: f64,
    t_end: f64,
    max_seconds: Option<f64>,
    /// `(wall, t)` at the start of the current and the previous measuring windows.
    windows: [(f64, f64); 2],
    /// Why the run was stopped, once it was.
    pub stopped: Option<Stop>,
    ticker: Ticker,
    label: String,
    /// Calls of [`keep_going`](Self::keep_going) so far.
    calls: u64,
}

/// Steps between two looks at the clock (and the projection): a run stops within 64 steps of
/// its limit — milliseconds even for the largest scenes — while the cheapest scenes, whose steps
/// take about as long as reading the clock, are not slowed by it.
const CHECK_EVERY: u64 = 64;

impl Watch {
    /// Watch a run of `label` from `t0` to `t_end`, stopped at `max_seconds` of wall time,
    /// saying where it is through `ticker`.
    pub fn new(label: &str, t0: f64, t_end: f64, max_seconds: Option<f64>, ticker: Ticker) -> Watch {
        Watch {
            start: Instant::now(),
            t0,
            t_end,
            max_seconds,
            windows: [(0.0, t0); 2],
            stopped: None,
            ticker,
            label: label.to_string(),
            calls: 0,
        }
    }

    /// Seconds since the run started.
    pub fn elapsed(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    /// The simulated seconds per wall second over the last window, and over the one before.
    fn rates(&self, wall: f64, t: f64) -> (Option<f64>, Option<f64>) {
        let [(w0, t_0), (w1, t_1)] = self.windows;
        let rate = |dw: f64, dt: f64| (dw > 0.0 && dt > 0.0).then(|| dt / dw);
        (rate(wall - w1, t - t_1), rate(w1 - w0, t_1 - t_0))
    }

    /// The projected wall time left from `t` (s): the last window's rate, scaled by its trend
    /// (the ratio to the window before) once for the rest — a motion that keeps speeding up
    /// keeps slowing the run down.
    pub fn left(&self, t: f64) -> Option<f64> {
        let wall = self.elapsed();
        let (recent, before) = self.rates(wall, t);
        let recent = recent.or_else(|| (t > self.t0 && wall > 0.0).then(|| (t - self.t0) / wall))?;
        let trend = before.map_or(1.0, |b| (recent / b).clamp(0.1, 10.0));
        Some((self.t_end - t) / (recent * trend.min(1.0)))
    }

    /// Whether the run goes on past `t`: `false` once the wall-time limit has passed, or once the
    /// measured progress (after a tenth of it) projects the run beyond three times it.
    pub fn keep_going(&mut self, t: f64) -> bool {
        // Asked after every step: the clock and the projection only every CHECK_EVERY steps.
        self.calls += 1;
        if !self.calls.is_multiple_of(CHECK_EVERY) {
            return true;
        }
        let wall = self.elapsed();
        // Windows of a quarter of the time so far: the rate of the recent part of the run.
        if wall - self.windows[1].0 >= 0.25 * wall.max(0.4) {
            self.windows = [self.windows[1], (wall, t)];
        }
        let (label, t_end) = (&self.label, self.t_end);
        let left = self.left(t);
        self.ticker.tick(|| {
            let left = left.map_or_else(|| "unknown".to_string(), duration);
            format!("{label}: t = {t:.4} of {t_end} s after {}, about {left} left", duration(wall))
        });
        let Some(limit) = self.max_seconds else { return true };
        if wall > limit {
            self.stopped = Some(Stop::Deadline);
            return false;
        }
        if wall >= PREDICT_AFTER * limit
            && let Some(left) = left
            && wall + left > PREDICT_FACTOR * limit
        {
            self.stopped = Some(Stop::WillNotFinish { seconds: wall + left });
            return false;
        }
        true
    }
}
