//! Long work, as the command line says it: the refusal of a request whose estimated cost
//! ([`lagrange_validation::cost`]) is absurd, with the estimate and the flag to change
//! (`--force` runs it anyway); the wall-time limit a request runs under; and progress bars with
//! an estimate of the time left, drawn only when standard error is a terminal.

use crate::error::CliError;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use lagrange_validation::cost::BYTES_PER_NUMBER;
pub use lagrange_validation::cost::{Estimate, Run, Stop, TIME_LIMIT_S, Ticker, Watch, duration, size, wall_time};
use std::io::IsTerminal;

/// The same limit in words, for the refusal.
pub const TIME_LIMIT: &str = "2 minutes";

/// Estimated output beyond which a request is refused without `--force` (bytes): 1 GB of CSV
/// (the trajectory is also held in memory while it runs, at 8 bytes per number).
pub const OUTPUT_LIMIT_BYTES: f64 = 1e9;

/// The same limit in words.
pub const OUTPUT_LIMIT: &str = "1 GB of output";

/// Refuse a run whose estimated wall time is beyond [`TIME_LIMIT_S`], unless forced.
///
/// # Errors
/// [`CliError::TooCostly`] with `what` (the request and how the estimate was made) and `flag`.
pub fn check_time(estimate: Option<Estimate>, force: bool, what: &str, flag: &'static str) -> Result<(), CliError> {
    match estimate {
        Some(Estimate { seconds, at_least }) if seconds > TIME_LIMIT_S && !force => {
            let bound = if at_least { "at least " } else { "" };
            Err(CliError::TooCostly {
                estimate: format!("{what}: estimated {bound}{}", duration(seconds)),
                limit: TIME_LIMIT,
                flag,
            })
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

/// A [`Ticker`] saying its lines on standard error when that is not a terminal (a log file, a
/// CI job, where the progress bars are hidden); silent on a terminal.
pub fn ticker() -> Ticker {
    Ticker::new((!shows_progress()).then_some(crate::output::warn as fn(&str)))
}

/// The wall-time limit a request runs under without `--max-seconds` and without `--force`:
/// twice [`TIME_LIMIT_S`]. The up-front estimate admits requests within [`TIME_LIMIT_S`], but a
/// motion that speeds up past the calibration's beginning (Andrews' squeezer) can take ten
/// times longer; the measured progress stops such a run early.
pub const WATCH_LIMIT_S: f64 = 2.0 * TIME_LIMIT_S;

/// The limit a request runs under, in seconds, and how to say it: `--max-seconds`, checked
/// positive and finite; without it, [`WATCH_LIMIT_S`] unless `--force`.
///
/// # Errors
/// [`CliError::NotPositive`].
pub fn max_seconds(value: Option<f64>, force: bool) -> Result<Option<(f64, String)>, CliError> {
    match value {
        Some(v) if !(v > 0.0 && v.is_finite()) => Err(CliError::NotPositive { flag: "--max-seconds", value: v }),
        Some(v) => Ok(Some((v, format!("--max-seconds {v}")))),
        None if force => Ok(None),
        None => Ok(Some((
            WATCH_LIMIT_S,
            format!(
                "the {} limit of a request estimated within {TIME_LIMIT}; --force lifts it, --max-seconds sets another",
                duration(WATCH_LIMIT_S)
            ),
        ))),
    }
}
