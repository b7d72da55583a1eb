//! Running an integrator over an interval and recording `t, q, q̇` and the energy.

use super::{Dopri5, Rk4, Tolerances, Variational, check_step};
use crate::{Dynamics, Error, State};

/// Which integrator, with its step or tolerances.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Classical RK4 with fixed step `dt`.
    Rk4 {
        /// Step.
        dt: f64,
    },
    /// Dormand–Prince 5(4) with error control.
    Adaptive {
        /// Tolerances.
        tol: Tolerances,
    },
    /// Variational midpoint (discrete Euler–Lagrange) with fixed step `dt`.
    Variational {
        /// Step.
        dt: f64,
    },
}

impl Method {
    /// Short name: `rk4`, `adaptive`, `variational`.
    pub fn name(&self) -> &'static str {
        match self {
            Method::Rk4 { .. } => "rk4",
            Method::Adaptive { .. } => "adaptive",
            Method::Variational { .. } => "variational",
        }
    }
}

/// When to record the state.
#[derive(Clone, Debug, PartialEq)]
pub enum Output {
    /// At `t0, t0 + Δ, t0 + 2Δ, …` and at the end. For fixed-step methods `Δ` must be a
    /// multiple of the step.
    Every(f64),
    /// At the given increasing times within `[t0, t_end]` (fixed-step methods: on the step grid
    /// `t0 + k dt`, or `t_end`).
    Times(Vec<f64>),
    /// At the start and the end only.
    Ends,
}

/// Work counters of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps (adaptive).
    pub rejected: usize,
    /// Evaluations of the equations of motion (explicit methods).
    pub evaluations: usize,
    /// Newton iterations (implicit methods).
    pub newton_iterations: usize,
}

/// A recorded trajectory: rows at the output times.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    /// Number of coordinates.
    pub n: usize,
    /// Output times.
    pub t: Vec<f64>,
    /// Coordinates, row-major (samples × n).
    pub q: Vec<f64>,
    /// Velocities, row-major (samples × n).
    pub qdot: Vec<f64>,
    /// Energy function `h` at each sample.
    pub energy: Vec<f64>,
    /// Work done.
    pub stats: Stats,
}

impl Trajectory {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Coordinates of sample `k`.
    pub fn q(&self, k: usize) -> &[f64] {
        &self.q[k * self.n..(k + 1) * self.n]
    }

    /// Velocities of sample `k`.
    pub fn qdot(&self, k: usize) -> &[f64] {
        &self.qdot[k * self.n..(k + 1) * self.n]
    }

    /// The last sample as a state.
    pub fn last_state(&self) -> Option<State> {
        let k = self.len().checked_sub(1)?;
        Some(State::new(self.t[k], self.q(k), self.qdot(k)))
    }

    fn with_capacity(n: usize, samples: usize) -> Self {
        Self {
            n,
            t: Vec::with_capacity(samples),
            q: Vec::with_capacity(samples * n),
            qdot: Vec::with_capacity(samples * n),
            energy: Vec::with_capacity(samples),
            stats: Stats::default(),
        }
    }

    fn push<D: Dynamics>(
        &mut self,
        system: &D,
        ws: &mut D::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<(), Error> {
        self.t.push(t);
        self.q.extend_from_slice(q);
        self.qdot.extend_from_slice(qdot);
        self.energy.push(system.energy(ws, t, q, qdot)?);
        Ok(())
    }
}

/// Safety cap on the number of steps of one run.
const MAX_STEPS: usize = 500_000_000;

/// Integrate `system` from `initial` to `t_end` with `method`, recording at `output`.
///
/// # Errors
/// [`Error::InvalidSetting`] for a bad horizon, step, tolerance or output grid;
/// [`Error::Diverged`] when the state stops being finite; any error of the equations of motion
/// or of the integrator.
pub fn simulate<D: Dynamics>(
    system: &D,
    initial: &State,
    t_end: f64,
    method: Method,
    output: &Output,
) -> Result<Trajectory, Error> {
    let n = system.dof();
    if initial.q.len() != n || initial.qdot.len() != n {
        return Err(Error::DimensionMismatch {
            what: "initial state",
            expected: n,
            got: initial.q.len().min(initial.qdot.len()),
        });
    }
    let t0 = initial.t;
    if !(t_end.is_finite() && t_end >= t0) {
        return Err(Error::InvalidSetting {
            what: "horizon",
            value: t_end,
            why: "must be finite and not before the start",
        });
    }
    let times = output_times(t0, t_end, output)?;
    let mut ws = system.new_workspace();
    let mut trajectory = Trajectory::with_capacity(n, times.len());
    match method {
        Method::Rk4 { dt } => {
            check_step(dt)?;
            let mut rk4 = Rk4::new(n);
            let mut state = initial.clone();
            run_fixed(t0, dt, &times, &mut trajectory, |traj, event| match event {
                Event::Step { h, k } => {
                    state.t = t0 + k as f64 * dt;
                    rk4.step(system, &mut ws, &mut state, h).map_err(|e| diverged(e, state.t, k))?;
                    check_finite(&state.q, &state.qdot, state.t, k)
                }
                Event::Record { t } => {
                    state.t = t;
                    traj.push(system, &mut ws, t, &state.q, &state.qdot)
                }
            })?;
            trajectory.stats.evaluations = 4 * trajectory.stats.steps;
        }
        Method::Variational { dt } => {
            check_step(dt)?;
            let mut integrator = Variational::new(system);
            integrator.start(system, t0, &initial.q, &initial.qdot)?;
            let mut qdot = vec![0.0; n];
            let mut q = vec![0.0; n];
            run_fixed(t0, dt, &times, &mut trajectory, |traj, event| match event {
                Event::Step { h, k } => {
                    let t = integrator.t();
                    integrator.step(system, h).map_err(|e| diverged(e, t, k))?;
                    check_finite(integrator.q(), integrator.momenta(), integrator.t(), k)
                }
                Event::Record { t } => {
                    if t == t0 {
                        qdot.copy_from_slice(&initial.qdot);
                    } else {
                        integrator.velocities(system, &mut qdot)?;
                    }
                    q.copy_from_slice(integrator.q());
                    traj.push(system, &mut ws, t, &q, &qdot)
                }
            })?;
            trajectory.stats.newton_iterations = integrator.newton_iterations;
        }
        Method::Adaptive { tol } => {
            let mut integrator = Dopri5::new(n, tol)?;
            let span = (t_end - t0).max(f64::MIN_POSITIVE);
            integrator.start(system, &mut ws, t0, &initial.q, &initial.qdot, span)?;
            let mut q = vec![0.0; n];
            let mut qdot = vec![0.0; n];
            let mut steps = 0;
            for &t_out in &times {
                while integrator.t() < t_out {
                    if steps >= MAX_STEPS {
                        return Err(Error::TooManySteps { steps, t: integrator.t(), t_end });
                    }
                    integrator.step(system, &mut ws, t_end).map_err(|e| diverged(e, integrator.t(), steps))?;
                    steps += 1;
                    check_finite(integrator.q(), integrator.qdot(), integrator.t(), steps)?;
                }
                if t_out == integrator.t() {
                    q.copy_from_slice(integrator.q());
                    qdot.copy_from_slice(integrator.qdot());
                } else {
                    integrator.interpolate(t_out, &mut q, &mut qdot);
                }
                trajectory.push(system, &mut ws, t_out, &q, &qdot)?;
            }
            trajectory.stats.steps = integrator.stats.accepted;
            trajectory.stats.rejected = integrator.stats.rejected;
            trajectory.stats.evaluations = integrator.stats.evaluations;
        }
    }
    Ok(trajectory)
}

/// What the fixed-step driver asks of a method.
enum Event {
    /// Take step number `k` of length `h`.
    Step { h: f64, k: usize },
    /// Record the state, which is at time `t`.
    Record { t: f64 },
}

/// Drive a fixed-step method over the output times: whole steps on the grid `t0 + k dt`, and
/// one shorter last step when the final output is off the grid.
fn run_fixed(
    t0: f64,
    dt: f64,
    times: &[f64],
    trajectory: &mut Trajectory,
    mut method: impl FnMut(&mut Trajectory, Event) -> Result<(), Error>,
) -> Result<(), Error> {
    let mut k: usize = 0;
    for (index, &t_out) in times.iter().enumerate() {
        let exact = (t_out - t0) / dt;
        let target = exact.round();
        let on_grid = (exact - target).abs() <= 1e-9 * exact.max(1.0);
        if !on_grid && index + 1 != times.len() {
            return Err(Error::InvalidSetting {
                what: "output time",
                value: t_out,
                why: "fixed-step output times must lie on the step grid t0 + k dt",
            });
        }
        let whole = if on_grid { target as usize } else { exact.floor() as usize };
        if whole > MAX_STEPS {
            return Err(Error::TooManySteps { steps: MAX_STEPS, t: t0, t_end: t_out });
        }
        while k < whole {
            method(trajectory, Event::Step { h: dt, k })?;
            k += 1;
        }
        if !on_grid {
            let t = t0 + k as f64 * dt;
            method(trajectory, Event::Step { h: t_out - t, k })?;
            k += 1;
        }
        trajectory.stats.steps = k;
        method(trajectory, Event::Record { t: t_out })?;
    }
    Ok(())
}

fn output_times(t0: f64, t_end: f64, output: &Output) -> Result<Vec<f64>, Error> {
    match output {
        Output::Ends => Ok(if t_end > t0 { vec![t0, t_end] } else { vec![t0] }),
        Output::Every(every) => {
            if !(*every > 0.0 && every.is_finite()) {
                return Err(Error::InvalidSetting {
                    what: "output interval",
                    value: *every,
                    why: "must be positive and finite",
                });
            }
            let count = ((t_end - t0) / every * (1.0 + 1e-12)).floor() as usize;
            if count > 100_000_000 {
                return Err(Error::InvalidSetting {
                    what: "output interval",
                    value: *every,
                    why: "gives more than 1e8 samples",
                });
            }
            let mut times: Vec<f64> = (0..=count).map(|k| t0 + k as f64 * every).collect();
            if let Some(last) = times.last_mut() {
                if (t_end - *last).abs() <= 1e-9 * every {
                    *last = t_end;
                } else {
                    times.push(t_end);
                }
            }
            Ok(times)
        }
        Output::Times(times) => {
            let increasing = times.windows(2).all(|w| w[1] > w[0]);
            if !increasing || times.iter().any(|t| !(*t >= t0 && *t <= t_end)) {
                return Err(Error::InvalidSetting {
                    what: "output times",
                    value: f64::NAN,
                    why: "must be increasing and within [t0, t_end]",
                });
            }
            Ok(times.clone())
        }
    }
}

fn check_finite(q: &[f64], v: &[f64], t: f64, step: usize) -> Result<(), Error> {
    if crate::error::all_finite(q) && crate::error::all_finite(v) {
        Ok(())
    } else {
        Err(Error::Diverged { t, step, quantity: "the state is no longer finite".into() })
    }
}

/// A non-finite evaluation during a run is a divergence of the run.
fn diverged(error: Error, t: f64, step: usize) -> Error {
    match error {
        Error::NonFinite { stage, .. } => Error::Diverged { t, step, quantity: format!("non-finite {stage}") },
        other => other,
    }
}
