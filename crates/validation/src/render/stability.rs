//! The stability section of report.md, and its lines in the terminal summary.

use super::cells;
use crate::stability::{Case, Check, Measurement, StabilityReport};
use std::fmt::Write;

/// `1.23e-4`, or `—`.
fn number(value: Option<f64>) -> String {
    value.map_or_else(|| "—".to_string(), |v| format!("{v:.4e}"))
}

/// The check in words: `≤ 1e-8`, `within 1 % of 2.8284`, …
fn check(m: &Measurement) -> String {
    let theory = number(m.theory);
    let bound = m.bound.map_or_else(|| "—".to_string(), |b| format!("{b:.1e}"));
    match m.check {
        Check::RelativeToTheory => format!("within {bound} (relative) of {theory}"),
        Check::AbsoluteToTheory => format!("within {bound} of {theory}"),
        Check::WithinFactor => format!("within a factor {} of {theory}", m.bound.unwrap_or(f64::NAN)),
        Check::AtMost => format!("≤ {bound}"),
        Check::AtLeast => format!("≥ {bound}"),
        Check::Exact => format!("exactly {theory}"),
        Check::TypedError => "a typed error".into(),
        Check::Finite => "finite".into(),
        Check::FiniteOrTypedError => "finite or a typed error".into(),
        Check::None => match m.theory {
            Some(t) => format!("reported (theory {})", number(Some(t))),
            None => "reported".into(),
        },
    }
}

fn verdict(pass: Option<bool>) -> &'static str {
    match pass {
        Some(true) => "pass",
        Some(false) => "**fail**",
        None => "—",
    }
}

fn setting(m: &Measurement) -> String {
    let s = &m.settings;
    let mut parts = Vec::new();
    if let Some(dt) = s.dt {
        parts.push(format!("dt = {dt:.3e}"));
    }
    if let Some(tol) = s.tolerance {
        parts.push(format!("tol = {tol:.0e}"));
    }
    if let Some(k) = s.substeps {
        parts.push(format!("{k} substep{}", if k == 1 { "" } else { "s" }));
    }
    if let Some(t) = s.horizon_s {
        parts.push(format!("{t:.4} s"));
    }
    parts.join(", ")
}

fn cost(m: &Measurement) -> String {
    let c = &m.cost;
    let mut parts = Vec::new();
    if let Some(steps) = c.steps {
        parts.push(format!("{steps} steps"));
    }
    if let Some(n) = c.evaluations {
        parts.push(format!("{n} evals"));
    }
    if let (Some(j), Some(f)) = (c.jacobians, c.factorizations) {
        parts.push(format!("{j} Jac., {f} LU"));
    }
    if let Some(n) = c.fallbacks {
        parts.push(format!("{n} steps by RK4"));
    }
    if c.wall_time_s > 0.0 {
        parts.push(format!("{:.2e} s", c.wall_time_s));
    }
    parts.join(", ")
}

fn case_section(md: &mut String, case: &Case) {
    let status = match case.pass {
        Some(true) => "every check passes",
        Some(false) => "**some checks fail**",
        None => "reported only",
    };
    let _ = writeln!(md, "### {}\n\n{} ({status}; {:.1} s).\n", case.id, case.title, case.wall_time_s);
    let _ = writeln!(md, "- **Setup**: {}", case.setup);
    let _ = writeln!(md, "- **Theory**: {}\n", case.theory);
    let _ = writeln!(md, "| label | scene | method | setting | quantity | value | check | verdict | cost | note |");
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|");
    for m in &case.measurements {
        let value = if m.status == "failed" && m.value.is_none() { "failed".to_string() } else { number(m.value) };
        let note = cells::text(m.note.as_deref().unwrap_or(""));
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {value} | {} | {} | {} | {note} |",
            cells::text(&m.label),
            cells::text(&m.scene),
            cells::text(m.method),
            cells::text(&setting(m)),
            cells::text(&m.quantity),
            cells::text(&check(m)),
            verdict(m.pass),
            cells::text(&cost(m))
        );
    }
    let _ = writeln!(md);
}

/// The "Stability" section of report.md.
pub fn markdown(md: &mut String, report: &StabilityReport) {
    let _ = writeln!(md, "## Stability\n");
    let _ = writeln!(
        md,
        "For each case: which methods stay stable and accurate, at what cost, against theory where theory exists \
         ({} mode). Every row is one measurement: its check against theory or a derived bound, and its verdict \
         (— = reported without a check). {} checks pass, {} fail, {} are reported only; {:.1} s in all.\n",
        report.mode, report.passed, report.failed, report.unchecked, report.wall_time_s
    );
    for case in &report.cases {
        case_section(md, case);
    }
}

/// A few lines for the terminal: one per case, with its failures named.
pub fn terminal(text: &mut String, report: &StabilityReport) {
    let _ = writeln!(
        text,
        "\nstability ({:.1} s): {} checks pass, {} fail, {} reported only",
        report.wall_time_s, report.passed, report.failed, report.unchecked
    );
    for case in &report.cases {
        let checked: Vec<&Measurement> = case.measurements.iter().filter(|m| m.pass.is_some()).collect();
        let failing: Vec<String> = checked
            .iter()
            .filter(|m| m.pass == Some(false))
            .map(|m| format!("{} {} {}", m.scene, m.method, m.label))
            .collect();
        let passed = checked.len() - failing.len();
        let mut line = format!("  {:<20} {passed}/{} pass", case.id, checked.len());
        if !failing.is_empty() {
            let shown: Vec<&str> = failing.iter().take(3).map(String::as_str).collect();
            let more = if failing.len() > 3 { format!(" (+{} more)", failing.len() - 3) } else { String::new() };
            let _ = write!(line, "; failing: {}{more}", shown.join(", "));
        }
        let _ = writeln!(text, "{line}");
    }
}
