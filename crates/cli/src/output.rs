//! Standard output and the messages of every command, in one place.
//!
//! Every command writes its results through [`outln!`] and [`out!`] (or [`print`](fn@print)): a write that
//! fails becomes [`CliError::Stdout`] instead of the panic of `println!`. `main` then ends a
//! run whose reader went away (a closed pipe, `lagrange compare … | head -1`) quietly with exit
//! 0, as the usual Unix tools do ([`is_closed_pipe`]), and reports any other failure (a full
//! disk, `lagrange scenes > /dev/full`) as a one-line error with exit 1. Messages on standard
//! error go through [`warn`], which never fails, and numbers in messages through [`compact`].

use crate::error::CliError;
use std::fmt;
use std::io::Write;

/// Write formatted text to standard output, as `print!`; evaluates to `Result<(), CliError>`.
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::output::print(&format!($($arg)*))
    };
}

/// Write a formatted line to standard output, as `println!`; evaluates to
/// `Result<(), CliError>`.
macro_rules! outln {
    () => {
        $crate::output::print("\n")
    };
    ($($arg:tt)*) => {
        $crate::output::print(&format!("{}\n", format_args!($($arg)*)))
    };
}

pub(crate) use {out, outln};

/// Write `text` to standard output.
///
/// # Errors
/// [`CliError::Stdout`] when the write fails (a closed pipe, a full disk).
pub fn print(text: &str) -> Result<(), CliError> {
    std::io::stdout().lock().write_all(text.as_bytes()).map_err(CliError::Stdout)
}

/// Flush standard output (the text after the last newline is still buffered), so that a write
/// that fails there is reported too.
///
/// # Errors
/// [`CliError::Stdout`] when the flush fails.
pub fn flush() -> Result<(), CliError> {
    std::io::stdout().lock().flush().map_err(CliError::Stdout)
}

/// Whether the error is a write to standard output whose reader has gone away: the run ends
/// quietly and successfully, its reader having taken all it wanted.
pub fn is_closed_pipe(error: &CliError) -> bool {
    matches!(error, CliError::Stdout(e) if e.kind() == std::io::ErrorKind::BrokenPipe)
}

/// Write one line to standard error (a warning, an error message). A standard error that cannot
/// be written is ignored: there is nowhere left to report it.
pub fn warn(line: &str) {
    let _ = writeln!(std::io::stderr().lock(), "{line}");
}

/// A number for a message, in its shortest form that reads back to the same `f64`: plain between
/// 1e-4 and 1e6, scientific outside (`1e-20`, not `0.00000000000000000001`).
#[derive(Clone, Copy, Debug)]
pub struct Compact(pub f64);

impl fmt::Display for Compact {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0;
        if v == 0.0 || !v.is_finite() || (1e-4..1e6).contains(&v.abs()) { write!(f, "{v}") } else { write!(f, "{v:e}") }
    }
}

/// [`Compact`] of a value.
pub fn compact(value: f64) -> Compact {
    Compact(value)
}

/// Values for a message, each [`Compact`], comma-separated in brackets.
pub fn compact_all(values: &[f64]) -> String {
    let values: Vec<String> = values.iter().map(|v| compact(*v).to_string()).collect();
    format!("[{}]", values.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compact_numbers_are_short_and_exact() {
        let shown: Vec<String> =
            [1e-20, -1e-3, 0.0, 1.0, 0.5, 2.5e6, 1e-320, f64::NAN, -f64::INFINITY, 123456.0, 0.1 + 0.2]
                .iter()
                .map(|v| compact(*v).to_string())
                .collect();
        assert_eq!(
            shown,
            ["1e-20", "-0.001", "0", "1", "0.5", "2.5e6", "1e-320", "NaN", "-inf", "123456", "0.30000000000000004"]
        );
        assert_eq!(compact_all(&[1e-20, 2.0]), "[1e-20, 2]");
    }
}
