//! Running an integrator over an interval and recording `t, q, q̇` and the energy.

use super::{Dopri5, Gauss4, Rk4, Sdirk4, Tolerances, Variational, check_step, non_finite_quantity};
use crate::{Coordinate, Dynamics, Error, State};

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
    /// L-stable SDIRK4 ([`Sdirk4`]) with error control, for stiff problems.
    Implicit {
        /// Tolerances.
        tol: Tolerances,
    },
    /// Gauss–Legendre of order 4 ([`Gauss4`]), symplectic, with fixed step `dt`.
    Gauss {
        /// Step.
        dt: f64,
    },
}

impl Method {
    /// Short name: `rk4`, `adaptive`, `variational`, `implicit`, `gauss`.
    pub fn name(&self) -> &'static str {
        match self {
            Method::Rk4 { .. } => "rk4",
            Method::Adaptive { .. } => "adaptive",
            Method::Variational { .. } => "variational",
            Method::Implicit { .. } => "implicit",
            Method::Gauss { .. } => "gauss",
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
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps (adaptive and implicit-adaptive).
    pub rejected: usize,
    /// Evaluations of the equations of motion `q̈` in `f64` (RK4, the adaptive methods and
    /// Gauss; the variational integrator evaluates the Lagrangian instead).
    pub evaluations: usize,
    /// Newton iterations (implicit methods).
    pub newton_iterations: usize,
    /// Evaluations of the acceleration Jacobian (implicit Runge–Kutta methods).
    pub jacobians: usize,
    /// LU factorizations of a Newton matrix (implicit Runge–Kutta methods).
    pub factorizations: usize,
    /// The time at which the explicit adaptive integrator's stiffness test first fired
    /// ([`Method::Adaptive`] only; `None` otherwise).
    pub stiffness: Option<f64>,
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
        step: usize,
    ) -> Result<(), Error> {
        // A finite state whose energy overflows (a run growing past ~1e150) has diverged.
        let energy = system.energy(ws, t, q, qdot).map_err(|error| match error {
            Error::NonFinite { stage, .. } if !self.t.is_empty() => {
                let largest = q.iter().chain(qdot).fold(0.0_f64, |m, v| m.max(v.abs()));
                Error::Diverged {
                    t,
                    step,
                    quantity: format!("energy = non-finite ({stage}), the state reaching |q|, |q̇| = {largest:e}"),
                }
            }
            other => other,
        })?;
        self.t.push(t);
        self.q.extend_from_slice(q);
        self.qdot.extend_from_slice(qdot);
        self.energy.push(energy);
        Ok(())
    }
}

/// Safety cap on the number of steps of one run.
const MAX_STEPS: usize = 500_000_000;

/// Integrate `system` from `initial` to `t_end` with `method`, recording at `output`.
///
/// # Errors
/// [`Error::InvalidSetting`] for a bad horizon, step, tolerance or output grid;
/// [`Error::Diverged`] (naming the quantity) when the state, a stage value or the recorded
/// energy stops being finite; [`Error::Stiff`] when the explicit adaptive method runs out of
/// step or of steps after its stiffness test fired; any error of the equations of motion or
/// of the integrator ([`Error::NewtonFailed`], [`Error::StepSizeUnderflow`], …).
///
/// [`Method::Implicit`] lands its steps on the output times; [`Method::Adaptive`] interpolates
/// (dense output) and records in [`Stats::stiffness`] when its stiffness test fired.
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
            run_state_stepper(system, &mut ws, initial, dt, &times, &mut trajectory, |ws, state, h| {
                rk4.step(system, ws, state, h)
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
                    integrator.step(system, h).map_err(|e| diverged(system, e, t, k))?;
                    check_finite_momenta(system, integrator.q(), integrator.momenta(), integrator.t(), k)
                }
                Event::Record { t } => {
                    if t == t0 {
                        qdot.copy_from_slice(&initial.qdot);
                    } else {
                        integrator.velocities(system, &mut qdot)?;
                    }
                    q.copy_from_slice(integrator.q());
                    traj.push(system, &mut ws, t, &q, &qdot, traj.stats.steps)
                }
            })?;
            trajectory.stats.newton_iterations = integrator.newton_iterations;
        }
        Method::Gauss { dt } => {
            check_step(dt)?;
            let mut gauss = Gauss4::new(n);
            run_state_stepper(system, &mut ws, initial, dt, &times, &mut trajectory, |ws, state, h| {
                gauss.step(system, ws, state, h)
            })?;
            let stats = &mut trajectory.stats;
            stats.evaluations = gauss.stats.evaluations;
            stats.newton_iterations = gauss.stats.newton_iterations;
            stats.jacobians = gauss.stats.jacobians;
            stats.factorizations = gauss.stats.factorizations;
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
                        return Err(match integrator.stats.stiffness {
                            Some(_) => Error::Stiff { t: integrator.t(), h: integrator.proposed_step() },
                            None => Error::TooManySteps { steps, t: integrator.t(), t_end },
                        });
                    }
                    integrator.step(system, &mut ws, t_end).map_err(|e| diverged(system, e, integrator.t(), steps))?;
                    steps += 1;
                    check_finite(system, integrator.q(), integrator.qdot(), integrator.t(), steps)?;
                }
                if t_out == integrator.t() {
                    q.copy_from_slice(integrator.q());
                    qdot.copy_from_slice(integrator.qdot());
                } else {
                    integrator.interpolate(t_out, &mut q, &mut qdot);
                }
                trajectory.push(system, &mut ws, t_out, &q, &qdot, steps)?;
            }
            trajectory.stats.steps = integrator.stats.accepted;
            trajectory.stats.rejected = integrator.stats.rejected;
            trajectory.stats.evaluations = integrator.stats.evaluations;
            trajectory.stats.stiffness = integrator.stats.stiffness;
        }
        Method::Implicit { tol } => {
            let mut integrator = Sdirk4::new(n, tol)?;
            let span = (t_end - t0).max(f64::MIN_POSITIVE);
            integrator.start(system, &mut ws, t0, &initial.q, &initial.qdot, span)?;
            let mut steps = 0;
            for &t_out in &times {
                while integrator.t() < t_out {
                    if steps >= MAX_STEPS {
                        return Err(Error::TooManySteps { steps, t: integrator.t(), t_end });
                    }
                    // Steps land on the output times (no interpolation of stiff velocities).
                    integrator.step(system, &mut ws, t_out).map_err(|e| diverged(system, e, integrator.t(), steps))?;
                    steps += 1;
                    check_finite(system, integrator.q(), integrator.qdot(), integrator.t(), steps)?;
                }
                trajectory.push(system, &mut ws, t_out, integrator.q(), integrator.qdot(), steps)?;
            }
            let stats = &mut trajectory.stats;
            stats.steps = integrator.stats.accepted;
            stats.rejected = integrator.stats.rejected;
            stats.evaluations = integrator.stats.evaluations;
            stats.newton_iterations = integrator.stats.newton_iterations;
            stats.jacobians = integrator.stats.jacobians;
            stats.factorizations = integrator.stats.factorizations;
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
/// [`run_fixed`] for a one-step method that advances a [`State`] in place (RK4, Gauss): the
/// state's time is set from the grid before every step, so it carries no accumulated round-off.
fn run_state_stepper<D: Dynamics>(
    system: &D,
    ws: &mut D::Workspace,
    initial: &State,
    dt: f64,
    times: &[f64],
    trajectory: &mut Trajectory,
    mut step: impl FnMut(&mut D::Workspace, &mut State, f64) -> Result<(), Error>,
) -> Result<(), Error> {
    let t0 = initial.t;
    let mut state = initial.clone();
    run_fixed(t0, dt, times, trajectory, |traj, event| match event {
        Event::Step { h, k } => {
            state.t = t0 + k as f64 * dt;
            step(ws, &mut state, h).map_err(|e| diverged(system, e, state.t, k))?;
            check_finite(system, &state.q, &state.qdot, state.t, k)
        }
        Event::Record { t } => {
            state.t = t;
            traj.push(system, ws, t, &state.q, &state.qdot, traj.stats.steps)
        }
    })
}

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

/// The state after a step must be finite; the error names the first coordinate that is not.
fn check_finite<D: Dynamics>(system: &D, q: &[f64], v: &[f64], t: f64, step: usize) -> Result<(), Error> {
    match non_finite_quantity(system.coordinates(), q, v) {
        None => Ok(()),
        Some(quantity) => Err(Error::Diverged { t, step, quantity }),
    }
}

/// As [`check_finite`] for the variational integrator's `(q, p)`.
fn check_finite_momenta<D: Dynamics>(system: &D, q: &[f64], p: &[f64], t: f64, step: usize) -> Result<(), Error> {
    match non_finite_quantity(system.coordinates(), q, &[]) {
        Some(quantity) => Err(Error::Diverged { t, step, quantity }),
        None => match p.iter().position(|v| !v.is_finite()) {
            Some(i) => {
                let quantity = format!("p[{}] = {}", coordinate_name(system.coordinates(), i), p[i]);
                Err(Error::Diverged { t, step, quantity })
            }
            None => Ok(()),
        },
    }
}

fn coordinate_name(coordinates: &[Coordinate], i: usize) -> String {
    coordinates.get(i).map_or_else(|| i.to_string(), |c| c.name.clone())
}

/// A non-finite evaluation during a run is a divergence of the run: name the coordinate of the
/// stage state that blew up when it is one, or else the stage of the evaluation.
fn diverged<D: Dynamics>(system: &D, error: Error, t: f64, step: usize) -> Error {
    match error {
        Error::NonFinite { stage, q, .. } => {
            let quantity = match non_finite_quantity(system.coordinates(), &q, &[]) {
                Some(named) => format!("{named} within the step"),
                None if stage == crate::Stage::State => "q̇ non-finite within the step".to_string(),
                None => format!("non-finite {stage} at q = {q:?} within the step"),
            };
            Error::Diverged { t, step, quantity }
        }
        other => other,
    }
}
