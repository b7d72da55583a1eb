//! The constrained solve of a kinematic tree with many loops, in sparse form.
//!
//! The same numerical method as [`constraints::solve`](super::constraints) after
//! `factor_mass_matrix` — `M = Lᵀ D L`, `U = D^(−1/2) L⁻ᵀ Gᵀ`, `S = G M⁻¹ Gᵀ = U Uᵀ`, the
//! shifted LDLᵀ of `S + μ̄ I` with [`REFINEMENTS`](super::constraints::REFINEMENTS) steps of
//! iterative refinement, `q̈ = q̈_u − M⁻¹ Gᵀ λ` — on structure found once at model
//! construction ([`SparseStructure`]):
//!
//! - body `b` of a [`Tree`] moves with the coordinates of its ancestors (and its own) only, so
//!   the pose Jacobian is found by column compression with one colour per tree depth (one
//!   vector-dual pass per [`CHUNK`] depths), and `M_ij ≠ 0` only where `i` is an ancestor of
//!   `j` or the other way round: factored as `M = Lᵀ D L` in the tree's order with children
//!   eliminated before parents (Featherstone's LTDL, RBDA §6.5), without fill;
//! - the rows of `G = Φ_q` involve few coordinates each: their pattern is the union of the
//!   nonzeros at the probe states, verified at another state, and `G` is found by column
//!   compression too (greedy colouring: columns that share no row share a colour);
//! - row `r` of `U` is nonzero only on the ancestors of row `r`'s coordinates (its *reach*),
//!   `S_rs ≠ 0` only where two reaches overlap, and `S + μ̄ I` is factored in envelope
//!   storage in the constraints' own order (no fill outside the envelope).
//!
//! Each evaluation costs `O(colours · n + Σ depth² + Σ_r |reach_r| · overlaps)` instead of
//! `O(n³)`, and allocates nothing (every buffer is in [`SparseBuffers`]). The projection onto
//! the constraints after each integration step ([`project`](crate::project)) runs on the same
//! structure: `M` factored once at the step's end, then per Gauss–Newton iteration the
//! compressed `G`, `S` and the step `M⁻¹ Gᵀ S⁻¹ Φ`, and one step of the rates.

use crate::Error;
use crate::eom::constraints::{REFINEMENTS, REGULARIZATION, at_roundoff, refinement_stops, step_and_size};
use crate::eom::{all_finite, non_finite};
use crate::error::{Stage, bad_pivot};
use crate::linalg::PIVOT_RTOL;
use crate::mechanism::Mechanism;
use crate::model::Model;
use crate::pose::Pose;
use crate::probe::ProbeStates;
use crate::scalar::Scalar;
use crate::seed::{self, CHUNK, Lanes, lane};
use crate::tree::Tree;
use crate::workspace::{ConstraintBuffers, Workspace};
use num_dual::{Dual2, Dual64};

/// The number of coordinates from which a tree with holonomic constraints takes the sparse
/// path (below it, the dense one): the sparse path was the faster at every size measured, down
/// to two parallelogram windows (the figures are in this constant's commit history), so every such tree
/// takes it.
pub(crate) const SPARSE_FROM: usize = 1;

const NONE: usize = usize::MAX;

/// The structure of `M`, `G`, `U` and `S` of a model, found once.
#[derive(Clone, Debug)]
pub(crate) struct SparseStructure {
    /// Parent coordinate (= body) of each coordinate in the tree, [`NONE`] for the ground.
    parent: Vec<usize>,
    /// Depth of each coordinate (0 for a body hung from the ground).
    depth: Vec<usize>,
    /// Entry `(i, d)` — coordinate `i` and its `d`-th ancestor, `0 ≤ d ≤ depth_i` — of the
    /// per-body Jacobian, of `M` and of its factor is at `offset[i] + d` (n + 1).
    offset: Vec<usize>,
    /// Vector-dual passes of the poses (`⌈(max depth + 1) / CHUNK⌉`).
    pose_passes: usize,
    /// Pattern of `G` (m rows): row `r`'s columns, ascending, are `column[start[r]..start[r+1]]`.
    g_start: Vec<usize>,
    g_column: Vec<usize>,
    /// Colour of each coordinate in the compressed `G` pass ([`NONE`]: in no row).
    colour: Vec<usize>,
    /// Vector-dual passes of the constraints (`⌈colours / CHUNK⌉`).
    constraint_passes: usize,
    /// Reach of row `r` (the ancestors of its columns, themselves included), descending.
    reach_start: Vec<usize>,
    reach: Vec<usize>,
    /// The rows `s ≤ r` whose reach overlaps row `r`'s, ascending (`r` last).
    pair_start: Vec<usize>,
    pair: Vec<usize>,
    /// Envelope of `S`: row `r` holds columns `first[r] ..= r` at `env_start[r]` on.
    first: Vec<usize>,
    env_start: Vec<usize>,
}

/// The buffers of the sparse constrained solve in scalar `S`, sized by a [`SparseStructure`].
#[derive(Clone, Debug)]
pub(crate) struct SparseBuffers<S: Scalar> {
    /// Compressed pose Jacobian: entry `(b, d)` is `∂p_b/∂q_a` for `a` the `d`-th ancestor.
    jx: Vec<S>,
    jy: Vec<S>,
    ja: Vec<S>,
    /// `M` (the same entries), factored in place into `L` (off the diagonal) and `D`.
    mass: Vec<S>,
    /// `M`'s diagonal before factoring (n), then `D^(−1/2)` (n).
    diagonal: Vec<S>,
    scale: Vec<S>,
    /// Values of `G` on its pattern.
    g: Vec<S>,
    /// Values of `U` on the reaches.
    u: Vec<S>,
    /// A dense n-vector, zero between uses.
    dense: Vec<S>,
    /// `S` and the factor of `S + μ̄ I` on the envelope; `S λ` (c).
    schur: Vec<S>,
    schur_factor: Vec<S>,
    product: Vec<S>,
    /// `|S| |λ|` (c): the scale of the round-off of `S λ`.
    bound: Vec<f64>,
}

impl<S: Scalar> SparseBuffers<S> {
    pub(crate) fn new(s: &SparseStructure) -> Self {
        let z = S::zero();
        let n = s.parent.len();
        let entries = s.offset[n];
        let env = *s.env_start.last().unwrap_or(&0);
        Self {
            jx: vec![z; entries],
            jy: vec![z; entries],
            ja: vec![z; entries],
            mass: vec![z; entries],
            diagonal: vec![z; n],
            scale: vec![z; n],
            g: vec![z; s.g_column.len()],
            u: vec![z; s.reach.len()],
            dense: vec![z; n],
            schur: vec![z; env],
            schur_factor: vec![z; env],
            product: vec![z; s.first.len()],
            bound: vec![0.0; s.first.len()],
        }
    }
}

impl SparseStructure {
    /// The structure of a tree with `m` holonomic constraints (no velocity constraints), or
    /// `None` when the compressed Jacobians do not reproduce the dense ones at a verification
    /// state (a pattern that the probe states did not reveal): the dense path then serves.
    pub(crate) fn new<M: Mechanism>(mechanism: &M, tree: &Tree, m: usize, probes: &ProbeStates) -> Option<Self> {
        let n = tree.len();
        // The pattern by bisection at one probe state (`O(log n)` passes); should it miss a
        // column (an entry zero there by coincidence), the union over every probe state of
        // the dense Jacobian (`O(n)` passes).
        let (q, _, t) = probes.state(0);
        let bisected = bisected_pattern(mechanism, n, m, t, q, probes.direction(0));
        Self::with_pattern(mechanism, tree, m, probes, bisected)
            .or_else(|| Self::with_pattern(mechanism, tree, m, probes, jacobian_pattern(mechanism, n, m, probes)))
    }

    /// The structure on a given pattern of `G`, if it reproduces the exact Jacobians.
    fn with_pattern<M: Mechanism>(
        mechanism: &M,
        tree: &Tree,
        m: usize,
        probes: &ProbeStates,
        (g_start, g_column): (Vec<usize>, Vec<usize>),
    ) -> Option<Self> {
        let n = tree.len();
        let (parent, depth, offset) = tree_layout(tree);
        let max_depth: usize = depth.iter().copied().max().unwrap_or(0);
        let pose_passes = (max_depth + 1).div_ceil(CHUNK);
        let (colour, colours) = colour_columns(n, &g_start, &g_column);
        let constraint_passes = colours.div_ceil(CHUNK);
        let (reach_start, reach) = reaches(&parent, &g_start, &g_column);
        let (pair_start, pair, first, env_start) = overlaps(n, &reach_start, &reach);
        let structure = Self {
            parent,
            depth,
            offset,
            pose_passes,
            g_start,
            g_column,
            colour,
            constraint_passes,
            reach_start,
            reach,
            pair_start,
            pair,
            first,
            env_start,
        };
        structure.reproduces(mechanism, m, probes).then_some(structure)
    }

    /// Whether the compressed Jacobians equal the exact ones at a state between the probes:
    /// `G v` and `J v` along a direction `v` mixing every coordinate
    /// ([`ProbeStates::direction`]), each by one dual pass, against the same products of the
    /// compressed entries — a column missing from the pattern changes its row's product by
    /// `G_rj v_j` — to `1e-12` of the largest product's terms (the same derivatives by the same
    /// arithmetic, summed in another order, where a missed dependence is off by its whole size).
    fn reproduces<M: Mechanism>(&self, mechanism: &M, m: usize, probes: &ProbeStates) -> bool {
        let n = self.parent.len();
        let (q0, _, t0) = probes.state(0);
        let (q1, _, t1) = probes.state(1 % probes.len());
        let q: Vec<f64> =
            q0.iter().zip(q1).enumerate().map(|(j, (a, b))| 0.6 * a + 0.4 * b + 0.01 * j as f64).collect();
        let t = 0.5 * (t0 + t1);
        let v = probes.direction(0);
        let mut b = SparseBuffers::<f64>::new(self);
        let mut q_lanes = vec![Lanes::from_re(0.0); n];
        let mut phi_lanes = vec![Lanes::from_re(0.0); m];
        let mut poses_lanes = vec![Pose::default(); n];
        let mut residual = vec![0.0; m];
        self.pose_jacobian(mechanism, &mut q_lanes, &mut poses_lanes, &mut b, t, &q);
        self.constraint_jacobian(mechanism, &mut q_lanes, &mut phi_lanes, &mut b.g, &mut residual, t, &q);
        let q_dual: Vec<Dual64> = q.iter().zip(v).map(|(&x, &d)| Dual64::new(x, d)).collect();
        // Each product with the sum of its terms' sizes.
        let (mut exact, mut compressed) = (Vec::new(), Vec::new());
        let mut phi = vec![Dual64::from_re(0.0); m];
        mechanism.constraints(Dual64::from_re(t), &q_dual, &mut phi);
        for r in 0..m {
            exact.push(phi[r].eps);
            let terms = (self.g_start[r]..self.g_start[r + 1]).map(|e| b.g[e] * v[self.g_column[e]]);
            compressed.push((terms.clone().sum::<f64>(), terms.map(f64::abs).sum::<f64>()));
        }
        // Pose Jacobian: only the components that carry mass enter M.
        let bodies = &mechanism.description().bodies;
        let mut poses = vec![Pose::<Dual64>::default(); n];
        mechanism.poses(Dual64::from_re(t), &q_dual, &mut poses);
        for body in 0..n {
            let (mass, inertia) = (bodies[body].mass != 0.0, bodies[body].inertia != 0.0);
            let parts = [
                (mass, &b.jx, poses[body].x.eps),
                (mass, &b.jy, poses[body].y.eps),
                (inertia, &b.ja, poses[body].angle.eps),
            ];
            for (carried, entries, along) in parts {
                if !carried {
                    continue;
                }
                let (mut a, mut sum, mut size) = (body, 0.0, 0.0);
                for d in 0..=self.depth[body] {
                    let term = entries[self.offset[body] + d] * v[a];
                    sum += term;
                    size += term.abs();
                    a = self.parent[a];
                }
                exact.push(along);
                compressed.push((sum, size));
            }
        }
        let scale = compressed.iter().fold(0.0_f64, |s, &(_, size)| s.max(size));
        exact.iter().zip(&compressed).all(|(x, (y, _))| (x - y).abs() <= 1e-12 * scale)
    }

    /// The compressed pose Jacobian into `b.jx`, `b.jy`, `b.ja`: pass `p` seeds, in lane
    /// `d − p·CHUNK`, every coordinate of depth `d` in `[p·CHUNK, (p+1)·CHUNK)`; body `b` has
    /// exactly one ancestor at each depth up to its own, so the lane is that ancestor's column.
    fn pose_jacobian<M: Mechanism, S: Scalar>(
        &self,
        mechanism: &M,
        q_lanes: &mut [Lanes<S>],
        poses: &mut [Pose<Lanes<S>>],
        b: &mut SparseBuffers<S>,
        t: S,
        q: &[S],
    ) {
        let t_lanes = Lanes::from_re(t);
        for p in 0..self.pose_passes {
            let low = p * CHUNK;
            for (j, (d, &x)) in q_lanes.iter_mut().zip(q).enumerate() {
                *d = Lanes::from_re(x);
                if (low..low + CHUNK).contains(&self.depth[j]) {
                    *d = d.derivative(self.depth[j] - low);
                }
            }
            mechanism.poses(t_lanes, q_lanes, poses);
            for (body, pose) in poses.iter().enumerate() {
                let depth = self.depth[body];
                // Ancestor at chain position d has depth `depth − d`.
                for d in 0..=depth {
                    let at = depth - d;
                    if (low..low + CHUNK).contains(&at) {
                        let e = self.offset[body] + d;
                        b.jx[e] = lane(&pose.x, at - low);
                        b.jy[e] = lane(&pose.y, at - low);
                        b.ja[e] = lane(&pose.angle, at - low);
                    }
                }
            }
        }
    }

    /// The values of `G` on its pattern into `g` and `Φ` into `residual`: pass `p` seeds, in
    /// lane `c − p·CHUNK`, every column of colour `c` in `[p·CHUNK, (p+1)·CHUNK)`.
    #[allow(clippy::too_many_arguments)]
    fn constraint_jacobian<M: Mechanism, S: Scalar>(
        &self,
        mechanism: &M,
        q_lanes: &mut [Lanes<S>],
        phi_lanes: &mut [Lanes<S>],
        g: &mut [S],
        residual: &mut [S],
        t: S,
        q: &[S],
    ) {
        let t_lanes = Lanes::from_re(t);
        for p in 0..self.constraint_passes.max(1) {
            let low = p * CHUNK;
            for (j, (d, &x)) in q_lanes.iter_mut().zip(q).enumerate() {
                *d = Lanes::from_re(x);
                let c = self.colour[j];
                if c != NONE && (low..low + CHUNK).contains(&c) {
                    *d = d.derivative(c - low);
                }
            }
            mechanism.constraints(t_lanes, q_lanes, phi_lanes);
            for r in 0..phi_lanes.len() {
                for e in self.g_start[r]..self.g_start[r + 1] {
                    let c = self.colour[self.g_column[e]];
                    if (low..low + CHUNK).contains(&c) {
                        g[e] = lane(&phi_lanes[r], c - low);
                    }
                }
            }
        }
        for (out, phi) in residual.iter_mut().zip(phi_lanes.iter()) {
            *out = phi.re;
        }
    }
}

/// The constrained `q̈` and `λ` of a tree model with a [`SparseStructure`], from the
/// unconstrained `q̈_u` in `ws.qddot` (the articulated-body pass).
pub(crate) fn solve<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    structure: &SparseStructure,
    ws: &mut Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<(), Error> {
    let st = structure;
    let n = model.n;
    let c = model.constraint_counts.0;
    let mut b = ws.sparse.take().expect("a sparse model's workspace has sparse buffers");
    let mut cb = ws.constraints.take().expect("a constrained model's workspace has constraint buffers");
    let result = (|| {
        st.factor_mass(model, &mut ws.q_lanes, &mut ws.poses_lanes, &mut b, t, q)?;
        // G, Φ, and the rates and convective terms along (q̇, 1).
        st.constraint_jacobian(&model.mechanism, &mut ws.q_lanes, &mut cb.phi_lanes, &mut b.g, &mut cb.residual, t, q);
        seed::along2(&mut ws.q_dual2, q, qdot);
        model.mechanism.constraints(Dual2::new(t, S::one(), S::zero()), &ws.q_dual2, &mut cb.phi_dual2);
        for (i, phi) in cb.phi_dual2.iter().enumerate() {
            cb.rate[i] = phi.v1;
            cb.convective[i] = phi.v2;
        }
        st.scatter_g(n, c, &b.g, &mut cb.jacobian);
        if !(all_finite(&b.g) && all_finite(&cb.convective)) {
            return Err(non_finite(Stage::Constraints, t, q));
        }
        st.schur(c, &mut b, &mut cb.dependent);
        // λ = S⁻¹ (G q̈_u + γ) by the regularized, refined solve.
        for r in 0..c {
            cb.multipliers[r] = (st.g_start[r]..st.g_start[r + 1])
                .fold(S::zero(), |sum, e| sum + b.g[e] * ws.qddot[st.g_column[e]])
                + cb.convective[r];
        }
        let ConstraintBuffers { dependent, multipliers, right, refine, .. } = &mut cb;
        solve_envelope(st, c, &mut b, dependent, (&mut multipliers[..], &mut right[..], &mut refine[..]));
        // q̈ −= M⁻¹ Gᵀ λ.
        st.along_forces(n, c, &mut b, &cb.multipliers);
        for k in 0..n {
            ws.qddot[k] -= b.dense[k];
            b.dense[k] = S::zero();
        }
        Ok(())
    })();
    ws.sparse = Some(b);
    ws.constraints = Some(cb);
    result
}

impl SparseStructure {
    /// The compressed pose Jacobian, `M = Σ_b J_bᵀ D_b J_b` on the ancestor pairs and its
    /// factor `M = Lᵀ D L` (children before parents, RBDA Table 6.3) into `b.mass`, with
    /// `D^(−1/2)` into `b.scale`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::SingularMassMatrix`] (a pivot that is not positive).
    pub(crate) fn factor_mass<M: Mechanism, S: Scalar>(
        &self,
        model: &Model<M>,
        q_lanes: &mut [Lanes<S>],
        poses_lanes: &mut [Pose<Lanes<S>>],
        b: &mut SparseBuffers<S>,
        t: S,
        q: &[S],
    ) -> Result<(), Error> {
        let st = self;
        let n = model.n;
        st.pose_jacobian(&model.mechanism, q_lanes, poses_lanes, b, t, q);
        b.mass.fill(S::zero());
        for body in 0..n {
            let (m, inertia) = (model.mass[body], model.inertia[body]);
            let base = st.offset[body];
            let depth = st.depth[body];
            let mut i = body;
            for d1 in 0..=depth {
                let (xi, yi, ai) = (b.jx[base + d1] * m, b.jy[base + d1] * m, b.ja[base + d1] * inertia);
                let row = st.offset[i];
                for d2 in d1..=depth {
                    let e = base + d2;
                    b.mass[row + d2 - d1] += xi * b.jx[e] + yi * b.jy[e] + ai * b.ja[e];
                }
                i = st.parent[i];
            }
        }
        for k in 0..n {
            b.diagonal[k] = b.mass[st.offset[k]];
        }
        for k in (0..n).rev() {
            let row = st.offset[k];
            let (d, diagonal) = (b.mass[row], b.diagonal[k].re());
            if !(diagonal > 0.0 && d.re() / diagonal > PIVOT_RTOL) {
                if !all_finite(&b.mass) {
                    return Err(non_finite(Stage::Kinematics, t, q));
                }
                return Err(bad_pivot(t, q, &model.coordinates()[k].name, d.re(), diagonal));
            }
            let mut i = st.parent[k];
            let mut di = 1;
            while i != NONE {
                let a = b.mass[row + di] / d;
                // H_ij −= H_kj a for j = i and its ancestors (the (di + e)-th ancestors of k).
                let ri = st.offset[i];
                for e in 0..=st.depth[i] {
                    let h = b.mass[row + di + e];
                    b.mass[ri + e] -= h * a;
                }
                b.mass[row + di] = a;
                i = st.parent[i];
                di += 1;
            }
        }
        for k in 0..n {
            b.scale[k] = b.mass[st.offset[k]].sqrt().recip();
        }
        Ok(())
    }

    /// `G` on its pattern (`g`, c rows) written densely into `jacobian` (c × n, whose
    /// entries off the pattern stay zero).
    fn scatter_g<S: Scalar>(&self, n: usize, c: usize, g: &[S], jacobian: &mut [S]) {
        for r in 0..c {
            for e in self.g_start[r]..self.g_start[r + 1] {
                jacobian[r * n + self.g_column[e]] = g[e];
            }
        }
    }

    /// `U_r = D^(−1/2) L⁻ᵀ G_rᵀ` on each row's reach, `S = U Uᵀ` on the overlapping pairs (the
    /// rest of the envelope zero) and the factor of `S + μ̄ I`, from `G` in `b.g` and the
    /// factor of `M` ([`factor_mass`](Self::factor_mass)).
    fn schur<S: Scalar>(&self, c: usize, b: &mut SparseBuffers<S>, dependent: &mut [bool]) {
        let st = self;
        for r in 0..c {
            let reach = &st.reach[st.reach_start[r]..st.reach_start[r + 1]];
            for &a in reach {
                b.dense[a] = S::zero();
            }
            for e in st.g_start[r]..st.g_start[r + 1] {
                b.dense[st.g_column[e]] = b.g[e];
            }
            for (slot, &k) in reach.iter().enumerate() {
                let v = b.dense[k];
                let (mut i, mut di, row) = (st.parent[k], 1, st.offset[k]);
                while i != NONE {
                    b.dense[i] -= b.mass[row + di] * v;
                    i = st.parent[i];
                    di += 1;
                }
                b.u[st.reach_start[r] + slot] = v * b.scale[k];
            }
        }
        for &a in &st.reach {
            b.dense[a] = S::zero();
        }
        b.schur.fill(S::zero());
        for r in 0..c {
            let (from, to) = (st.reach_start[r], st.reach_start[r + 1]);
            for (slot, &a) in st.reach[from..to].iter().enumerate() {
                b.dense[a] = b.u[from + slot];
            }
            for &s in &st.pair[st.pair_start[r]..st.pair_start[r + 1]] {
                let (sf, stt) = (st.reach_start[s], st.reach_start[s + 1]);
                let sum =
                    st.reach[sf..stt].iter().zip(&b.u[sf..stt]).fold(S::zero(), |sum, (&a, &u)| sum + u * b.dense[a]);
                b.schur[st.env_start[r] + s - st.first[r]] = sum;
            }
            for &a in &st.reach[from..to] {
                b.dense[a] = S::zero();
            }
        }
        factor_envelope(st, c, &b.schur, &mut b.schur_factor, dependent);
    }

    /// `Φ` into `cb.residual` and `G` on its pattern into `sb.g` at `(t, q)`, for a projection.
    pub(crate) fn holonomic_rows<M: Mechanism>(
        &self,
        mechanism: &M,
        q_lanes: &mut [Lanes<f64>],
        cb: &mut ConstraintBuffers<f64>,
        sb: &mut SparseBuffers<f64>,
        t: f64,
        q: &[f64],
    ) {
        self.constraint_jacobian(mechanism, q_lanes, &mut cb.phi_lanes, &mut sb.g, &mut cb.residual, t, q);
    }

    /// The velocity residuals `Φ̇ = G q̇ + Φ_t` into `cb.rate` at `(t, q, q̇)`: one dual pass
    /// along `(q̇, 1)`.
    pub(crate) fn holonomic_rates<M: Mechanism>(
        &self,
        mechanism: &M,
        q_dual: &mut [Dual64],
        cb: &mut ConstraintBuffers<f64>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) {
        seed::along(q_dual, q, qdot);
        mechanism.constraints(Dual64::new(t, 1.0), q_dual, &mut cb.phi_dual);
        for (rate, phi) in cb.rate.iter_mut().zip(&cb.phi_dual) {
            *rate = phi.eps;
        }
    }

    /// `Σ_j |G_ij q̇_j|` of each holonomic row `i` (`G` as in `sb.g`) into `out` (m), with
    /// the number of its entries: the size of the terms its rate `Φ̇_i` sums.
    pub(crate) fn rate_terms(&self, sb: &SparseBuffers<f64>, qdot: &[f64], out: &mut [(f64, usize)]) {
        for (r, o) in out.iter_mut().enumerate() {
            let range = self.g_start[r]..self.g_start[r + 1];
            let sum = range.clone().map(|e| (sb.g[e] * qdot[self.g_column[e]]).abs()).sum();
            *o = (sum, range.len());
        }
    }

    /// The projection's step in the metric of `M` (factored by
    /// [`factor_mass`](Self::factor_mass)): `cb.step = M⁻¹ Gᵀ μ` with `(G M⁻¹ Gᵀ) μ = rhs` by
    /// the regularized, refined solve, `G` the one in `sb.g`.
    pub(crate) fn min_norm_step(
        &self,
        n: usize,
        sb: &mut SparseBuffers<f64>,
        cb: &mut ConstraintBuffers<f64>,
        rhs: crate::eom::constraints::Rhs,
    ) {
        let c = self.first.len();
        let ConstraintBuffers { gram_solution: mu, gram_dependent, residual, rate, step, right, refine, .. } = cb;
        self.schur(c, sb, gram_dependent);
        mu[..c].copy_from_slice(match rhs {
            crate::eom::constraints::Rhs::Residual => &residual[..c],
            crate::eom::constraints::Rhs::Rate => &rate[..c],
        });
        solve_envelope(self, c, sb, gram_dependent, (&mut mu[..], &mut right[..], &mut refine[..]));
        self.along_forces(n, c, sb, mu);
        step.copy_from_slice(&sb.dense);
        sb.dense.fill(0.0);
    }

    /// `M⁻¹ Gᵀ λ = L⁻¹ D^(−1/2) Uᵀ λ` into `b.dense` (zero on entry; the caller zeroes it
    /// after use).
    fn along_forces<S: Scalar>(&self, n: usize, c: usize, b: &mut SparseBuffers<S>, lambda: &[S]) {
        let st = self;
        for r in 0..c {
            let (from, to) = (st.reach_start[r], st.reach_start[r + 1]);
            let l = lambda[r];
            for (slot, &a) in st.reach[from..to].iter().enumerate() {
                b.dense[a] += b.u[from + slot] * l;
            }
        }
        for k in 0..n {
            let mut y = b.dense[k] * b.scale[k];
            let (mut i, mut di, row) = (st.parent[k], 1, st.offset[k]);
            while i != NONE {
                y -= b.mass[row + di] * b.dense[i];
                i = st.parent[i];
                di += 1;
            }
            b.dense[k] = y;
        }
    }
}

/// [`regularized_factor`](super::constraints::regularized_factor) on the envelope of `S`, by
/// rows: the same sums in the same order, the entries outside the envelope being zero.
fn factor_envelope<S: Scalar>(st: &SparseStructure, c: usize, schur: &[S], factor: &mut [S], dependent: &mut [bool]) {
    let at = |r: usize, s: usize| st.env_start[r] + s - st.first[r];
    let trace = (0..c).map(|i| schur[at(i, i)].re()).sum::<f64>();
    let shift = REGULARIZATION * trace / c.max(1) as f64;
    factor.copy_from_slice(schur);
    for i in 0..c {
        factor[at(i, i)] += S::from(shift);
        for j in st.first[i]..i {
            if dependent[j] {
                factor[at(i, j)] = S::zero();
                continue;
            }
            let mut l = factor[at(i, j)];
            for k in st.first[i].max(st.first[j])..j {
                if !dependent[k] {
                    l -= factor[at(i, k)] * factor[at(j, k)] * factor[at(k, k)];
                }
            }
            factor[at(i, j)] = l / factor[at(j, j)];
        }
        let mut d = factor[at(i, i)];
        for k in st.first[i]..i {
            if !dependent[k] {
                d -= factor[at(i, k)] * factor[at(i, k)] * factor[at(k, k)];
            }
        }
        dependent[i] = d.re().partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater);
        factor[at(i, i)] = d;
    }
}

/// [`regularized_solve`](super::constraints::regularized_solve) on the envelope, with `S` and
/// its factor from `sb` ([`SparseStructure::schur`]).
fn solve_envelope<S: Scalar>(
    st: &SparseStructure,
    c: usize,
    sb: &mut SparseBuffers<S>,
    dependent: &[bool],
    (rhs, right, residual): (&mut [S], &mut [S], &mut [S]),
) {
    let SparseBuffers { schur, schur_factor: factor, product, bound, .. } = sb;
    let at = |r: usize, s: usize| st.env_start[r] + s - st.first[r];
    // A row of the symmetric envelope holds at most 2 · width − 1 entries.
    let width = (0..c).map(|i| i + 1 - st.first[i]).max().unwrap_or(0);
    right[..c].copy_from_slice(&rhs[..c]);
    residual[..c].copy_from_slice(&rhs[..c]);
    rhs[..c].iter_mut().for_each(|v| *v = S::zero());
    for _ in 0..=REFINEMENTS {
        // z ← L⁻¹ z (skipping dependent columns).
        for i in 0..c {
            for k in st.first[i]..i {
                if !dependent[k] {
                    let l = factor[at(i, k)] * residual[k];
                    residual[i] -= l;
                }
            }
        }
        // z ← D⁻¹ z, then Lᵀ x = z by columns (0 on the dependent rows).
        for i in 0..c {
            residual[i] = if dependent[i] { S::zero() } else { residual[i] / factor[at(i, i)] };
        }
        for i in (0..c).rev() {
            if dependent[i] {
                residual[i] = S::zero();
                continue;
            }
            let x = residual[i];
            for k in st.first[i]..i {
                if !dependent[k] {
                    residual[k] -= factor[at(i, k)] * x;
                }
            }
        }
        for i in 0..c {
            rhs[i] += residual[i];
        }
        let (moved, size) = step_and_size(&residual[..c], &rhs[..c]);
        // ρ = r − S λ (S symmetric, stored by its lower envelope), and the sizes of its terms.
        product[..c].iter_mut().for_each(|v| *v = S::zero());
        bound[..c].iter_mut().for_each(|v| *v = 0.0);
        for i in 0..c {
            for s in st.first[i]..i {
                let v = schur[at(i, s)];
                product[i] += v * rhs[s];
                product[s] += v * rhs[i];
                bound[i] += (v.re() * rhs[s].re()).abs();
                bound[s] += (v.re() * rhs[i].re()).abs();
            }
            product[i] += schur[at(i, i)] * rhs[i];
            bound[i] += (schur[at(i, i)].re() * rhs[i].re()).abs();
        }
        let mut floor = true;
        for i in 0..c {
            residual[i] = right[i] - product[i];
            floor &= at_roundoff(residual[i].re(), bound[i] + right[i].re().abs(), 2 * width);
        }
        if refinement_stops(moved, size, floor) {
            break;
        }
    }
}

/// Each body's parent (`NONE`: the ground), depth below the ground, and the offset of its
/// ancestor list in a flat array of `Σ (depth + 1)` entries.
fn tree_layout(tree: &Tree) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
    let n = tree.len();
    let parent: Vec<usize> = tree.links().iter().map(|l| l.parent.unwrap_or(NONE)).collect();
    let mut depth = vec![0; n];
    for i in 0..n {
        if parent[i] != NONE {
            depth[i] = depth[parent[i]] + 1;
        }
    }
    let mut offset = vec![0; n + 1];
    for i in 0..n {
        offset[i + 1] = offset[i] + depth[i] + 1;
    }
    (parent, depth, offset)
}

/// The pattern of `G` (`m × n`), compressed by rows: the union of its nonzeros at the probe
/// states, as row starts and column indices.
fn jacobian_pattern<M: Mechanism>(mechanism: &M, n: usize, m: usize, probes: &ProbeStates) -> (Vec<usize>, Vec<usize>) {
    // Pattern of G: the union of its nonzeros at the probe states.
    let mut pattern = vec![false; m * n];
    let (mut q_lanes, mut phi_lanes) = (vec![Lanes::from_re(0.0); n], vec![Lanes::from_re(0.0); m]);
    let (mut dense, mut residual) = (vec![0.0; m * n], vec![0.0; m]);
    for k in 0..probes.len() {
        let (q, _, t) = probes.state(k);
        crate::eom::constraints::holonomic_chunks(
            mechanism,
            &mut q_lanes,
            &mut phi_lanes,
            &mut dense,
            &mut residual,
            t,
            q,
        );
        for (p, g) in pattern.iter_mut().zip(&dense) {
            *p |= *g != 0.0;
        }
    }
    let mut g_start = vec![0];
    let mut g_column = Vec::new();
    for r in 0..m {
        g_column.extend((0..n).filter(|&j| pattern[r * n + j]));
        g_start.push(g_column.len());
    }
    (g_start, g_column)
}

/// The pattern of `G` (`m × n`) at `(t, q)`, compressed by rows, found by bisection: every
/// row starts with the block of all coordinates; each round splits the blocks a row still
/// holds in two and keeps the halves along which the row's derivative is not zero, until
/// blocks are single columns. A test seeds the coordinates `j` of a block with `weight_j` (sizes
/// in `[½, 1]`, random signs: entries of a block do not cancel but by coincidence, which the
/// structure's verification catches) in one lane of a vector-dual pass; blocks that no row holds
/// together share a lane (greedy colouring), so a round of a mechanism whose rows involve few
/// coordinates costs a few passes and the whole search `O(log n)` of them.
fn bisected_pattern<M: Mechanism>(
    mechanism: &M,
    n: usize,
    m: usize,
    t: f64,
    q: &[f64],
    weight: &[f64],
) -> (Vec<usize>, Vec<usize>) {
    let (mut q_lanes, mut phi_lanes) = (vec![Lanes::from_re(0.0); n], vec![Lanes::from_re(0.0); m]);
    let t_lanes = Lanes::from_re(t);
    // Each row's blocks under test this round, and its columns found.
    let mut testing: Vec<Vec<(usize, usize)>> = vec![vec![(0, n)]; m];
    let mut columns: Vec<Vec<usize>> = vec![Vec::new(); m];
    // The blocks of one round partition the coordinates: a block is known by its first one.
    let mut id_of = vec![NONE; n];
    // Buffers kept across rounds (a row's lists are cleared, not dropped).
    let (mut blocks, mut rows_of, mut colour, mut taken) =
        (Vec::new(), Vec::<Vec<usize>>::new(), Vec::new(), Vec::new());
    let mut kept: Vec<Vec<(usize, usize)>> = vec![Vec::new(); m];
    while testing.iter().any(|t| !t.is_empty()) {
        blocks.clear();
        for (r, held) in testing.iter().enumerate() {
            for &(lo, hi) in held {
                if id_of[lo] == NONE {
                    id_of[lo] = blocks.len();
                    blocks.push((lo, hi));
                    if rows_of.len() < blocks.len() {
                        rows_of.push(Vec::new());
                    }
                    rows_of[blocks.len() - 1].clear();
                }
                rows_of[id_of[lo]].push(r);
            }
        }
        // Greedy colouring: a block takes the smallest colour no block sharing a row has.
        colour.clear();
        colour.resize(blocks.len(), NONE);
        for b in 0..blocks.len() {
            taken.clear();
            for &r in &rows_of[b] {
                taken.extend(testing[r].iter().map(|&(lo, _)| colour[id_of[lo]]).filter(|&c| c != NONE));
            }
            colour[b] = (0..).find(|c| !taken.contains(c)).unwrap_or(0);
        }
        let colours = colour.iter().map(|&c| c + 1).max().unwrap_or(0);
        for low in (0..colours).step_by(CHUNK) {
            for (d, &x) in q_lanes.iter_mut().zip(q) {
                *d = Lanes::from_re(x);
            }
            for (b, &(lo, hi)) in blocks.iter().enumerate() {
                if (low..low + CHUNK).contains(&colour[b]) {
                    for j in lo..hi {
                        let mut d = Lanes::from_re(q[j]).derivative(colour[b] - low);
                        d.eps *= weight[j];
                        q_lanes[j] = d;
                    }
                }
            }
            mechanism.constraints(t_lanes, &q_lanes, &mut phi_lanes);
            for (r, held) in testing.iter().enumerate() {
                for &(lo, hi) in held {
                    let c = colour[id_of[lo]];
                    if (low..low + CHUNK).contains(&c) && lane(&phi_lanes[r], c - low) != 0.0 {
                        kept[r].push((lo, hi));
                    }
                }
            }
        }
        for &(lo, _) in &blocks {
            id_of[lo] = NONE;
        }
        for (r, held) in kept.iter_mut().enumerate() {
            testing[r].clear();
            for (lo, hi) in held.drain(..) {
                if hi - lo == 1 {
                    columns[r].push(lo);
                } else {
                    let mid = lo + (hi - lo) / 2;
                    testing[r].extend([(lo, mid), (mid, hi)]);
                }
            }
        }
    }
    let mut g_start = vec![0];
    let mut g_column = Vec::new();
    for mut row in columns {
        row.sort_unstable();
        g_column.extend(row);
        g_start.push(g_column.len());
    }
    (g_start, g_column)
}

/// A greedy colouring of the columns of `G`: a column takes the smallest colour none of the
/// columns sharing a row with it has (`NONE` for a column in no row); returns the colours and
/// their number.
fn colour_columns(n: usize, g_start: &[usize], g_column: &[usize]) -> (Vec<usize>, usize) {
    let m = g_start.len() - 1;
    let mut rows_of = vec![Vec::new(); n];
    for r in 0..m {
        for &j in &g_column[g_start[r]..g_start[r + 1]] {
            rows_of[j].push(r);
        }
    }
    let mut colour = vec![NONE; n];
    let mut taken = Vec::new();
    for j in 0..n {
        if rows_of[j].is_empty() {
            continue;
        }
        taken.clear();
        for &r in &rows_of[j] {
            taken.extend(g_column[g_start[r]..g_start[r + 1]].iter().map(|&k| colour[k]).filter(|&c| c != NONE));
        }
        colour[j] = (0..).find(|c| !taken.contains(c)).unwrap_or(0);
    }
    let colours = colour.iter().filter(|&&c| c != NONE).map(|&c| c + 1).max().unwrap_or(0);
    (colour, colours)
}

/// Each row's reach: the ancestors of its columns, descending, compressed by rows.
fn reaches(parent: &[usize], g_start: &[usize], g_column: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let (n, m) = (parent.len(), g_start.len() - 1);
    let mut reach_start = vec![0];
    let mut reach = Vec::new();
    let mut mark = vec![false; n];
    for r in 0..m {
        let from = reach.len();
        for &j in &g_column[g_start[r]..g_start[r + 1]] {
            let mut a = j;
            while a != NONE && !mark[a] {
                mark[a] = true;
                reach.push(a);
                a = parent[a];
            }
        }
        reach[from..].sort_unstable_by(|a, b| b.cmp(a));
        for &a in &reach[from..] {
            mark[a] = false;
        }
        reach_start.push(reach.len());
    }
    (reach_start, reach)
}

/// The pairs of rows whose reaches overlap (each row with the earlier rows it meets, ascending,
/// compressed by rows), each row's first such row, and the envelope of the Schur complement.
#[allow(clippy::type_complexity)]
fn overlaps(n: usize, reach_start: &[usize], reach: &[usize]) -> (Vec<usize>, Vec<usize>, Vec<usize>, Vec<usize>) {
    let m = reach_start.len() - 1;
    let mut rows_reaching = vec![Vec::new(); n];
    for r in 0..m {
        for &a in &reach[reach_start[r]..reach_start[r + 1]] {
            rows_reaching[a].push(r);
        }
    }
    let (mut pair_start, mut pair, mut first, mut env_start) = (vec![0], Vec::new(), Vec::new(), vec![0]);
    let mut seen = vec![false; m];
    for r in 0..m {
        let from = pair.len();
        for &a in &reach[reach_start[r]..reach_start[r + 1]] {
            for &s in &rows_reaching[a] {
                if s <= r && !seen[s] {
                    seen[s] = true;
                    pair.push(s);
                }
            }
        }
        pair[from..].sort_unstable();
        for &s in &pair[from..] {
            seen[s] = false;
        }
        pair_start.push(pair.len());
        let f = pair[from..].first().copied().unwrap_or(r).min(r);
        first.push(f);
        env_start.push(env_start[r] + r - f + 1);
    }
    (pair_start, pair, first, env_start)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::{GROUND, GraphBody, GraphJoint, GraphMechanism, JointGraph};
    use crate::{accelerations, constraint_multipliers};
    use num_dual::Dual64;

    fn rod(name: &str, mass: f64, length: f64) -> GraphBody {
        GraphBody::rigid(name, mass, mass * length * length / 12.0)
    }

    /// The parallelogram chain of `scratch_pchain`: `windows + 1` cranks on the ground,
    /// `windows` couplers; `2 windows + 1` coordinates, `2 windows` loop rows. The bodies are
    /// and joints listed in the spanning tree's breadth-first order (cranks, then couplers), so
    /// that the graph declares its tree.
    fn chain(windows: usize) -> JointGraph {
        let mut g = JointGraph::new("pchain", 9.81);
        for k in 0..=windows {
            g = g.with_body(rod(&format!("crank{k}"), 1.0, 1.0));
        }
        for k in 0..windows {
            g = g.with_body(rod(&format!("coupler{k}"), 1.3, 1.0));
        }
        for k in 0..=windows {
            let (pivot, crank) = (format!("pivot{k}"), format!("crank{k}"));
            g = g.with_joint(GraphJoint::revolute(pivot, GROUND, [k as f64, 0.0], crank, [-0.5, 0.0]).absolute());
        }
        for k in 0..windows {
            let (crank, coupler) = (format!("crank{k}"), format!("coupler{k}"));
            g = g.with_joint(GraphJoint::revolute(format!("pin{k}a"), crank, [0.5, 0.0], coupler, [-0.5, 0.0]));
        }
        for k in 1..=windows {
            let (coupler, crank) = (format!("coupler{}", k - 1), format!("crank{k}"));
            g = g.with_joint(GraphJoint::revolute(format!("pin{k}b"), coupler, [0.5, 0.0], crank, [0.5, 0.0]));
        }
        g
    }

    /// The four-bar of the graph tests, bodies and joints in breadth-first order
    /// (so that the graph declares its tree).
    fn four_bar() -> JointGraph {
        JointGraph::new("four-bar", 9.81)
            .with_body(rod("crank", 1.0, 1.0))
            .with_body(rod("rocker", 1.0, 2.0))
            .with_body(rod("coupler", 1.0, 2.0))
            .with_joint(GraphJoint::revolute("θ2", GROUND, [0.0, 0.0], "crank", [-0.5, 0.0]))
            .with_joint(GraphJoint::revolute("θ4", GROUND, [2.0, 0.0], "rocker", [-1.0, 0.0]))
            .with_joint(GraphJoint::revolute("θ3", "crank", [0.5, 0.0], "coupler", [-1.0, 0.0]).absolute())
            .with_joint(GraphJoint::revolute("B", "coupler", [1.0, 0.0], "rocker", [1.0, 0.0]).closing())
    }

    /// The redundant parallelogram of the graph tests (one of its 4 rows is always dependent),
    /// bodies and joints in breadth-first order.
    fn redundant_parallelogram() -> JointGraph {
        JointGraph::new("parallelogram", 9.81)
            .with_body(rod("crank", 1.0, 1.0))
            .with_body(rod("rocker", 1.0, 1.0))
            .with_body(rod("third", 1.0, 1.0))
            .with_body(rod("coupler", 1.0, 2.0))
            .with_joint(GraphJoint::revolute("θ1", GROUND, [0.0, 0.0], "crank", [-0.5, 0.0]))
            .with_joint(GraphJoint::revolute("θ2", GROUND, [2.0, 0.0], "rocker", [-0.5, 0.0]))
            .with_joint(GraphJoint::revolute("θ3", GROUND, [1.0, 0.0], "third", [-0.5, 0.0]))
            .with_joint(GraphJoint::revolute("φ", "crank", [0.5, 0.0], "coupler", [-1.0, 0.0]))
            .with_joint(GraphJoint::revolute("B", "coupler", [1.0, 0.0], "rocker", [0.5, 0.0]))
            .with_joint(GraphJoint::revolute("C", "coupler", [0.0, 0.0], "third", [0.5, 0.0]))
    }

    /// The dense and the sparse model of one graph (the sparse structure forced at any size).
    fn both(graph: JointGraph) -> (Model<GraphMechanism>, Model<GraphMechanism>) {
        let dense = Model::new(GraphMechanism::new(graph).unwrap()).unwrap();
        let mut sparse = dense.clone();
        let (m, _) = dense.constraint_counts;
        let tree = dense.declared_tree().expect("a graph declares its spanning tree");
        sparse.sparse = SparseStructure::new(&dense.mechanism, tree, m, &ProbeStates::new(dense.n)).map(Box::new);
        assert!(sparse.sparse.is_some(), "the compressed Jacobians reproduce the dense ones");
        let mut dense = dense;
        dense.sparse = None;
        (dense, sparse)
    }

    /// A fixed sequence of numbers uniform in `[0, 1)` (a 64-bit LCG).
    fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// `max |a − b| / max(1, max |a|)`.
    fn relative(a: &[f64], b: &[f64]) -> f64 {
        let scale = a.iter().fold(1.0_f64, |s, v| s.max(v.abs()));
        a.iter().zip(b).fold(0.0_f64, |d, (x, y)| d.max((x - y).abs())) / scale
    }

    /// Sparse and dense `q̈` and `λ` agree at random states, in `f64` and in `Dual64` (the
    /// derivative of `q̈` along a random direction), for the parallelogram chain of 1, 3 and 8
    /// windows and for the crate's other constrained graph models.
    ///
    /// Tolerance `1e-11`, relative to `max(1, max |·|)`: both paths evaluate the same
    /// `S = G M⁻¹ Gᵀ` by different factorizations of `M` and summation orders (round-off
    /// ≈ n ε ≈ 4e-15 at n = 17), which the regularized solve with `S + μ̄ I` multiplies by the
    /// conditioning of `S` at the state. Measured at these states: at most 1e-14 on the chains
    /// and the four-bar, 7.4e-14 on the redundant parallelogram (a singular `S`, whose
    /// near-null direction the shift `μ̄` damps); `1e-11` leaves a factor 100 above that and is
    /// still orders of magnitude below what a missed entry of `G` or `M` would change.
    #[test]
    fn the_sparse_solve_is_the_dense_one() {
        let mut next = uniform(0x0123_4567_89AB_CDEF);
        let graphs = [
            ("chain of 1", chain(1)),
            ("chain of 3", chain(3)),
            ("chain of 8", chain(8)),
            ("four-bar", four_bar()),
            ("redundant parallelogram", redundant_parallelogram()),
        ];
        for (name, graph) in graphs {
            let (dense, sparse) = both(graph);
            let n = dense.n;
            for _ in 0..5 {
                let q: Vec<f64> = (0..n).map(|_| 6.0 * next() - 3.0).collect();
                let qdot: Vec<f64> = (0..n).map(|_| 4.0 * next() - 2.0).collect();
                let dq: Vec<f64> = (0..n).map(|_| 2.0 * next() - 1.0).collect();
                let t = next();
                let (mut wd, mut ws) = (dense.workspace(), sparse.workspace());
                let a = accelerations(&dense, &mut wd, t, &q, &qdot).unwrap().to_vec();
                let b = accelerations(&sparse, &mut ws, t, &q, &qdot).unwrap().to_vec();
                assert!(relative(&a, &b) < 1e-11, "{name} (n = {n}): q̈ {a:?} vs {b:?}");
                let la = constraint_multipliers(&dense, &mut wd, t, &q, &qdot).unwrap().to_vec();
                let lb = constraint_multipliers(&sparse, &mut ws, t, &q, &qdot).unwrap().to_vec();
                assert!(relative(&la, &lb) < 1e-11, "{name} (n = {n}): λ {la:?} vs {lb:?}");
                // Dual numbers flow through: ∂q̈/∂q along dq.
                let qd: Vec<Dual64> = q.iter().zip(&dq).map(|(&x, &d)| Dual64::new(x, d)).collect();
                let vd: Vec<Dual64> = qdot.iter().map(|&x| Dual64::from_re(x)).collect();
                let (mut wd, mut ws) = (dense.workspace_in::<Dual64>(), sparse.workspace_in::<Dual64>());
                let t = Dual64::from_re(t);
                let a: Vec<f64> = accelerations(&dense, &mut wd, t, &qd, &vd).unwrap().iter().map(|v| v.eps).collect();
                let b: Vec<f64> = accelerations(&sparse, &mut ws, t, &qd, &vd).unwrap().iter().map(|v| v.eps).collect();
                assert!(relative(&a, &b) < 1e-11, "{name} (n = {n}): ∂q̈ {a:?} vs {b:?}");
            }
        }
    }

    /// Rows whose entries cancel under equal weights (`q₀ − q₁`), a row of two coordinates
    /// apart, and a row that involves no coordinate.
    #[derive(Clone, Debug)]
    struct Rows(crate::Description);

    impl Mechanism for Rows {
        fn description(&self) -> &crate::Description {
            &self.0
        }
        fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
            for (pose, &x) in p.iter_mut().zip(q) {
                *pose = Pose::point(x, S::zero());
            }
        }
        fn constraints<S: Scalar>(&self, t: S, q: &[S], phi: &mut [S]) {
            phi[0] = q[0] - q[1];
            phi[1] = q[2].sin() + q[4] * q[4];
            phi[2] = t - S::one();
        }
    }

    /// The bisection finds the pattern the dense Jacobians show: for the chains of 1 to 40
    /// windows, the four-bar and the redundant parallelogram, the columns found at the first
    /// probe state by bisection are exactly the union of the nonzeros of the dense `G` at every
    /// probe state; and on rows that cancel under equal weights, skip a coordinate or involve
    /// none, exactly the columns written.
    #[test]
    fn bisection_finds_the_dense_pattern() {
        let graphs = [chain(1), chain(3), chain(8), chain(40), four_bar(), redundant_parallelogram()];
        for graph in graphs {
            let name = graph.name.clone();
            let model = Model::new_generic(GraphMechanism::new(graph).unwrap()).unwrap();
            let (n, (m, _)) = (model.n, model.constraint_counts);
            let probes = ProbeStates::new(n);
            let (q, _, t) = probes.state(0);
            let bisected = bisected_pattern(&model.mechanism, n, m, t, q, probes.direction(0));
            assert_eq!(bisected, jacobian_pattern(&model.mechanism, n, m, &probes), "{name}");
        }
        let mut description = crate::Description::new();
        for i in 0..5 {
            description = description.angle(format!("q{i}")).point(format!("b{i}"), 1.0);
        }
        let rows = Rows(description.constraint("a").constraint("b").constraint("c"));
        let probes = ProbeStates::new(5);
        let (q, _, t) = probes.state(0);
        let expected = (vec![0, 2, 4, 4], vec![0, 1, 2, 4]);
        assert_eq!(bisected_pattern(&rows, 5, 3, t, q, probes.direction(0)), expected);
        assert_eq!(jacobian_pattern(&rows, 5, 3, &probes), expected);
    }

    /// The projection after a step takes the sparse path on a sparse model and lands where the
    /// dense one does: from a consistent state (assembled with the first crank held) disturbed
    /// by 1e-6 in every coordinate and 1e-3 in every rate — a step's drift — both paths end on
    /// the constraints and agree to `1e-12`. Both take the same Gauss–Newton steps in the same
    /// metric and stop at the same `16 ε L` residual; what differs is the round-off of the two
    /// factorizations: measured, identical positions and rates within 1.4e-17; `1e-12` leaves
    /// room for other machines' summation orders and is far below the drift (1e-6)
    /// that either path removes.
    #[test]
    fn the_sparse_projection_is_the_dense_one() {
        let mut next = uniform(0x0FED_CBA9_8765_4321);
        // Near a parallelogram (cranks at 0.3, couplers at −0.3 relative) and a four-bar's
        // open branch.
        let near = |windows: usize| (0..=2 * windows).map(move |j| if j <= windows { 0.3 } else { -0.3 }).collect();
        let cases: [(&str, JointGraph, Vec<f64>); 3] = [
            ("chain of 3", chain(3), near(3)),
            ("chain of 8", chain(8), near(8)),
            ("four-bar", four_bar(), vec![0.5, 1.6, 0.3]),
        ];
        for (name, graph, guess) in cases {
            let (dense, sparse) = both(graph);
            let n = dense.n;
            let mut held = vec![false; n];
            held[0] = true;
            for _ in 0..5 {
                let guess = crate::State {
                    t: 0.0,
                    q: guess.iter().map(|x: &f64| x + 0.05 * next()).collect(),
                    qdot: (0..n).map(|_| 2.0 * next() - 1.0).collect(),
                };
                let start = crate::assemble(&dense, &guess, &held).unwrap();
                let q: Vec<f64> = start.q.iter().map(|x| x + 1e-6 * (2.0 * next() - 1.0)).collect();
                let qdot: Vec<f64> = start.qdot.iter().map(|x| x + 1e-3 * (2.0 * next() - 1.0)).collect();
                let (mut qa, mut va, mut qb, mut vb) = (q.clone(), qdot.clone(), q.clone(), qdot.clone());
                let (mut wd, mut ws) = (dense.workspace(), sparse.workspace());
                crate::project(&dense, &mut wd, 0.0, &mut qa, &mut va).unwrap();
                crate::project(&sparse, &mut ws, 0.0, &mut qb, &mut vb).unwrap();
                assert!(relative(&qa, &qb) < 1e-12, "{name}: q {qa:?} vs {qb:?}");
                assert!(relative(&va, &vb) < 1e-12, "{name}: q̇ {va:?} vs {vb:?}");
                let [position, velocity] = crate::eom::constraints::violation(&sparse, &mut ws, 0.0, &qb, &vb).unwrap();
                assert!(position < 1e-13 && velocity < 1e-12, "{name}: violation {position:e}, {velocity:e}");
            }
        }
    }
}
