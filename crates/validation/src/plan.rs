//! What the report runs: the horizon, the saved times, the sweep of every method family, and
//! how runs are timed — one plan for the full report, a smaller one for `--quick`.

use crate::Error;
use lagrange::integrate::MethodKind;
use lagrange_maximal::Engine;

/// Interval between saved times (s). Every fixed step of the sweeps is `0.05 · 2⁻ᵏ` or
/// `1/60 · 4⁻ᵏ`, so every saved time `k · 0.05` lies exactly on every step grid.
pub const SAMPLE_INTERVAL: f64 = 0.05;

/// Horizon of the full report (s).
pub const FULL_HORIZON: f64 = 10.0;

/// Horizon of `--quick` (s).
pub const QUICK_HORIZON: f64 = 2.0;

/// Tolerance of the reduced reference solution where a scene has no closed form: near the
/// tightest an error-controlled method takes (10 ε ≈ 2.2e-15), below every swept tolerance, so
/// that the sweeps' runs at 1e-14 are measured against something better than themselves.
pub const REFERENCE_TOLERANCE: f64 = 3e-15;

/// The method of a computed reference: Dormand–Prince 8(5,3) at [`REFERENCE_TOLERANCE`], whose
/// global error is one to two orders below that of Dormand–Prince 5(4) at the same tolerance
/// (docs/validation.md#references gives the measured agreements).
pub fn reference_method() -> lagrange::Method {
    lagrange::Method::Dop853 { tol: lagrange::Tolerances::uniform(REFERENCE_TOLERANCE) }
}

/// Tolerance of the Cartesian run the reduced reference is checked against.
pub const CARTESIAN_CHECK_TOLERANCE: f64 = 1e-12;

/// The error at which times are compared (docs/validation.md#targets).
pub const EQUAL_ERROR: f64 = 1e-4;

/// The error levels at which the report states how long our fastest run needs
/// (docs/validation.md#targets: 1e-10 within 5 ms on the four-bar and Andrews' squeezer, and
/// 1e-12 reached at all).
pub const ACCURACY_LEVELS: [f64; 2] = [1e-10, 1e-12];

/// docs/validation.md#targets: at equal wall time, our error is at least this many times smaller than rapier's.
pub const ERROR_RATIO_TARGET: f64 = 1e4;

/// docs/validation.md#targets: at equal error, our run takes at least this many times less wall time.
pub const TIME_RATIO_TARGET: f64 = 100.0;

/// rapier steps swept (s). rapier is first order in the substep `h = dt / substeps` and two runs
/// with the same `h` give the same trajectory (docs/rapier.md#the-substep-scheme), while a substep costs less
/// than a step: so the coarsest step is swept over many substeps (the cheapest way to a small
/// `h`) and the finer steps over a few.
const RAPIER_STEPS: [f64; 4] = [1.0 / 60.0, 1.0 / 240.0, 1.0 / 960.0, 1.0 / 3840.0];

/// Substeps swept at the coarsest step, and at the finer ones.
const RAPIER_SUBSTEPS_COARSE: [usize; 6] = [1, 4, 16, 64, 256, 1024];
const RAPIER_SUBSTEPS_FINE: [usize; 2] = [1, 4];

/// Smallest substep `h` swept for rapier in f64 (s): its cost grows as its error falls, and this
/// keeps the full report within its time budget on the slowest (multibody pulley) scenes.
const RAPIER_MIN_SUBSTEP: f64 = 1.0 / 61440.0;

/// Smallest substep swept in f32 and with `--quick` (s): f32 round-off dominates the error near
/// it (docs/rapier.md#versions-and-precision), and the f32 builds are not part of the summary ratios.
const RAPIER_MIN_SUBSTEP_COARSE: f64 = 1.0 / 15360.0;

/// A family of runs: one integrator of the reduced solver, or one maximal engine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// Reduced coordinates with one of the solver's integrators: RK4 and the variational
    /// midpoint swept over the step, Dormand–Prince 5(4) and 8(5,3) over the tolerance.
    Reduced(MethodKind),
    /// A maximal-coordinate engine: Cartesian (over tolerances) or rapier (over `dt` and substeps).
    Maximal(Engine),
}

impl Family {
    /// Every family, in report order.
    pub const ALL: [Family; 9] = [
        Family::Reduced(MethodKind::Rk4),
        Family::Reduced(MethodKind::Dopri5),
        Family::Reduced(MethodKind::Dop853),
        Family::Reduced(MethodKind::Variational),
        Family::Maximal(Engine::Cartesian),
        Family::Maximal(Engine::RapierImpulse),
        Family::Maximal(Engine::RapierMultibody),
        Family::Maximal(Engine::RapierImpulseF32),
        Family::Maximal(Engine::RapierMultibodyF32),
    ];

    /// The families that make up "ours" in the summary ratios: the reduced solver.
    pub const OURS: [Family; 4] = [Family::ALL[0], Family::ALL[1], Family::ALL[2], Family::ALL[3]];

    /// The rapier engines the summary ratios compare against (f64).
    pub const RAPIER_F64: [Engine; 2] = [Engine::RapierImpulse, Engine::RapierMultibody];

    /// The name in reports: `rk4`, `adaptive`, `dop853`, `variational`, or the engine's name.
    pub fn name(self) -> &'static str {
        match self {
            Family::Reduced(kind) => kind.name(),
            Family::Maximal(engine) => engine.name(),
        }
    }

    /// `reduced` or `maximal`.
    pub fn solver(self) -> &'static str {
        if self.is_reduced() { "reduced" } else { "maximal" }
    }

    /// Whether this is an integrator of the reduced solver.
    pub fn is_reduced(self) -> bool {
        !matches!(self, Family::Maximal(_))
    }
}

/// One point of a sweep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Setting {
    /// A fixed step (RK4, variational).
    Step {
        /// Step (s).
        dt: f64,
    },
    /// A relative and absolute tolerance (adaptive, Cartesian).
    Tolerance {
        /// Tolerance.
        tol: f64,
    },
    /// A rapier step and its substeps.
    Rapier {
        /// Step of `PhysicsPipeline::step` (s).
        dt: f64,
        /// Substeps per step.
        substeps: usize,
    },
}

impl Setting {
    /// `dt = 3.1e-3`, `tol = 1e-8`, `dt = 1/240, 4 substeps`.
    pub fn describe(&self) -> String {
        match *self {
            Setting::Step { dt } => format!("dt = {dt:.3e}"),
            Setting::Tolerance { tol } => format!("tol = {tol:.0e}"),
            Setting::Rapier { dt, substeps } => {
                let plural = if substeps == 1 { "" } else { "s" };
                format!("dt = 1/{:.0}, {substeps} substep{plural}", 1.0 / dt)
            }
        }
    }
}

/// How runs are timed: one warm-up run (the one whose errors are measured), then timed
/// repetitions until `repetitions` are done or their total exceeds `budget` (at least one);
/// the run's time is the minimum. A measured run that lasts at least `measured_is_timed_above`
/// counts as the first timed repetition: what a warm-up removes (first touch of code and data,
/// allocation) takes microseconds, under 1e-4 of such a run, so a second run would only repeat
/// it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timing {
    /// Warm-up runs before the timed ones (the first is the measured run).
    pub warmup: usize,
    /// Most timed repetitions.
    pub repetitions: usize,
    /// Stop repeating once the timed repetitions add up to this (s).
    pub budget: f64,
    /// A measured run at least this long (s) is also the first timed repetition.
    pub measured_is_timed_above: f64,
}

/// A measured run at least this long (s) is also timed (see [`Timing`]).
pub const MEASURED_IS_TIMED_ABOVE: f64 = 0.2;

/// Everything the report runs, for every scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// `--quick`.
    pub quick: bool,
    /// Simulated time from the initial state (s).
    pub horizon: f64,
    /// Saved times `0, 0.05, …, horizon` (s), where errors are measured.
    pub times: Vec<f64>,
    /// RK4 steps.
    pub rk4_steps: Vec<f64>,
    /// Adaptive (Dormand–Prince 5(4)) tolerances.
    pub tolerances: Vec<f64>,
    /// Dormand–Prince 8(5,3) tolerances.
    pub high_order_tolerances: Vec<f64>,
    /// Variational steps.
    pub variational_steps: Vec<f64>,
    /// Cartesian tolerances.
    pub cartesian_tolerances: Vec<f64>,
    /// rapier `(dt, substeps)` before the smallest-substep cut.
    pub rapier: Vec<(f64, usize)>,
    /// Smallest rapier substep in f64 (s).
    pub rapier_min_substep: f64,
    /// Timing policy.
    pub timing: Timing,
    /// The factor every time of the plan was scaled by ([`Plan::scaled_to`]): 1 for the
    /// report's own horizon.
    pub time_scale: f64,
}

impl Plan {
    /// The full plan (10 s) or the quick one (2 s), optionally with another horizon.
    ///
    /// # Errors
    /// A horizon that is not a positive multiple of [`SAMPLE_INTERVAL`].
    pub fn new(quick: bool, horizon: Option<f64>) -> Result<Plan, Error> {
        let horizon = horizon.unwrap_or(if quick { QUICK_HORIZON } else { FULL_HORIZON });
        let count = (horizon / SAMPLE_INTERVAL).round();
        let on_grid = (horizon / SAMPLE_INTERVAL - count).abs() <= 1e-9 * count.max(1.0);
        if !(horizon.is_finite() && horizon > 0.0 && count >= 1.0 && on_grid) {
            return Err(Error::HorizonNotOnGrid { horizon, interval: SAMPLE_INTERVAL });
        }
        if count > 1e5 {
            return Err(Error::HorizonTooLong { horizon, limit: 1e5 * SAMPLE_INTERVAL });
        }
        let times = (0..=count as usize).map(|k| k as f64 * SAMPLE_INTERVAL).collect();
        let halvings = |k: usize| (0..k).map(|j| SAMPLE_INTERVAL / f64::powi(2.0, j as i32)).collect();
        let decades = |from: i32, to: i32, by: usize| (from..=to).step_by(by).map(|e| 10f64.powi(-e)).collect();
        Ok(if quick {
            Plan {
                quick,
                horizon,
                times,
                rk4_steps: halvings(7),
                tolerances: decades(3, 12, 1),
                high_order_tolerances: decades(4, 14, 2),
                variational_steps: halvings(7),
                cartesian_tolerances: decades(6, 12, 3),
                rapier: rapier_ladder(),
                rapier_min_substep: RAPIER_MIN_SUBSTEP_COARSE,
                timing: Timing {
                    warmup: 1,
                    repetitions: 1,
                    budget: 0.0,
                    measured_is_timed_above: MEASURED_IS_TIMED_ABOVE,
                },
                time_scale: 1.0,
            }
        } else {
            Plan {
                quick,
                horizon,
                times,
                rk4_steps: halvings(8),
                tolerances: decades(3, 12, 1),
                high_order_tolerances: decades(4, 14, 1),
                variational_steps: halvings(9),
                cartesian_tolerances: decades(4, 12, 2),
                rapier: rapier_ladder(),
                rapier_min_substep: RAPIER_MIN_SUBSTEP,
                timing: Timing {
                    warmup: 1,
                    repetitions: 3,
                    budget: 0.5,
                    measured_is_timed_above: MEASURED_IS_TIMED_ABOVE,
                },
                time_scale: 1.0,
            }
        })
    }

    /// This plan with every time in it (horizon, saved times, fixed steps, rapier steps and
    /// smallest substep) multiplied by `horizon / self.horizon`: the same sweep, relative to
    /// the scene's own span of time ([`Scene::horizon`](lagrange_scenes::Scene::horizon)).
    /// Every saved time stays on every step grid, since all are scaled alike.
    pub fn scaled_to(&self, horizon: f64) -> Plan {
        let scale = horizon / self.horizon;
        let times = |v: &[f64]| v.iter().map(|t| t * scale).collect::<Vec<f64>>();
        Plan {
            horizon,
            times: times(&self.times),
            rk4_steps: times(&self.rk4_steps),
            variational_steps: times(&self.variational_steps),
            rapier: self.rapier.iter().map(|&(dt, substeps)| (dt * scale, substeps)).collect(),
            rapier_min_substep: self.rapier_min_substep * scale,
            time_scale: self.time_scale * scale,
            ..self.clone()
        }
    }

    /// The interval between saved times (s): [`SAMPLE_INTERVAL`] for the unscaled plan.
    pub fn sample_interval(&self) -> f64 {
        self.times.get(1).map_or(SAMPLE_INTERVAL, |t| t - self.times[0])
    }

    /// The sweep of `family`. A rapier build that ignores substeps (scenes driven by per-step
    /// forces run one substep per step whatever is asked) is swept over `dt` alone, down to the
    /// same smallest substep.
    pub fn settings(&self, family: Family, honours_substeps: bool) -> Vec<Setting> {
        let engine = match family {
            Family::Reduced(MethodKind::Rk4) => return self.rk4_steps.iter().map(|&dt| Setting::Step { dt }).collect(),
            Family::Reduced(MethodKind::Variational) => {
                return self.variational_steps.iter().map(|&dt| Setting::Step { dt }).collect();
            }
            Family::Reduced(MethodKind::Dopri5) => {
                return self.tolerances.iter().map(|&tol| Setting::Tolerance { tol }).collect();
            }
            Family::Reduced(MethodKind::Dop853) => {
                return self.high_order_tolerances.iter().map(|&tol| Setting::Tolerance { tol }).collect();
            }
            // Not swept by the report.
            Family::Reduced(MethodKind::Sdirk4 | MethodKind::Gauss4) => return Vec::new(),
            Family::Maximal(Engine::Cartesian) => {
                return self.cartesian_tolerances.iter().map(|&tol| Setting::Tolerance { tol }).collect();
            }
            Family::Maximal(engine) => engine,
        };
        let smallest = match engine {
            Engine::RapierImpulseF32 | Engine::RapierMultibodyF32 => RAPIER_MIN_SUBSTEP_COARSE * self.time_scale,
            _ => self.rapier_min_substep,
        };
        let fine_enough = |h: f64| h >= smallest * (1.0 - 1e-9);
        if honours_substeps {
            self.rapier
                .iter()
                .filter(|(dt, substeps)| fine_enough(dt / *substeps as f64))
                .map(|&(dt, substeps)| Setting::Rapier { dt, substeps })
                .collect()
        } else {
            let steps = std::iter::successors(Some(RAPIER_STEPS[0] * self.time_scale), |dt| Some(dt / 4.0));
            steps.take_while(|&dt| fine_enough(dt)).map(|dt| Setting::Rapier { dt, substeps: 1 }).collect()
        }
    }
}

/// Every `(dt, substeps)` of the rapier sweep, coarsest first.
fn rapier_ladder() -> Vec<(f64, usize)> {
    let coarse = RAPIER_SUBSTEPS_COARSE.iter().map(|&s| (RAPIER_STEPS[0], s));
    let fine = RAPIER_STEPS[1..].iter().flat_map(|&dt| RAPIER_SUBSTEPS_FINE.iter().map(move |&s| (dt, s)));
    coarse.chain(fine).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn saved_times_lie_on_every_step_grid() {
        let plan = Plan::new(false, None).unwrap();
        let rapier: Vec<f64> = (0..6).map(|k| RAPIER_STEPS[0] / f64::powi(4.0, k)).collect();
        let steps = plan.rk4_steps.iter().chain(&plan.variational_steps).chain(&rapier);
        for &dt in steps {
            for &t in &plan.times {
                let k = t / dt;
                assert!((k - k.round()).abs() <= 1e-9 * k.max(1.0), "t = {t} is off the grid of dt = {dt}");
            }
        }
    }

    /// A plan scaled to a scene's own span keeps every saved time on every step grid and
    /// sweeps the same substeps relative to its span.
    #[test]
    fn a_scaled_plan_is_the_same_sweep_on_the_scenes_span() {
        for quick in [false, true] {
            let plan = Plan::new(quick, None).unwrap();
            let scaled = plan.scaled_to(0.03);
            assert_eq!(scaled.times.len(), plan.times.len());
            assert!((scaled.times.last().unwrap() - 0.03).abs() < 1e-15);
            let rapier: Vec<f64> = (0..6).map(|k| RAPIER_STEPS[0] * scaled.time_scale / f64::powi(4.0, k)).collect();
            for &dt in scaled.rk4_steps.iter().chain(&scaled.variational_steps).chain(&rapier) {
                for &t in &scaled.times {
                    let k = t / dt;
                    assert!((k - k.round()).abs() <= 1e-9 * k.max(1.0), "t = {t} is off the grid of dt = {dt}");
                }
            }
            for honours in [true, false] {
                let ours = plan.settings(Family::Maximal(Engine::RapierImpulse), honours);
                let theirs = scaled.settings(Family::Maximal(Engine::RapierImpulse), honours);
                assert_eq!(ours.len(), theirs.len(), "quick {quick}, substeps honoured {honours}");
            }
        }
    }

    #[test]
    fn horizons_must_be_whole_sample_intervals() {
        assert!(Plan::new(true, Some(0.07)).is_err());
        assert!(Plan::new(true, Some(-1.0)).is_err());
        assert!(Plan::new(true, Some(f64::NAN)).is_err());
        assert_eq!(Plan::new(true, Some(0.5)).unwrap().times.len(), 11);
    }

    #[test]
    fn rapier_sweeps_stop_at_the_smallest_substep() {
        let substep = |s: &Setting| match *s {
            Setting::Rapier { dt, substeps } => dt / substeps as f64,
            _ => unreachable!(),
        };
        for (quick, engine, smallest) in [
            (false, Engine::RapierImpulse, RAPIER_MIN_SUBSTEP),
            (false, Engine::RapierMultibodyF32, RAPIER_MIN_SUBSTEP_COARSE),
            (true, Engine::RapierImpulse, RAPIER_MIN_SUBSTEP_COARSE),
        ] {
            let plan = Plan::new(quick, None).unwrap();
            for honours in [true, false] {
                let settings = plan.settings(Family::Maximal(engine), honours);
                let finest = settings.iter().map(substep).fold(f64::INFINITY, f64::min);
                assert!((finest / smallest - 1.0).abs() < 1e-9, "{settings:?}");
            }
        }
    }
}
