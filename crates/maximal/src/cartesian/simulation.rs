//! A running Cartesian simulation: Dormand–Prince 5(4) on `(z, ż)`, stepping exactly to each
//! requested time, with a projection onto `Φ = 0`, `Φ̇ = 0` after every accepted step.
//!
//! The system runs in a frame at the bodies' initial centroid ([`CartesianSystem::centred`]):
//! positions are of the mechanism's size whatever the world's origin, in the equations, in the
//! projection's round-off and in the integrator's error weights `atol + rtol |z_i|`, so that
//! moving a mechanism (bodies and ground points) does not change its motion. [`bodies`] adds the
//! frame back; the `q` of an error during the run is in the frame.
//!
//! [`bodies`]: MaximalSimulation::bodies

use super::system::{CartesianSystem, CartesianWorkspace};
use crate::{BodyState, Engine, MaximalSimulation};
use lagrange::Error;
use lagrange::integrate::{Dopri5, Tolerances};

/// The initial body states must satisfy `max|Φ| ≤ INITIAL_VIOLATION` (m or rad): the reduced
/// model's poses satisfy the constraints identically, so only round-off (~1e-15 for the scenes'
/// O(10 m) lengths) may remain; more means a constraint is written wrong.
const INITIAL_VIOLATION: f64 = 1e-12;

/// Safety cap on the number of accepted steps of one simulation (as the reduced driver's).
const MAX_STEPS: usize = 500_000_000;

/// A scene in Cartesian coordinates with multipliers, at time `t`.
pub(crate) struct CartesianSimulation {
    /// The system.
    pub(crate) system: CartesianSystem,
    /// Its buffers.
    pub(crate) ws: CartesianWorkspace,
    /// The integrator, started at the first [`advance_to`](MaximalSimulation::advance_to).
    integrator: Dopri5,
    /// Whether the integrator has been started.
    started: bool,
    /// Current time.
    t: f64,
    /// Current poses (3B), positions relative to the system's frame
    /// ([`CartesianSystem::frame`]: the bodies' initial centroid).
    pub(crate) z: Vec<f64>,
    /// Current velocities (3B).
    pub(crate) zdot: Vec<f64>,
    /// Accepted steps so far.
    steps: usize,
}

impl CartesianSimulation {
    /// Start `system` at time `t0` from the body states `initial`, integrating at `tolerance`
    /// (relative and absolute).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for the wrong number of bodies; [`Error::NonFinite`] for a
    /// non-finite start; [`Error::Inconsistent`] when the initial states violate a constraint
    /// (position or velocity) beyond round-off; [`Error::SingularMassMatrix`] when the KKT
    /// matrix is singular there; [`Error::InvalidSetting`] for a bad tolerance.
    pub(crate) fn new(system: CartesianSystem, initial: &[BodyState], t0: f64, tolerance: f64) -> Result<Self, Error> {
        let n = system.n();
        if 3 * initial.len() != n {
            return Err(Error::DimensionMismatch { what: "body states", expected: n / 3, got: initial.len() });
        }
        let world: Vec<f64> = initial.iter().flat_map(|b| b.pose).collect();
        let zdot: Vec<f64> = initial.iter().flat_map(|b| b.velocity).collect();
        if !(t0.is_finite() && world.iter().chain(&zdot).all(|v| v.is_finite())) {
            return Err(Error::NonFinite { stage: lagrange::error::Stage::State, t: t0, q: world });
        }
        // The system in a frame at the bodies' initial centroid (CartesianSystem::centred).
        let bodies = initial.len().max(1) as f64;
        let centroid = [0, 1].map(|c| initial.iter().map(|b| b.pose[c]).sum::<f64>() / bodies);
        let system = system.centred(centroid)?;
        let frame = system.frame();
        let z: Vec<f64> =
            initial.iter().flat_map(|b| [b.pose[0] - frame[0], b.pose[1] - frame[1], b.pose[2]]).collect();
        let integrator = Dopri5::new(n, Tolerances::uniform(tolerance))?;
        let mut ws = system.workspace();
        // The reduced model's body states must satisfy Φ = 0 and Φ̇ = 0.
        system.constraint_values(t0, &z, &mut ws.phi);
        system.constraint_rate(&mut ws, t0, &z, &zdot);
        let speed = zdot.iter().fold(1.0_f64, |s, v| s.max(v.abs()));
        for i in 0..system.m() {
            // Velocity constraints (after the holonomic rows) have no position residual.
            let (position, velocity) = (ws.phi.get(i).copied().unwrap_or(0.0), ws.rate[i]);
            if !(position.abs() <= INITIAL_VIOLATION && velocity.abs() <= INITIAL_VIOLATION * speed) {
                return Err(Error::Inconsistent {
                    what: format!(
                        "{}: the initial body states violate the Cartesian constraint `{}` (Φ = {position:e}, \
                         Φ̇ = {velocity:e})",
                        system.scene,
                        system.equation_name(i)
                    ),
                });
            }
        }
        system.check_well_posed(&mut ws, t0, &z)?;
        Ok(Self { system, ws, integrator, started: false, t: t0, z, zdot, steps: 0 })
    }

    /// `z̈` and `λ` at the current state (into the workspace).
    ///
    /// # Errors
    /// As [`CartesianSystem::evaluate`].
    pub(crate) fn evaluate(&mut self) -> Result<(), Error> {
        self.system.evaluate(&mut self.ws, self.t, &self.z, &self.zdot)
    }
}

impl MaximalSimulation for CartesianSimulation {
    fn engine(&self) -> Engine {
        Engine::Cartesian
    }

    fn t(&self) -> f64 {
        self.t
    }

    /// Integrate to exactly `t`: accepted steps never pass `t` and the last one ends on it;
    /// after each, project onto `Φ = 0` and `Φ̇ = 0` and restart the integrator there. The
    /// first call starts the integrator with at most the whole interval as its first step
    /// (as the reduced driver does for its horizon).
    fn advance_to(&mut self, t: f64) -> Result<(), Error> {
        if !(t.is_finite() && t >= self.t) {
            return Err(Error::InvalidSetting {
                what: "time",
                value: t,
                why: "must be finite and not before the current time",
            });
        }
        // A target within a few ulps of the current time (a sum of read intervals that rounds
        // to 0.09999999999999999 before a read at 0.1) is reached: no step can be that short,
        // and the state moves by far less than its own round-off over it.
        if t - self.t <= 4.0 * f64::EPSILON * t.abs().max(1.0) {
            self.t = t;
            return Ok(());
        }
        let (system, ws) = (&self.system, &mut self.ws);
        if !self.started {
            self.integrator.start(system, ws, self.t, &self.z, &self.zdot, t - self.t)?;
            self.started = true;
        }
        while self.integrator.t() < t {
            if self.steps >= MAX_STEPS {
                return Err(Error::TooManySteps { steps: self.steps, t: self.integrator.t(), t_end: t });
            }
            self.integrator.step(system, ws, t)?;
            self.steps += 1;
            let now = self.integrator.t();
            self.z.copy_from_slice(self.integrator.q());
            self.zdot.copy_from_slice(self.integrator.qdot());
            if !self.z.iter().chain(&self.zdot).all(|v| v.is_finite()) {
                return Err(Error::Diverged { t: now, step: self.steps, quantity: "body state".into() });
            }
            // Back onto the constraint manifold, and continue from there.
            system.project(ws, now, &mut self.z, &mut self.zdot).map_err(|error| match error {
                Error::Diverged { t, quantity, .. } => Error::Diverged { t, step: self.steps, quantity },
                other => other,
            })?;
            self.integrator.restart(system, ws, &self.z, &self.zdot)?;
            self.t = now;
        }
        self.t = t;
        Ok(())
    }

    fn bodies(&self) -> Vec<BodyState> {
        let frame = self.system.frame();
        self.z
            .chunks_exact(3)
            .zip(self.zdot.chunks_exact(3))
            .map(|(pose, velocity)| BodyState {
                pose: [pose[0] + frame[0], pose[1] + frame[1], pose[2]],
                velocity: [velocity[0], velocity[1], velocity[2]],
            })
            .collect()
    }

    fn constraint_violation(&self) -> Option<f64> {
        Some(self.system.violation(self.t, &self.z))
    }

    /// `−Φ_zᵀ λ` at the current state; `None` if the equations cannot be evaluated there.
    fn constraint_forces(&mut self) -> Option<Vec<f64>> {
        self.evaluate().ok()?;
        let mut forces = vec![0.0; self.system.n()];
        self.system.constraint_forces(&self.ws, &mut forces);
        Some(forces)
    }

    fn steps(&self) -> usize {
        self.steps
    }
}
