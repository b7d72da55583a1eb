//! One run of one method at one setting: its error against the reference at every saved time,
//! its energy error and constraint violation where they mean something, and its wall time.
//!
//! A maximal engine is measured by ONE loop, [`track`] (advance → read back → error, energy,
//! violation, time, and whatever else the caller reads at each sample), used by the report's
//! [`maximal`] and by [`crate::compare`].

use crate::Error;
use crate::plan::Timing;
use crate::reference::Reference;
use lagrange::{Method, Output, State, System};
use lagrange_maximal::{BodyState, Built, Engine, MaximalSimulation, Settings, build};
use lagrange_scenes::{Params, Scene};
use lagrange_testing::nan_max;
use std::hint::black_box;
use std::time::Instant;

/// `|E − E₀| / |E₀|`, or `|E − E₀|` (J) when `E₀ = 0` exactly: a mechanism whose energy is zero
/// at its start (a disc released at rest at the zero of its potential) has no scale of its own
/// to divide by.
pub fn energy_drift(energy: f64, initial: f64) -> f64 {
    let drift = (energy - initial).abs();
    if initial != 0.0 { drift / initial.abs() } else { drift }
}

/// `max_k` [`energy_drift`]`(E_k, E_0)` (NaN-aware).
pub fn relative_energy_error(energy: &[f64]) -> f64 {
    let e0 = energy[0];
    energy.iter().fold(0.0, |m, &e| nan_max(m, energy_drift(e, e0)))
}

/// What one run measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    /// `‖q − q_ref‖∞` at each saved time (positions in m, angles in rad).
    pub errors: Vec<f64>,
    /// `max |E − E₀| / |E₀|` over the saved times, where the scene conserves energy.
    pub energy_error: Option<f64>,
    /// Largest constraint violation over the saved times, where the engine has one.
    pub constraint_violation: Option<f64>,
    /// Steps taken (accepted steps of the adaptive integrators, rapier steps).
    pub steps: usize,
    /// Minimum wall time over the timed repetitions (s).
    pub wall_time: f64,
    /// Timed repetitions.
    pub timed_repetitions: usize,
}

impl Measured {
    /// Largest error over the saved times.
    pub fn max_error(&self) -> f64 {
        self.errors.iter().copied().fold(0.0, nan_max)
    }

    /// Error at the last saved time.
    pub fn final_error(&self) -> f64 {
        self.errors.last().copied().unwrap_or(0.0)
    }

    /// Whether every error is finite (a run that blew up has NaN or infinite errors).
    pub fn is_finite(&self) -> bool {
        self.errors.iter().all(|e| e.is_finite()) && self.energy_error.is_none_or(f64::is_finite)
    }
}

/// Time a run whose measured (first) run took `measured` seconds in its timed part: when that
/// is at least `timing.measured_is_timed_above` it is the first timed repetition; otherwise run
/// `once` (which returns the wall time of its timed part) `timing.warmup − 1` more times
/// untimed. Then repeat `once` up to `timing.repetitions` timed runs in all, stopping once they
/// add up to `timing.budget` (at least one); the minimum and the number of timed runs.
fn time(timing: &Timing, measured: f64, mut once: impl FnMut() -> Result<f64, Error>) -> Result<(f64, usize), Error> {
    let (mut best, mut total, mut count) = if measured >= timing.measured_is_timed_above {
        (measured, measured, 1)
    } else {
        for _ in 1..timing.warmup {
            once()?;
        }
        (f64::INFINITY, 0.0, 0)
    };
    while count < timing.repetitions.max(1) && !(count > 0 && total >= timing.budget) {
        let seconds = once()?;
        best = best.min(seconds);
        total += seconds;
        count += 1;
        if total >= timing.budget {
            break;
        }
    }
    Ok((best, count))
}

/// A reduced-solver run: `simulate` from `initial` recording at `times`; the first run is the
/// warm-up and is measured, the timed ones are whole `simulate` calls.
///
/// # Errors
/// A failing run, as a sentence.
pub fn reduced(
    system: &dyn System,
    initial: &State,
    times: &[f64],
    method: Method,
    reference: &Reference,
    timing: &Timing,
) -> Result<Measured, Error> {
    let t_end = times.last().copied().unwrap_or(initial.t);
    let output = Output::Times(times.to_vec());
    let start = Instant::now();
    let trajectory = system.simulate(initial, t_end, method, &output)?;
    let measured = start.elapsed().as_secs_f64();
    let errors = (0..trajectory.len()).map(|k| reference.error(k, trajectory.q(k))).collect();
    let energy_error = system.conserves_energy().then(|| relative_energy_error(&trajectory.energy));
    let (wall_time, timed_repetitions) = time(timing, measured, || {
        let start = Instant::now();
        let trajectory = system.simulate(black_box(initial), t_end, method, &output)?;
        let seconds = start.elapsed().as_secs_f64();
        black_box(trajectory);
        Ok(seconds)
    })?;
    // The largest violation of any recorded sample, positions and velocities together.
    let constraint_violation =
        (!trajectory.violation.is_empty()).then(|| trajectory.violation.iter().flatten().copied().fold(0.0, nan_max));
    Ok(Measured {
        errors,
        energy_error,
        constraint_violation,
        steps: trajectory.stats.steps,
        wall_time,
        timed_repetitions,
    })
}

/// Advance `simulation` through `times`, timing only the `advance_to` calls.
fn advance(simulation: &mut dyn MaximalSimulation, times: &[f64]) -> Result<f64, Error> {
    let start = Instant::now();
    for &t in times {
        simulation.advance_to(t)?;
    }
    Ok(start.elapsed().as_secs_f64())
}

/// The problem a maximal engine runs: a scene with its parameters, the initial state and the
/// saved times at which it is measured.
#[derive(Clone, Copy)]
pub struct Problem<'a> {
    /// The scene.
    pub scene: &'a dyn Scene,
    /// Its parameters, as the user asked for them.
    pub params: &'a Params,
    /// The initial state of the reduced model.
    pub initial: &'a State,
    /// The saved times.
    pub times: &'a [f64],
}

/// A maximal-engine run of `problem` (with the parameters the user asked for): `built`
/// (already built with `settings`, so that its deviations could choose the reference; it may
/// carry other parameters) is advanced through the saved times and read back into generalized
/// coordinates at each; the timed repetitions rebuild it (untimed) and time the `advance_to`
/// calls alone.
///
/// # Errors
/// A failing run, as a sentence.
pub fn maximal(
    problem: &Problem<'_>,
    engine: Engine,
    settings: &Settings,
    built: Built,
    reference: &Reference,
    timing: &Timing,
) -> Result<Measured, Error> {
    let mut built = built;
    // The reduced model of what the engine simulates (with its deviations), for the admissible
    // region and the first read's acceleration.
    let mut reduced = problem.scene.build(&built.params).map_err(|e| Error::scene(problem.scene.id(), e))?;
    let error = |k: usize, q: &[f64]| reference.error(k, q);
    let pass = track(&mut built, reduced.as_mut(), problem.initial, problem.times, error, |_| Ok(()))?;
    let (errors, energy_error, violation) = (pass.errors, pass.energy_error, pass.constraint_violation);
    let steps = pass.steps;
    let (wall_time, timed_repetitions) = time(timing, pass.advance_time, || {
        let mut built = build(engine, problem.scene, problem.params, problem.initial, settings)?;
        advance(built.simulation.as_mut(), problem.times)
    })?;
    Ok(Measured { errors, energy_error, constraint_violation: violation, steps, wall_time, timed_repetitions })
}

/// What one pass of a maximal engine through the sample times measured ([`track`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Pass {
    /// The error at each sample time, as the caller's `error` computed it.
    pub errors: Vec<f64>,
    /// `max |E − E₀| / |E₀|` (or `|E − E₀|` when `E₀ = 0`) of the engine's bodies over the
    /// samples, where the scene conserves energy (NaN-aware).
    pub energy_error: Option<f64>,
    /// Largest constraint violation over the samples, where the engine measures one (NaN-aware).
    pub constraint_violation: Option<f64>,
    /// Steps the engine took.
    pub steps: usize,
    /// Wall time of the `advance_to` calls alone (s).
    pub advance_time: f64,
}

/// The largest turn (rad) of any angle between two read-backs of a [`track`] pass: the branch
/// of an angle read back from a rotation is the one nearest the prediction from the previous
/// read, so the prediction must be off by less than π; with a turn of at most half a radian
/// predicted to second order, it is off by a small part of that.
const READ_TURN: f64 = 0.5;

/// A read-back of a [`track`] pass: the coordinates, rates and (estimated) accelerations.
struct Read {
    t: f64,
    q: Vec<f64>,
    qdot: Vec<f64>,
    qddot: Vec<f64>,
}

impl Read {
    /// The next time to read at on the way to the saved time `t`: `t` itself, or earlier where
    /// some angle would turn by more than [`READ_TURN`] (`|q̇| h + ½ |q̈| h² ≤ READ_TURN`), but
    /// not less than `shortest` later (an engine that turns faster than that between reads
    /// is far from any motion it should be compared with).
    fn next_read(&self, t: f64, angles: &[bool], shortest: f64) -> f64 {
        let mut h = t - self.t;
        for (i, _) in angles.iter().enumerate().filter(|(_, a)| **a) {
            let (v, a) = (self.qdot[i].abs(), self.qddot[i].abs());
            let turn = v * h + 0.5 * a * h * h;
            if turn > READ_TURN {
                // The positive root of ½ a h² + v h = READ_TURN.
                let root =
                    if a > 0.0 { 2.0 * READ_TURN / (v + (v * v + 2.0 * a * READ_TURN).sqrt()) } else { READ_TURN / v };
                h = h.min(root);
            }
        }
        let h = h.max(shortest);
        if h.is_finite() && self.t + h < t { self.t + h } else { t }
    }

    /// The coordinates carried forward to time `t` by the rates and accelerations.
    fn predicted(&self, t: f64) -> Vec<f64> {
        let h = t - self.t;
        self.q.iter().zip(&self.qdot).zip(&self.qddot).map(|((q, v), a)| q + v * h + 0.5 * a * h * h).collect()
    }
}

/// One sample of a [`track`] pass, for the caller's own readings.
pub struct Sample<'a> {
    /// Its time.
    pub t: f64,
    /// The generalized coordinates read back from the bodies.
    pub q: &'a [f64],
    /// The generalized velocities read back from the bodies.
    pub qdot: &'a [f64],
    /// The engine's bodies.
    pub bodies: &'a [BodyState],
    /// The engine, for its constraint forces.
    pub simulation: &'a mut dyn MaximalSimulation,
    /// The reduced model the pass checks against, for its momenta and reactions.
    pub reduced: &'a mut dyn System,
}

/// The measurement loop of a maximal engine: advance `built` from `initial` to each of the saved
/// `times`, read its bodies back into generalized coordinates (with the read-back it carries),
/// check them against the admissible region of `reduced` — the scene's reduced model with the
/// parameters `built` simulates — as the reduced integrators do after every step
/// (docs/method.md#admissible-regions), and measure the error `error(k, q)` against the
/// caller's reference, the energy error (when `reduced` conserves energy), the constraint
/// violation, and the time of the advances; `each` reads what else the caller needs at every
/// sample.
///
/// # Errors
/// A failing advance, read-back or energy, a read-back state outside the admissible region
/// ([`lagrange::Error::Inadmissible`]), or an error of `each`.
pub fn track(
    built: &mut Built,
    reduced: &mut dyn System,
    initial: &State,
    times: &[f64],
    error: impl Fn(usize, &[f64]) -> f64,
    mut each: impl FnMut(Sample<'_>) -> Result<(), Error>,
) -> Result<Pass, Error> {
    let Built { simulation, read_back, .. } = built;
    let simulation = simulation.as_mut();
    let conserves_energy = reduced.conserves_energy();
    let initial_energy = read_back.energy(initial.t, &simulation.bodies());
    let angles: Vec<bool> = reduced.coordinates().iter().map(|c| c.kind == lagrange::CoordinateKind::Angle).collect();
    // Angles are read back on the branch nearest the previous read carried forward by its rate
    // and acceleration, and read often enough between the saved times that none turns by more
    // than READ_TURN between reads (a four-bar's crank turns 10 rad between samples 0.5 s
    // apart while its rate varies fourfold; a rolling disc turns by more than π). The first
    // acceleration is the reduced model's at the initial state.
    let mut last = Read {
        t: initial.t,
        q: initial.q.clone(),
        qdot: initial.qdot.clone(),
        qddot: reduced
            .accelerations(initial.t, &initial.q, &initial.qdot)
            .map_or_else(|_| vec![0.0; initial.q.len()], <[f64]>::to_vec),
    };
    let (mut errors, mut energy_error, mut violation) = (Vec::with_capacity(times.len()), 0.0, None::<f64>);
    let mut advance_time = 0.0;
    for (k, &t) in times.iter().enumerate() {
        // At most 1024 reads between two saved times.
        let shortest = (t - last.t) / 1024.0;
        let (bodies, q, qdot) = loop {
            let target = last.next_read(t, &angles, shortest);
            let start = Instant::now();
            simulation.advance_to(target)?;
            advance_time += start.elapsed().as_secs_f64();
            let bodies = simulation.bodies();
            let (q, qdot) = read_back.generalized(target, &bodies, &last.predicted(target));
            let span = target - last.t;
            let qddot = if span > 0.0 {
                qdot.iter().zip(&last.qdot).map(|(v, w)| (v - w) / span).collect()
            } else {
                last.qddot.clone()
            };
            if target == t {
                last = Read { t, q: q.clone(), qdot: qdot.clone(), qddot };
                break (bodies, q, qdot);
            }
            last = Read { t: target, q, qdot, qddot };
        };
        match reduced.check_admissible(t, &q, &qdot) {
            Err(lagrange::Error::Inadmissible { t, quantity, bound, value, limit, .. }) => {
                let inside_until = k.checked_sub(1).map(|previous| times[previous]);
                return Err(lagrange::Error::Inadmissible { t, inside_until, quantity, bound, value, limit }.into());
            }
            result => result?,
        };
        errors.push(error(k, &q));
        if conserves_energy {
            let energy = read_back.energy(t, &bodies);
            energy_error = nan_max(energy_error, energy_drift(energy, initial_energy));
        }
        if let Some(v) = simulation.constraint_violation() {
            violation = Some(nan_max(violation.unwrap_or(0.0), v));
        }
        each(Sample { t, q: &q, qdot: &qdot, bodies: &bodies, simulation, reduced: &mut *reduced })?;
    }
    Ok(Pass {
        errors,
        energy_error: conserves_energy.then_some(energy_error),
        constraint_violation: violation,
        steps: simulation.steps(),
        advance_time,
    })
}
