//! The terminal summary: one line per scene with its reference, our best error, the ratios
//! against rapier and the wall time our fastest run needs for errors 1e-10 and 1e-12; then whether the targets (docs/validation.md#targets) are met, one line per stability case, and
//! where the files went.

use super::cells;
use super::markdown::targets_met;
use crate::plan::{EQUAL_ERROR, ERROR_RATIO_TARGET, TIME_RATIO_TARGET};
use crate::schema::Report;
use std::fmt::Write;
use std::path::Path;

/// The summary, as printed.
pub fn render(report: &Report, out: &Path, files: usize) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "lagrange report ({} mode): {} s horizon, errors at {} saved times; ours = reduced solver (rk4, adaptive, dop853, variational)",
        report.mode, report.horizon_s, report.samples
    );
    let _ = writeln!(
        text,
        "ratios vs rapier f64: e_rapier/e_ours at equal wall time (target ≥ {ERROR_RATIO_TARGET:.0e}), \
         t_rapier/t_ours at error {EQUAL_ERROR:.0e} (target ≥ {TIME_RATIO_TARGET}); — = not measurable, see report.md\n"
    );
    let _ = writeln!(
        text,
        "{:<21} {:<17} {:>9} {:>21} {:>21} {:>21} {:>21} {:>11} {:>11}",
        "scene",
        "reference",
        "best err",
        "impulse e-ratio",
        "impulse t-ratio",
        "multibody e-ratio",
        "multibody t-ratio",
        "t(1e-10)",
        "t(1e-12)"
    );
    for scene in &report.scenes {
        let best = scene.summary.ours_front.last().map(|p| p.max_error);
        let mut line = format!("{:<21} {:<17} {:>9}", scene.scene, scene.reference.kind, cells::number(best));
        for v in &scene.summary.versus {
            if v.status == "ok" {
                let _ = write!(
                    line,
                    " {:>21} {:>21}",
                    cells::equal_time(&v.error_ratio_at_equal_time),
                    cells::equal_error(&v.time_ratio_at_equal_error)
                );
            } else {
                let _ = write!(line, " {:>21} {:>21}", v.status, v.status);
            }
        }
        for r in &scene.summary.time_to_error {
            let cell = if r.seconds.is_some() { cells::time_to_error(r) } else { "—".to_string() };
            let _ = write!(line, " {cell:>11}");
        }
        let _ = writeln!(text, "{line}");
    }
    let (comparisons, time_met, error_met) = targets_met(report);
    let _ = writeln!(
        text,
        "\ntargets (docs/validation.md#targets): error ratio met on {time_met} of {comparisons} comparisons, time ratio met on \
         {error_met} of {comparisons}; total {:.1} s",
        report.total_wall_time_s
    );
    super::stability::terminal(&mut text, &report.stability);
    let _ = writeln!(text, "wrote {} (report.json, report.md, {files} SVG plots)", out.display());
    text
}
