//! The SVG plots of a scene: work-precision (max error against wall time, log-log, one line per
//! method family through its sweep) and the reference trajectory above each family's error
//! over time. Each is drawn in memory and returned as the SVG text.

use crate::pareto::{Front, Point};
use crate::plan::{Family, Setting};
use crate::reference::Reference;
use crate::runs::{FamilyRuns, Run, SceneRuns};
use plotters::coord::Shift;
use plotters::prelude::*;

/// One colour per family, in `Family::ALL` order; the f32 builds are lighter than their f64 twins.
const PALETTE: [RGBColor; Family::ALL.len()] = [
    RGBColor(31, 119, 180),  // rk4
    RGBColor(44, 160, 44),   // adaptive
    RGBColor(23, 190, 207),  // dop853
    RGBColor(148, 103, 189), // variational
    RGBColor(30, 30, 30),    // cartesian
    RGBColor(214, 39, 40),   // rapier-impulse
    RGBColor(255, 127, 14),  // rapier-multibody
    RGBColor(240, 140, 140), // rapier-impulse-f32
    RGBColor(250, 190, 120), // rapier-multibody-f32
];

/// One colour per coordinate of the reference plot, cycled: saturated enough to read on white
/// (plotters' `Palette99` starts with a pale yellow).
const COORDINATE_COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 150, 34),
];

fn colour(family: Family) -> RGBColor {
    let index = Family::ALL.iter().position(|f| *f == family).unwrap_or(0);
    PALETTE[index]
}

/// A plot that could not be drawn: plotters' error, as text.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct PlotError(pub String);

/// The [`PlotError`] of a drawing error.
fn drawing_error(source: DrawingAreaErrorKind<std::io::Error>) -> PlotError {
    PlotError(source.to_string())
}

/// A log axis range around positive `values`, with a margin of `factor` on both sides.
fn log_range(values: impl Iterator<Item = f64>, factor: f64) -> Option<std::ops::Range<f64>> {
    let (low, high) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0_f64), |(low, high), v| (low.min(v), high.max(v)));
    (low <= high).then(|| low / factor..high * factor)
}

fn exponent_label(v: &f64) -> String {
    format!("{v:.0e}")
}

/// `(wall time, max error)` of the successful runs of a family, in sweep order.
fn work_precision_points(family: &FamilyRuns) -> Vec<(f64, f64)> {
    family
        .runs
        .iter()
        .filter_map(|run| run.outcome.as_ref().ok())
        .map(|m| (m.wall_time, m.max_error()))
        .filter(|(t, e)| *t > 0.0 && *e > 0.0)
        .collect()
}

/// A legend in its own panel, beside the chart rather than over the data.
fn draw_legend(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    top: i32,
    entries: &[(String, RGBColor)],
) -> Result<(), PlotError> {
    for (k, (label, colour)) in entries.iter().enumerate() {
        let y = top + 22 * k as i32;
        area.draw(&PathElement::new(vec![(4, y), (28, y)], colour.stroke_width(3))).map_err(drawing_error)?;
        area.draw(&Text::new(label.clone(), (34, y - 7), ("sans-serif", 13))).map_err(drawing_error)?;
    }
    Ok(())
}

/// `DIR/<scene>_work_precision.svg`: every successful run as a marker (filled on its family's
/// Pareto front), and one line per family along its front.
///
/// # Errors
/// The file cannot be written.
pub fn work_precision(runs: &SceneRuns, horizon: f64) -> Result<String, PlotError> {
    let mut svg = String::new();
    draw_work_precision(SVGBackend::with_string(&mut svg, (1100, 640)).into_drawing_area(), runs, horizon)?;
    Ok(svg)
}

/// [`work_precision`] drawn into `root`.
fn draw_work_precision(
    root: DrawingArea<SVGBackend<'_>, Shift>,
    runs: &SceneRuns,
    horizon: f64,
) -> Result<(), PlotError> {
    let series: Vec<(Family, Vec<(f64, f64)>)> =
        runs.families.iter().map(|f| (f.family, work_precision_points(f))).filter(|(_, p)| !p.is_empty()).collect();
    let all = || series.iter().flat_map(|(_, p)| p.iter().copied());
    root.fill(&WHITE).map_err(drawing_error)?;
    let (Some(x), Some(y)) = (log_range(all().map(|p| p.0), 1.5), log_range(all().map(|p| p.1), 3.0)) else {
        root.titled(&format!("{}: no successful run", runs.scene.id()), ("sans-serif", 20)).map_err(drawing_error)?;
        return root.present().map_err(drawing_error);
    };
    let (left, right) = root.split_horizontally(880);
    let caption =
        format!("{} — work-precision over {horizon} s (max error over saved times vs wall time)", runs.scene.id());
    let mut chart = ChartBuilder::on(&left)
        .caption(caption, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(x.log_scale(), y.log_scale())
        .map_err(drawing_error)?;
    chart
        .configure_mesh()
        .x_desc("wall time (s), minimum over repetitions")
        .y_desc("max ‖q − q_ref‖∞ (m, rad)")
        .x_label_formatter(&exponent_label)
        .y_label_formatter(&exponent_label)
        .draw()
        .map_err(drawing_error)?;
    let mut legend = Vec::new();
    for (family, points) in &series {
        let colour = colour(*family);
        let front =
            Front::new(points.iter().enumerate().map(|(run, &(time, error))| Point { time, error, family: 0, run }));
        let line: Vec<(f64, f64)> = front.points.iter().map(|p| (p.time, p.error)).collect();
        chart.draw_series(LineSeries::new(line, colour.stroke_width(2))).map_err(drawing_error)?;
        let on_front = |k: usize| front.points.iter().any(|p| p.run == k);
        chart
            .draw_series(points.iter().enumerate().map(|(k, &p)| {
                let style = if on_front(k) { colour.filled() } else { colour.stroke_width(1) };
                Circle::new(p, 3, style)
            }))
            .map_err(drawing_error)?;
        legend.push((family.name().to_string(), colour));
    }
    draw_legend(&right, 60, &legend)?;
    let note = ("sans-serif", 12);
    right.draw(&Text::new("lines: Pareto fronts", (4, 70 + 22 * legend.len() as i32), note)).map_err(drawing_error)?;
    right
        .draw(&Text::new("hollow: dominated runs", (4, 86 + 22 * legend.len() as i32), note))
        .map_err(drawing_error)?;
    root.present().map_err(drawing_error)
}

/// The wall time the error plot picks runs at: rapier's (impulse, else multibody, f64) run
/// nearest to `h = 1/960`, a typical game-physics setting; without rapier, the median of all.
fn representative_time(runs: &SceneRuns) -> Option<f64> {
    for engine in Family::RAPIER_F64 {
        let family = runs.families.iter().find(|f| f.family == Family::Maximal(engine));
        let nearest = family.and_then(|f| {
            f.runs
                .iter()
                .filter_map(|run| match (run.setting, &run.outcome) {
                    (Setting::Rapier { dt, substeps }, Ok(m)) => {
                        Some(((dt / substeps as f64 * 960.0).ln().abs(), m.wall_time))
                    }
                    _ => None,
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))
        });
        if let Some((_, time)) = nearest {
            return Some(time);
        }
    }
    let mut times: Vec<f64> = runs
        .families
        .iter()
        .flat_map(|f| f.runs.iter().filter_map(|r| r.outcome.as_ref().ok()))
        .map(|m| m.wall_time)
        .collect();
    times.sort_by(f64::total_cmp);
    times.get(times.len() / 2).copied()
}

/// Each family's successful run nearest (in log) to `time`.
fn representatives(runs: &SceneRuns, time: f64) -> Vec<(Family, &Run)> {
    runs.families
        .iter()
        .filter_map(|f| {
            let run = f
                .runs
                .iter()
                .filter(|r| r.outcome.is_ok())
                .min_by(|a, b| distance(a, time).total_cmp(&distance(b, time)))?;
            Some((f.family, run))
        })
        .collect()
}

fn distance(run: &Run, time: f64) -> f64 {
    run.outcome.as_ref().map_or(f64::INFINITY, |m| (m.wall_time / time).ln().abs())
}

/// The reference trajectory `q_ref(t)`, one line per coordinate.
fn draw_reference(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    runs: &SceneRuns,
    reference: &Reference,
    times: &[f64],
) -> Result<(), PlotError> {
    let values = || reference.q.iter().flatten().copied();
    let (low, high) = values().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
    let pad = ((high - low) * 0.05).max(1e-9);
    let t_end = times.last().copied().unwrap_or(1.0);
    let caption = format!("{} — reference ({})", runs.scene.id(), reference.kind.name().replace('_', " "));
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..t_end, (low - pad)..(high + pad))
        .map_err(drawing_error)?;
    chart.configure_mesh().x_desc("t (s)").y_desc("q_ref (m, rad)").draw().map_err(drawing_error)?;
    for (i, coordinate) in runs.coordinates.iter().enumerate() {
        let colour = COORDINATE_COLOURS[i % COORDINATE_COLOURS.len()];
        let points = times.iter().zip(&reference.q).map(|(&t, q)| (t, q[i]));
        chart
            .draw_series(LineSeries::new(points, colour.stroke_width(2)))
            .map_err(drawing_error)?
            .label(coordinate.name.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(drawing_error)
}

/// One line of the error plot.
struct Curve {
    colour: RGBColor,
    label: String,
    points: Vec<(f64, f64)>,
}

/// `DIR/<scene>_error.svg`: the reference trajectory, and below it `‖q − q_ref‖∞` over time of
/// one run per family, each the one nearest in wall time to rapier's run at `h ≈ 1/960`.
///
/// # Errors
/// The file cannot be written.
pub fn errors_over_time(runs: &SceneRuns, times: &[f64]) -> Result<String, PlotError> {
    let mut svg = String::new();
    draw_errors_over_time(SVGBackend::with_string(&mut svg, (1160, 900)).into_drawing_area(), runs, times)?;
    Ok(svg)
}

/// [`errors_over_time`] drawn into `root`.
fn draw_errors_over_time(
    root: DrawingArea<SVGBackend<'_>, Shift>,
    runs: &SceneRuns,
    times: &[f64],
) -> Result<(), PlotError> {
    root.fill(&WHITE).map_err(drawing_error)?;
    let (top, bottom) = root.split_vertically(360);
    let (bottom, legend_area) = bottom.split_horizontally(780);
    draw_reference(&top, runs, &runs.reference, times)?;
    let Some(time) = representative_time(runs) else {
        return root.present().map_err(drawing_error);
    };
    // Errors at t = 0 vanish and have no logarithm: each curve starts at the first positive one.
    let curves: Vec<Curve> = representatives(runs, time)
        .iter()
        .filter_map(|(family, run)| {
            let m = run.outcome.as_ref().ok()?;
            let points: Vec<(f64, f64)> = times
                .iter()
                .copied()
                .zip(m.errors.iter().copied())
                .filter(|(_, e)| *e > 0.0 && e.is_finite())
                .collect();
            let label = format!("{} {} ({:.2e} s)", family.name(), run.setting.describe(), m.wall_time);
            (!points.is_empty()).then_some(Curve { colour: colour(*family), label, points })
        })
        .collect();
    let t_end = times.last().copied().unwrap_or(1.0);
    let Some(y) = log_range(curves.iter().flat_map(|c| c.points.iter().map(|p| p.1)), 3.0) else {
        return root.present().map_err(drawing_error);
    };
    let caption = format!("errors over time, one run per method at about {time:.2e} s of wall time");
    let mut chart = ChartBuilder::on(&bottom)
        .caption(caption, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..t_end, y.log_scale())
        .map_err(drawing_error)?;
    chart
        .configure_mesh()
        .x_desc("t (s)")
        .y_desc("‖q − q_ref‖∞ (m, rad)")
        .y_label_formatter(&exponent_label)
        .draw()
        .map_err(drawing_error)?;
    let mut legend = Vec::new();
    for curve in curves {
        chart.draw_series(LineSeries::new(curve.points, curve.colour.stroke_width(2))).map_err(drawing_error)?;
        legend.push((curve.label, curve.colour));
    }
    draw_legend(&legend_area, 60, &legend)?;
    root.present().map_err(drawing_error)
}
