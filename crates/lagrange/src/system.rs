//! An object-safe facade over any [`Dynamics`], for code that picks systems at run time
//! (scene registries, the command line).

use crate::integrate::{Method, Output, Sink, Stats, Trajectory, simulate, simulate_into};
use crate::{Body, Bounds, Coordinate, Dynamics, Error, State};

/// A system with its own workspace, usable as `Box<dyn System>`. All results are `f64` and
/// borrowed from internal buffers.
///
/// This is the run-time facade (scene registries, the command line pick a system by name); its
/// methods run [`Dynamics`], which runs the free functions [`accelerations`](crate::accelerations),
/// [`mass_matrix`](crate::mass_matrix), [`momenta`](crate::momenta),
/// [`energy_function`](crate::energy_function) — the spelling to use on a model whose type is
/// known (any scalar, no buffers of its own).
pub trait System {
    /// The generalized coordinates.
    fn coordinates(&self) -> &[Coordinate];

    /// The bodies (empty for a raw Lagrangian).
    fn bodies(&self) -> &[Body];

    /// `q̈` at `(t, q, q̇)`.
    ///
    /// # Errors
    /// As [`Dynamics::accelerations`].
    fn accelerations(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<&[f64], Error>;

    /// The acceleration Jacobian `∂q̈/∂(q, q̇)` (n × 2n, row-major, columns `q` then `q̇`).
    ///
    /// # Errors
    /// As [`Dynamics::acceleration_jacobian`].
    fn acceleration_jacobian(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<&[f64], Error>;

    /// The energy function `h`.
    ///
    /// # Errors
    /// On a malformed state.
    fn energy_function(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<f64, Error>;

    /// The mass matrix `M = ∂²L/∂q̇²` (n × n, row-major).
    ///
    /// # Errors
    /// On a malformed state.
    fn mass_matrix(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<&[f64], Error>;

    /// Generalized momenta `p = ∂L/∂q̇`.
    ///
    /// # Errors
    /// On a malformed state.
    fn momenta(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<&[f64], Error>;

    /// Constraint forces `(F_x, F_y, τ)` per body (3B), or `None` without bodies.
    ///
    /// # Errors
    /// As [`reaction_forces`](crate::reaction_forces).
    fn reaction_forces(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<Option<&[f64]>, Error>;

    /// The numbers of holonomic and velocity constraints among the coordinates `(m, k)`;
    /// `(0, 0)` for independent coordinates.
    fn constraint_counts(&self) -> (usize, usize);

    /// The constraint violation `[max |Φ|, max |G q̇ + Φ_t, A q̇ + b|]` at `(t, q, q̇)`, `None`
    /// without constraints.
    ///
    /// # Errors
    /// On a malformed or non-finite state.
    fn constraint_violation(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<Option<[f64; 2]>, Error>;

    /// The constraint multipliers `λ` (`m + k`, with `M q̈ + Gᵀ λ = f`), or `None` without
    /// constraints; see [`constraint_multipliers`](crate::constraint_multipliers).
    ///
    /// # Errors
    /// As [`accelerations`](Self::accelerations).
    fn constraint_multipliers(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<Option<&[f64]>, Error>;

    /// How far the equations determine the constraint multipliers at `(t, q, q̇)`, or `None`
    /// without constraints (the default); see [`multiplier_rank`](crate::multiplier_rank).
    ///
    /// # Errors
    /// As [`accelerations`](Self::accelerations).
    fn multiplier_rank(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<Option<crate::MultiplierRank>, Error> {
        let _ = (t, q, qdot);
        Ok(None)
    }

    /// The constraint Jacobian `G = [Φ_q; A]` (`(m + k) × n`, row-major) at `(t, q, q̇)`, or
    /// `None` without constraints (the default); see [`Dynamics::constraint_rows`].
    ///
    /// # Errors
    /// On a malformed or non-finite state or non-finite constraint rows.
    fn constraint_jacobian(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<Option<&[f64]>, Error> {
        let _ = (t, q, qdot);
        Ok(None)
    }

    /// A state on the constraints near `approximate`, the coordinates marked in `held` (and
    /// their rates) kept; see [`assemble`](crate::assemble). The state itself without
    /// constraints.
    ///
    /// # Errors
    /// As [`assemble`](crate::assemble).
    fn assemble(&self, approximate: &State, held: &[bool]) -> Result<State, Error>;

    /// Which coordinates are cyclic.
    fn cyclic_coordinates(&self) -> &[bool];

    /// Whether `h` is a constant of the motion.
    fn conserves_energy(&self) -> bool;

    /// Whether forces act beyond gravity, the potential and the constraints — generalized
    /// forces `Q` or forces applied at points of bodies ([`Dynamics::has_external_forces`]);
    /// [`reaction_forces`](Self::reaction_forces) then includes what cannot be attributed to
    /// one body.
    fn has_external_forces(&self) -> bool;

    /// Integrate from `initial` to `t_end`; see [`simulate`](crate::simulate).
    ///
    /// # Errors
    /// As [`simulate`](crate::simulate).
    fn simulate(&self, initial: &State, t_end: f64, method: Method, output: &Output) -> Result<Trajectory, Error>;

    /// Check `(t, q, q̇)` against the system's admissible region
    /// ([`Mechanism::admissible`](crate::Mechanism::admissible)): `Ok(false)` when it declares
    /// none, `Ok(true)` inside ([`Bounds::check`]).
    ///
    /// # Errors
    /// [`Error::Inadmissible`] naming the first bound that fails.
    fn check_admissible(&self, t: f64, q: &[f64], qdot: &[f64]) -> Result<bool, Error>;

    /// Integrate from `initial` to `t_end` into any `sink`; see
    /// [`simulate_into`](crate::integrate::simulate_into).
    ///
    /// # Errors
    /// As [`simulate`](crate::simulate).
    fn simulate_into(
        &self,
        initial: &State,
        t_end: f64,
        method: Method,
        output: &Output,
        sink: &mut dyn Sink,
    ) -> Result<Stats, Error>;
}

/// A [`Dynamics`] together with its workspace and result buffers: the [`System`] of any body
/// model or raw model (`Box::new(Buffered::new(Model::new(mechanism)?))`).
pub struct Buffered<D: Dynamics> {
    system: D,
    ws: D::Workspace,
    /// `q̈` or `p` (n).
    out: Vec<f64>,
    /// `M` (n × n).
    mass: Vec<f64>,
    /// Reaction forces (3B).
    reaction: Vec<f64>,
    /// Constraint multipliers (m + k).
    multipliers: Vec<f64>,
    /// Acceleration Jacobian (n × 2n).
    jacobian: Vec<f64>,
    /// Constraint Jacobian ((m + k) × n), holonomic residuals (m) and velocity residuals
    /// (m + k).
    rows: (Vec<f64>, Vec<f64>, Vec<f64>),
}

impl<D: Dynamics> Buffered<D> {
    /// Wrap a system, allocating its workspace.
    pub fn new(system: D) -> Self {
        let ws = system.workspace();
        let out = vec![0.0; system.dof()];
        let mass = vec![0.0; system.dof() * system.dof()];
        let reaction = vec![0.0; 3 * system.bodies().len()];
        let jacobian = vec![0.0; 2 * system.dof() * system.dof()];
        let (m, k) = Dynamics::constraint_counts(&system);
        let multipliers = vec![0.0; m + k];
        let rows = (vec![0.0; (m + k) * system.dof()], vec![0.0; m], vec![0.0; m + k]);
        Self { system, ws, out, mass, reaction, multipliers, jacobian, rows }
    }

    /// The wrapped system.
    pub fn system(&self) -> &D {
        &self.system
    }
}

impl<D: Dynamics> System for Buffered<D> {
    fn coordinates(&self) -> &[Coordinate] {
        self.system.coordinates()
    }

    fn bodies(&self) -> &[Body] {
        self.system.bodies()
    }

    fn accelerations(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<&[f64], Error> {
        self.system.accelerations(&mut self.ws, t, q, qdot, &mut self.out)?;
        Ok(&self.out)
    }

    fn acceleration_jacobian(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<&[f64], Error> {
        self.system.acceleration_jacobian(&mut self.ws, t, q, qdot, &mut self.jacobian)?;
        Ok(&self.jacobian)
    }

    fn energy_function(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<f64, Error> {
        self.system.energy_function(&mut self.ws, t, q, qdot)
    }

    fn mass_matrix(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<&[f64], Error> {
        self.system.mass_matrix(&mut self.ws, t, q, qdot, &mut self.mass)?;
        Ok(&self.mass)
    }

    fn momenta(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<&[f64], Error> {
        self.system.momenta(&mut self.ws, t, q, qdot, &mut self.out)?;
        Ok(&self.out)
    }

    fn reaction_forces(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<Option<&[f64]>, Error> {
        if self.system.reaction_forces(&mut self.ws, t, q, qdot, &mut self.reaction)? {
            Ok(Some(&self.reaction))
        } else {
            Ok(None)
        }
    }

    fn constraint_counts(&self) -> (usize, usize) {
        Dynamics::constraint_counts(&self.system)
    }

    fn constraint_violation(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<Option<[f64; 2]>, Error> {
        self.system.constraint_violation(&mut self.ws, t, q, qdot)
    }

    fn constraint_multipliers(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<Option<&[f64]>, Error> {
        if self.system.constraint_multipliers(&mut self.ws, t, q, qdot, &mut self.multipliers)? {
            Ok(Some(&self.multipliers))
        } else {
            Ok(None)
        }
    }

    fn multiplier_rank(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<Option<crate::MultiplierRank>, Error> {
        self.system.multiplier_rank(&mut self.ws, t, q, qdot)
    }

    fn constraint_jacobian(&mut self, t: f64, q: &[f64], qdot: &[f64]) -> Result<Option<&[f64]>, Error> {
        let (jacobian, residual, rate) = &mut self.rows;
        if self.system.constraint_rows(&mut self.ws, (t, q, qdot), jacobian, residual, rate)? {
            Ok(Some(jacobian))
        } else {
            Ok(None)
        }
    }

    fn assemble(&self, approximate: &State, held: &[bool]) -> Result<State, Error> {
        self.system.assemble(approximate, held)
    }

    fn cyclic_coordinates(&self) -> &[bool] {
        self.system.cyclic_coordinates()
    }

    fn conserves_energy(&self) -> bool {
        self.system.conserves_energy()
    }

    fn has_external_forces(&self) -> bool {
        self.system.has_external_forces()
    }

    fn simulate(&self, initial: &State, t_end: f64, method: Method, output: &Output) -> Result<Trajectory, Error> {
        simulate(&self.system, initial, t_end, method, output)
    }

    fn check_admissible(&self, t: f64, q: &[f64], qdot: &[f64]) -> Result<bool, Error> {
        Bounds::check(&self.system, t, q, qdot)
    }

    fn simulate_into(
        &self,
        initial: &State,
        t_end: f64,
        method: Method,
        output: &Output,
        sink: &mut dyn Sink,
    ) -> Result<Stats, Error> {
        simulate_into(&self.system, initial, t_end, method, output, sink)
    }
}
