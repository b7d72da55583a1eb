//! Energies, the energy function and the generalized momenta of a body model (the body half
//! of [`momenta`](crate::momenta), [`energy_function`](crate::energy_function) and
//! [`lagrangian`](crate::lagrangian); the energies `T`, `V`, `T + V` are body-only).

use super::{all_finite, check_state, kinematics, non_finite};
use crate::error::Stage;
use crate::seed;
use crate::{Error, Mechanism, Model, Scalar, Workspace};
use num_dual::Dual;

/// Kinetic energy `T = Σ_b ½ m_b |ṗ_b|² + ½ I_b φ̇_b²` (one velocity pass).
pub fn kinetic_energy<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<S, Error> {
    check_state(model.n, t, q, Some(qdot))?;
    kinematics::velocity_pass(model, ws, t, q, qdot);
    Ok(kinetic_from_velocity(model, ws))
}

fn kinetic_from_velocity<M: Mechanism, S: Scalar>(model: &Model<M>, ws: &Workspace<S>) -> S {
    let mut kinetic = S::zero();
    for b in 0..model.description().bodies.len() {
        let v = &ws.velocity[3 * b..3 * b + 3];
        kinetic += (v[0] * v[0] + v[1] * v[1]) * (0.5 * model.mass[b]) + v[2] * v[2] * (0.5 * model.inertia[b]);
    }
    kinetic
}

/// Potential energy `V + Σ_b m_b g y_b` (gravity included).
pub fn potential_energy<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    t: S,
    q: &[S],
) -> Result<S, Error> {
    check_state(model.n, t, q, None)?;
    kinematics::position_pass(model, ws, t, q);
    let mut potential = S::zero();
    for b in 0..model.description().bodies.len() {
        potential += ws.position[3 * b + 1] * (model.mass[b] * model.gravity);
    }
    if model.has_potential {
        let t_dual = num_dual::Dual::from_re(t);
        if let Some(v) = model.mechanism.potential(t_dual, &ws.q_dual, &ws.poses_dual) {
            potential += v.re;
        }
    }
    Ok(potential)
}

/// The Lagrangian `L = T − V`.
pub(crate) fn lagrangian<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<S, Error> {
    Ok(kinetic_energy(model, ws, t, q, qdot)? - potential_energy(model, ws, t, q)?)
}

/// Generalized momenta `p = ∂L/∂q̇ = Σ_b J_bᵀ D_b ṗ_b`, borrowed from the workspace.
///
/// # Errors
/// [`Error::DimensionMismatch`], or [`Error::NonFinite`] for a non-finite state or momenta
/// that overflow.
pub(crate) fn momenta<'w, M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &'w mut Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<&'w [S], Error> {
    check_state(model.n, t, q, Some(qdot))?;
    let n = model.n;
    kinematics::jacobian_pass(model, ws, t, q, false);
    kinematics::velocity_pass(model, ws, t, q, qdot);
    ws.momenta.fill(S::zero());
    for b in 0..model.description().bodies.len() {
        let (m, inertia) = (model.mass[b], model.inertia[b]);
        let (vx, vy, va) = (ws.velocity[3 * b] * m, ws.velocity[3 * b + 1] * m, ws.velocity[3 * b + 2] * inertia);
        for j in 0..n {
            ws.momenta[j] += ws.jacobian[3 * b * n + j] * vx
                + ws.jacobian[(3 * b + 1) * n + j] * vy
                + ws.jacobian[(3 * b + 2) * n + j] * va;
        }
    }
    if !all_finite(&ws.momenta) {
        return Err(non_finite(Stage::Kinematics, t, q));
    }
    Ok(&ws.momenta)
}

/// The energy function `h = q̇·∂L/∂q̇ − L` (Jacobi's integral). For scleronomic mechanisms it is
/// `T + V`; it is conserved whenever `∂L/∂t = 0` and `Q = 0`, and in general
/// `dh/dt = Q·q̇ − ∂L/∂t`.
///
/// # Errors
/// [`Error::DimensionMismatch`] or [`Error::NonFinite`] for a bad state or an energy that is
/// not finite (stage [`Potential`](Stage::Potential) for a potential that is not finite here,
/// a singular point).
pub(crate) fn energy_function<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<S, Error> {
    check_state(model.n, t, q, Some(qdot))?;
    // q̇·p = Σ_b (J_b q̇)·D_b ṗ_b with J_b q̇ = ṗ_b − ∂p_b/∂t: the body velocities along the
    // motion (q̇, 1) and along time alone, two passes instead of the pose Jacobian's n columns.
    kinematics::velocity_pass(model, ws, t, q, qdot);
    seed::constant(&mut ws.q_dual, q);
    model.mechanism.poses(Dual::new(t, S::one()), &ws.q_dual, &mut ws.poses_dual);
    let mut qdot_p = S::zero();
    for (b, pose) in ws.poses_dual.iter().enumerate() {
        let v = &ws.velocity[3 * b..3 * b + 3];
        let (m, inertia) = (model.mass[b], model.inertia[b]);
        qdot_p +=
            ((v[0] - pose.x.eps) * v[0] + (v[1] - pose.y.eps) * v[1]) * m + (v[2] - pose.angle.eps) * v[2] * inertia;
    }
    let kinetic = kinetic_from_velocity(model, ws);
    let potential = potential_energy(model, ws, t, q)?;
    let energy = qdot_p - kinetic + potential;
    if !energy.re().is_finite() {
        let stage = if potential.re().is_finite() { Stage::Kinematics } else { Stage::Potential };
        return Err(non_finite(stage, t, q));
    }
    Ok(energy)
}

/// The total energy `T + V` (gravity included). It equals the energy function `h` of
/// [`energy_function`](crate::energy_function) for scleronomic mechanisms; for rheonomic ones (poses that depend on
/// time) they differ, and `h`, not `T + V`, is the one conserved when `∂L/∂t = 0`.
///
/// # Errors
/// As [`kinetic_energy`] and [`potential_energy`].
pub fn total_energy<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<S, Error> {
    Ok(kinetic_energy(model, ws, t, q, qdot)? + potential_energy(model, ws, t, q)?)
}
