//! Position stage: body poses, the pose Jacobian, the potential gradient; velocity stage: body
//! velocities and convective accelerations.

use crate::mechanism::Mechanism;
use crate::model::Model;
use crate::scalar::Scalar;
use crate::workspace::Workspace;
use crate::{passes, seed};
use num_dual::Dual;

/// Fill `ws.position`, `ws.jacobian` and — with `potential` and a model that has one —
/// `ws.potential` and `ws.potential_gradient`.
///
/// Below [`LANES_FROM`] coordinates, one first-order dual pass per coordinate `j` (seed `q_j`):
/// the dual parts of the poses are column `j` of `J`, and the dual part of `V(q, poses(q), t)`
/// is `∂V/∂q_j` (total derivative, through the poses). From [`LANES_FROM`] on, one vector-dual
/// pass per chunk of [`seed::CHUNK`] coordinates (lane `k` seeds `q_{j0+k}`) gives the chunk's
/// columns at once: every sine and cosine of the poses is evaluated once per chunk rather than
/// once per column. Both keep their lanes on the stack, so no `n` allocates.
pub(crate) fn jacobian_pass<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    t: S,
    q: &[S],
    potential: bool,
) {
    let n = model.n;
    let potential = potential && model.has_potential;
    let Workspace {
        q_dual,
        poses_dual,
        q_lanes,
        poses_lanes,
        jacobian,
        position,
        potential_gradient,
        potential: value,
        ..
    } = ws;
    if n < LANES_FROM {
        passes::jacobian_columns(&model.mechanism, q_dual, poses_dual, t, q, |j, q_dual, poses, t_dual| {
            // Column j of J; the poses themselves once.
            for (b, pose) in poses.iter().enumerate() {
                jacobian[3 * b * n + j] = pose.x.eps;
                jacobian[(3 * b + 1) * n + j] = pose.y.eps;
                jacobian[(3 * b + 2) * n + j] = pose.angle.eps;
                if j == 0 {
                    position[3 * b] = pose.x.re;
                    position[3 * b + 1] = pose.y.re;
                    position[3 * b + 2] = pose.angle.re;
                }
            }
            // ∂V/∂q_j through the same seeded poses.
            if potential && let Some(v) = model.mechanism.potential(t_dual, q_dual, poses) {
                potential_gradient[j] = v.eps;
                *value = v.re;
            }
        });
        return;
    }
    passes::jacobian_chunks(&model.mechanism, q_lanes, poses_lanes, t, q, |j0, width, q_lanes, poses, t_lanes| {
        // The chunk's columns of J; the poses themselves once.
        for (b, pose) in poses.iter().enumerate() {
            for k in 0..width {
                jacobian[3 * b * n + j0 + k] = seed::lane(&pose.x, k);
                jacobian[(3 * b + 1) * n + j0 + k] = seed::lane(&pose.y, k);
                jacobian[(3 * b + 2) * n + j0 + k] = seed::lane(&pose.angle, k);
            }
            if j0 == 0 {
                position[3 * b] = pose.x.re;
                position[3 * b + 1] = pose.y.re;
                position[3 * b + 2] = pose.angle.re;
            }
        }
        // ∂V/∂q_j through the same seeded poses.
        if potential && let Some(v) = model.mechanism.potential(t_lanes, q_lanes, poses) {
            for k in 0..width {
                potential_gradient[j0 + k] = seed::lane(&v, k);
            }
            *value = v.re;
        }
    });
}

/// The number of coordinates from which the Jacobian passes (of the poses and of the
/// constraints) seed [`seed::CHUNK`] coordinates at once: below it, one scalar dual pass per
/// coordinate is as fast (measured; the figures are in this constant's commit history).
pub(crate) const LANES_FROM: usize = 3;

/// Fill `ws.velocity` (`ṗ = J q̇ + ∂p/∂t`) and `ws.convective` (`γ = d²/ds² p(q + s q̇, t + s)`):
/// one second-order dual pass along the motion `(q̇, 1)`.
pub(crate) fn velocity_pass<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) {
    passes::moving_poses(&model.mechanism, &mut ws.q_dual2, &mut ws.poses_dual2, t, q, qdot);
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
    seed::constant(&mut ws.q_dual, q);
    model.mechanism.poses(Dual::from_re(t), &ws.q_dual, &mut ws.poses_dual);
    for (b, pose) in ws.poses_dual.iter().enumerate() {
        ws.position[3 * b] = pose.x.re;
        ws.position[3 * b + 1] = pose.y.re;
        ws.position[3 * b + 2] = pose.angle.re;
    }
}
