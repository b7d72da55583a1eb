//! Cartesian coordinates with holonomic constraints and Lagrange multipliers — the lecture's
//! starting point, as an independent check of the reduced solver.
//!
//! The state is every body's full pose `z = (x_b, y_b, φ_b)` (3B coordinates, bodies in the
//! reduced model's order) and its velocity `ż`. Each scene's joints, ropes, rails and inclines
//! are written by hand as holonomic constraints `Φ(z, t) = 0` (m equations; each
//! scene's file in `src/scenes/`, from the building blocks of `constraints.rs`), generic over the
//! scalar, and the equations of motion are
//!
//! ```text
//! M z̈ + Φ_zᵀ λ = F,        Φ_z z̈ = −γ_Φ,        γ_Φ = d²/ds² Φ(z + s ż, t + s) = (Φ_z ż)_z ż + 2 Φ_zt ż + Φ_tt,
//! ```
//!
//! with `M = diag(m_b, m_b, I_b)` (zero entries allowed: massless pulleys and the orientation
//! of point masses are fixed by constraints), `F` = gravity `(0, −m_b g, 0)` + the scene
//! potential's forces `−∂V/∂p_b` ([`ReadBack::potential`](crate::maps::ReadBack::potential)) + the scene's
//! non-conservative forces in Cartesian form (the oscillator's damping `−c ẋ`, the charged
//! particle's Lorentz force `e B (ẏ, −ẋ)`). `Φ_z` comes from first-order dual passes over the
//! coordinates of the bodies each constraint touches, `γ_Φ` from one second-order dual pass
//! along `(ż, 1)`. Velocity constraints `A(z) ż = 0` (the sleigh's knife edge, the disc's rolling
//! contact) join `Φ_z` as further rows, with the convective term `(∂(A ż)/∂z) ż` from one
//! first-order dual pass. Nothing of the reduced solver's equations of motion is used: the
//! reduced model enters only through the initial body states ([`ReadBack::body_states`](crate::maps::ReadBack::body_states)), the masses
//! and inertias ([`ReadBack::bodies`](crate::maps::ReadBack::bodies)) and the scene potential.
//!
//! The KKT system `[[M, Φ_zᵀ], [Φ_z, 0]] (z̈, λ) = (F, −γ_Φ)` is solved by the Schur complement
//! on the block-diagonal mass matrix, `S λ = Φ_z M⁻¹ F + γ_Φ` with `S = Φ_z M⁻¹ Φ_zᵀ` sparse
//! (rows coupled only through a shared body), factored by faer's sparse Cholesky (ordering and
//! elimination tree once per system, the numeric factor per evaluation into memory allocated
//! once), shifted by `μ diag(S)` and refined against the unshifted `S`: exact where the rows are
//! independent, continuous where `Φ_z` loses rank (a parallelogram lying flat), the least
//! `Σ S_ii λ_i²` multipliers where rows are redundant (a third parallel crank: the reactions are
//! not unique there, and this is the choice), and [`lagrange::Error::InconsistentConstraints`]
//! where the rows cannot hold together. The rows that fix coordinates without mass are added to
//! the mass matrix exactly (`system/sparsity.rs`, `system/schur.rs`).
//!
//! `(z, ż)` is integrated by the solver's [`Dopri5`](lagrange::integrate::Dopri5) at the
//! requested tolerance, stepping exactly to each requested time, in a frame at the bodies'
//! initial centroid (so that nothing, round-off included, depends on where the world's origin
//! is); after every accepted step the state is projected onto `Φ = 0` (Gauss–Newton with the
//! least mass-weighted change, `z ← z − M⁻¹ Φ_zᵀ S⁻¹ Φ`, to the round-off of each equation's
//! own size) and `Φ̇ = 0` (`ż ← ż − M⁻¹ Φ_zᵀ S⁻¹ (Φ_z ż + Φ_t)`), and the integrator restarts
//! there. The constraint forces are `−Φ_zᵀ λ`, comparable to [`lagrange::reaction_forces`].

pub(crate) mod constraints;
#[cfg(test)]
mod linkage_tests;
pub(crate) mod simulation;
pub(crate) mod system;
#[cfg(test)]
mod tests;

use crate::{BuildError, Built, Settings};
use lagrange::State;
use lagrange_scenes::{Params, Scene};
pub(crate) use simulation::CartesianSimulation;
use system::CartesianSystem;

/// Build the Cartesian + multiplier simulation of `scene` with `params`, starting from the
/// body states of the reduced `initial` state, integrating at `settings.tolerance`. The
/// simulated parameters are the requested ones (no deviations are needed).
///
/// # Errors
/// As [`crate::build`]: [`BuildError::Invalid`] for invalid parameters, a
/// state of the wrong size, a bad tolerance, or a coordinate without mass that no constraint
/// fixes.
pub fn build(scene: &dyn Scene, params: &Params, initial: &State, settings: &Settings) -> Result<Built, BuildError> {
    let system = CartesianSystem::new(scene, params)?;
    let read_back = system.read_back.clone();
    let states = read_back.body_states(initial)?;
    let simulation = CartesianSimulation::new(system, &states, initial.t, settings.tolerance)?;
    Ok(Built {
        simulation: Box::new(simulation),
        params: params.clone(),
        deviations: Vec::new(),
        graph: None,
        read_back,
    })
}
