//! Equations of motion of a body model, stage by stage:
//! position (`kinematics`) → mass matrix → right-hand side (`bias`) → `solve`; for kinematic
//! trees the articulated-body algorithm (`articulated`) instead; plus the quantities derived
//! from the same passes (`energy`, `reactions`) and the raw-Lagrangian path (`raw`). The
//! public spelling of both paths is in `equations`: free functions over either model.

pub(crate) mod applied;
pub(crate) mod articulated;
pub(crate) mod bias;
pub(crate) mod constraints;
pub(crate) mod energy;
pub(crate) mod equations;
pub(crate) mod kinematics;
pub(crate) mod mass_matrix;
pub(crate) mod point;
pub(crate) mod raw;
pub(crate) mod reactions;
pub(crate) mod sparse;

use crate::error::{Stage, bad_pivot};
pub(crate) use crate::error::{all_finite, non_finite};
use crate::linalg::{self, size};
use crate::{Error, Mechanism, Model, Scalar, Workspace};

/// Generalized accelerations `q̈ = M(q, t)⁻¹ f(q, q̇, t)` of a body model (the body half of
/// [`accelerations`](crate::accelerations)).
///
/// `M = Σ_b J_bᵀ D_b J_b`, `f = Σ_b J_bᵀ (F_b − D_b γ_b) − ∂V/∂q + Q`: `n` first-order dual
/// passes give `J` (and `∂V/∂q`), one second-order pass along `(q̇, 1)` gives `γ`, then an
/// in-place LDLᵀ solve. A model with a constant mass matrix skips all of it but the potential
/// gradient and the solve with the stored factor. A model of a kinematic tree
/// ([`Mechanism::tree`], [`Model::uses_tree_path`]) runs the articulated-body algorithm
/// instead: `O(n)`, with the same result to round-off. Generic over the scalar, so `q̈` itself
/// can be differentiated. The result is borrowed from the workspace.
///
/// # Errors
/// [`Error::DimensionMismatch`], [`Error::NonFinite`] (naming the stage), or
/// [`Error::SingularMassMatrix`] where the coordinates are not independent.
pub(crate) fn accelerations<'w, M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &'w mut Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<&'w [S], Error> {
    check_state(model.n, t, q, Some(qdot))?;
    if let Some(tree) = model.declared_tree() {
        articulated::solve(model, tree, ws, t, q, qdot)?;
        if let Some(structure) = &model.sparse {
            // Many loops on a tree: the same solve on the sparsity found at construction.
            sparse::solve(model, structure, ws, t, q, qdot)?;
        } else if model.is_constrained() {
            // The articulated-body pass has no factor of M: the constrained solve needs one.
            factor_mass_matrix(model, ws, t, q)?;
            constraints::solve(model, ws, t, q, qdot)?;
        }
    } else {
        size::with_size!(model.n, n => solve_sized(model, ws, n, t, q, qdot))?;
        if model.is_constrained() {
            constraints::solve(model, ws, t, q, qdot)?;
        }
    }
    if model.is_constrained() && !all_finite(&ws.qddot) {
        return Err(non_finite(Stage::Constraints, t, q));
    }
    Ok(&ws.qddot)
}

/// The stages of [`accelerations`], compiled for the number of coordinates.
fn solve_sized<M: Mechanism, S: Scalar, N: size::Size>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    size: N,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<(), Error> {
    if model.constant.is_some() {
        // Constant M: potential gradient, right-hand side, stored factor.
        if model.has_potential {
            kinematics::jacobian_pass(model, ws, t, q, true);
        } else if model.has_applied {
            kinematics::position_pass(model, ws, t, q);
        }
        bias::assemble(model, ws, size, t, q, qdot);
        ws.qddot.copy_from_slice(&ws.rhs);
        linalg::ldlt_solve_sized(size, &ws.constant_factor, &mut ws.qddot);
    } else {
        // Position and velocity stages.
        kinematics::jacobian_pass(model, ws, t, q, true);
        kinematics::velocity_pass(model, ws, t, q, qdot);
        // Mass matrix and its factor.
        mass_matrix::assemble(model, ws, size);
        ws.factor.copy_from_slice(&ws.mass_matrix);
        if let Err(bad) = linalg::ldlt_factor_sized(size, &mut ws.factor) {
            if !all_finite(&ws.mass_matrix) {
                return Err(non_finite(Stage::Kinematics, t, q));
            }
            return Err(bad_pivot(t, q, &model.coordinates()[bad.index].name, bad.pivot, bad.diagonal));
        }
        // Right-hand side and solve.
        bias::assemble(model, ws, size, t, q, qdot);
        ws.qddot.copy_from_slice(&ws.rhs);
        linalg::ldlt_solve_sized(size, &ws.factor, &mut ws.qddot);
    }
    if !all_finite(&ws.qddot) {
        return Err(diagnose(model, ws, t, q));
    }
    Ok(())
}

/// Assemble `M` and factor it into `ws.factor` (for the constrained solve on the tree path).
pub(crate) fn factor_mass_matrix<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    t: S,
    q: &[S],
) -> Result<(), Error> {
    kinematics::jacobian_pass(model, ws, t, q, false);
    mass_matrix::assemble(model, ws, size::Dynamic(model.n));
    ws.factor.copy_from_slice(&ws.mass_matrix);
    if let Err(bad) = linalg::ldlt_factor(model.n, &mut ws.factor) {
        if !all_finite(&ws.mass_matrix) {
            return Err(non_finite(Stage::Kinematics, t, q));
        }
        return Err(bad_pivot(t, q, &model.coordinates()[bad.index].name, bad.pivot, bad.diagonal));
    }
    Ok(())
}

/// Find the first stage that produced a non-finite value (only after the result was one).
fn diagnose<M: Mechanism, S: Scalar>(model: &Model<M>, ws: &Workspace<S>, t: S, q: &[S]) -> Error {
    let stage = if model.constant.is_none() && !(all_finite(&ws.jacobian) && all_finite(&ws.convective)) {
        Stage::Kinematics
    } else {
        force_stage(model, ws).unwrap_or(Stage::Accelerations)
    };
    non_finite(stage, t, q)
}

/// The first of the joint-space forces (potential gradient, generalized force, applied
/// forces) that is not finite, if one is not.
pub(crate) fn force_stage<M: Mechanism, S: Scalar>(model: &Model<M>, ws: &Workspace<S>) -> Option<Stage> {
    if model.has_potential && !all_finite(&ws.potential_gradient) {
        Some(Stage::Potential)
    } else if model.has_force && !all_finite(&ws.generalized_force) {
        Some(Stage::GeneralizedForce)
    } else if model.has_applied && !all_finite(&ws.applied_force) {
        Some(Stage::AppliedForce)
    } else {
        None
    }
}

/// Check lengths and finiteness of a state handed to the engine.
pub(crate) fn check_state<S: Scalar>(n: usize, t: S, q: &[S], qdot: Option<&[S]>) -> Result<(), Error> {
    if q.len() != n {
        return Err(Error::DimensionMismatch { what: "q", expected: n, got: q.len() });
    }
    if let Some(qdot) = qdot {
        if qdot.len() != n {
            return Err(Error::DimensionMismatch { what: "q̇", expected: n, got: qdot.len() });
        }
        if !all_finite(qdot) {
            return Err(non_finite(Stage::Velocities, t, q));
        }
    }
    if !(t.re().is_finite() && all_finite(q)) {
        return Err(non_finite(Stage::State, t, q));
    }
    Ok(())
}

/// The mass matrix `M(q, t) = Σ_b J_bᵀ D_b J_b` (n × n, row-major) of a body model, borrowed
/// from the workspace (the body half of [`mass_matrix`](crate::mass_matrix), without `q̇`).
///
/// # Errors
/// [`Error::DimensionMismatch`] or [`Error::NonFinite`] for a bad configuration.
pub(crate) fn mass_matrix<'w, M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &'w mut Workspace<S>,
    t: S,
    q: &[S],
) -> Result<&'w [S], Error> {
    check_state(model.n, t, q, None)?;
    if let Some(constant) = &model.constant {
        for (m, c) in ws.mass_matrix.iter_mut().zip(&constant.mass_matrix) {
            *m = S::from(*c);
        }
    } else {
        kinematics::jacobian_pass(model, ws, t, q, false);
        mass_matrix::assemble(model, ws, size::Dynamic(model.n));
    }
    if !all_finite(&ws.mass_matrix) {
        return Err(non_finite(Stage::Kinematics, t, q));
    }
    Ok(&ws.mass_matrix)
}
