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
        let bodies = ws.jacobian.chunks_exact(3 * n).zip(ws.convective.chunks_exact(3));
        for ((block, gamma), (&m, &inertia)) in bodies.zip(model.mass.iter().zip(&model.inertia)) {
            let (jx, rest) = block.split_at(n);
            let (jy, ja) = rest.split_at(n);
            let wx = gamma[0] * (-m);
            let wy = gamma[1] * (-m) - m * g;
            for ((r, &x), &y) in ws.rhs.iter_mut().zip(jx).zip(jy) {
                *r += x * wx + y * wy;
            }
            if inertia != 0.0 {
                let wa = gamma[2] * (-inertia);
                for (r, &a) in ws.rhs.iter_mut().zip(ja) {
                    *r += a * wa;
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
