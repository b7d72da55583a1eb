//! Right-hand side `f = Σ_b J_bᵀ (F_b − D_b γ_b) − ∂V/∂q + Q`, with `F_b = (0, −m_b g, 0)`.

use crate::linalg::size::Size;
use crate::{Mechanism, Model, Scalar, Workspace};

/// Assemble `ws.rhs`. Reads `ws.jacobian` and `ws.convective` (general models) or the constant
/// terms (constant `M`), `ws.potential_gradient` when the model has a potential, and
/// `ws.position` when it has applied forces.
pub(crate) fn assemble<M: Mechanism, S: Scalar, N: Size>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    size: N,
    t: S,
    q: &[S],
    qdot: &[S],
) {
    let n = size.get();
    if model.constant.is_some() {
        // Constant M: γ = 0 and the generalized gravity is precomputed.
        ws.rhs.copy_from_slice(&ws.constant_gravity);
    } else {
        // Gravity minus the inertial (convective) forces, projected body by body.
        let rhs = &mut ws.rhs[..n];
        rhs.fill(S::zero());
        let g = model.gravity;
        for (b, (&m, &inertia)) in model.mass.iter().zip(&model.inertia).enumerate() {
            let rows = &ws.jacobian[3 * b * n..3 * (b + 1) * n];
            let gamma = &ws.convective[3 * b..3 * b + 3];
            let wx = gamma[0] * (-m);
            let wy = gamma[1] * (-m) - m * g;
            for j in 0..n {
                rhs[j] += rows[j] * wx + rows[n + j] * wy;
            }
            if inertia != 0.0 {
                let wa = gamma[2] * (-inertia);
                for j in 0..n {
                    rhs[j] += rows[2 * n + j] * wa;
                }
            }
        }
    }
    add_joint_forces(model, ws, model.constant.is_some(), t, q, qdot);
}

/// Add the joint-space forces to `ws.rhs`: `−∂V/∂q` (from `ws.potential_gradient`), `+ Q`,
/// and `+ Σ_b J_bᵀ w_b` of the forces applied at points of bodies (the caller filled the
/// poses; `constant`: the model's constant Jacobian holds them). The bias path and the
/// articulated-body algorithm share it.
pub(crate) fn add_joint_forces<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    constant: bool,
    t: S,
    q: &[S],
    qdot: &[S],
) {
    // − ∂V/∂q.
    if model.has_potential {
        for (r, g) in ws.rhs.iter_mut().zip(&ws.potential_gradient) {
            *r -= *g;
        }
    }
    // + Q.
    if model.has_force {
        ws.generalized_force.fill(S::zero());
        model.mechanism.generalized_force(t, q, qdot, &mut ws.generalized_force);
        for (r, f) in ws.rhs.iter_mut().zip(&ws.generalized_force) {
            *r += *f;
        }
    }
    // + Σ_b J_bᵀ w_b (forces applied at points of bodies; the caller filled the poses).
    if model.has_applied {
        super::applied::add(model, ws, constant, t, q, qdot);
    }
}
