//! Deterministic probe states at which the engine checks a mechanism's structure once, and
//! the checks [`Model::new`](crate::Model::new) runs there: below the model, working on the
//! user's [`Mechanism`] and [`Tree`] directly (no evaluation stage of `eom`).

use crate::error::{Derived, Error, Stage, bad_pivot, non_finite};
use crate::linalg::{self, size::Dynamic};
use crate::mechanism::{LagrangianFunction, Mechanism};
use crate::passes::{jacobian_columns, moving_poses};
use crate::pose::Pose;
use crate::seed;
use crate::tree::Tree;
use num_dual::{Dual2, Dual64};

/// A few fixed, generic states `(q, q̇, t)`: away from 0 and from special angles, so that an
/// identity that holds at all of them holds structurally (it is evaluated exactly by AD).
pub(crate) struct ProbeStates {
    n: usize,
    q: Vec<f64>,
    qdot: Vec<f64>,
    t: Vec<f64>,
    /// One direction in `q` per probe, every `|v_j|` in `[½, 1]` with a random sign.
    direction: Vec<f64>,
}

const PROBES: usize = 3;

impl ProbeStates {
    pub(crate) fn new(n: usize) -> Self {
        // splitmix64: a fixed, portable sequence.
        let mut seed: u64 = 0x5EED_1A6A_A6E0_0001;
        let mut next = move || {
            seed = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = seed;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let q = (0..PROBES * n).map(|_| 0.35 + 0.5 * next()).collect();
        let qdot = (0..PROBES * n).map(|_| 0.8 * next() - 0.4).collect();
        let t = (0..PROBES).map(|_| 0.1 + next()).collect();
        let direction = (0..PROBES * n)
            .map(|_| {
                let u = next();
                if u < 0.5 { -0.5 - u } else { u }
            })
            .collect();
        Self { n, q, qdot, t, direction }
    }

    pub(crate) fn len(&self) -> usize {
        PROBES
    }

    /// Probe state `k`: `(q, q̇, t)`.
    pub(crate) fn state(&self, k: usize) -> (&[f64], &[f64], f64) {
        let r = k * self.n..(k + 1) * self.n;
        (&self.q[r.clone()], &self.qdot[r], self.t[k])
    }

    /// Direction `k` in `q`, for a test of all coordinates at once by one directional
    /// derivative: every `|v_j|` in `[½, 1]` and a random sign, so that a derivative the test
    /// should see, `v_j ∂f/∂q_j`, is never scaled away and generic sums of them do not cancel.
    pub(crate) fn direction(&self, k: usize) -> &[f64] {
        &self.direction[k * self.n..(k + 1) * self.n]
    }

    /// Which coordinates are cyclic: `∂L/∂q_j` exactly zero at every probe (one dual pass per
    /// coordinate and probe, `O(n)` passes: asked for when needed, not at construction).
    pub(crate) fn cyclic<F: LagrangianFunction>(&self, f: &F) -> Vec<bool> {
        let n = self.n;
        let mut scratch = f.scratch::<Dual64>();
        let mut q = vec![Dual64::from(0.0); n];
        let mut qdot = vec![Dual64::from(0.0); n];
        let mut cyclic = vec![true; n];
        for k in 0..PROBES {
            let (q0, qdot0, t0) = self.state(k);
            seed::constant(&mut qdot, qdot0);
            seed::constant(&mut q, q0);
            for j in 0..n {
                q[j].eps = 1.0;
                let l = f.lagrangian_with(&mut scratch, Dual64::from(t0), &q, &qdot);
                q[j].eps = 0.0;
                cyclic[j] &= l.eps == 0.0;
            }
        }
        cyclic
    }

    /// Whether the Lagrangian is autonomous: `∂L/∂t` exactly zero at every probe (one pass each).
    pub(crate) fn autonomous<F: LagrangianFunction>(&self, f: &F) -> bool {
        let n = self.n;
        let mut scratch = f.scratch::<Dual64>();
        let mut q = vec![Dual64::from(0.0); n];
        let mut qdot = vec![Dual64::from(0.0); n];
        (0..PROBES).all(|k| {
            let (q0, qdot0, t0) = self.state(k);
            seed::constant(&mut qdot, qdot0);
            seed::constant(&mut q, q0);
            f.lagrangian_with(&mut scratch, Dual64::new(t0, 1.0), &q, &qdot).eps == 0.0
        })
    }
}

/// Terms computed once for a mechanism that declares a constant mass matrix.
#[derive(Clone, Debug)]
pub(crate) struct ConstantTerms {
    /// `J` (3B × n), body-major rows.
    pub jacobian: Vec<f64>,
    /// `M` (n × n).
    pub mass_matrix: Vec<f64>,
    /// LDLᵀ factor of `M` (n × n): unit lower triangle below the diagonal, `D` on it.
    pub factor: Vec<f64>,
    /// `Σ_b J_bᵀ (0, −m_b g, 0)` (n).
    pub gravity_force: Vec<f64>,
}

/// `J` (3B × n, body-major rows) of `mechanism` at `(q, t)`, in `f64`.
fn jacobian<M: Mechanism>(mechanism: &M, t: f64, q: &[f64], jacobian: &mut [f64]) {
    let n = q.len();
    let mut q_dual = vec![Dual64::from_re(0.0); n];
    let mut poses = vec![Pose::default(); mechanism.description().bodies.len()];
    jacobian_columns(mechanism, &mut q_dual, &mut poses, t, q, |j, _, poses, _| {
        for (b, pose) in poses.iter().enumerate() {
            jacobian[3 * b * n + j] = pose.x.eps;
            jacobian[(3 * b + 1) * n + j] = pose.y.eps;
            jacobian[(3 * b + 2) * n + j] = pose.angle.eps;
        }
    });
}

/// Body velocities and convective accelerations (3B each) of `mechanism` at `(q, q̇, t)`.
fn velocities<M: Mechanism>(mechanism: &M, t: f64, q: &[f64], qdot: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mut q_dual2 = vec![Dual2::from_re(0.0); q.len()];
    let mut poses = vec![Pose::default(); mechanism.description().bodies.len()];
    moving_poses(mechanism, &mut q_dual2, &mut poses, t, q, qdot);
    let velocity = poses.iter().flat_map(|p| [p.x.v1, p.y.v1, p.angle.v1]).collect();
    let convective = poses.iter().flat_map(|p| [p.x.v2, p.y.v2, p.angle.v2]).collect();
    (velocity, convective)
}

/// Check a declared constant mass matrix at the probe states and compute its terms.
pub(crate) fn constant_terms<M: Mechanism>(mechanism: &M, probes: &ProbeStates) -> Result<ConstantTerms, Error> {
    let n = probes.n;
    let bodies = &mechanism.description().bodies;
    let mut jac = vec![0.0; 3 * bodies.len() * n];
    let mut reference: Option<Vec<f64>> = None;
    for k in 0..probes.len() {
        let (q, qdot, t) = probes.state(k);
        jacobian(mechanism, t, q, &mut jac);
        let (velocity, convective) = velocities(mechanism, t, q, qdot);
        match &reference {
            None => reference = Some(jac.clone()),
            Some(j0) => {
                let scale = j0.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
                if j0.iter().zip(&jac).any(|(a, b)| (a - b).abs() > 1e-12 * scale) {
                    return Err(Error::Inconsistent {
                        what: "declared a constant mass matrix, but the pose Jacobian changes with q or t".into(),
                    });
                }
            }
        }
        let scale = velocity.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        if convective.iter().any(|g| g.abs() > 1e-12 * scale) {
            return Err(Error::Inconsistent {
                what: "declared a constant mass matrix, but the convective term p̈ − J q̈ is not zero".into(),
            });
        }
    }
    // Probe 0 again, with q̇ = 0: a time-dependent pose would show a velocity.
    let (q, _, t) = probes.state(0);
    let (velocity, _) = velocities(mechanism, t, q, &vec![0.0; n]);
    if velocity.iter().any(|v| *v != 0.0) {
        return Err(Error::Inconsistent {
            what: "declared a constant mass matrix, but the poses depend on time".into(),
        });
    }
    jacobian(mechanism, t, q, &mut jac);
    let mass: Vec<f64> = bodies.iter().map(|b| b.mass).collect();
    let inertia: Vec<f64> = bodies.iter().map(|b| b.inertia).collect();
    let mut mass_matrix = vec![0.0; n * n];
    linalg::mass_matrix_sized(Dynamic(n), &mass, &inertia, &jac, &mut mass_matrix);
    let mut factor = mass_matrix.clone();
    linalg::ldlt_factor(n, &mut factor).map_err(|bad| {
        bad_pivot(t, q, &mechanism.description().coordinates[bad.index].name, bad.pivot, bad.diagonal)
    })?;
    let gravity = mechanism.description().gravity;
    let mut gravity_force = vec![0.0; n];
    for (b, m) in mass.iter().enumerate() {
        for j in 0..n {
            gravity_force[j] -= jac[(3 * b + 1) * n + j] * m * gravity;
        }
    }
    Ok(ConstantTerms { jacobian: jac, mass_matrix, factor, gravity_force })
}

/// Check a declared tree against the mechanism: bodies, gravity, and — at every probe state —
/// poses, velocities and convective accelerations from one second-order dual pass of each.
pub(crate) fn check_tree<M: Mechanism>(mechanism: &M, tree: &Tree, probes: &ProbeStates) -> Result<(), Error> {
    let inconsistent =
        |what: String| Err(Error::Inconsistent { what: format!("declared a kinematic tree, but {what}") });
    let bodies = &mechanism.description().bodies;
    let (n, gravity) = (probes.n, mechanism.description().gravity);
    if tree.len() != bodies.len() || tree.len() != n {
        return inconsistent(format!(
            "it has {} bodies and coordinates where the mechanism has {} bodies and {} coordinates",
            tree.len(),
            bodies.len(),
            n
        ));
    }
    for (mine, theirs) in bodies.iter().zip(&tree.description().bodies) {
        if (mine.mass, mine.inertia) != (theirs.mass, theirs.inertia) {
            return inconsistent(format!("its body `{}` differs from the mechanism's `{}`", theirs.name, mine.name));
        }
    }
    if tree.description().gravity != gravity {
        return inconsistent(format!(
            "its g = {} differs from the mechanism's {}",
            tree.description().gravity,
            gravity
        ));
    }
    let b = bodies.len();
    let (mut mine, mut theirs) = (vec![Pose::<Dual2<f64>>::default(); b], vec![Pose::<Dual2<f64>>::default(); b]);
    let mut seeded = vec![Dual2::from_re(0.0); n];
    for k in 0..probes.len() {
        let (q, qdot, t) = probes.state(k);
        moving_poses(mechanism, &mut seeded, &mut mine, t, q, qdot);
        moving_poses(tree, &mut seeded, &mut theirs, t, q, qdot);
        // Components: x and y of bodies with mass, the angle of bodies with inertia.
        let carried = |b: usize, c: usize| if c < 2 { bodies[b].mass != 0.0 } else { bodies[b].inertia != 0.0 };
        for (order, part) in [("pose", 0), ("velocity", 1), ("convective acceleration", 2)] {
            let get = |d: &Dual2<f64>| [d.re, d.v1, d.v2][part];
            let pairs = || {
                (0..b)
                    .flat_map(move |body| (0..3).map(move |c| (body, c)))
                    .filter(|&(body, c)| carried(body, c))
                    .map(|(body, c)| (body, c, get(&components(&mine[body])[c]), get(&components(&theirs[body])[c])))
            };
            let scale = pairs().fold(1.0_f64, |m, (_, _, x, y)| m.max(x.abs()).max(y.abs()));
            // A NaN difference fails too.
            let agrees = |x: f64, y: f64| (x - y).abs() <= 1e-12 * scale;
            if let Some((body, c, x, y)) = pairs().find(|&(_, _, x, y)| !agrees(x, y)) {
                return inconsistent(format!(
                    "its {order} of body `{}` differs in {}: {} from the tree, {} from the poses, at q = {q:?}",
                    bodies[body].name, COMPONENTS[c], y, x
                ));
            }
        }
    }
    Ok(())
}

/// The components of a pose, by name.
const COMPONENTS: [&str; 3] = ["x", "y", "angle"];

fn components<S: Copy>(pose: &Pose<S>) -> [S; 3] {
    [pose.x, pose.y, pose.angle]
}

/// `f64` poses at `(q, t)`, pre-filled with NaN so that a component `poses` leaves unwritten
/// stays NaN.
fn poses_f64<M: Mechanism>(mechanism: &M, t: f64, q: &[f64], out: &mut [Pose<f64>]) {
    out.fill(Pose::new(f64::NAN, f64::NAN, f64::NAN));
    mechanism.poses(t, q, out);
}

/// Compare an exact derivative with the central difference of the values `[f(x + h),
/// f(x − h), f(x + 2h), f(x − 2h)]`: `Ok` when they agree, else `Err(D(h))`.
///
/// The difference quotient `D(h) = (f(x + h) − f(x − h)) / 2h`, `h = ε^{1/3} max(|x|, 1)`,
/// errs by its truncation `c h²` and its round-off `≤ k ε P / h` (`P` the size of the
/// values, `k` the ulps a user's formula may lose; we allow `k = 64`). The truncation is
/// measured rather than assumed: `D(h) − D(2h) ≈ −3 c h²`, so `|D(h) − D(2h)|` bounds it three
/// times over. A derivative fails when it differs from `D(h)` by more than
/// `4 (|D(h) − D(2h)| + 64 ε P / h)`; a dropped derivative is off by its whole size, orders of
/// magnitude above that for any smooth function. A NaN fails too.
fn central_difference(exact: f64, [plus, minus, plus2, minus2]: [f64; 4], h: f64) -> Result<(), f64> {
    let narrow = (plus - minus) / (2.0 * h);
    let broad = (plus2 - minus2) / (4.0 * h);
    let size = [plus, minus, plus2, minus2].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let tolerance = 4.0 * ((narrow - broad).abs() + 64.0 * f64::EPSILON * size / h);
    if (exact - narrow).abs() <= tolerance { Ok(()) } else { Err(narrow) }
}

/// Check, at every probe state, that `poses` writes every component of every body (the
/// buffer is pre-filled with NaN: a forgotten body would otherwise sit wherever the buffer
/// left it), and that the exact derivatives of the components that carry mass agree with
/// central differences of the `f64` poses ([`central_difference`]) — they differ when `poses`
/// reads the real part of `t` or of a coordinate (`t.re()`), which silently drops that
/// derivative.
///
/// The coordinates are tested together, along one direction `v` per probe
/// ([`ProbeStates::direction`]): a dropped `∂p/∂q_j` changes the derivative along
/// `v` by `v_j ∂p/∂q_j`, never zero for a dropped derivative that is not, so a single
/// dual pass and four `f64` passes test all `n` coordinates (the cost grows with one
/// evaluation of the poses, not with `n` of them). Only a failing probe sweeps the
/// coordinates one by one, to name the one whose derivative was lost; `t` is tested on its
/// own.
pub(crate) fn check_poses<M: Mechanism>(mechanism: &M, probes: &ProbeStates) -> Result<(), Error> {
    let bodies = &mechanism.description().bodies;
    let n = probes.n;
    let mut poses = vec![Pose::default(); bodies.len()];
    let mut q_dual = vec![Dual64::from_re(0.0); n];
    let mut exact = vec![Pose::<Dual64>::default(); bodies.len()];
    for k in 0..probes.len() {
        let (q, _, t) = probes.state(k);
        poses_f64(mechanism, t, q, &mut poses);
        for (body, pose) in bodies.iter().zip(&poses) {
            if let Some(c) = components(pose).iter().position(|v| v.is_nan()) {
                return Err(Error::UnwrittenPose {
                    body: body.name.clone(),
                    component: COMPONENTS[c],
                    t,
                    q: q.to_vec(),
                });
            }
        }
        let direction = probes.direction(k);
        // Along v: the exact derivative by one pass with q seeded by v, the differences along q + s v.
        seed::along(&mut q_dual, q, direction);
        mechanism.poses(Dual64::from_re(t), &q_dual, &mut exact);
        let along_q = |s: f64, out: &mut [Pose<f64>]| {
            let moved: Vec<f64> = q.iter().zip(direction).map(|(x, v)| x + s * v).collect();
            poses_f64(mechanism, t, &moved, out);
        };
        if lost_derivative(bodies, &exact, 0.0, along_q).is_some()
            && let Some(error) = name_lost_derivative(mechanism, t, q)
        {
            return Err(error);
        }
        // Along t.
        seed::constant(&mut q_dual, q);
        mechanism.poses(Dual64::new(t, 1.0), &q_dual, &mut exact);
        let along_t = |s: f64, out: &mut [Pose<f64>]| poses_f64(mechanism, t + s, q, out);
        if let Some((b, c, exact, finite_difference)) = lost_derivative(bodies, &exact, t, along_t) {
            return Err(Error::LostDerivative {
                of: Derived::Pose { body: bodies[b].name.clone(), component: COMPONENTS[c] },
                variable: "t".into(),
                exact,
                finite_difference,
            });
        }
    }
    Ok(())
}

/// The first body component carrying mass whose exact derivative (`exact`, the `eps` parts)
/// disagrees with the central difference of `at(s, poses)` around `s = 0`, the variable being
/// `x` (its size sets the difference step): `(body, component, exact, difference)`.
fn lost_derivative(
    bodies: &[crate::mechanism::Body],
    exact: &[Pose<Dual64>],
    x: f64,
    mut at: impl FnMut(f64, &mut [Pose<f64>]),
) -> Option<(usize, usize, f64, f64)> {
    let h = f64::EPSILON.cbrt() * x.abs().max(1.0);
    let mut moved: [Vec<Pose<f64>>; 4] = std::array::from_fn(|_| vec![Pose::default(); bodies.len()]);
    for (out, step) in moved.iter_mut().zip([h, -h, 2.0 * h, -2.0 * h]) {
        at(step, out);
    }
    for (b, body) in bodies.iter().enumerate() {
        for c in 0..3 {
            let carries_mass = if c < 2 { body.mass != 0.0 } else { body.inertia != 0.0 };
            if !carries_mass {
                continue;
            }
            let derivative = components(&exact[b])[c].eps;
            let values = moved.each_ref().map(|p| components(&p[b])[c]);
            if let Err(finite_difference) = central_difference(derivative, values, h) {
                return Some((b, c, derivative, finite_difference));
            }
        }
    }
    None
}

/// The error for a derivative of the poses that [`check_poses`] found lost along a direction
/// at `(q, t)`: the coordinates one by one (one dual pass and four `f64` passes each) name
/// the first whose derivative disagrees. `None` when every coordinate passes on its own (the
/// test along the direction judged a curvature its difference step did not resolve, not a
/// lost derivative): the per-coordinate test is the definition, the directional one its
/// shortcut.
fn name_lost_derivative<M: Mechanism>(mechanism: &M, t: f64, q: &[f64]) -> Option<Error> {
    let bodies = &mechanism.description().bodies;
    let coordinates = &mechanism.description().coordinates;
    let mut q_dual = vec![Dual64::from_re(0.0); q.len()];
    let mut exact = vec![Pose::<Dual64>::default(); bodies.len()];
    seed::constant(&mut q_dual, q);
    for j in 0..q.len() {
        q_dual[j].eps = 1.0;
        mechanism.poses(Dual64::from_re(t), &q_dual, &mut exact);
        q_dual[j].eps = 0.0;
        let along = |s: f64, out: &mut [Pose<f64>]| {
            let mut moved = q.to_vec();
            moved[j] += s;
            poses_f64(mechanism, t, &moved, out);
        };
        if let Some((b, c, exact, finite_difference)) = lost_derivative(bodies, &exact, q[j], along) {
            return Some(Error::LostDerivative {
                of: Derived::Pose { body: bodies[b].name.clone(), component: COMPONENTS[c] },
                variable: coordinates[j].name.clone(),
                exact,
                finite_difference,
            });
        }
    }
    None
}

/// Check a raw Lagrangian at every probe state: `L` is finite, and its exact first derivatives
/// `∂L/∂q_j`, `∂L/∂q̇_j` and `∂L/∂t` (one `Dual64` pass each) are finite and agree with central
/// differences of the `f64` Lagrangian ([`central_difference`], the same test as for the
/// poses) — they differ when `L` reads the real part of `t`, a coordinate or a velocity.
pub(crate) fn check_lagrangian<F: LagrangianFunction>(f: &F, probes: &ProbeStates) -> Result<(), Error> {
    let n = probes.n;
    let mut scratch = f.scratch::<f64>();
    let mut dual_scratch = f.scratch::<Dual64>();
    let (mut q_dual, mut qdot_dual) = (vec![Dual64::from_re(0.0); n], vec![Dual64::from_re(0.0); n]);
    for k in 0..probes.len() {
        let (q, qdot, t) = probes.state(k);
        if !f.lagrangian_with(&mut scratch, t, q, qdot).is_finite() {
            return Err(non_finite(Stage::Lagrangian, t, q));
        }
        seed::constant(&mut q_dual, q);
        seed::constant(&mut qdot_dual, qdot);
        let (mut q_moved, mut qdot_moved) = (q.to_vec(), qdot.to_vec());
        // Variable j < n is q_j, n ≤ j < 2n is q̇_{j−n}, j = 2n is t.
        for j in 0..=2 * n {
            let exact = if j < n {
                q_dual[j].eps = 1.0;
                let l = f.lagrangian_with(&mut dual_scratch, Dual64::from_re(t), &q_dual, &qdot_dual);
                q_dual[j].eps = 0.0;
                l.eps
            } else if j < 2 * n {
                qdot_dual[j - n].eps = 1.0;
                let l = f.lagrangian_with(&mut dual_scratch, Dual64::from_re(t), &q_dual, &qdot_dual);
                qdot_dual[j - n].eps = 0.0;
                l.eps
            } else {
                f.lagrangian_with(&mut dual_scratch, Dual64::new(t, 1.0), &q_dual, &qdot_dual).eps
            };
            if !exact.is_finite() {
                return Err(non_finite(Stage::Lagrangian, t, q));
            }
            let x = if j < n {
                q[j]
            } else if j < 2 * n {
                qdot[j - n]
            } else {
                t
            };
            let h = f64::EPSILON.cbrt() * x.abs().max(1.0);
            let mut at = |step: f64| {
                let mut time = t;
                if j < n {
                    q_moved[j] = x + step;
                } else if j < 2 * n {
                    qdot_moved[j - n] = x + step;
                } else {
                    time = x + step;
                }
                let value = f.lagrangian_with(&mut scratch, time, &q_moved, &qdot_moved);
                q_moved.copy_from_slice(q);
                qdot_moved.copy_from_slice(qdot);
                value
            };
            let values = [at(h), at(-h), at(2.0 * h), at(-2.0 * h)];
            if let Err(finite_difference) = central_difference(exact, values, h) {
                let coordinates = f.coordinates();
                let variable = if j < n {
                    coordinates[j].name.clone()
                } else if j < 2 * n {
                    format!("{}\u{307}", coordinates[j - n].name)
                } else {
                    "t".into()
                };
                return Err(Error::LostDerivative { of: Derived::Lagrangian, variable, exact, finite_difference });
            }
        }
    }
    Ok(())
}

/// Dual buffers for evaluating a mechanism's holonomic and velocity constraints together at a
/// seeded state (`q`, `qdot`), for the constraint probes.
struct ConstraintDuals {
    counts: (usize, usize),
    phi: Vec<Dual64>,
    residual: Vec<Dual64>,
    q: Vec<Dual64>,
    qdot: Vec<Dual64>,
}

impl ConstraintDuals {
    fn new(n: usize, counts: (usize, usize)) -> Self {
        let zero = Dual64::from(0.0);
        Self {
            counts,
            phi: vec![zero; counts.0],
            residual: vec![zero; counts.1],
            q: vec![zero; n],
            qdot: vec![zero; n],
        }
    }

    /// `Φ` and the velocity residuals at `(t, q, qdot)`, one after the other.
    fn evaluate<M: Mechanism>(&mut self, mechanism: &M, t: Dual64) -> impl Iterator<Item = &Dual64> {
        if self.counts.0 > 0 {
            mechanism.constraints(t, &self.q, &mut self.phi);
        }
        if self.counts.1 > 0 {
            mechanism.velocity_constraint(t, &self.q, &self.qdot, &mut self.residual);
        }
        self.phi.iter().chain(&self.residual)
    }
}

/// Check the declared constraints at the probe states — every residual and its derivatives
/// along a direction mixing every coordinate and along `t` finite, every velocity constraint
/// affine in `q̇` (`c(2q̇) − 2c(q̇) + c(0) = 0` to round-off) — and return whether they are free
/// of explicit time (`∂Φ/∂t` and `b` exactly time-independent; a moving constraint does work,
/// so `h` is not conserved). Two dual passes per probe, whatever the number of coordinates.
///
/// # Errors
/// [`Error::NonFinite`] (stage [`Constraints`](Stage::Constraints)) for a non-finite residual
/// or derivative; [`Error::Inconsistent`] for a velocity constraint that is not linear in `q̇`.
pub(crate) fn check_constraints<M: Mechanism>(
    mechanism: &M,
    (holonomic, velocity): (usize, usize),
    probes: &ProbeStates,
) -> Result<bool, Error> {
    let mut duals = ConstraintDuals::new(probes.n, (holonomic, velocity));
    let mut autonomous = true;
    for k in 0..probes.len() {
        let (q, qdot, t) = probes.state(k);
        seed::constant(&mut duals.qdot, qdot);
        // Along the probe's direction in q (a non-finite entry of G makes the sum non-finite),
        // then along t.
        for along_t in [false, true] {
            let direction = if along_t { None } else { Some(probes.direction(k)) };
            for (j, x) in duals.q.iter_mut().enumerate() {
                *x = Dual64::new(q[j], direction.map_or(0.0, |d| d[j]));
            }
            let t_dual = Dual64::new(t, if along_t { 1.0 } else { 0.0 });
            let (finite, still) = duals
                .evaluate(mechanism, t_dual)
                .fold((true, true), |(f, s), v| (f && v.re.is_finite() && v.eps.is_finite(), s && v.eps == 0.0));
            if !finite {
                return Err(non_finite(Stage::Constraints, t, q));
            }
            if along_t {
                autonomous &= still;
            }
        }
        if velocity > 0 {
            // Affine in q̇: c(2q̇) − 2 c(q̇) + c(0) = 0 up to round-off of the three evaluations.
            let at = |scale: f64, out: &mut [Dual64]| {
                let v: Vec<Dual64> = qdot.iter().map(|&v| Dual64::from(scale * v)).collect();
                mechanism.velocity_constraint(Dual64::from(t), &duals.q, &v, out);
            };
            let (mut c0, mut c1, mut c2) = (
                vec![Dual64::from(0.0); velocity],
                vec![Dual64::from(0.0); velocity],
                vec![Dual64::from(0.0); velocity],
            );
            at(0.0, &mut c0);
            at(1.0, &mut c1);
            at(2.0, &mut c2);
            for i in 0..velocity {
                let (a, b, c) = (c0[i].re, c1[i].re, c2[i].re);
                let scale = a.abs().max(b.abs()).max(c.abs()).max(1.0);
                if (c - 2.0 * b + a).abs() > 1e3 * f64::EPSILON * scale {
                    return Err(Error::Inconsistent {
                        what: format!(
                            "velocity constraint {} is not linear in q̇ (c(2q̇) − 2c(q̇) + c(0) = {:e})",
                            mechanism.description().constraint_name(holonomic + i),
                            c - 2.0 * b + a
                        ),
                    });
                }
            }
        }
    }
    Ok(autonomous)
}

/// Which coordinates the constraints involve: column `j` of `G` (or of a velocity constraint's
/// `A`, through `q` or `q̇`) not exactly zero at some probe — a constraint force can act along
/// `q_j`, so its momentum is not conserved even when `q_j` is cyclic in `L`. One dual pass per
/// coordinate and probe (`O(n)` passes): asked for with the cyclic coordinates.
pub(crate) fn constraint_involvement<M: Mechanism>(
    mechanism: &M,
    (holonomic, velocity): (usize, usize),
    probes: &ProbeStates,
) -> Vec<bool> {
    let n = probes.n;
    let mut involves = vec![false; n];
    let mut duals = ConstraintDuals::new(n, (holonomic, velocity));
    for k in 0..probes.len() {
        let (q, qdot, t) = probes.state(k);
        seed::constant(&mut duals.q, q);
        seed::constant(&mut duals.qdot, qdot);
        for j in 0..n {
            // Along q_j, then (velocity rows: A q̇ itself moves the momenta of the coordinates
            // it names) along q̇_j.
            duals.q[j].eps = 1.0;
            involves[j] |= duals.evaluate(mechanism, Dual64::from(t)).any(|v| v.eps != 0.0);
            duals.q[j].eps = 0.0;
            if velocity > 0 {
                duals.qdot[j].eps = 1.0;
                involves[j] |= duals.evaluate(mechanism, Dual64::from(t)).skip(holonomic).any(|v| v.eps != 0.0);
                duals.qdot[j].eps = 0.0;
            }
        }
    }
    involves
}
