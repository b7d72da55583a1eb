//! Long work: what a request will cost, estimated before it runs; the refusal of a request
//! whose cost is absurd (with the estimate and the flag to change; `--force` runs it anyway);
//! and progress bars with an estimate of the time left, drawn only when standard error is a
//! terminal.
//!
//! The wall time is estimated by running the request itself over the first `τ, 2τ, 4τ, …` of
//! its horizon until one calibration run takes [`CALIBRATION_S`] or covers the whole horizon,
//! then scaling that run's wall time by `horizon / τ`. The cost of a run grows linearly with
//! the simulated time (steps at a rate the calibration measures), so the scaling is an
//! estimate of the right order; it overestimates rather than under (the first steps of an
//! adaptive run are its smallest, and the calibration's own overhead is counted). The
//! calibration costs at most about twice [`CALIBRATION_S`] per estimate.

use crate::error::CliError;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::Instant;

/// Estimated wall time beyond which a request is refused without `--force` (s): two minutes,
/// longer than any interactive use of `simulate` or `compare` with the defaults (the slowest,
/// `compare chain` at its default `N`, takes seconds) and short enough that a mistyped
/// horizon or step is caught before it runs for hours.
pub const TIME_LIMIT_S: f64 = 120.0;

/// The same limit in words, for the refusal.
pub const TIME_LIMIT: &str = "2 minutes";

/// Estimated output beyond which a request is refused without `--force` (bytes): 1 GB of CSV
/// (the trajectory is also held in memory while it runs, at 8 bytes per number).
pub const OUTPUT_LIMIT_BYTES: f64 = 1e9;

/// The same limit in words.
pub const OUTPUT_LIMIT: &str = "1 GB of output";

/// Wall time of the calibration run from which an estimate is scaled (s).
pub const CALIBRATION_S: f64 = 0.05;

/// Bytes of one CSV number: `f64`'s shortest round-trip form is at most 24 characters
/// (`-1.2345678901234567e-100`), 18 to 20 for a typical value; with its separator, 20 is the
/// typical width.
pub const BYTES_PER_NUMBER: f64 = 20.0;

/// Estimated wall time (s) of a run over `span` simulated seconds, from `calibrate(τ)` — the
/// same run over the first `τ` of the horizon, returning `false` if it failed — for
/// `τ = first, 2 first, …` up to `span`. `None` when a calibration run fails (the real run will
/// say why).
pub fn wall_time(span: f64, first: f64, mut calibrate: impl FnMut(f64) -> bool) -> Option<f64> {
    let mut tau = first.min(span);
    loop {
        let start = Instant::now();
        if !calibrate(tau) {
            return None;
        }
        let wall = start.elapsed().as_secs_f64();
        if wall >= CALIBRATION_S || tau >= span {
            return Some(wall * span / tau);
        }
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

/// `850 MB`, `3.1 GB`.
pub fn size(bytes: f64) -> String {
    if bytes < 1e9 { format!("{:.0} MB", bytes / 1e6) } else { format!("{:.1} GB", bytes / 1e9) }
}

/// Refuse a run whose estimated wall time is beyond [`TIME_LIMIT_S`], unless forced.
///
/// # Errors
/// [`CliError::TooCostly`] with `what` (the request and how the estimate was made) and `flag`.
pub fn check_time(seconds: Option<f64>, force: bool, what: &str, flag: &'static str) -> Result<(), CliError> {
    match seconds {
        Some(s) if s > TIME_LIMIT_S && !force => {
            Err(CliError::TooCostly { estimate: format!("{what}: estimated {}", duration(s)), limit: TIME_LIMIT, flag })
        }
        _ => Ok(()),
    }
}

/// Refuse an output whose estimated size is beyond [`OUTPUT_LIMIT_BYTES`], unless forced.
///
/// # Errors
/// [`CliError::TooCostly`] naming `flag`.
pub fn check_output(rows: f64, numbers_per_row: usize, force: bool, flag: &'static str) -> Result<(), CliError> {
    let bytes = rows * numbers_per_row as f64 * BYTES_PER_NUMBER;
    if bytes > OUTPUT_LIMIT_BYTES && !force {
        return Err(CliError::TooCostly {
            estimate: format!(
                "{rows:.2e} rows of {numbers_per_row} numbers: estimated {} of CSV ({BYTES_PER_NUMBER} bytes a number)",
                size(bytes)
            ),
            limit: OUTPUT_LIMIT,
            flag,
        });
    }
    Ok(())
}

/// A progress bar of `total` units on standard error with the elapsed time and an estimate of
/// the time left; hidden (drawing nothing) when standard error is not a terminal.
pub fn progress_bar(total: u64) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
    if !std::io::stderr().is_terminal() {
        bar.set_draw_target(ProgressDrawTarget::hidden());
    }
    if let Ok(style) =
        ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {percent:>3}% eta {eta_precise} {wide_msg}")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

/// Whether progress bars are drawn (standard error is a terminal): work that must be arranged
/// differently to report progress is arranged so only then.
pub fn shows_progress() -> bool {
    std::io::stderr().is_terminal()
}
