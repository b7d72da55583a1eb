//! Position stage: body poses, the pose Jacobian, the potential gradient; velocity stage: body
//! velocities and convective accelerations.

use crate::{Mechanism, Model, Scalar, Workspace};
use num_dual::{Dual, Dual2};

/// Fill `ws.position`, `ws.jacobian` and — with `potential` and a model that has one —
/// `ws.potential` and `ws.potential_gradient`.
///
/// One first-order dual pass per coordinate `j` (seed `q_j`): the dual parts of the poses are
/// column `j` of `J`, and the dual part of `V(q, poses(q), t)` is `∂V/∂q_j` (total derivative,
/// through the poses). Scalar passes keep the user's `Copy` bound and allocate nothing for any `n`.
pub(crate) fn jacobian_pass<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    t: S,
    q: &[S],
    potential: bool,
) {
    let n = model.n;
    let potential = potential && model.has_potential;
    let t_dual = Dual::from_re(t);
    for (d, &qi) in ws.q_dual.iter_mut().zip(q) {
        *d = Dual::from_re(qi);
    }
    for j in 0..n {
        // Seed coordinate j.
        ws.q_dual[j].eps = S::one();
        model.mechanism.poses(&ws.q_dual, t_dual, &mut ws.poses_dual);
        // Column j of J; the poses themselves once.
        for (b, pose) in ws.poses_dual.iter().enumerate() {
            ws.jacobian[3 * b * n + j] = pose.x.eps;
            ws.jacobian[(3 * b + 1) * n + j] = pose.y.eps;
            ws.jacobian[(3 * b + 2) * n + j] = pose.angle.eps;
            if j == 0 {
                ws.position[3 * b] = pose.x.re;
                ws.position[3 * b + 1] = pose.y.re;
                ws.position[3 * b + 2] = pose.angle.re;
            }
        }
        // ∂V/∂q_j through the same seeded poses.
        if potential && let Some(v) = model.mechanism.potential(&ws.q_dual, &ws.poses_dual, t_dual) {
            ws.potential_gradient[j] = v.eps;
            ws.potential = v.re;
        }
        ws.q_dual[j].eps = S::zero();
    }
}

/// Fill `ws.velocity` (`ṗ = J q̇ + ∂p/∂t`) and `ws.convective` (`γ = d²/ds² p(q + s q̇, t + s)`):
/// one second-order dual pass along the motion `(q̇, 1)`.
pub(crate) fn velocity_pass<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) {
    for ((d, &qi), &vi) in ws.q_dual2.iter_mut().zip(q).zip(qdot) {
        *d = Dual2::new(qi, vi, S::zero());
    }
    let t_dual = Dual2::new(t, S::one(), S::zero());
    model.mechanism.poses(&ws.q_dual2, t_dual, &mut ws.poses_dual2);
    for (b, pose) in ws.poses_dual2.iter().enumerate() {
        ws.velocity[3 * b] = pose.x.v1;
        ws.velocity[3 * b + 1] = pose.y.v1;
        ws.velocity[3 * b + 2] = pose.angle.v1;
        ws.convective[3 * b] = pose.x.v2;
        ws.convective[3 * b + 1] = pose.y.v2;
        ws.convective[3 * b + 2] = pose.angle.v2;
    }
}

/// Fill `ws.position` only (one real pass).
pub(crate) fn position_pass<M: Mechanism, S: Scalar>(model: &Model<M>, ws: &mut Workspace<S>, t: S, q: &[S]) {
    // Reuse the first-order buffers with zero dual parts.
    for (d, &qi) in ws.q_dual.iter_mut().zip(q) {
        *d = Dual::from_re(qi);
    }
    model.mechanism.poses(&ws.q_dual, Dual::from_re(t), &mut ws.poses_dual);
    for (b, pose) in ws.poses_dual.iter().enumerate() {
        ws.position[3 * b] = pose.x.re;
        ws.position[3 * b + 1] = pose.y.re;
        ws.position[3 * b + 2] = pose.angle.re;
    }
}
