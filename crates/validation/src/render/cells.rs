//! How numbers and ratios read in report.md and on the terminal.

use crate::pareto::{EqualError, EqualTime, TimeToError};

/// `1.23e-4`, or `—` for a metric that does not apply.
pub fn number(value: Option<f64>) -> String {
    value.map_or_else(|| "—".to_string(), |v| format!("{v:.2e}"))
}

/// `met`, `not met` or `undetermined`.
pub fn verdict(met: Option<bool>) -> &'static str {
    match met {
        Some(true) => "met",
        Some(false) => "not met",
        None => "undetermined",
    }
}

/// A ratio: its value, or `≥ bound`, or `—`, with the verdict.
pub fn ratio(value: Option<f64>, lower_bound: Option<f64>, met: Option<bool>) -> String {
    match (value, lower_bound) {
        (Some(v), _) => format!("{v:.2e} ({})", verdict(met)),
        (None, Some(bound)) => format!("≥ {bound:.2e} ({})", verdict(met)),
        (None, None) => "—".to_string(),
    }
}

/// The equal-time ratio as a cell.
pub fn equal_time(r: &EqualTime) -> String {
    ratio(r.value, r.lower_bound, r.met)
}

/// The equal-error ratio as a cell.
pub fn equal_error(r: &EqualError) -> String {
    ratio(r.value, r.lower_bound, r.met)
}

/// The time to an error level: `3.1e-3 s`, `≤ 2.0e-4 s`, or `— (best 1.4e-12)`.
pub fn time_to_error(r: &TimeToError) -> String {
    match (r.seconds, r.best) {
        (Some(t), _) => format!("{}{t:.1e} s", if r.at_most { "≤ " } else { "" }),
        (None, Some((error, _))) => format!("— (best {error:.1e})"),
        (None, None) => "—".to_string(),
    }
}

/// Free text as one Markdown table cell: a `|` would end the cell (GitHub-flavoured Markdown
/// splits on it even inside a code span), so it is escaped as `\|`; a line break would end the
/// row, so it becomes a space.
pub fn text(value: &str) -> String {
    value.replace('|', "\\|").replace(['\r', '\n'], " ")
}
