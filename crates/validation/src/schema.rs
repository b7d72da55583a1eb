//! `report.json`, schema version 1: the types serialized, field for field as documented in
//! `crates/cli/REPORT_SCHEMA.md`. Change them only together with that document, and bump
//! [`SCHEMA_VERSION`] when a field changes meaning or disappears.

use crate::pareto::{EqualError, EqualTime, TimeToError};
use crate::stability::StabilityReport;
use serde::Serialize;

/// Version of the layout below.
pub const SCHEMA_VERSION: u32 = 1;

/// The whole report.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// [`SCHEMA_VERSION`].
    pub schema_version: u32,
    /// `lagrange-cli <version>`.
    pub generator: String,
    /// `full` or `quick`.
    pub mode: &'static str,
    /// Simulated time of every run (s).
    pub horizon_s: f64,
    /// Interval of the saved times where errors are measured (s).
    pub sample_interval_s: f64,
    /// Number of saved times, including `t = 0`.
    pub samples: usize,
    /// How wall times are measured.
    pub timing: TimingReport,
    /// targets (docs/validation.md#targets) of the summary ratios.
    pub targets: Targets,
    /// One entry per scene, in registry order.
    pub scenes: Vec<SceneReport>,
    /// The stability cases (documented in REPORT_SCHEMA.md, "Stability").
    pub stability: StabilityReport,
    /// Wall time of the whole report (s).
    pub total_wall_time_s: f64,
}

/// The timing policy.
#[derive(Clone, Debug, Serialize)]
pub struct TimingReport {
    /// Untimed warm-up runs per setting (the first is the measured run).
    pub warmup_runs: usize,
    /// Most timed repetitions per setting.
    pub max_timed_repetitions: usize,
    /// Repetitions stop once their total reaches this (s).
    pub repetition_budget_s: f64,
    /// A measured run at least this long (s) is also the first timed repetition.
    pub measured_is_timed_above_s: f64,
    /// What is timed and which statistic is kept.
    pub statistic: &'static str,
}

/// The targets (docs/validation.md#targets).
#[derive(Clone, Debug, Serialize)]
pub struct Targets {
    /// At equal wall time, `e_rapier / e_ours` at least this.
    pub error_ratio_at_equal_time: f64,
    /// At equal error, `t_rapier / t_ours` at least this.
    pub time_ratio_at_equal_error: f64,
    /// The error level of the time ratio.
    pub equal_error: f64,
}

/// One scene.
#[derive(Clone, Debug, Serialize)]
pub struct SceneReport {
    /// Scene id.
    pub scene: &'static str,
    /// Title.
    pub title: &'static str,
    /// Generalized coordinate names.
    pub coordinates: Vec<String>,
    /// Whether the energy function is a constant of the motion (else every `energy_error` is null).
    pub conserves_energy: bool,
    /// The scene's own span (s), over which it is run instead of the report's horizon, with
    /// the saved times and fixed steps scaled alike (null for scenes that run the report's
    /// horizon).
    pub horizon_s: Option<f64>,
    /// The reference the errors are measured against.
    pub reference: ReferenceReport,
    /// One entry per method family, in the order of `Family::ALL`.
    pub methods: Vec<MethodReport>,
    /// Fronts and ratios.
    pub summary: Summary,
    /// The plots, as file names in the output directory.
    pub plots: Plots,
    /// Wall time spent on this scene: every run, warm-up and repetition (s).
    pub scene_wall_time_s: f64,
}

/// The scene's reference.
#[derive(Clone, Debug, Serialize)]
pub struct ReferenceReport {
    /// `closed_form` or `reduced_dop853`.
    pub kind: &'static str,
    /// Tolerance of a `reduced_dop853` reference (null for a closed form).
    pub tolerance: Option<f64>,
    /// Tolerance of the Cartesian run it is checked against.
    pub cartesian_tolerance: f64,
    /// `max ‖q_ref − q_cartesian‖∞` over the saved times (null if that run is missing).
    pub cartesian_agreement: Option<f64>,
    /// Where a solution of the default state is published (null otherwise).
    pub published_source: Option<&'static str>,
    /// `max_i |q_ref,i − q_pub,i| / |q_pub,i|` at the published time (null without one).
    pub published_agreement: Option<f64>,
}

/// One method family on one scene.
#[derive(Clone, Debug, Serialize)]
pub struct MethodReport {
    /// `rk4`, `adaptive`, `variational`, `cartesian`, `rapier-impulse`, `rapier-multibody`,
    /// `rapier-impulse-f32`, `rapier-multibody-f32`.
    pub method: &'static str,
    /// `reduced` or `maximal`.
    pub solver: &'static str,
    /// `ok`, `unbuildable` or `failed`.
    pub status: &'static str,
    /// Why it is unbuildable or failed.
    pub reason: Option<String>,
    /// Deviations from the requested scene the engine needs (its errors are measured against a
    /// reference with the same deviations).
    pub deviations: Vec<String>,
    /// Kind of the reference its errors are measured against (null when unbuildable).
    pub reference: Option<&'static str>,
    /// Remarks on the sweep (e.g. substeps the build does not honour).
    pub note: Option<String>,
    /// The observed order of convergence in the step or rapier substep
    /// ([`observed_order`](crate::assemble::observed_order)); null for tolerance sweeps or
    /// too few runs in the asymptotic range.
    pub observed_order: Option<f64>,
    /// The sweep, in order.
    pub runs: Vec<RunReport>,
}

/// The settings of one run (the fields a family does not use are null).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct SettingsReport {
    /// Fixed step (RK4, variational) or rapier step (s).
    pub dt: Option<f64>,
    /// Tolerance (adaptive, Cartesian).
    pub tolerance: Option<f64>,
    /// rapier substeps per step (the ones the build uses).
    pub substeps: Option<usize>,
    /// rapier substep `dt / substeps` (s).
    pub h: Option<f64>,
}

/// One run.
#[derive(Clone, Debug, Serialize)]
pub struct RunReport {
    /// Its settings.
    pub settings: SettingsReport,
    /// `ok` or `failed`.
    pub status: &'static str,
    /// Why it failed.
    pub reason: Option<String>,
    /// `max_k ‖q(t_k) − q_ref(t_k)‖∞` over the saved times.
    pub max_error: Option<f64>,
    /// `‖q − q_ref‖∞` at the horizon.
    pub final_error: Option<f64>,
    /// `max_k |E(t_k) − E(0)| / |E(0)|`, where the scene conserves energy.
    pub energy_error: Option<f64>,
    /// Largest constraint violation over the saved times, where the engine has one.
    pub constraint_violation: Option<f64>,
    /// Minimum wall time over the timed repetitions (s).
    pub wall_time_s: Option<f64>,
    /// Timed repetitions.
    pub timed_repetitions: usize,
    /// Steps taken.
    pub steps: Option<usize>,
    /// Whether the run is on its family's work-precision front.
    pub on_front: bool,
}

/// A point of a front.
#[derive(Clone, Debug, Serialize)]
pub struct FrontPoint {
    /// Family.
    pub method: &'static str,
    /// Settings, as text.
    pub setting: String,
    /// Wall time (s).
    pub wall_time_s: f64,
    /// Max error.
    pub max_error: f64,
}

/// The summary of a scene.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// The families whose union is "ours".
    pub ours: Vec<&'static str>,
    /// Our front (fastest first).
    pub ours_front: Vec<FrontPoint>,
    /// One comparison per rapier f64 engine.
    pub versus: Vec<Versus>,
    /// The wall time our front needs to reach each of [`ACCURACY_LEVELS`](crate::plan::ACCURACY_LEVELS).
    pub time_to_error: Vec<TimeToError>,
}

/// Ours against one rapier engine.
#[derive(Clone, Debug, Serialize)]
pub struct Versus {
    /// The engine.
    pub rapier: &'static str,
    /// `ok`, `unbuildable` or `failed`.
    pub status: &'static str,
    /// Why it is unbuildable or failed.
    pub reason: Option<String>,
    /// Its front (fastest first).
    pub rapier_front: Vec<FrontPoint>,
    /// `e_rapier / e_ours` at equal wall time.
    pub error_ratio_at_equal_time: EqualTime,
    /// `t_rapier / t_ours` at equal error.
    pub time_ratio_at_equal_error: EqualError,
}

/// Plot file names.
#[derive(Clone, Debug, Serialize)]
pub struct Plots {
    /// Error against wall time, log-log.
    pub work_precision: String,
    /// Reference trajectory and errors over time.
    pub error: String,
    /// The scene's animation page (`<scene>.html`), where it could be made.
    pub animation: Option<String>,
}
