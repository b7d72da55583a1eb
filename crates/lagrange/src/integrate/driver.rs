//! Running an integrator over an interval: one loop over the output times, writing each sample
//! into a [`Sink`] (a [`Trajectory`] being one).

use super::{Dop853, Dopri5, Gauss4, Grid, Integrator, Method, Rk4, Sdirk4, Stats, Variational, non_finite_quantity};
use crate::{Bounds, Dynamics, Error, State};

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
    /// Constraint violation `[max |Φ|, max |G q̇ + ∂Φ/∂t|]` (velocity rows included) at each
    /// sample, for a system with constraints among its coordinates; empty otherwise
    /// (docs/method.md#constraints).
    pub violation: Vec<[f64; 2]>,
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

    /// An empty trajectory of `n` coordinates with room for `samples` samples.
    pub fn with_capacity(n: usize, samples: usize) -> Self {
        Self {
            n,
            t: Vec::with_capacity(samples),
            q: Vec::with_capacity(samples * n),
            qdot: Vec::with_capacity(samples * n),
            energy: Vec::with_capacity(samples),
            violation: Vec::new(),
            stats: Stats::default(),
        }
    }
}

/// One recorded sample.
#[derive(Clone, Copy, Debug)]
pub struct Sample<'a> {
    /// Time.
    pub t: f64,
    /// Coordinates (n).
    pub q: &'a [f64],
    /// Velocities (n).
    pub qdot: &'a [f64],
    /// The energy function `h`, when the sink asked for it ([`Sink::wants_energy`]).
    pub energy: Option<f64>,
    /// The constraint violation `[max |Φ|, max |G q̇ + ∂Φ/∂t|]` of the recorded state, for a
    /// constrained system whose sink asked for it ([`Sink::wants_violation`]).
    pub violation: Option<[f64; 2]>,
}

/// Where [`run`] writes the samples of a run.
pub trait Sink {
    /// Whether each sample needs the energy function `h` (computed only then).
    fn wants_energy(&self) -> bool {
        false
    }

    /// Whether each sample of a constrained system needs its constraint violation (computed
    /// only then; never for a system without constraints).
    fn wants_violation(&self) -> bool {
        false
    }

    /// Take one sample, at the next output time.
    fn record(&mut self, sample: Sample<'_>);

    /// The work done, at the end of a successful run.
    fn finish(&mut self, _stats: Stats) {}

    /// Asked after every accepted step, with the time reached: `false` stops the run there
    /// with [`Error::Stopped`] (a caller's deadline, a user's interrupt). The samples recorded
    /// so far stay in the sink.
    fn keep_going(&mut self, _t: f64) -> bool {
        true
    }
}

/// A trajectory records every sample, with its energy, and the run's statistics.
impl Sink for Trajectory {
    fn wants_energy(&self) -> bool {
        true
    }

    fn wants_violation(&self) -> bool {
        true
    }

    fn record(&mut self, sample: Sample<'_>) {
        self.t.push(sample.t);
        self.q.extend_from_slice(sample.q);
        self.qdot.extend_from_slice(sample.qdot);
        self.energy.push(sample.energy.unwrap_or(f64::NAN));
        if let Some(violation) = sample.violation {
            self.violation.push(violation);
        }
    }

    fn finish(&mut self, stats: Stats) {
        self.stats = stats;
    }
}

/// Safety cap on the number of steps of one run.
const MAX_STEPS: usize = 500_000_000;

/// Integrate `system` from `initial` to `t_end` with `method`, recording at `output`.
///
/// # Errors
/// [`Error::InvalidSetting`] for a bad horizon, step, tolerance or output grid;
/// [`Error::Inadmissible`] when the initial state, the state after an accepted step or a
/// recorded sample lies outside the system's admissible region
/// ([`Mechanism::admissible`](crate::Mechanism::admissible));
/// [`Error::Diverged`] (naming the quantity) when the state, a stage value or the recorded
/// energy stops being finite; [`Error::Stiff`] when the explicit adaptive method runs out of
/// step or of steps after its stiffness test fired; any error of the equations of motion or
/// of the integrator ([`Error::NewtonFailed`], [`Error::StepSizeUnderflow`], …).
///
/// [`Method::Sdirk4`] lands its steps on the output times; [`Method::Dopri5`] interpolates
/// (dense output) and records in [`Stats::stiffness`] when its stiffness test fired.
pub fn simulate<D: Dynamics>(
    system: &D,
    initial: &State,
    t_end: f64,
    method: Method,
    output: &Output,
) -> Result<Trajectory, Error> {
    let times = check_run(system, initial, t_end, output)?;
    let mut trajectory = Trajectory::with_capacity(system.dof(), times.len());
    simulate_into(system, initial, t_end, method, output, &mut trajectory)?;
    Ok(trajectory)
}

/// [`simulate`] into any [`Sink`] (a progress display wrapping a [`Trajectory`], a sink that
/// keeps only what it needs): the one place where a [`Method`] picks its integrator.
///
/// # Errors
/// As [`simulate`].
pub fn simulate_into<D: Dynamics, S: Sink + ?Sized>(
    system: &D,
    initial: &State,
    t_end: f64,
    method: Method,
    output: &Output,
    sink: &mut S,
) -> Result<Stats, Error> {
    let n = system.dof();
    match method {
        Method::Rk4 { dt } => run(system, &mut Rk4::new(n).with_step(dt)?, initial, t_end, output, sink),
        Method::Dopri5 { tol } => run(system, &mut Dopri5::new(n, tol)?, initial, t_end, output, sink),
        Method::Dop853 { tol } => run(system, &mut Dop853::new(n, tol)?, initial, t_end, output, sink),
        Method::Variational { dt } => {
            run(system, &mut Variational::new(system).with_step(dt)?, initial, t_end, output, sink)
        }
        Method::Sdirk4 { tol } => run(system, &mut Sdirk4::new(n, tol)?, initial, t_end, output, sink),
        Method::Gauss4 { dt } => run(system, &mut Gauss4::new(n).with_step(dt)?, initial, t_end, output, sink),
    }
}

/// Integrate `system` from `initial` to `t_end` with `integrator`, writing a sample at each time
/// of `output` into `sink`; returns the work done (also given to [`Sink::finish`]).
///
/// Fixed-step integrators step on the grid `t0 + k dt`: every output time but the last must lie
/// on it. The energy function `h` is evaluated only for a sink that
/// [wants it](Sink::wants_energy).
///
/// Every step is checked here, once for all integrators: the state after each accepted step
/// must be finite (each integrator's [`advance`](Integrator::advance)) and, when the system
/// declares an admissible region, inside it — as must the initial state and every recorded
/// sample (docs/method.md#admissible-regions).
///
/// # Errors
/// As [`simulate`].
pub fn run<D: Dynamics, I: Integrator<D>, S: Sink + ?Sized>(
    system: &D,
    integrator: &mut I,
    initial: &State,
    t_end: f64,
    output: &Output,
    sink: &mut S,
) -> Result<Stats, Error> {
    let n = system.dof();
    let times = check_run(system, initial, t_end, output)?;
    let t0 = initial.t;
    let mut ws = system.workspace();
    // Asked once: a system without a region is never checked again.
    let region = non_finite_quantity(&[], &initial.q, &initial.qdot).is_none()
        && Bounds::check(system, t0, &initial.q, &initial.qdot)?;
    let constrained = Dynamics::constraint_counts(system) != (0, 0);
    if constrained {
        check_consistent(system, &mut ws, initial)?;
    }
    integrator.begin(system, &mut ws, initial, t_end)?;
    // A method that keeps the constraints itself is not projected: its state is its own.
    let project = constrained && !integrator.keeps_constraints();
    if let Some(dt) = integrator.fixed_step() {
        check_on_grid(t0, dt, &times)?;
    }
    let (mut q, mut qdot) = (vec![0.0; n], vec![0.0; n]);
    let mut steps = 0;
    // The last time the state was found inside: the crossing of a boundary is bracketed.
    let mut inside = t0;
    let mut check = |t: f64, q: &[f64], qdot: &[f64]| match Bounds::check(system, t, q, qdot) {
        Err(Error::Inadmissible { t, quantity, bound, value, limit, .. }) => {
            Err(Error::Inadmissible { t, inside_until: Some(inside), quantity, bound, value, limit })
        }
        result => {
            // A sample read back inside the last step is earlier than that step's end.
            inside = inside.max(t);
            result.map(drop)
        }
    };
    for (index, &t_out) in times.iter().enumerate() {
        while !integrator.reached(t_out) {
            if steps >= MAX_STEPS {
                let t = integrator.t();
                return Err(match integrator.stats().stiffness {
                    Some(_) => Error::Stiff { t, h: integrator.proposed_step() },
                    None => Error::TooManySteps { steps, t, t_end },
                });
            }
            integrator.advance(system, &mut ws, t_out, t_end)?;
            steps += 1;
            if project {
                integrator.project(system, &mut ws)?;
            }
            if region {
                let (q, qdot) = integrator.current();
                check(integrator.t(), q, qdot)?;
            }
            if !sink.keep_going(integrator.t()) {
                return Err(Error::Stopped { t: integrator.t(), steps });
            }
        }
        integrator.read(system, &mut ws, t_out, &mut q, &mut qdot)?;
        if project && steps > 0 {
            // A dense-output sample inside the last step is not on the constraints by itself.
            // A sample before the first step is the initial state, checked consistent above and
            // recorded as the user gave it.
            system.project(&mut ws, t_out, &mut q, &mut qdot)?;
        }
        if region {
            check(t_out, &q, &qdot)?;
        }
        let energy =
            if sink.wants_energy() { Some(energy(system, &mut ws, t_out, &q, &qdot, index, steps)?) } else { None };
        let violation = if constrained && sink.wants_violation() {
            system.constraint_violation(&mut ws, t_out, &q, &qdot)?
        } else {
            None
        };
        sink.record(Sample { t: t_out, q: &q, qdot: &qdot, energy, violation });
    }
    let stats = integrator.stats();
    sink.finish(stats);
    Ok(stats)
}

/// A fixed-step run's output times: every one but the last on the grid `t0 + k dt`, none more
/// than [`MAX_STEPS`] steps away.
fn check_on_grid(t0: f64, dt: f64, times: &[f64]) -> Result<(), Error> {
    for (index, &t_out) in times.iter().enumerate() {
        let (whole, on_grid) = Grid::position(t0, dt, t_out);
        if !on_grid && index + 1 != times.len() {
            return Err(Error::InvalidSetting {
                what: "output time",
                value: t_out,
                why: "fixed-step output times must lie on the step grid t0 + k dt",
            });
        }
        if whole > MAX_STEPS {
            return Err(Error::TooManySteps { steps: MAX_STEPS, t: t0, t_end: t_out });
        }
    }
    Ok(())
}

/// An initial state must satisfy the constraints to `CONSISTENT_START` relative to its size:
/// the integrators keep a run on them, but do not choose the user's starting point.
const CONSISTENT_START: f64 = 1e-10;

fn check_consistent<D: Dynamics>(system: &D, ws: &mut D::Workspace, initial: &State) -> Result<(), Error> {
    let Some([position, velocity]) = system.constraint_violation(ws, initial.t, &initial.q, &initial.qdot)? else {
        return Ok(());
    };
    let largest = |v: &[f64]| 1.0 + v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let (q_scale, v_scale) = (largest(&initial.q), largest(&initial.qdot));
    if position > CONSISTENT_START * q_scale {
        return Err(Error::InvalidSetting {
            what: "initial constraint residual max |Φ|",
            value: position,
            why: "the initial positions do not satisfy the constraints; make them consistent with lagrange::assemble",
        });
    }
    if velocity > CONSISTENT_START * v_scale.max(q_scale) {
        return Err(Error::InvalidSetting {
            what: "initial velocity-constraint residual",
            value: velocity,
            why: "the initial velocities do not satisfy the constraints; make them consistent with lagrange::assemble",
        });
    }
    Ok(())
}

/// The energy function at a sample; after the first sample a finite state whose energy
/// overflows (a run growing past ~1e150) has diverged.
fn energy<D: Dynamics>(
    system: &D,
    ws: &mut D::Workspace,
    t: f64,
    q: &[f64],
    qdot: &[f64],
    sample: usize,
    step: usize,
) -> Result<f64, Error> {
    system.energy_function(ws, t, q, qdot).map_err(|error| match error {
        Error::NonFinite { stage, .. } if sample > 0 => {
            let largest = q.iter().chain(qdot).fold(0.0_f64, |m, v| m.max(v.abs()));
            Error::Diverged {
                t,
                step,
                quantity: format!("energy = non-finite ({stage}), the state reaching |q|, |q̇| = {largest:e}"),
            }
        }
        other => other,
    })
}

/// Check the initial state's size and the horizon; the output times.
fn check_run<D: Dynamics>(system: &D, initial: &State, t_end: f64, output: &Output) -> Result<Vec<f64>, Error> {
    let n = system.dof();
    if initial.q.len() != n || initial.qdot.len() != n {
        return Err(Error::DimensionMismatch {
            what: "initial state",
            expected: n,
            got: initial.q.len().min(initial.qdot.len()),
        });
    }
    if !(t_end.is_finite() && t_end >= initial.t) {
        return Err(Error::InvalidSetting {
            what: "horizon",
            value: t_end,
            why: "must be finite and not before the start",
        });
    }
    output_times(initial.t, t_end, output)
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
            // The first time that is out of order or outside [t0, t_end] is the one reported.
            let outside = |t: f64| !(t >= t0 && t <= t_end);
            let first_bad =
                times.iter().enumerate().find(|&(i, &t)| outside(t) || (i > 0 && t <= times[i - 1])).map(|(_, &t)| t);
            if let Some(value) = first_bad {
                return Err(Error::InvalidSetting {
                    what: "output time",
                    value,
                    why: "output times must be increasing and within [t0, t_end]",
                });
            }
            Ok(times.clone())
        }
    }
}
