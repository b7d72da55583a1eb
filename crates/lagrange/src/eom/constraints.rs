//! Constraints among the coordinates: holonomic `Φ(t, q) = 0` (m) and velocity constraints
//! `A(t, q) q̇ + b(t, q) = 0` (k), with multipliers.
//!
//! With `c = m + k` constraint rows `G = [Φ_q; A]` and convective terms
//! `γ = [d²/ds² Φ(t + s, q + s q̇); ∂(A q̇ + b)/∂q · q̇ + ∂(A q̇ + b)/∂t]`, the equations of
//! motion are
//!
//! ```text
//! M q̈ + Gᵀ λ = f,      G q̈ = −γ,
//! ```
//!
//! solved by the Schur complement on the factor `M = L D Lᵀ` the unconstrained solve already
//! has: `q̈_u = M⁻¹ f`, `U = D^(−1/2) L⁻¹ Gᵀ`, `S = G M⁻¹ Gᵀ = U Uᵀ` (c × c, symmetric positive
//! semi-definite by construction), `S λ = G q̈_u + γ`, `q̈ = q̈_u − L⁻ᵀ D^(−1/2) Uᵀ λ`. The
//! Schur complement reuses the unconstrained path unchanged (one factorization of `M`, `c`
//! forward substitutions and one backward substitution, a c × c factorization): for a loop
//! closed on a tree of `n` coordinates with a few constraints it costs little more than the
//! tree itself, where a null-space method would need a basis of `ker G` (an n × (n − c)
//! QR) at every evaluation.
//!
//! Redundant constraints (a parallelogram with a third parallel link) make `S` singular
//! everywhere, a linkage passing a singular configuration (a parallelogram laid flat) for an
//! instant; `q̈` stays unique. `S λ = r` is solved by the factor of `S + μ̄ I` and iterative
//! refinement ([`REGULARIZATION`], [`REFINEMENTS`]): exact to round-off wherever no row is
//! nearly dependent, smooth where rows become dependent (no rank decision that flips between
//! evaluations), and the minimum-norm `λ` at a redundancy (the reactions of redundant
//! constraints are not unique; this one spreads the force evenly).

use crate::eom::kinematics::LANES_FROM;
use crate::eom::sparse::SparseBuffers;
use crate::error::{Error, Stage};
use crate::mechanism::{CoordinateKind, Mechanism};
use crate::model::Model;
use crate::scalar::Scalar;
use crate::seed;
use crate::seed::{CHUNK, Lanes, lane};
use crate::workspace::Workspace;
use num_dual::{Dual, Dual2};

/// A constraint row is dependent on the rows before it when its LDLᵀ pivot of `S = G M⁻¹ Gᵀ`
/// falls below this fraction of its diagonal: 1e-10 leaves about 6 correct digits of the
/// remaining rows' multipliers at the worst accepted conditioning, and is far above the
/// round-off (≈ n ε) that an exactly dependent row leaves in its pivot.
pub(crate) const DEPENDENT: f64 = 1e-10;

/// A dependent row's own residual after elimination must be below this fraction of the
/// right-hand side's scale `max |G q̈_u + γ|` (plus an absolute `ε`): what exactly consistent
/// rows leave is round-off, ≈ 1e-15 relative.
pub(crate) const CONSISTENT: f64 = 1e-8;

/// The buffers of the constrained solve in scalar `S` (`c = m + k` rows, `n` coordinates).
#[derive(Clone, Debug)]
pub struct ConstraintBuffers<S: Scalar> {
    /// Constraint Jacobian `G = [Φ_q; A]` (c × n, row-major).
    pub jacobian: Vec<S>,
    /// Convective terms `γ` (c): `G q̈ + γ = 0` along every motion.
    pub convective: Vec<S>,
    /// Holonomic residuals `Φ(t, q)` (m).
    pub residual: Vec<S>,
    /// Velocity residuals (c): `Φ̇ = G_Φ q̇ + Φ_t` for the holonomic rows, `A q̇ + b` for the
    /// velocity rows.
    pub rate: Vec<S>,
    /// Multipliers `λ` (c): the generalized constraint force is `−Gᵀ λ`.
    pub multipliers: Vec<S>,
    /// Whether each row was found dependent on the rows before it (its `λ` is 0).
    pub dependent: Vec<bool>,
    /// `U = D^(−1/2) L⁻¹ Gᵀ` with `M = L D Lᵀ`, stored by rows (c × n): `G M⁻¹ Gᵀ = U Uᵀ`.
    pub(crate) mobility: Vec<S>,
    /// `S = G M⁻¹ Gᵀ` and its LDLᵀ factor (c × c).
    pub(crate) schur: Vec<S>,
    /// The LDLᵀ factor of `S + μ̄ I` (c × c) and the residual of the refined solve (c).
    pub(crate) schur_factor: Vec<S>,
    pub(crate) refine: Vec<S>,
    pub(crate) right: Vec<S>,
    /// Seeded copies of `q̇` (n), the holonomic residuals along the motion (m) and the
    /// velocity residuals (k).
    pub(crate) qdot_dual: Vec<Dual<S>>,
    /// The holonomic residuals seeded for one column of `G_Φ` (m), below `LANES_FROM`
    /// coordinates.
    pub(crate) phi_dual: Vec<Dual<S>>,
    /// Coordinates seeded for one chunk of columns of `G_Φ` (n) and the seeded residuals (m).
    pub(crate) q_lanes: Vec<Lanes<S>>,
    pub(crate) phi_lanes: Vec<Lanes<S>>,
    pub(crate) phi_dual2: Vec<Dual2<S>>,
    pub(crate) velocity_dual: Vec<Dual<S>>,
    /// Projection scratch: `G Gᵀ` and its factor (c × c), its solution (c), a step (n).
    pub(crate) gram: Vec<S>,
    pub(crate) gram_solution: Vec<S>,
    pub(crate) step: Vec<S>,
    /// The coordinates a damped Gauss–Newton step starts from (n).
    pub(crate) start: Vec<S>,
    pub(crate) gram_dependent: Vec<bool>,
    /// The state a watched projection started from (n, n).
    pub(crate) position_before: Vec<S>,
    pub(crate) velocity_before: Vec<S>,
    /// The body poses (B), for the scale of the positions a projection meets.
    pub(crate) poses: Vec<crate::Pose<S>>,
    /// Each row's `Σ_j |G_ij q̇_j|` and number of terms (c): the round-off scale of its rate.
    pub(crate) rate_terms: Vec<(f64, usize)>,
}

impl<S: Scalar> ConstraintBuffers<S> {
    pub(crate) fn new(n: usize, bodies: usize, holonomic: usize, velocity: usize) -> Self {
        let zero = S::zero();
        let c = holonomic + velocity;
        Self {
            jacobian: vec![zero; c * n],
            convective: vec![zero; c],
            residual: vec![zero; holonomic],
            rate: vec![zero; c],
            multipliers: vec![zero; c],
            dependent: vec![false; c],
            mobility: vec![zero; c * n],
            schur: vec![zero; c * c],
            schur_factor: vec![zero; c * c],
            refine: vec![zero; c],
            right: vec![zero; c],
            qdot_dual: vec![Dual::from_re(zero); n],
            phi_dual: vec![Dual::from_re(zero); holonomic],
            q_lanes: vec![Lanes::from_re(zero); n],
            phi_lanes: vec![Lanes::from_re(zero); holonomic],
            phi_dual2: vec![Dual2::from_re(zero); holonomic],
            velocity_dual: vec![Dual::from_re(zero); velocity],
            gram: vec![zero; c * c],
            gram_solution: vec![zero; c],
            step: vec![zero; n],
            start: vec![zero; n],
            gram_dependent: vec![false; c],
            position_before: vec![zero; n],
            velocity_before: vec![zero; n],
            poses: vec![crate::Pose::default(); bodies],
            rate_terms: vec![(0.0, 0); c],
        }
    }
}

/// Which constraint rows [`evaluate`] fills.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Rows {
    /// Holonomic and velocity rows.
    All,
    /// The holonomic rows only (`G_Φ`, `Φ`, `Φ̇`, `γ_Φ`).
    Holonomic,
    /// The velocity rows only (`A`, `A q̇ + b`, their `γ`).
    Velocity,
}

/// Fill `G`, `γ`, `Φ` and the velocity residuals at `(t, q, q̇)`: one dual pass of `Φ` per
/// coordinate (below `LANES_FROM` coordinates) or one vector-dual pass per chunk of [`CHUNK`]
/// coordinates (lane `k` seeds `q_{j0+k}`), one second-order pass of `Φ` along `(q̇, 1)`; for the velocity rows `n`
/// passes seeding `q̇_j` (the columns of `A`) and one pass along `(q̇, 1)` with `q̇` held
/// (the convective term `∂(A q̇ + b)/∂q · q̇ + ∂(A q̇ + b)/∂t`). `rows` picks which of the two
/// kinds to evaluate; the others keep what they hold.
#[allow(clippy::too_many_arguments)]
pub(crate) fn evaluate<M: Mechanism, S: Scalar>(
    mechanism: &M,
    (holonomic, velocity): (usize, usize),
    rows: Rows,
    q_dual: &mut [Dual<S>],
    q_dual2: &mut [Dual2<S>],
    buffers: &mut ConstraintBuffers<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) {
    let n = q.len();
    let ConstraintBuffers {
        jacobian,
        convective,
        residual,
        rate,
        qdot_dual,
        phi_dual,
        q_lanes,
        phi_lanes,
        phi_dual2,
        velocity_dual,
        ..
    } = buffers;
    if holonomic > 0 && rows != Rows::Velocity && n < LANES_FROM {
        // G_Φ column by column (one dual pass each), Φ itself once.
        let t_dual = Dual::from_re(t);
        seed::constant(q_dual, q);
        for j in 0..n {
            q_dual[j].eps = S::one();
            mechanism.constraints(t_dual, q_dual, phi_dual);
            for (i, phi) in phi_dual.iter().enumerate() {
                jacobian[i * n + j] = phi.eps;
                residual[i] = phi.re;
            }
            q_dual[j].eps = S::zero();
        }
    } else if holonomic > 0 && rows != Rows::Velocity {
        holonomic_chunks(mechanism, q_lanes, phi_lanes, jacobian, residual, t, q);
    }
    if holonomic > 0 && rows != Rows::Velocity {
        seed::along2(q_dual2, q, qdot);
        mechanism.constraints(Dual2::new(t, S::one(), S::zero()), q_dual2, phi_dual2);
        for (i, phi) in phi_dual2.iter().enumerate() {
            rate[i] = phi.v1;
            convective[i] = phi.v2;
        }
    }
    if velocity > 0 && rows != Rows::Holonomic {
        let t_dual = Dual::from_re(t);
        seed::constant(q_dual, q);
        seed::constant(qdot_dual, qdot);
        for j in 0..n {
            qdot_dual[j].eps = S::one();
            mechanism.velocity_constraint(t_dual, q_dual, qdot_dual, velocity_dual);
            for (i, r) in velocity_dual.iter().enumerate() {
                jacobian[(holonomic + i) * n + j] = r.eps;
            }
            qdot_dual[j].eps = S::zero();
        }
        seed::along(q_dual, q, qdot);
        mechanism.velocity_constraint(Dual::new(t, S::one()), q_dual, qdot_dual, velocity_dual);
        for (i, r) in velocity_dual.iter().enumerate() {
            rate[holonomic + i] = r.re;
            convective[holonomic + i] = r.eps;
        }
    }
}

/// `G_Φ` (m × n) and `Φ` in chunks of [`CHUNK`] columns: one vector-dual pass of the
/// constraints per chunk, lane `k` seeding `q_{j0+k}`.
pub(crate) fn holonomic_chunks<M: Mechanism, S: Scalar>(
    mechanism: &M,
    q_lanes: &mut [Lanes<S>],
    phi_lanes: &mut [Lanes<S>],
    jacobian: &mut [S],
    residual: &mut [S],
    t: S,
    q: &[S],
) {
    let n = q.len();
    let t_lanes = Lanes::from_re(t);
    for j0 in (0..n).step_by(CHUNK) {
        let width = seed::chunk(q_lanes, q, j0);
        mechanism.constraints(t_lanes, q_lanes, phi_lanes);
        for (i, phi) in phi_lanes.iter().enumerate() {
            for k in 0..width {
                jacobian[i * n + j0 + k] = lane(phi, k);
            }
        }
    }
    for (r, phi) in residual.iter_mut().zip(phi_lanes.iter()) {
        *r = phi.re;
    }
}

/// Turn the unconstrained `q̈_u` in `ws.qddot` into the constrained `q̈` and fill the
/// multipliers, with the LDLᵀ factor of `M` of the unconstrained solve (`ws.factor`, or the
/// stored factor of a constant `M`).
pub(crate) fn solve<M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &mut Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<(), Error> {
    let n = model.n;
    let counts = model.constraint_counts;
    let c = counts.0 + counts.1;
    let mut buffers = ws.constraints.take().expect("a constrained model's workspace has constraint buffers");
    evaluate(&model.mechanism, counts, Rows::All, &mut ws.q_dual, &mut ws.q_dual2, &mut buffers, t, q, qdot);
    let factor = if model.constant.is_some() { &ws.constant_factor } else { &ws.factor };
    let result = schur_solve(&mut buffers, &mut ws.qddot, factor, n, c, t, q);
    ws.constraints = Some(buffers);
    result
}

#[allow(clippy::too_many_arguments)]
fn schur_solve<S: Scalar>(
    b: &mut ConstraintBuffers<S>,
    qddot: &mut [S],
    factor: &[S],
    n: usize,
    c: usize,
    t: S,
    q: &[S],
) -> Result<(), Error> {
    if !(crate::eom::all_finite(&b.jacobian) && crate::eom::all_finite(&b.convective)) {
        return Err(crate::eom::non_finite(Stage::Constraints, t, q));
    }
    schur_complement(n, c, factor, &b.jacobian, &mut b.mobility, &mut b.schur, &mut b.step);
    // Right-hand side G q̈_u + γ in λ.
    for i in 0..c {
        b.multipliers[i] = dot(&b.jacobian[i * n..(i + 1) * n], qddot) + b.convective[i];
    }
    let ConstraintBuffers { schur, schur_factor, multipliers, dependent, refine, right, .. } = b;
    regularized_factor(c, REGULARIZATION, schur, schur_factor, dependent);
    regularized_solve(c, (schur, schur_factor, dependent), multipliers, right, refine);
    // q̈ = q̈_u − M⁻¹ Gᵀ λ.
    along_forces(n, c, factor, &b.mobility, &b.multipliers, &mut b.step);
    for (a, d) in qddot.iter_mut().zip(b.step.iter()) {
        *a -= *d;
    }
    Ok(())
}

/// `U = D^(−1/2) L⁻¹ Gᵀ` (stored by rows, `rows × n`) from the first `rows` rows of `g` and the
/// LDLᵀ factor of `M = L D Lᵀ`, forward substitutions only, and `S = G M⁻¹ Gᵀ = U Uᵀ`
/// (`rows × rows`); `scale` ends holding `D^(−1/2)` for [`along_forces`].
fn schur_complement<S: Scalar>(
    n: usize,
    rows: usize,
    factor: &[S],
    g: &[S],
    mobility: &mut [S],
    schur: &mut [S],
    scale: &mut [S],
) {
    mobility[..rows * n].copy_from_slice(&g[..rows * n]);
    for j in 0..n {
        scale[j] = factor[j * n + j].sqrt().recip();
    }
    for row in mobility[..rows * n].chunks_mut(n) {
        crate::linalg::ldlt_forward(n, factor, row);
        for (u, w) in row.iter_mut().zip(scale.iter()) {
            *u *= *w;
        }
    }
    for i in 0..rows {
        let u = &mobility[i * n..(i + 1) * n];
        for k in 0..=i {
            let s = dot(u, &mobility[k * n..(k + 1) * n]);
            schur[i * rows + k] = s;
            schur[k * rows + i] = s;
        }
    }
}

/// `M⁻¹ Gᵀ λ = L⁻ᵀ D^(−1/2) Uᵀ λ` into `scale` (which holds `D^(−1/2)` from
/// [`schur_complement`] on entry): one backward substitution.
fn along_forces<S: Scalar>(n: usize, rows: usize, factor: &[S], mobility: &[S], lambda: &[S], scale: &mut [S]) {
    for (j, w) in scale.iter_mut().enumerate() {
        let sum = (0..rows).fold(S::zero(), |sum, i| sum + mobility[i * n + j] * lambda[i]);
        *w *= sum;
    }
    crate::linalg::ldlt_backward(n, factor, scale);
}

/// The shift of the regularized constrained solve, relative to the mean diagonal of `S`:
/// `S + μ̄ I` with `μ̄ = REGULARIZATION · trace(S)/c` is factored instead of `S`, and the exact
/// `S λ = r` is approached by up to [`REFINEMENTS`] steps of iterative refinement. A direction
/// of `S` with eigenvalue `s ≫ μ̄` is solved to round-off in two or three steps (each divides
/// its error by `s/μ̄`); one with `s ≪ μ̄` (a constraint row that has become dependent on the
/// others, as at a linkage's flat position) is enforced only in part, smoothly, instead of by a
/// rank decision that flips from one evaluation to the next; one in between gains a factor
/// `1 + s/μ̄` per step. Shift and steps form a filter: the directions it leaves out are those
/// whose part of `λ` an integrator's round-off would dominate near a singular configuration
/// (there `Φ` sees a displacement along the crossing branch at distance `δ` only as `δ p`, and
/// the acceleration's solve divides once more by `δ`), the directions it keeps are solved
/// exactly. The pair was chosen by measuring the parallelogram chain's error against its exact
/// solution over many flat positions for several shifts and step counts: a smaller shift lets
/// the amplified round-off through (the error then grows as the tolerance tightens), a larger
/// one leaves out more of the vanishing rows' force (an error floor).
pub(crate) const REGULARIZATION: f64 = 1e-7;

/// Iterative refinement steps after the first solve with `S + μ̄ I`, at most: the refinement
/// stops earlier once a step changes `λ` by no more than round-off ([`SETTLED`]), or by no
/// more than [`NOISE_STEP`] with the residual down to the round-off of computing it
/// ([`at_roundoff`]).
pub(crate) const REFINEMENTS: usize = 16;

/// A refinement step that moves no entry of `λ` by more than this fraction of its largest
/// entry has settled it: round-off.
pub(crate) const SETTLED: f64 = 4.0 * f64::EPSILON;

/// The largest entry of a refinement step and of the solution it was added to (real parts;
/// derivative parts converge with them), for the tests `step ≤ SETTLED · size` and
/// `step ≤ NOISE_STEP · size`.
pub(crate) fn step_and_size<S: Scalar>(step: &[S], x: &[S]) -> (f64, f64) {
    let largest = |v: &[S]| v.iter().fold(0.0_f64, |m, v| m.max(v.re().abs()));
    (largest(step), largest(x))
}

/// A refinement step whose residual is at round-off ([`at_roundoff`]) ends the refinement only
/// if it moved `λ` by no more than this fraction: 100 times the steps measured at that point on
/// the 80-window parallelogram chain away from flat positions (1e-14, `ε` times the
/// conditioning of its `S`). Near a flat position a direction that the shift leaves nearly
/// free converges slowly with steps far larger than this, and goes on converging even where its
/// residual has sunk below round-off: stopping it there leaves out more of the vanishing rows'
/// force than the filter of [`REGULARIZATION`] and [`REFINEMENTS`] was chosen to.
pub(crate) const NOISE_STEP: f64 = 1e-12;

/// Whether iterative refinement stops after a step that moved `λ` by at most `moved` (largest
/// entry) when `λ`'s largest entry is `size`, with `at_roundoff` whether every row's residual
/// is at the round-off of computing it: the step settled `λ` ([`SETTLED`]), or the residual
/// is noise and the step no larger than noise makes ([`NOISE_STEP`]). The one policy of the
/// dense and the sparse solve.
pub(crate) fn refinement_stops(moved: f64, size: f64, at_roundoff: bool) -> bool {
    moved <= SETTLED * size || at_roundoff && moved <= NOISE_STEP * size
}

/// Whether a residual entry `ρ_i = r_i − Σ_j S_ij λ_j`, summed over `terms` products, is no
/// larger than the round-off of computing it, `γ_{terms+1} (|r_i| + Σ_j |S_ij| |λ_j|)` with
/// `bound` that sum of sizes (Higham, *Accuracy and Stability of Numerical Algorithms*, §3.5
/// and §12.1): below it a refinement step is computed from noise and moves `λ` by that noise
/// times the conditioning of `S`. Where `S` is ill-conditioned (a long chain of loops) the
/// steps stall there, orders of magnitude above [`SETTLED`]; where a direction is still
/// converging (a nearly dependent row, slowly, by design) its residual is far above it.
pub(crate) fn at_roundoff(residual: f64, bound: f64, terms: usize) -> bool {
    residual.abs() <= (terms + 1) as f64 * f64::EPSILON * bound
}

/// Factor `S + μ̄ I` (`S` symmetric positive semi-definite, c × c, row-major) into `factor`:
/// see [`REGULARIZATION`]. Only an all-zero or non-finite `S` leaves a pivot that is not
/// positive; such rows are marked in `dependent` and solved as 0.
pub(crate) fn regularized_factor<S: Scalar>(c: usize, mu: f64, schur: &[S], factor: &mut [S], dependent: &mut [bool]) {
    let trace = (0..c).map(|i| schur[i * c + i].re()).sum::<f64>();
    let shift = mu * trace / c.max(1) as f64;
    factor[..c * c].copy_from_slice(&schur[..c * c]);
    for i in 0..c {
        factor[i * c + i] += S::from(shift);
    }
    // Pivots of the shifted matrix are positive unless S is zero or not finite: no threshold.
    factor_with(c, factor, dependent, 0.0);
}

/// Solve `S λ = r` by the factor of `S + μ̄ I` and at most [`REFINEMENTS`] refinement steps: `rhs`
/// holds `r` on entry and `λ` on return; `right` (c) keeps `r`, `residual` (c) is scratch. A
/// single row (`c = 1`, where `μ̄` is `REGULARIZATION` times `S` itself and the refinement
/// always converges to `r / S`) is divided directly.
pub(crate) fn regularized_solve<S: Scalar>(
    c: usize,
    (schur, factor, dependent): (&[S], &[S], &[bool]),
    rhs: &mut [S],
    right: &mut [S],
    residual: &mut [S],
) {
    if c == 1 {
        rhs[0] = if dependent[0] { S::zero() } else { rhs[0] / schur[0] };
        return;
    }
    right[..c].copy_from_slice(&rhs[..c]);
    residual[..c].copy_from_slice(&rhs[..c]);
    rhs[..c].iter_mut().for_each(|v| *v = S::zero());
    for refinement in 0..=REFINEMENTS {
        // δ = (S + μ̄ I)⁻¹ ρ (in ρ's place), λ += δ, then ρ = r − S λ.
        forward_skipping(c, factor, dependent, residual);
        backward_skipping(c, factor, dependent, residual);
        for i in 0..c {
            rhs[i] += residual[i];
        }
        let (moved, size) = step_and_size(&residual[..c], &rhs[..c]);
        // (The residual and its round-off bound only where a next step or the stop rule reads
        // them.)
        if refinement == REFINEMENTS || refinement_stops(moved, size, false) {
            break;
        }
        let noise = moved <= NOISE_STEP * size;
        let mut floor = noise;
        for i in 0..c {
            let row = &schur[i * c..(i + 1) * c];
            residual[i] = right[i] - dot(row, &rhs[..c]);
            if floor {
                let bound =
                    row.iter().zip(&rhs[..c]).fold(right[i].re().abs(), |b, (s, x)| b + (s.re() * x.re()).abs());
                floor = at_roundoff(residual[i].re(), bound, c);
            }
        }
        if refinement_stops(moved, size, floor) {
            break;
        }
    }
}

/// LDLᵀ of the symmetric `c × c` matrix `a` in place (lower triangle; unit `L` below the
/// diagonal, `D` on it), rows in the order given. A row whose pivot is not above
/// [`DEPENDENT`] times its diagonal (zero, negative or NaN) depends on the rows before it: it
/// is marked in `dependent` and its column of `L` is zero.
pub(crate) fn factor_skipping<S: Scalar>(c: usize, a: &mut [S], dependent: &mut [bool]) {
    factor_with(c, a, dependent, DEPENDENT);
}

/// [`factor_skipping`] with a row dependent when its pivot is not above `threshold` times its
/// diagonal (or its diagonal is zero).
fn factor_with<S: Scalar>(c: usize, a: &mut [S], dependent: &mut [bool], threshold: f64) {
    for j in 0..c {
        let diagonal = a[j * c + j].re();
        let mut d = a[j * c + j];
        for k in (0..j).filter(|&k| !dependent[k]) {
            d -= a[j * c + k] * a[j * c + k] * a[k * c + k];
        }
        dependent[j] =
            d.re().partial_cmp(&(threshold * diagonal.abs())) != Some(std::cmp::Ordering::Greater) || diagonal == 0.0;
        a[j * c + j] = d;
        for i in j + 1..c {
            if dependent[j] {
                a[i * c + j] = S::zero();
                continue;
            }
            let mut l = a[i * c + j];
            for k in (0..j).filter(|&k| !dependent[k]) {
                l -= a[i * c + k] * a[j * c + k] * a[k * c + k];
            }
            a[i * c + j] = l / d;
        }
    }
}

/// `z ← L⁻¹ z` with the factor of [`factor_skipping`]: a dependent row is left holding its
/// residual after elimination (zero when it is consistent with the rows before it).
pub(crate) fn forward_skipping<S: Scalar>(c: usize, a: &[S], dependent: &[bool], z: &mut [S]) {
    for i in 0..c {
        for k in (0..i).filter(|&k| !dependent[k]) {
            let l = a[i * c + k] * z[k];
            z[i] -= l;
        }
    }
}

/// `z ← D⁻¹ Lᵀ⁻¹ z` after [`forward_skipping`]: the basic solution, 0 on the dependent rows.
pub(crate) fn backward_skipping<S: Scalar>(c: usize, a: &[S], dependent: &[bool], z: &mut [S]) {
    for i in (0..c).rev() {
        if dependent[i] {
            z[i] = S::zero();
            continue;
        }
        let mut v = z[i] / a[i * c + i];
        for k in (i + 1..c).filter(|&k| !dependent[k]) {
            v -= a[k * c + i] * z[k];
        }
        z[i] = v;
    }
}

/// `‖v‖₂`.
fn l2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn dot<S: Scalar>(a: &[S], b: &[S]) -> S {
    a.iter().zip(b).fold(S::zero(), |sum, (&x, &y)| sum + x * y)
}

/// The constraint rows at `(t, q, q̇)` of a constrained [`Model`]: `G = [Φ_q; A]` (c × n) into
/// `jacobian`, `Φ` (m) into `residual`, the velocity residuals `[Φ_q q̇ + Φ_t; A q̇ + b]` (c)
/// into `rate`.
///
/// # Errors
/// [`Error::NonFinite`] for a bad state or non-finite rows.
pub(crate) fn rows_at<M: Mechanism>(
    model: &Model<M>,
    ws: &mut Workspace<f64>,
    (t, q, qdot): (f64, &[f64], &[f64]),
    jacobian: &mut [f64],
    residual: &mut [f64],
    rate: &mut [f64],
) -> Result<(), Error> {
    crate::eom::check_state(model.n, t, q, Some(qdot))?;
    let mut b = ws.constraints.take().expect("a constrained model's workspace has constraint buffers");
    evaluate(&model.mechanism, model.constraint_counts, Rows::All, &mut ws.q_dual, &mut ws.q_dual2, &mut b, t, q, qdot);
    jacobian.copy_from_slice(&b.jacobian);
    residual.copy_from_slice(&b.residual);
    rate.copy_from_slice(&b.rate);
    ws.constraints = Some(b);
    if crate::eom::all_finite(jacobian) && crate::eom::all_finite(residual) && crate::eom::all_finite(rate) {
        Ok(())
    } else {
        Err(crate::eom::non_finite(Stage::Constraints, t, q))
    }
}

/// The constraint rows of one step of a discrete method from `q₀` to `q₁ = q₀ + Δq` over `h`
/// (docs/method.md#constraints): the holonomic rows at the end, `Φ(t₁, q₁)` into `residual` and
/// `Φ_q(t₁, q₁)` into `jacobian`; the velocity rows at the midpoint, `A(t_m, q_m) v + b(t_m, q_m)`
/// with `q_m = q₀ + Δq/2`, `v = Δq/h`, and their derivative with respect to `Δq`,
/// `½ ∂(A v + b)/∂q + A/h` (one dual pass per column, seeding `q_m` by ½ and `v` by `1/h`).
///
/// # Errors
/// [`Error::NonFinite`] for non-finite rows.
pub(crate) fn step_rows<M: Mechanism>(
    model: &Model<M>,
    ws: &mut Workspace<f64>,
    (t1, q1): (f64, &[f64]),
    (tm, qm, vm, h): (f64, &[f64], &[f64], f64),
    residual: &mut [f64],
    jacobian: &mut [f64],
) -> Result<(), Error> {
    let n = model.n;
    let (m, k) = model.constraint_counts;
    let mut b = ws.constraints.take().expect("a constrained model's workspace has constraint buffers");
    if m > 0 {
        evaluate(&model.mechanism, (m, k), Rows::Holonomic, &mut ws.q_dual, &mut ws.q_dual2, &mut b, t1, q1, vm);
        jacobian[..m * n].copy_from_slice(&b.jacobian[..m * n]);
        residual[..m].copy_from_slice(&b.residual);
    }
    if k > 0 {
        let t_dual = Dual::from_re(tm);
        seed::constant(&mut ws.q_dual, qm);
        seed::constant(&mut b.qdot_dual, vm);
        for j in 0..n {
            ws.q_dual[j].eps = 0.5;
            b.qdot_dual[j].eps = 1.0 / h;
            model.mechanism.velocity_constraint(t_dual, &ws.q_dual, &b.qdot_dual, &mut b.velocity_dual);
            for (i, r) in b.velocity_dual.iter().enumerate() {
                jacobian[(m + i) * n + j] = r.eps;
                residual[m + i] = r.re;
            }
            ws.q_dual[j].eps = 0.0;
            b.qdot_dual[j].eps = 0.0;
        }
    }
    ws.constraints = Some(b);
    if crate::eom::all_finite(jacobian) && crate::eom::all_finite(residual) {
        Ok(())
    } else {
        Err(crate::eom::non_finite(Stage::Constraints, t1, q1))
    }
}

/// Iterations of Gauss–Newton before [`Error::AssemblyFailed`]: quadratic convergence from any
/// guess within the basin needs a handful; 50 leaves room for guesses far from the manifold.
const ASSEMBLY_ITERATIONS: usize = 50;

/// The largest turn (rad) of any angle in one Gauss–Newton step of the projection: the
/// constraints' linear model in an angle (`sin`, `cos`) holds for turns well below a radian, and
/// a longer step from far off the constraints (a nearly dependent `G`) jumps to an unrelated
/// configuration rather than the nearest one.
const MAX_TURN: f64 = 0.5;

/// Halvings of a Gauss–Newton step of the projection until `‖Φ‖₂` falls; past them the step is
/// taken as it is (a step of 2⁻¹⁰ of its length that still cannot reduce `‖Φ‖₂` sits at a
/// stationary point of `‖Φ‖₂`, where the iteration fails anyway).
const HALVINGS: usize = 10;

/// The positions are on `Φ = 0` when `max |Φ| ≤ POSITION_TOLERANCE · L`, with `L` the scale
/// of the positions the constraints compare ([`position_scale`]): a few ε of the round-off of
/// evaluating `Φ` itself (a difference of two positions of size `L`), what Gauss–Newton
/// reaches in one or two iterations from a step's `O(tol)` drift, and far enough above it that
/// round-off cannot stall the loop.
pub(crate) const POSITION_TOLERANCE: f64 = 16.0 * f64::EPSILON;

/// A Gauss–Newton iteration that no longer halves `max |Φ|` has reached the round-off of `Φ`
/// when `max |Φ|` is within this factor of [`POSITION_TOLERANCE`]` · L`: a position found by
/// forward kinematics sums `d` terms of size up to `L`, with a round-off of about `d ε L`, so
/// the band covers chains thousands of bodies deep, while a loop that cannot close stalls at
/// the size of its gap, orders of magnitude above.
const ROUNDOFF_BAND: f64 = 1e3;

/// The shift of an assembly's solves with `G Gᵀ` (coordinates held, the plain smallest
/// change), relative to its mean diagonal: an assembly from far off must remove a
/// near-dependent row's residual almost completely (the refined solve is exact for every
/// direction with eigenvalue above `1e-15` of the mean), yet stay continuous where a row
/// becomes exactly dependent. A projection in the mass metric shifts by [`REGULARIZATION`]
/// instead: it leaves free the same nearly dependent directions that the accelerations leave
/// free, so that near a singular configuration the projection does not push the state along
/// a direction the equations of motion do not constrain (where it does, it turns the velocity
/// onto the crossing branch).
const ASSEMBLY_REGULARIZATION: f64 = 1e-15;

/// The scale `L` of the positions, from the bodies' `poses` at `(t, q)`: `1 + max(|x_b|, |y_b|)` and
/// `|q_j|` over the length coordinates. Angles do not enter (a turned crank is not larger), and
/// a mechanism far from the origin gets the tolerance its positions' round-off needs: the
/// outcome does not depend on where the world's origin is.
fn position_scale<M: Mechanism>(model: &Model<M>, poses: &[crate::Pose<f64>], q: &[f64]) -> f64 {
    let bodies = poses.iter().fold(0.0_f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    let lengths = model
        .coordinates()
        .iter()
        .zip(q)
        .filter(|(c, _)| c.kind == CoordinateKind::Length)
        .fold(0.0_f64, |m, (_, v)| m.max(v.abs()));
    let scale = 1.0 + bodies.max(lengths);
    if scale.is_finite() { scale } else { 1.0 }
}

/// The seeded-coordinate buffers of the projection's passes: vector duals (sparse path), duals
/// and second-order duals (dense path).
type Seeds<'a> = (&'a mut [Lanes<f64>], &'a mut [Dual<f64>], &'a mut [Dual2<f64>]);

/// `Φ` and `G`'s holonomic rows at `(t, q)` (and, on the dense path, `Φ̇` along `q̇`).
fn holonomic_rows<M: Mechanism>(
    model: &Model<M>,
    sparse: Option<&crate::eom::sparse::SparseStructure>,
    (b, sb): (&mut ConstraintBuffers<f64>, &mut Option<SparseBuffers<f64>>),
    (q_lanes, q_dual, q_dual2): Seeds,
    (t, q, qdot): (f64, &[f64], &[f64]),
) {
    match (sparse, sb.as_mut()) {
        (Some(st), Some(sb)) => st.holonomic_rows(&model.mechanism, q_lanes, b, sb, t, q),
        _ => evaluate(&model.mechanism, model.constraint_counts, Rows::Holonomic, q_dual, q_dual2, b, t, q, qdot),
    }
}

/// The velocity residuals at `(t, q, q̇)` into `b.rate`: the holonomic rows' `Φ̇` (the sparse
/// path's own pass; the dense path's holonomic evaluation at this `q` already holds them) and
/// the velocity constraints' rows with their `A` in `G`.
fn velocity_rows<M: Mechanism>(
    model: &Model<M>,
    sparse: Option<&crate::eom::sparse::SparseStructure>,
    (b, sb): (&mut ConstraintBuffers<f64>, &mut Option<SparseBuffers<f64>>),
    (_, q_dual, q_dual2): Seeds,
    (t, q, qdot): (f64, &[f64], &[f64]),
) {
    match (sparse, sb.as_mut()) {
        (Some(st), Some(_)) => st.holonomic_rates(&model.mechanism, q_dual, b, t, q, qdot),
        _ => evaluate(&model.mechanism, model.constraint_counts, Rows::Velocity, q_dual, q_dual2, b, t, q, qdot),
    }
}

/// Whether every velocity residual `ρ_i` (`b.rate`) is no larger than the round-off of summing
/// its terms `G_ij q̇_j` ([`at_roundoff`]: `|ρ_i| ≤ (terms + 1) ε Σ_j |G_ij q̇_j|`, `G` as the
/// last evaluation left it). A correction of that size is noise, so it is not made; over a run
/// the residual left stays within this bound plus one step's drift.
fn rates_at_roundoff(
    sparse: Option<&crate::eom::sparse::SparseStructure>,
    (b, sb): (&mut ConstraintBuffers<f64>, &Option<SparseBuffers<f64>>),
    n: usize,
    c: usize,
    qdot: &[f64],
) -> bool {
    if let (Some(st), Some(sb)) = (sparse, sb.as_ref()) {
        st.rate_terms(sb, qdot, &mut b.rate_terms[..c]);
    } else {
        for (i, o) in b.rate_terms[..c].iter_mut().enumerate() {
            let row = &b.jacobian[i * n..(i + 1) * n];
            *o = (row.iter().zip(qdot).map(|(g, v)| (g * v).abs()).sum(), n);
        }
    }
    b.rate[..c].iter().zip(&b.rate_terms[..c]).all(|(&r, &(bound, terms))| at_roundoff(r, bound, terms))
}

/// A projection after an integration step that turns an angle by more than this (rad), moves a
/// length coordinate by more than this fraction of the positions' scale `L`, or changes a
/// velocity by more than this fraction of the largest one (plus [`VELOCITY_FLOOR`]) did not
/// remove a step's drift: the step left the branch it started on (a singular configuration
/// passed too closely, a step too coarse for the motion, or constraints that no smooth motion
/// from the state meets). A resolved step drifts by its local error, orders of magnitude less.
const JUMP: f64 = 0.5;

/// The absolute part of the velocity bound of [`JUMP`], so that a mechanism at rest is not
/// judged by the round-off of its zero velocity.
const VELOCITY_FLOOR: f64 = 1e-6;

/// [`project`] with some coordinates held: `held[j]` keeps `q_j` and `q̇_j` as given. With
/// `watch`, a correction beyond [`JUMP`] is an error instead of a new state.
pub(crate) fn project_holding<M: Mechanism>(
    model: &Model<M>,
    ws: &mut Workspace<f64>,
    t: f64,
    (q, qdot): (&mut [f64], &mut [f64]),
    held: Option<&[bool]>,
    watch: bool,
) -> Result<(), Error> {
    crate::eom::check_state(model.n, t, q, Some(qdot))?;
    let n = model.n;
    let (m, k) = model.constraint_counts;
    // The mass metric of the corrections: M's factor at the state the projection starts from
    // (assembling coordinates held fixed take the plain smallest change instead).
    let weighted = held.is_none();
    // A tree with many loops solves in its sparse structure (no coordinate is held there).
    let sparse = if weighted { model.sparse.as_deref() } else { None };
    let mut sb = if sparse.is_some() { ws.sparse.take() } else { None };
    let mut b = ws.constraints.take().expect("a constrained model's workspace has constraint buffers");
    let result = (|| {
        model.mechanism.poses(t, q, &mut b.poses);
        let scale = position_scale(model, &b.poses, q);
        if watch {
            b.position_before.copy_from_slice(q);
            b.velocity_before.copy_from_slice(qdot);
        }
        // Φ and G at q, then — where the positions hold — the rates there: a state whose
        // residuals are both at their round-off is left as it is, without the mass metric's
        // factor (most projections after a step at a fine setting).
        holonomic_rows(
            model,
            sparse,
            (&mut b, &mut sb),
            (&mut ws.q_lanes, &mut ws.q_dual, &mut ws.q_dual2),
            (t, q, qdot),
        );
        let positions_hold = largest(&b.residual[..m]).1 <= POSITION_TOLERANCE * scale;
        if positions_hold {
            velocity_rows(
                model,
                sparse,
                (&mut b, &mut sb),
                (&mut ws.q_lanes, &mut ws.q_dual, &mut ws.q_dual2),
                (t, q, qdot),
            );
            if rates_at_roundoff(sparse, (&mut b, &sb), n, m + k, qdot) {
                return Ok(());
            }
        }
        // The mass metric of the corrections: M's factor at the state the projection starts
        // from (assembling coordinates held fixed take the plain smallest change instead).
        if let (Some(st), Some(sb)) = (sparse, sb.as_mut()) {
            st.factor_mass(model, &mut ws.q_lanes, &mut ws.poses_lanes, sb, t, q)?;
        } else if weighted && model.constant.is_none() {
            crate::eom::factor_mass_matrix(model, ws, t, q)?;
        }
        let weight: Option<&[f64]> = match (weighted, model.constant.is_some()) {
            (false, _) => None,
            (true, true) => Some(&ws.constant_factor),
            (true, false) => Some(&ws.factor),
        };
        // The smallest step that removes the first-order residual `rhs`.
        let step = |b: &mut ConstraintBuffers<f64>, sb: &mut Option<SparseBuffers<f64>>, rows: usize, rhs: Rhs| match (
            sparse,
            sb.as_mut(),
        ) {
            (Some(st), Some(sb)) => st.min_norm_step(n, sb, b, rhs),
            _ => min_norm_step(b, n, rows, rhs, held, weight),
        };
        if !positions_hold {
            // Φ and G at a trial q.
            let mut evaluate_at = |b: &mut ConstraintBuffers<f64>, sb: &mut Option<SparseBuffers<f64>>, q: &[f64]| {
                holonomic_rows(
                    model,
                    sparse,
                    (b, sb),
                    (&mut ws.q_lanes, &mut ws.q_dual, &mut ws.q_dual2),
                    (t, q, qdot),
                );
            };
            correct_positions(model, t, q, scale, (&mut b, &mut sb), &mut evaluate_at, &step)?;
            // Velocities at the final q: the holonomic rows (G and Φ̇) are those of the last
            // Gauss–Newton evaluation there.
            velocity_rows(
                model,
                sparse,
                (&mut b, &mut sb),
                (&mut ws.q_lanes, &mut ws.q_dual, &mut ws.q_dual2),
                (t, q, qdot),
            );
        }
        // Velocities: one exact linear step onto G q̇ + Φ_t = 0 and A q̇ + b = 0.
        step(&mut b, &mut sb, m + k, Rhs::Rate);
        for (v, d) in qdot.iter_mut().zip(&b.step) {
            *v -= d;
        }
        if watch {
            jump_check(model, &b, t, (q, qdot), scale)?;
        }
        Ok(())
    })();
    ws.constraints = Some(b);
    if sb.is_some() {
        ws.sparse = sb;
    }
    result
}

/// The Gauss–Newton iteration of a projection on the positions: smallest steps
/// (`step(…, Rhs::Residual)`) onto `Φ(t, q) = 0`, damped where the linear model does not hold,
/// until `max |Φ|` is below [`POSITION_TOLERANCE`]` · scale` or stalls at its round-off
/// ([`ROUNDOFF_BAND`]), from `Φ` and `G` evaluated at `q` on entry. `evaluate_at` refreshes
/// them at a trial `q`.
fn correct_positions<M: Mechanism>(
    model: &Model<M>,
    t: f64,
    q: &mut [f64],
    scale: f64,
    (b, sb): (&mut ConstraintBuffers<f64>, &mut Option<SparseBuffers<f64>>),
    evaluate_at: &mut impl FnMut(&mut ConstraintBuffers<f64>, &mut Option<SparseBuffers<f64>>, &[f64]),
    step: &impl Fn(&mut ConstraintBuffers<f64>, &mut Option<SparseBuffers<f64>>, usize, Rhs),
) -> Result<(), Error> {
    let m = model.constraint_counts.0;
    let (mut iterations, mut previous) = (0, f64::INFINITY);
    loop {
        let (worst, value) = largest(&b.residual);
        if !value.is_finite() {
            return Err(crate::eom::non_finite(Stage::Constraints, t, q));
        }
        if value <= POSITION_TOLERANCE * scale
            || iterations > 0 && value > 0.5 * previous && value <= ROUNDOFF_BAND * POSITION_TOLERANCE * scale
        {
            // Converged, or stalled at the round-off of Φ.
            break;
        }
        previous = value;
        if iterations == ASSEMBLY_ITERATIONS {
            return Err(Error::AssemblyFailed {
                t,
                constraint: model.mechanism.description().constraint_name(worst).to_string(),
                residual: value,
                iterations,
            });
        }
        // Smallest step: Δq = −Gᵀ (G Gᵀ)⁻¹ Φ over the free coordinates.
        step(b, sb, m, Rhs::Residual);
        // Damped where the linear model does not hold: no angle turned by more than
        // MAX_TURN, then halved until ‖Φ‖₂ falls. Near the constraints (every projection
        // after an integration step) the full step is taken at no extra cost.
        let norm = l2(&b.residual);
        let turn = largest_turn(model, &b.step);
        let mut fraction = if turn > MAX_TURN { MAX_TURN / turn } else { 1.0 };
        b.start.copy_from_slice(q);
        for halving in 0..=HALVINGS {
            for ((qi, start), d) in q.iter_mut().zip(&b.start).zip(&b.step) {
                *qi = start - fraction * d;
            }
            evaluate_at(b, sb, q);
            let trial = l2(&b.residual);
            if trial < norm || largest(&b.residual).1 <= POSITION_TOLERANCE * scale || halving == HALVINGS {
                break;
            }
            fraction *= 0.5;
        }
        iterations += 1;
    }
    Ok(())
}

/// The largest turn `|Δq_j|` over the angle coordinates of a step.
fn largest_turn<M: Mechanism>(model: &Model<M>, step: &[f64]) -> f64 {
    model
        .coordinates()
        .iter()
        .zip(step)
        .filter(|(c, _)| c.kind == CoordinateKind::Angle)
        .fold(0.0_f64, |a, (_, d)| a.max(d.abs()))
}

/// The error of a projection after a step that moved the state beyond [`JUMP`].
fn jump_check<M: Mechanism>(
    model: &Model<M>,
    b: &ConstraintBuffers<f64>,
    t: f64,
    (q, qdot): (&[f64], &[f64]),
    scale: f64,
) -> Result<(), Error> {
    let coordinates = &model.mechanism.description().coordinates;
    for (j, coordinate) in coordinates.iter().enumerate() {
        let moved = (q[j] - b.position_before[j]).abs();
        let limit = if coordinate.kind == CoordinateKind::Angle { JUMP } else { JUMP * scale };
        if moved > limit || moved.is_nan() {
            return Err(Error::Diverged {
                t,
                step: 0,
                quantity: format!(
                    "the projection onto the constraints after the step moved {} by {moved:.3e} {} (more than {limit}): \
                     the step left the branch it started on (a singular configuration passed too closely, a step too \
                     coarse for the motion, or constraints that no smooth motion from this state meets)",
                    coordinate.name,
                    coordinate.unit()
                ),
            });
        }
    }
    let speed = b.velocity_before.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let limit = JUMP * speed + VELOCITY_FLOOR;
    if let Some(j) = (0..q.len()).find(|&j| {
        matches!((qdot[j] - b.velocity_before[j]).abs().partial_cmp(&limit), Some(std::cmp::Ordering::Greater) | None)
    }) {
        let changed = (qdot[j] - b.velocity_before[j]).abs();
        return Err(Error::Diverged {
            t,
            step: 0,
            quantity: format!(
                "the projection onto the constraints after the step changed the rate of {} by {changed:.3e} (more than \
                 {JUMP} of the largest rate): the step left the branch it started on (a singular configuration passed \
                 too closely, or a step too coarse for the motion)",
                coordinates[j].name
            ),
        });
    }
    Ok(())
}

/// The smallest change that moves the first-order residual of the first `rows` rows of `G`
/// by `rhs`, into `step`. With the mass matrix's factor (`weight`, no coordinate held): in
/// the metric of `M`, `step = M⁻¹ Gᵀ μ` with `(G M⁻¹ Gᵀ) μ = rhs` — the correction an impulse
/// along the constraint forces makes, which leaves the kinetic energy of the motion along the
/// constraints untouched (a Euclidean correction of a drift along the constraint forces also
/// changes the speed along the motion). Otherwise `step = Gᵀ μ` with `(G Gᵀ) μ = rhs` over the
/// free coordinates (the held columns removed).
fn min_norm_step(
    b: &mut ConstraintBuffers<f64>,
    n: usize,
    rows: usize,
    rhs: Rhs,
    held: Option<&[bool]>,
    weight: Option<&[f64]>,
) {
    let free = |j: usize| held.is_none_or(|h| !h[j]);
    let ConstraintBuffers {
        jacobian: g,
        gram,
        gram_solution: mu,
        gram_dependent: dependent,
        residual,
        rate,
        step,
        schur_factor: gram_factor,
        right,
        refine: residual_scratch,
        mobility,
        ..
    } = b;
    let rhs: &[f64] = match rhs {
        Rhs::Residual => residual,
        Rhs::Rate => rate,
    };
    if let Some(factor) = weight {
        debug_assert!(held.is_none(), "the mass metric is for projections that hold no coordinate");
        // In the metric of M: U Uᵀ μ = rhs with U = D^(−1/2) L⁻¹ Gᵀ, step = M⁻¹ Gᵀ μ.
        schur_complement(n, rows, factor, g, mobility, gram, step);
        regularized_factor(rows, REGULARIZATION, gram, gram_factor, dependent);
        mu[..rows].copy_from_slice(&rhs[..rows]);
        regularized_solve(rows, (gram, gram_factor, dependent), mu, right, residual_scratch);
        along_forces(n, rows, factor, mobility, mu, step);
        return;
    }
    for i in 0..rows {
        for l in 0..=i {
            let s: f64 = (0..n).filter(|&j| free(j)).map(|j| g[i * n + j] * g[l * n + j]).sum();
            gram[i * rows + l] = s;
        }
    }
    for i in 0..rows {
        for l in 0..i {
            gram[l * rows + i] = gram[i * rows + l];
        }
    }
    regularized_factor(rows, ASSEMBLY_REGULARIZATION, gram, gram_factor, dependent);
    mu[..rows].copy_from_slice(&rhs[..rows]);
    regularized_solve(rows, (gram, gram_factor, dependent), mu, right, residual_scratch);
    for j in 0..n {
        step[j] = if free(j) { (0..rows).map(|i| g[i * n + j] * mu[i]).sum() } else { 0.0 };
    }
}

/// Which residual a projection step removes.
#[derive(Clone, Copy)]
pub(crate) enum Rhs {
    /// `Φ` (positions).
    Residual,
    /// `G q̇ + Φ_t`, `A q̇ + b` (velocities).
    Rate,
}

/// The index and size of the largest `|v_i|`.
fn largest(v: &[f64]) -> (usize, f64) {
    v.iter().enumerate().fold((0, 0.0), |(i, m), (j, x)| if x.abs() > m || x.is_nan() { (j, x.abs()) } else { (i, m) })
}

/// `[max |Φ|, max |rate|]` at `(t, q, q̇)`.
pub(crate) fn violation<M: Mechanism>(
    model: &Model<M>,
    ws: &mut Workspace<f64>,
    t: f64,
    q: &[f64],
    qdot: &[f64],
) -> Result<[f64; 2], Error> {
    crate::eom::check_state(model.n, t, q, Some(qdot))?;
    let (m, k) = model.constraint_counts;
    let mut b = ws.constraints.take().expect("a constrained model's workspace has constraint buffers");
    // Φ and Φ̇ = Φ_q q̇ + Φ_t from one dual pass along (q̇, 1); A q̇ + b from one real pass: no
    // Jacobian is needed for the residuals.
    if m > 0 {
        seed::along(&mut ws.q_dual, q, qdot);
        model.mechanism.constraints(Dual::new(t, 1.0), &ws.q_dual, &mut b.phi_dual);
        for (i, phi) in b.phi_dual.iter().enumerate() {
            b.residual[i] = phi.re;
            b.rate[i] = phi.eps;
        }
    }
    if k > 0 {
        seed::constant(&mut ws.q_dual, q);
        seed::constant(&mut b.qdot_dual, qdot);
        model.mechanism.velocity_constraint(Dual::from_re(t), &ws.q_dual, &b.qdot_dual, &mut b.velocity_dual);
        for (i, r) in b.velocity_dual.iter().enumerate() {
            b.rate[m + i] = r.re;
        }
    }
    let result = [largest(&b.residual[..m]).1, largest(&b.rate[..m + k]).1];
    ws.constraints = Some(b);
    Ok(result)
}

/// Project `(q, q̇)` at time `t` onto the constraints of a constrained [`Model`], in place, by
/// the smallest change in the metric of the mass matrix `M` (factored once, at the given
/// `q`): Gauss–Newton `q ← q − α M⁻¹ Gᵀ (G M⁻¹ Gᵀ)⁻¹ Φ` until
/// `max |Φ| ≤ 16 ε L`, `L` the scale of the positions (`α = 1` near the constraints; from
/// far off, `α` keeps every angle's turn within half a radian and is halved until `‖Φ‖₂`
/// falls), then one step `q̇ ← q̇ − M⁻¹ Gᵀ (G M⁻¹ Gᵀ)⁻¹ r` with `r` the velocity residuals
/// `G q̇ + Φ_t` and `A q̇ + b`. Both solves are shifted and refined as the accelerations' are
/// (a shift of `1e-7` of the mean diagonal of `G M⁻¹ Gᵀ`, docs/method.md#constraints). A model
/// without constraints is left as it is. The integrators call
/// it after every step.
///
/// # Errors
/// [`Error::AssemblyFailed`] when Gauss–Newton does not reach `Φ = 0` in 50 iterations;
/// [`Error::NonFinite`] for a bad state or non-finite constraints.
pub fn project<M: Mechanism>(
    model: &Model<M>,
    ws: &mut Workspace<f64>,
    t: f64,
    q: &mut [f64],
    qdot: &mut [f64],
) -> Result<(), Error> {
    if !model.is_constrained() {
        return Ok(());
    }
    project_holding(model, ws, t, (q, qdot), None, false)
}

/// [`project`] after an integration step: a correction larger than a step's drift can be
/// ([`JUMP`]) is an error.
///
/// # Errors
/// As [`project`]; [`Error::Diverged`] naming the coordinate whose position or rate the
/// projection changed beyond [`JUMP`].
pub(crate) fn project_step<M: Mechanism>(
    model: &Model<M>,
    ws: &mut Workspace<f64>,
    t: f64,
    q: &mut [f64],
    qdot: &mut [f64],
) -> Result<(), Error> {
    if !model.is_constrained() {
        return Ok(());
    }
    project_holding(model, ws, t, (q, qdot), None, true)
}

/// A consistent initial state from an approximate one: the coordinates marked in `held` keep
/// their given values (and velocities), the others are moved as little as possible onto
/// `Φ(t, q) = 0`, and the free velocities onto `G q̇ + Φ_t = 0`, `A q̇ + b = 0`. For a four-bar,
/// hold the crank angle and its rate: the coupler and rocker angles and rates follow, on the
/// branch nearest the guess.
///
/// # Errors
/// [`Error::DimensionMismatch`] for a `held` of the wrong length; [`Error::AssemblyFailed`]
/// naming the constraint that cannot be met (links that cannot close, or a guess outside the
/// basin of Gauss–Newton); [`Error::NonFinite`].
pub fn assemble<M: Mechanism>(
    model: &Model<M>,
    approximate: &crate::State,
    held: &[bool],
) -> Result<crate::State, Error> {
    if held.len() != model.n {
        return Err(Error::DimensionMismatch { what: "held", expected: model.n, got: held.len() });
    }
    let mut state = approximate.clone();
    if model.is_constrained() {
        let mut ws = model.workspace();
        project_holding(model, &mut ws, state.t, (&mut state.q, &mut state.qdot), Some(held), false)?;
    }
    Ok(state)
}

/// The multipliers `λ` of the constraints at `(t, q, q̇)` (holonomic rows, then velocity rows),
/// borrowed from the workspace: `−Gᵀ λ` is the generalized constraint force, so that
/// `M q̈ = f − Gᵀ λ`. Empty for a model without constraints. Where the rows are redundant (a
/// parallelogram with a third parallel bar) or become dependent (a linkage at a singular
/// configuration), `λ` is not unique: `q̈` and the force on every body
/// ([`reaction_forces`](crate::reaction_forces)) are, but how it is shared among the rows is
/// not, and the solve returns the smallest `λ` along the directions the equations leave free
/// (docs/method.md#constraints). [`multiplier_rank`] says how many there are at a state.
///
/// # Errors
/// As [`accelerations`](crate::accelerations).
pub fn constraint_multipliers<'w, M: Mechanism, S: Scalar>(
    model: &Model<M>,
    ws: &'w mut Workspace<S>,
    t: S,
    q: &[S],
    qdot: &[S],
) -> Result<&'w [S], Error> {
    crate::eom::accelerations(model, ws, t, q, qdot)?;
    Ok(ws.constraints.as_ref().map_or(&[][..], |b| &b.multipliers))
}

/// How far the equations determine the constraint multipliers at a state
/// ([`multiplier_rank`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MultiplierRank {
    /// Constraint rows `c = m + k`.
    pub rows: usize,
    /// Directions of `λ` the equations determine: the eigenvalues of `S = G M⁻¹ Gᵀ` above the
    /// shift `μ̄` of the constrained solve (`1e-7` of its mean diagonal). Along the other
    /// `rows − determined` directions the multipliers returned are the solve's smallest choice.
    pub determined: usize,
    /// The smallest eigenvalue of `S` over its largest: round-off (~1e-16) at an exact
    /// redundancy, falling as the square of the distance to a singular configuration; 1 without
    /// constraints.
    pub conditioning: f64,
}

impl MultiplierRank {
    /// Whether the multipliers are unique (every direction determined).
    pub fn unique(&self) -> bool {
        self.determined == self.rows
    }
}

/// How many directions of the multipliers `λ` ([`constraint_multipliers`]) the equations of
/// motion determine at `(t, q, q̇)`: the eigenvalues of `S = G M⁻¹ Gᵀ` (c × c, the matrix of the
/// multipliers' equations `S λ = G M⁻¹ f + γ`) above the constrained solve's shift. Fewer than
/// the rows at a redundancy (everywhere for a parallelogram with a third parallel bar: one) and
/// at a singular configuration (a chain of `N` parallelogram windows laid flat: `N`), where the
/// multipliers returned are one choice among many. A dense eigendecomposition of `S` (`O(n³ +
/// c³)`): a diagnostic, not for a simulation's inner loop.
///
/// # Errors
/// As [`accelerations`](crate::accelerations): a malformed or non-finite state, a singular
/// mass matrix.
pub fn multiplier_rank<M: Mechanism>(
    model: &Model<M>,
    ws: &mut Workspace<f64>,
    t: f64,
    q: &[f64],
    qdot: &[f64],
) -> Result<MultiplierRank, Error> {
    crate::eom::check_state(model.n, t, q, Some(qdot))?;
    let (n, (m, k)) = (model.n, model.constraint_counts);
    let c = m + k;
    if c == 0 {
        return Ok(MultiplierRank { rows: 0, determined: 0, conditioning: 1.0 });
    }
    // The accelerations first: their checks of the state, the mass matrix and the constraints.
    crate::eom::accelerations(model, ws, t, q, qdot)?;
    let mass = nalgebra::DMatrix::from_row_slice(n, n, crate::mass_matrix(model, ws, t, q, qdot)?);
    let mut b = ws.constraints.take().expect("a constrained model's workspace has constraint buffers");
    evaluate(&model.mechanism, (m, k), Rows::All, &mut ws.q_dual, &mut ws.q_dual2, &mut b, t, q, qdot);
    let g = nalgebra::DMatrix::from_row_slice(c, n, &b.jacobian[..c * n]);
    ws.constraints = Some(b);
    // M passed the accelerations' LDLᵀ test (positive pivots): its Cholesky factor exists
    // unless round-off makes a pivot that was barely positive there not so here.
    let Some(factor) = mass.cholesky() else {
        return Err(crate::error::non_finite(Stage::Accelerations, t, q));
    };
    let schur = &g * factor.solve(&g.transpose());
    let shift = REGULARIZATION * schur.trace() / c as f64;
    let eigenvalues = nalgebra::SymmetricEigen::new(schur).eigenvalues;
    let largest = eigenvalues.max();
    Ok(MultiplierRank {
        rows: c,
        determined: eigenvalues.iter().filter(|&&s| s > shift).count(),
        conditioning: if largest > 0.0 { eigenvalues.min().max(0.0) / largest } else { 0.0 },
    })
}
