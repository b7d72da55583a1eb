//! The dual passes over a mechanism's poses that every evaluation is made of: the pose
//! Jacobian by columns or by chunks of lanes, the poses moving along `(q̇, 1)` (velocities and
//! convective terms), and the applied forces with their Jacobian. Used on the hot path (`eom`)
//! and by the construction-time checks (`probe`).

use crate::mechanism::Mechanism;
use crate::pose::Pose;
use crate::seed::{self, CHUNK, Lanes};
use num_dual::{Dual, Dual2};

/// The pose Jacobian column by column: `n` first-order dual passes of the poses at `(q, t)`,
/// pass `j` with `q_j` seeded; `column(j, seeded q, seeded poses)` reads each. The one
/// Jacobian pass of the engine (the evaluation stage `eom::kinematics` runs it too).
pub(crate) fn jacobian_columns<M: Mechanism, S: crate::scalar::Scalar>(
    mechanism: &M,
    q_dual: &mut [Dual<S>],
    poses: &mut [Pose<Dual<S>>],
    t: S,
    q: &[S],
    mut column: impl FnMut(usize, &[Dual<S>], &[Pose<Dual<S>>], Dual<S>),
) {
    let t_dual = Dual::from_re(t);
    seed::constant(q_dual, q);
    for j in 0..q.len() {
        q_dual[j].eps = S::one();
        mechanism.poses(t_dual, q_dual, poses);
        column(j, q_dual, poses, t_dual);
        q_dual[j].eps = S::zero();
    }
}

/// The pose Jacobian in chunks of [`CHUNK`] columns: one vector-dual pass of the poses per
/// chunk, the chunk's coordinates `q_{j0} … q_{j0+w−1}` seeded in lanes `0 … w−1`;
/// `chunk(j0, w, seeded q, seeded poses, t)` reads lane `k` as column `j0 + k` ([`lane`](seed::lane)).
/// Every sine and cosine of the user's poses is evaluated once per chunk instead of once per
/// column, which is most of the cost of a column pass.
pub(crate) fn jacobian_chunks<M: Mechanism, S: crate::scalar::Scalar>(
    mechanism: &M,
    q_lanes: &mut [Lanes<S>],
    poses: &mut [Pose<Lanes<S>>],
    t: S,
    q: &[S],
    mut chunk: impl FnMut(usize, usize, &[Lanes<S>], &[Pose<Lanes<S>>], Lanes<S>),
) {
    let t_lanes = Lanes::from_re(t);
    let n = q.len();
    for j0 in (0..n).step_by(CHUNK) {
        let width = seed::chunk(q_lanes, q, j0);
        mechanism.poses(t_lanes, q_lanes, poses);
        chunk(j0, width, q_lanes, poses, t_lanes);
    }
}

/// The pose Jacobian (3B × n), the poses and the applied body wrenches (3B) at `(t, q, q̇)`, in
/// the caller's buffers (the Lagrangian-function view of a model: variational integrator, raw
/// path over a model); `Q = Jᵀ w` is the caller's product.
pub(crate) fn applied_force<M: Mechanism, S: crate::scalar::Scalar>(
    mechanism: &M,
    (q_dual, poses_dual): (&mut [Dual<S>], &mut [Pose<Dual<S>>]),
    (jacobian, poses, wrench): (&mut [S], &mut [Pose<S>], &mut [S]),
    t: S,
    q: &[S],
    qdot: &[S],
) {
    let n = q.len();
    jacobian_columns(mechanism, q_dual, poses_dual, t, q, |j, _, seeded, _| {
        for (b, pose) in seeded.iter().enumerate() {
            jacobian[3 * b * n + j] = pose.x.eps;
            jacobian[(3 * b + 1) * n + j] = pose.y.eps;
            jacobian[(3 * b + 2) * n + j] = pose.angle.eps;
            if j == 0 {
                poses[b] = Pose::new(pose.x.re, pose.y.re, pose.angle.re);
            }
        }
    });
    wrench.fill(S::zero());
    let mut loads = crate::mechanism::Loads::new(poses, wrench);
    mechanism.applied_forces(t, q, qdot, poses, &mut loads);
}

/// Poses moving along `(q̇, 1)`: one second-order dual pass; `v1` parts are the body
/// velocities `ṗ = J q̇ + ∂p/∂t`, `v2` parts the convective accelerations `γ = p̈ − J q̈`.
pub(crate) fn moving_poses<M: Mechanism, S: crate::scalar::Scalar>(
    mechanism: &M,
    q_dual2: &mut [Dual2<S>],
    poses: &mut [Pose<Dual2<S>>],
    t: S,
    q: &[S],
    qdot: &[S],
) {
    seed::along2(q_dual2, q, qdot);
    mechanism.poses(Dual2::new(t, S::one(), S::zero()), q_dual2, poses);
}
