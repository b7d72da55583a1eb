//! Work-precision fronts and the summary ratios read off them.
//!
//! A family's **front** is its Pareto front in (wall time, max error): the runs that no other
//! run of the family beats in both, sorted by time (so errors strictly fall). Between two
//! consecutive front points the front is the straight line in log-log coordinates,
//! `log e = log e₀ + (log t − log t₀) · (log e₁ − log e₀) / (log t₁ − log t₀)`; outside its
//! first and last points it is not defined (no extrapolation). Runs that failed, or whose
//! error or time is not finite and positive, are left out (a zero error has no logarithm).
//!
//! * **Error ratio at equal wall time** `e_rapier(t) / e_ours(t)`, over the times both fronts
//!   cover. Both are piecewise linear in log-log, so the ratio's extremes lie at the front
//!   points inside the overlap or at its ends: the report gives the smallest (its value, the
//!   worst case for us), the largest, and where the smallest is. Without an overlap the value
//!   is null with the reason; when our whole front finishes before rapier's fastest run, at
//!   any rapier time we could have run our most accurate setting, so the ratio is at least
//!   `(rapier's best error) / (our best error)`, reported as a lower bound.
//! * **Time ratio at equal error** `t_rapier(E) / t_ours(E)` at `E = 1e-4`, each time read off
//!   its front (log-log, inverse). When a front never reaches `E` the value is null with the
//!   reason (the sweep's best error and its time); when every one of our runs is already below
//!   `E`, our fastest run bounds our time from above and the ratio from below (lower bound).
//!
//! A target counts as met when the value reaches it, or when a lower bound does; as not met
//! when the value falls short; and as undetermined (null) otherwise.

use serde::Serialize;

/// One run on a work-precision plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// Wall time (s).
    pub time: f64,
    /// Max error.
    pub error: f64,
    /// Index of the run's family in the caller's list.
    pub family: usize,
    /// Index of the run in its family.
    pub run: usize,
}

/// A Pareto front: time strictly increasing, error strictly decreasing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Front {
    /// The points, fastest first.
    pub points: Vec<Point>,
}

impl Front {
    /// The front of `points` (any order; unusable points are left out).
    pub fn new(points: impl IntoIterator<Item = Point>) -> Front {
        let mut all: Vec<Point> = points
            .into_iter()
            .filter(|p| p.time.is_finite() && p.time > 0.0 && p.error.is_finite() && p.error > 0.0)
            .collect();
        all.sort_by(|a, b| a.time.total_cmp(&b.time).then(a.error.total_cmp(&b.error)));
        let mut points: Vec<Point> = Vec::new();
        for p in all {
            if points.last().is_none_or(|last| p.error < last.error) {
                points.push(p);
            }
        }
        Front { points }
    }

    /// Whether it has no point.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    fn fastest(&self) -> Option<Point> {
        self.points.first().copied()
    }

    fn best(&self) -> Option<Point> {
        self.points.last().copied()
    }

    /// The error at wall time `t`, interpolated log-log, within the front's time range.
    pub fn error_at(&self, t: f64) -> Option<f64> {
        let (first, last) = (self.fastest()?, self.best()?);
        if !(t >= first.time && t <= last.time) {
            return None;
        }
        if t == last.time {
            return Some(last.error);
        }
        let i = self.points.partition_point(|p| p.time <= t) - 1;
        let (a, b) = (self.points[i], self.points[i + 1]);
        Some(log_lerp(a.time, a.error, b.time, b.error, t))
    }

    /// The wall time at which the front reaches `error`.
    pub fn time_at(&self, error: f64) -> Reach {
        let (Some(first), Some(last)) = (self.fastest(), self.best()) else {
            return Reach::Empty;
        };
        if error > first.error {
            return Reach::AlreadyBelow { fastest: first.time };
        }
        if error < last.error {
            return Reach::Unreached { best_error: last.error, best_time: last.time };
        }
        if error == first.error {
            return Reach::At(first.time);
        }
        // Errors fall along the front: the first point at or below `error` ends the segment.
        let j = self.points.partition_point(|p| p.error > error);
        let (a, b) = (self.points[j - 1], self.points[j]);
        Reach::At(log_lerp(a.error, a.time, b.error, b.time, error))
    }
}

/// `y(x)` on the straight line through `(x0, y0)` and `(x1, y1)` in log-log coordinates.
fn log_lerp(x0: f64, y0: f64, x1: f64, y1: f64, x: f64) -> f64 {
    if x1 == x0 {
        return y0;
    }
    let s = (x.ln() - x0.ln()) / (x1.ln() - x0.ln());
    (y0.ln() + s * (y1.ln() - y0.ln())).exp()
}

/// The wall time a front needs to reach an error level, as the report states it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TimeToError {
    /// The error level.
    pub error: f64,
    /// The wall time (s) read off the front (log-log); with `at_most`, an upper bound (the
    /// front's fastest run is already below the level); null when the front does not reach it.
    pub seconds: Option<f64>,
    /// Whether `seconds` is an upper bound.
    pub at_most: bool,
    /// The front's most accurate error and its time (s), when it does not reach the level.
    pub best: Option<(f64, f64)>,
}

impl TimeToError {
    /// Read `front` at `error`.
    pub fn new(front: &Front, error: f64) -> TimeToError {
        let (seconds, at_most, best) = match front.time_at(error) {
            Reach::At(t) => (Some(t), false, None),
            Reach::AlreadyBelow { fastest } => (Some(fastest), true, None),
            Reach::Unreached { best_error, best_time } => (None, false, Some((best_error, best_time))),
            Reach::Empty => (None, false, None),
        };
        TimeToError { error, seconds, at_most, best }
    }
}

/// Where a front stands with respect to an error level.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reach {
    /// The front has no point.
    Empty,
    /// It reaches the level at this wall time (s).
    At(f64),
    /// Even its fastest run is more accurate; that run's time bounds the time from above.
    AlreadyBelow {
        /// Wall time of the fastest run (s).
        fastest: f64,
    },
    /// Its most accurate run is still less accurate.
    Unreached {
        /// Error of the most accurate run.
        best_error: f64,
        /// Its wall time (s).
        best_time: f64,
    },
}

/// `e_rapier / e_ours` at equal wall time.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EqualTime {
    /// Smallest ratio over the overlap of the two fronts' time ranges (null without overlap).
    pub value: Option<f64>,
    /// Largest ratio over the overlap.
    pub max: Option<f64>,
    /// Wall time (s) where the smallest ratio is.
    pub at_wall_time_s: Option<f64>,
    /// The overlap `[from, to]` of the time ranges (s).
    pub overlap_s: Option<[f64; 2]>,
    /// A proven lower bound when there is no value (see the module docs), else null.
    pub lower_bound: Option<f64>,
    /// Why the value is null, or what the bound means.
    pub reason: Option<String>,
    /// docs/validation.md#targets target.
    pub target: f64,
    /// Whether the target is met (null: undetermined).
    pub met: Option<bool>,
}

/// `t_rapier / t_ours` at equal error.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EqualError {
    /// The error level.
    pub error: f64,
    /// The ratio (null when either front does not reach `error` inside its sweep).
    pub value: Option<f64>,
    /// Our time to reach `error` (s), when interpolated.
    pub ours_wall_time_s: Option<f64>,
    /// rapier's time to reach `error` (s), when interpolated.
    pub rapier_wall_time_s: Option<f64>,
    /// A proven lower bound when there is no value (see the module docs), else null.
    pub lower_bound: Option<f64>,
    /// Why the value is null, or what the bound means.
    pub reason: Option<String>,
    /// docs/validation.md#targets target.
    pub target: f64,
    /// Whether the target is met (null: undetermined).
    pub met: Option<bool>,
}

fn met(value: Option<f64>, lower_bound: Option<f64>, target: f64) -> Option<bool> {
    match (value, lower_bound) {
        (Some(v), _) => Some(v >= target),
        (None, Some(bound)) if bound >= target => Some(true),
        _ => None,
    }
}

fn range(front: &Front) -> String {
    match (front.fastest(), front.best()) {
        (Some(a), Some(b)) => format!("{:.2e}–{:.2e} s", a.time, b.time),
        _ => "no usable run".into(),
    }
}

impl EqualTime {
    /// An empty comparison, with the reason.
    pub fn none(reason: String, target: f64) -> EqualTime {
        EqualTime {
            value: None,
            max: None,
            at_wall_time_s: None,
            overlap_s: None,
            lower_bound: None,
            reason: Some(reason),
            target,
            met: None,
        }
    }

    /// Compare the fronts at equal wall time.
    pub fn new(ours: &Front, rapier: &Front, target: f64) -> EqualTime {
        let (Some(o_first), Some(o_last), Some(r_first), Some(r_last)) =
            (ours.fastest(), ours.best(), rapier.fastest(), rapier.best())
        else {
            let who = if ours.is_empty() { "ours" } else { "rapier" };
            return EqualTime::none(format!("{who} has no usable run"), target);
        };
        let (from, to) = (o_first.time.max(r_first.time), o_last.time.min(r_last.time));
        if from > to {
            let mut result = EqualTime::none(String::new(), target);
            if o_last.time < r_first.time {
                let bound = r_last.error / o_last.error;
                result.lower_bound = Some(bound);
                result.reason = Some(format!(
                    "the time ranges do not overlap (ours {}, rapier {}): our most accurate run ({:.2e}) \
                     finishes before rapier's fastest, so at any rapier time our error is at most \
                     {:.2e} and the ratio is at least rapier's best error over it, {bound:.2e}",
                    range(ours),
                    range(rapier),
                    o_last.error,
                    o_last.error
                ));
            } else {
                result.reason = Some(format!(
                    "the time ranges do not overlap (ours {}, rapier {}): rapier's slowest run is \
                     faster than our fastest",
                    range(ours),
                    range(rapier)
                ));
            }
            result.met = met(None, result.lower_bound, target);
            return result;
        }
        let mut times: Vec<f64> = vec![from, to];
        times.extend(ours.points.iter().chain(&rapier.points).map(|p| p.time).filter(|t| *t >= from && *t <= to));
        let (mut low, mut high, mut at) = (f64::INFINITY, 0.0_f64, from);
        for t in times {
            if let (Some(e_ours), Some(e_rapier)) = (ours.error_at(t), rapier.error_at(t)) {
                let ratio = e_rapier / e_ours;
                if ratio < low {
                    (low, at) = (ratio, t);
                }
                high = high.max(ratio);
            }
        }
        let value = low.is_finite().then_some(low);
        EqualTime {
            value,
            max: value.map(|_| high),
            at_wall_time_s: value.map(|_| at),
            overlap_s: Some([from, to]),
            lower_bound: None,
            reason: None,
            target,
            met: met(value, None, target),
        }
    }
}

impl EqualError {
    /// An empty comparison, with the reason.
    pub fn none(error: f64, reason: String, target: f64) -> EqualError {
        EqualError {
            error,
            value: None,
            ours_wall_time_s: None,
            rapier_wall_time_s: None,
            lower_bound: None,
            reason: Some(reason),
            target,
            met: None,
        }
    }

    /// Compare the fronts at equal error `error`.
    pub fn new(ours: &Front, rapier: &Front, error: f64, target: f64) -> EqualError {
        let mut result = EqualError::none(error, String::new(), target);
        let (o, r) = (ours.time_at(error), rapier.time_at(error));
        if let Reach::At(t) = o {
            result.ours_wall_time_s = Some(t);
        }
        if let Reach::At(t) = r {
            result.rapier_wall_time_s = Some(t);
        }
        result.reason = match (o, r) {
            (Reach::At(t_ours), Reach::At(t_rapier)) => {
                result.value = Some(t_rapier / t_ours);
                None
            }
            (Reach::Empty, _) => Some("ours has no usable run".into()),
            (_, Reach::Empty) => Some("rapier has no usable run".into()),
            (_, Reach::Unreached { best_error, best_time }) => Some(format!(
                "rapier's sweep does not reach {error:.0e}: its most accurate run has error {best_error:.2e} \
                 at {best_time:.2e} s"
            )),
            (Reach::Unreached { best_error, best_time }, _) => Some(format!(
                "our sweep does not reach {error:.0e}: our most accurate run has error {best_error:.2e} at \
                 {best_time:.2e} s"
            )),
            (Reach::AlreadyBelow { fastest }, Reach::At(t_rapier)) => {
                let bound = t_rapier / fastest;
                result.lower_bound = Some(bound);
                Some(format!(
                    "every run of ours is more accurate than {error:.0e}; our fastest ({fastest:.2e} s) bounds \
                     our time from above, so the ratio is at least {bound:.2e}"
                ))
            }
            (_, Reach::AlreadyBelow { fastest }) => Some(format!(
                "every rapier run is more accurate than {error:.0e} (its fastest takes {fastest:.2e} s), so \
                 its time to reach it is not measured"
            )),
        };
        result.met = met(result.value, result.lower_bound, target);
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn front(points: &[(f64, f64)]) -> Front {
        Front::new(points.iter().enumerate().map(|(run, &(time, error))| Point { time, error, family: 0, run }))
    }

    #[test]
    fn the_front_keeps_only_undominated_runs() {
        let f = front(&[(1.0, 1e-2), (2.0, 1e-1), (3.0, 1e-4), (0.5, 0.0), (4.0, f64::NAN), (5.0, 1e-4)]);
        let kept: Vec<(f64, f64)> = f.points.iter().map(|p| (p.time, p.error)).collect();
        assert_eq!(kept, vec![(1.0, 1e-2), (3.0, 1e-4)]);
    }

    #[test]
    fn interpolation_is_a_straight_line_in_log_log() {
        // e = 1e-2 at t = 1, 1e-6 at t = 100: slope −2, so e(10) = 1e-4 and t(1e-4) = 10.
        let f = front(&[(1.0, 1e-2), (100.0, 1e-6)]);
        let e = f.error_at(10.0).unwrap();
        assert!((e / 1e-4 - 1.0).abs() < 1e-12, "{e}");
        match f.time_at(1e-4) {
            Reach::At(t) => assert!((t / 10.0 - 1.0).abs() < 1e-12, "{t}"),
            other => panic!("{other:?}"),
        }
        assert_eq!(f.error_at(0.5), None);
        assert_eq!(f.error_at(100.0), Some(1e-6));
        assert_eq!(f.time_at(1e-1), Reach::AlreadyBelow { fastest: 1.0 });
        assert_eq!(f.time_at(1e-7), Reach::Unreached { best_error: 1e-6, best_time: 100.0 });
    }

    #[test]
    fn equal_time_takes_the_smallest_ratio_over_the_overlap() {
        let ours = front(&[(1.0, 1e-6), (10.0, 1e-10)]);
        let rapier = front(&[(2.0, 1e-2), (20.0, 1e-3)]);
        let r = EqualTime::new(&ours, &rapier, 1e4);
        let [from, to] = r.overlap_s.unwrap();
        assert_eq!((from, to), (2.0, 10.0));
        // The ratio grows along the overlap (ours falls faster): smallest at t = 2.
        assert_eq!(r.at_wall_time_s, Some(2.0));
        let expected = 1e-2 / ours.error_at(2.0).unwrap();
        assert!((r.value.unwrap() / expected - 1.0).abs() < 1e-12);
        assert_eq!(r.met, Some(true));
    }

    #[test]
    fn without_overlap_there_is_no_value_but_maybe_a_bound() {
        let ours = front(&[(1e-4, 1e-3), (1e-3, 1e-9)]);
        let rapier = front(&[(1e-2, 1e-2), (1e-1, 1e-3)]);
        let r = EqualTime::new(&ours, &rapier, 1e4);
        assert_eq!(r.value, None);
        assert_eq!(r.lower_bound, Some(1e-3 / 1e-9));
        assert_eq!(r.met, Some(true));
        let r = EqualTime::new(&rapier, &ours, 1e4);
        assert_eq!((r.value, r.lower_bound, r.met), (None, None, None));
        assert!(r.reason.unwrap().contains("do not overlap"));
    }

    #[test]
    fn equal_error_needs_both_fronts_to_reach_the_level() {
        let ours = front(&[(1e-4, 1e-3), (1e-3, 1e-9)]);
        let rapier = front(&[(1e-2, 1e-2), (1e-1, 1e-3)]);
        let r = EqualError::new(&ours, &rapier, 1e-4, 100.0);
        assert_eq!((r.value, r.met), (None, None));
        assert!(r.reason.unwrap().contains("rapier's sweep does not reach"));
        let rapier = front(&[(1e-2, 1e-2), (1e-1, 1e-5)]);
        let r = EqualError::new(&ours, &rapier, 1e-4, 100.0);
        let t_rapier = rapier.time_at(1e-4);
        let t_ours = ours.time_at(1e-4);
        match (t_rapier, t_ours) {
            (Reach::At(a), Reach::At(b)) => assert!((r.value.unwrap() / (a / b) - 1.0).abs() < 1e-12),
            other => panic!("{other:?}"),
        }
        // Every run of ours below the level: a lower bound from our fastest run.
        let ours = front(&[(1e-4, 1e-6)]);
        let r = EqualError::new(&ours, &rapier, 1e-4, 100.0);
        assert_eq!(r.value, None);
        assert!(r.lower_bound.unwrap() > 100.0 && r.met == Some(true));
    }
}
