//! The terminal summary: one line per scene with its reference, our best error, the ratios
//! against rapier and the wall time our fastest run needs for errors 1e-10 and 1e-12; then whether the targets (docs/validation.md#targets) are met, one line per stability case, and
//! where the files went.

use super::cells;
use super::markdown::targets_met;
use crate::catalogue::SceneEntry;
use crate::compare::Table;
use crate::plan::{EQUAL_ERROR, ERROR_RATIO_TARGET, REFERENCE_TOLERANCE, TIME_RATIO_TARGET};
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
    let animations = report.scenes.iter().filter(|s| s.plots.animation.is_some()).count();
    let _ = writeln!(
        text,
        "wrote {} (report.json, report.md, {files} SVG plots; index.html and {animations} animations to open in a browser)",
        out.display()
    );
    text
}

/// A comparison table (`lagrange compare`), as printed: the settings and what the errors are
/// measured against, then one line per engine (`—` where a quantity does not apply) with its
/// deviations under it.
pub fn comparison(table: &Table) -> String {
    let cell = |value: Option<f64>| value.map_or_else(|| "—".to_string(), |v| format!("{v:.2e}"));
    let against = if table.reference_tol.is_some() {
        format!("the reduced solution (dop853) at tol {REFERENCE_TOLERANCE:e}")
    } else {
        "the scene's closed form".to_string()
    };
    let mut text = String::new();
    let _ = writeln!(
        text,
        "{} over {} s (rapier dt = {:.3e}, {} substeps; Cartesian tol = {:e}); errors against {against}",
        table.scene, table.t_end, table.dt, table.substeps, table.tol,
    );
    let _ = writeln!(
        text,
        "{:<21} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>9}",
        "engine", "max err", "final err", "energy", "(ours)", "momentum", "violation", "force err", "µs/step"
    );
    for row in &table.rows {
        if let Some(reason) = &row.unbuildable {
            let _ = writeln!(text, "{:<21} not buildable: {reason}", row.engine);
            continue;
        }
        let _ = writeln!(
            text,
            "{:<21} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>9.2}",
            row.engine,
            cell(row.max_error),
            cell(row.final_error),
            cell(row.energy_drift),
            cell(row.reference_energy_drift),
            cell(row.momentum_drift),
            cell(row.constraint_violation),
            cell(row.force_error),
            row.microseconds_per_step.unwrap_or(0.0)
        );
        for deviation in &row.deviations {
            let _ = writeln!(text, "{:<21}   deviation: {deviation}", "");
        }
    }
    text
}

/// The scene catalogue (`lagrange scenes`), as printed: per scene its id, title and source, its
/// coordinates with their units, the default initial state to full precision, its constants of
/// the motion, and one line per parameter.
pub fn catalogue(scenes: &[SceneEntry]) -> String {
    let mut text = String::new();
    for s in scenes {
        let coordinates: Vec<String> = s.coordinates.iter().map(|c| format!("{} [{}]", c.name, c.unit)).collect();
        let _ = writeln!(text, "{} — {} ({})", s.id, s.title, s.reference);
        let _ = writeln!(text, "  coordinates: {}", coordinates.join(", "));
        // `{:?}`: full precision, as `accel` prints; `q̇[x']`, as `accel` names `q̈[x']`.
        let initial = &s.initial_state;
        let values = |values: &[f64], symbol: &str| -> Vec<String> {
            s.coordinates.iter().zip(values).map(|(c, v)| format!("{symbol}[{}] = {v:?}", c.name)).collect()
        };
        let _ = writeln!(
            text,
            "  initial state: t = {:?}; {}; {}",
            initial.t,
            values(&initial.q, "q").join(", "),
            values(&initial.qdot, "q̇").join(", ")
        );
        let _ = writeln!(
            text,
            "  conserved: {}",
            if s.conserved.is_empty() { "none".into() } else { s.conserved.join(", ") }
        );
        for p in &s.parameters {
            let unit = if p.unit.is_empty() { String::new() } else { format!(" {}", p.unit) };
            // The ASCII spelling of a Greek symbol is a key too (`--param alpha=0.3`).
            let symbol = if p.ascii_symbol == p.symbol {
                p.symbol.to_string()
            } else {
                format!("{} ({})", p.symbol, p.ascii_symbol)
            };
            let _ = writeln!(text, "  {:<22} {:<4} = {}{unit}  — {}", p.name, symbol, p.default, p.description);
        }
    }
    text
}
