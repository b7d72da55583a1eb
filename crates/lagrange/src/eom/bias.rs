//! Right-hand side `f = Σ_b J_bᵀ (F_b − D_b γ_b) − ∂V/∂q + Q`, with `F_b = (0, −m_b g, 0)`.

use crate::{Mechanism, Model, Scalar, Workspace};

/// Assemble `ws.rhs`. Reads `ws.jacobian` and `ws.convective` (general models) or the constant
/// terms (constant `M`), and `ws.potential_gradient` when the model has a potential.
pub(crate) fn assemble<M: Mechanism, S: Scalar>(model: &Model<M>, ws: &mut Workspace<S>, t: S, q: &[S], qdot: &[S]) {
    let n = model.n;
    if model.constant.is_some() {
        // Constant M: γ = 0 and the generalized gravity is precomputed.
        ws.rhs.copy_from_slice(&ws.constant_gravity);
    } else {
        // Gravity minus the inertial (convective) forces, projected body by body.
        ws.rhs.fill(S::zero());
        let g = model.gravity;
        for b in 0..model.bodies() {
            let (m, inertia) = (model.mass[b], model.inertia[b]);
            let wx = ws.convective[3 * b] * (-m);
            let wy = ws.convective[3 * b + 1] * (-m) - m * g;
            let jx = &ws.jacobian[3 * b * n..(3 * b + 1) * n];
            let jy = &ws.jacobian[(3 * b + 1) * n..(3 * b + 2) * n];
            for j in 0..n {
                ws.rhs[j] += jx[j] * wx + jy[j] * wy;
            }
            if inertia != 0.0 {
                let wa = ws.convective[3 * b + 2] * (-inertia);
                let ja = &ws.jacobian[(3 * b + 2) * n..(3 * b + 3) * n];
                for j in 0..n {
                    ws.rhs[j] += ja[j] * wa;
                }
            }
        }
    }
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
}
