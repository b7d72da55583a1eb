//! The multiplier equations by the Schur complement on the block-diagonal mass matrix,
//! factored sparsely, regularized and refined.
//!
//! With `M̃` the (augmented) block-diagonal mass matrix of [`super::sparsity`], the KKT system
//! `M̃ z̈ + Jᵀ λ = F̃`, `J z̈ = −γ` becomes
//!
//! ```text
//! S λ = J M̃⁻¹ F̃ + γ,      S = J M̃⁻¹ Jᵀ (m × m, sparse),      z̈ = M̃⁻¹ (F̃ − Jᵀ λ),
//! ```
//!
//! `S` is symmetric positive semi-definite, singular where `J` loses rank (a parallelogram lying
//! flat) and everywhere for redundant constraints (a third parallel crank). It is scaled to
//! unit diagonal, `Ŝ = D^(−1/2) S D^(−1/2)` with `D = diag(S)` (which makes everything below
//! independent of the units of each row), shifted, `Ŝ + μ I` (that is `S + μ diag(S)`), and
//! factored by faer's sparse Cholesky: the AMD ordering and elimination tree once per system,
//! the numeric factor per configuration into memory allocated once. The solution is then
//! refined against the unshifted `Ŝ` ([`REFINEMENTS`] steps of `x ← x + (Ŝ + μI)⁻¹ (b − Ŝ x)`,
//! the augmented-Lagrangian iteration of Bayo & Ledesma, Nonlinear Dynamics 9 (1996) 113–130):
//! along an eigenvector of `Ŝ` with eigenvalue `σ` the error shrinks by `μ / (σ + μ)` per step,
//! so well-conditioned directions converge to the exact `λ` (error `(μ/σ)^(k+1)`), directions
//! with `σ ≲ μ` are enforced partially and continuously in `σ` instead of by a rank decision,
//! and directions with `σ = 0` (redundant rows) receive nothing: `λ` is the solution of least
//! `Σ_i S_ii λ_i²` — the reactions at a redundancy are not unique, and this is the one chosen.
//! The residual `b − Ŝ x` after refinement says whether the rows can hold at all.

use super::sparsity::{SchurPattern, Sparsity};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::LltRef;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// The shift `μ` of `Ŝ + μ I` (`S + μ diag(S)`), chosen by measurement on the parallelogram
/// chains of `linkage_tests` (5 s at tolerance 1e-10 through ~10 flat positions, N = 2 and 10,
/// three initial rates; `δ` the distance from the flat position, `σ ≈ 0.3 δ²` the rank-loss
/// eigenvalue of `Ŝ` for N = 10):
///
/// | μ | energy error (N = 10) | cranks apart | moved 1e3 m: angles apart | `z̈` exact (≤ 1e-9) from |
/// |---|---|---|---|---|
/// | 1e-6 | 2.9e-9 | 2e-8 | 1.1e-10 | δ ≈ 3e-2 |
/// | 1e-8 | ≤ 9.3e-11 | ≤ 2.8e-11 | ≤ 1.7e-10 | δ = 1e-2 |
/// | 1e-9 | ≤ 1.7e-10 | ≤ 2.2e-12 | ≤ 1.7e-10 | δ = 1e-3 |
/// | 1e-10 | 6e-9 … 2e-8 | ≤ 2.6e-12 | up to 8e-9 | δ = 1e-3 |
///
/// A large `μ` leaves the loop tensions that keep the chain's cranks parallel out of a wide
/// window around the flat position; a small one leaves the steps just outside the window to the
/// solve's conditioning `1/σ`, whose round-off the velocity projection turns into differences
/// between the cranks' rates (`≈ ε ω / δ²`) and the step-size control into crawling towards the
/// flat position (1e-10, the first guess, fails the energy bound of 1e-8). 1e-9 is the smaller of
/// the two good values: exact accelerations closer to the rank loss, and less round-off in a
/// redundant direction's multipliers (`(k + 1) ε / μ ≈ 1e-6` of the right-hand side).
pub(crate) const REGULARIZATION: f64 = 1e-9;

/// Refinement steps against the unshifted `Ŝ`. Measured on the chain's accelerations (relative
/// error against the branch at `δ = 1e-2`, μ = 1e-8): 7.4e-6 unrefined, 7.5e-9 after one step,
/// 1.6e-13 after three (round-off), 9.3e-14 after six; at μ = 1e-10, δ = 1e-3: 7.0e-6, 7.2e-9,
/// 5.8e-12, 6.9e-12. Three reach round-off wherever `σ ≥ 300 μ` (the error falls as
/// `(μ/σ)^(k+1)`); more only widen the accurate region by `√2` in `δ` per doubling, and the
/// chain's runs (energy, parallel cranks) differ by less than their scatter between 1, 3 and 5.
/// Each step costs one sparse product and one pair of triangular solves.
pub(crate) const REFINEMENTS: usize = 3;

/// Relative pivot below which a block of the mass matrix is declared singular: the pivot after
/// eliminating the block's earlier coordinates, relative to its own diagonal entry (the reduced
/// solver's criterion, 1e-12 — well above the `~k ε` round-off of a well-posed block, far below
/// the `O(1)` ratios of the scenes' blocks).
pub(crate) const PIVOT_RTOL: f64 = 1e-12;

/// Memory for faer's numeric factorization and solves, allocated once.
pub(crate) struct Scratch {
    /// What it was sized for.
    requirement: StackReq,
    /// The memory.
    buffer: MemBuffer,
}

impl Scratch {
    fn new(requirement: StackReq) -> Self {
        Self { requirement, buffer: MemBuffer::new(requirement) }
    }
}

impl Clone for Scratch {
    fn clone(&self) -> Self {
        Self::new(self.requirement)
    }
}

impl std::fmt::Debug for Scratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Scratch").field("requirement", &self.requirement).finish()
    }
}

/// The numeric Schur complement over one [`SchurPattern`]'s `r` rows.
#[derive(Clone, Debug)]
pub(crate) struct SchurWork {
    /// `Ŝ = D^(−1/2) S D^(−1/2)`, the pattern's upper triangle (nnz); [`KktWorkspace::factor_schur`].
    values: Vec<f64>,
    /// `Ŝ + μ I` (nnz), the factored matrix; [`KktWorkspace::factor_schur`].
    shifted: Vec<f64>,
    /// The Cholesky factor of `Ŝ + μ I` (faer's layout); [`KktWorkspace::factor_schur`].
    factor: Vec<f64>,
    /// `D^(−1/2)` (r); [`KktWorkspace::factor_schur`].
    pub(crate) scale: Vec<f64>,
    /// The scaled right-hand side `D^(−1/2) b` (r); [`KktWorkspace::solve_schur`].
    target: Vec<f64>,
    /// The scaled residual `D^(−1/2) (b − S λ)` after refinement (r); [`KktWorkspace::solve_schur`].
    pub(crate) residual: Vec<f64>,
    /// Whether `factor` belongs to the current `J` and `M̃`.
    valid: bool,
    /// faer's scratch memory.
    scratch: Scratch,
}

impl SchurWork {
    fn new(pattern: &SchurPattern) -> Self {
        let (r, nnz) = (pattern.rows, pattern.row.len());
        let (factor, requirement) = match &pattern.symbolic {
            Some(symbolic) => (
                symbolic.len_val(),
                StackReq::any_of(&[
                    symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
                    symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
                ]),
            ),
            None => (0, StackReq::EMPTY),
        };
        Self {
            values: vec![0.0; nnz],
            shifted: vec![0.0; nnz],
            factor: vec![0.0; factor],
            scale: vec![1.0; r],
            target: vec![0.0; r],
            residual: vec![0.0; r],
            valid: false,
            scratch: Scratch::new(requirement),
        }
    }
}

/// Every buffer of the solve, allocated once: `J`'s values, the factored blocks of `M̃`, the
/// Schur complements.
#[derive(Clone, Debug)]
pub(crate) struct KktWorkspace {
    /// `J`'s values in [`Sparsity`]'s compressed rows (nnz(J)); `CartesianSystem::jacobian`.
    pub(crate) jacobian: Vec<f64>,
    /// Augmentation weight `w_i` of each augmented row (|R|); [`factor_mass`](Self::factor_mass).
    weights: Vec<f64>,
    /// The blocks of `M̃`, augmented ones as their Cholesky factors (`Σ k_B²`, row-major per
    /// block); [`factor_mass`](Self::factor_mass).
    blocks: Vec<f64>,
    /// `M̃_B⁻¹ J_(a,B)ᵀ` for the rows `a` of one block (p × k); [`factor_schur`](Self::factor_schur).
    mobility: Vec<f64>,
    /// One block's slice of a vector (k); [`solve_mass`](Self::solve_mass).
    gathered: Vec<f64>,
    /// All rows.
    all: SchurWork,
    /// The holonomic rows, when velocity rows follow them.
    holonomic: Option<SchurWork>,
}

impl KktWorkspace {
    /// Buffers for `sparsity`.
    pub(crate) fn new(sparsity: &Sparsity) -> Self {
        let (p, k) = sparsity.largest_block;
        Self {
            jacobian: vec![0.0; sparsity.column.len()],
            weights: vec![0.0; sparsity.augmented_rows.len()],
            blocks: vec![0.0; sparsity.block_storage],
            mobility: vec![0.0; p * k],
            gathered: vec![0.0; k],
            all: SchurWork::new(&sparsity.all),
            holonomic: sparsity.holonomic.as_ref().map(SchurWork::new),
        }
    }

    /// The Schur complement over the first `rows` rows.
    pub(crate) fn work(&self, rows: usize) -> &SchurWork {
        match &self.holonomic {
            Some(work) if work.scale.len() == rows => work,
            _ => &self.all,
        }
    }

    /// The augmentation weights and the blocks of `M̃ = M + Σ_R w_i J_iᵀ J_i`, factored, for the
    /// `J` in [`jacobian`](Self::jacobian); the Schur factors are stale afterwards.
    ///
    /// # Errors
    /// `(j, pivot)`: coordinate `j` moves no mass and no constraint fixes it here (its relative
    /// pivot in its block is at most [`PIVOT_RTOL`]).
    pub(crate) fn factor_mass(&mut self, sparsity: &Sparsity, mass: &[f64]) -> Result<(), (usize, f64)> {
        self.all.valid = false;
        if let Some(work) = &mut self.holonomic {
            work.valid = false;
        }
        if let Some(j) = sparsity.unfixed {
            return Err((j, 0.0));
        }
        // w_i = 1 / Σ_j J_ij² / m̄_j: the augmented row's own effective mass.
        for (w, &i) in self.weights.iter_mut().zip(&sparsity.augmented_rows) {
            let entries = sparsity.row_start[i]..sparsity.row_start[i + 1];
            let compliance: f64 =
                entries.map(|e| self.jacobian[e].powi(2) * sparsity.weight_inverse_mass[sparsity.column[e]]).sum();
            *w = if compliance > 0.0 { compliance.recip() } else { 0.0 };
        }
        // M̃_B = diag(M_B) + Σ w_a J_(a,B)ᵀ J_(a,B), factored.
        for block in sparsity.blocks.iter().filter(|b| b.augmented) {
            let k = block.coordinates.len();
            let matrix = &mut self.blocks[block.offset..block.offset + k * k];
            matrix.fill(0.0);
            for (c, &j) in block.coordinates.iter().enumerate() {
                matrix[c * k + c] = mass[j];
            }
            for &(a, r) in &block.augmenting {
                let entries = &block.entries[a];
                for &(c, e) in entries {
                    for &(d, f) in entries {
                        matrix[c * k + d] += self.weights[r] * self.jacobian[e] * self.jacobian[f];
                    }
                }
            }
            cholesky(k, matrix).map_err(|(c, pivot)| (block.coordinates[c], pivot))?;
        }
        Ok(())
    }

    /// `x ← M̃⁻¹ x` (n) with the blocks of [`factor_mass`](Self::factor_mass).
    pub(crate) fn solve_mass(&mut self, sparsity: &Sparsity, mass: &[f64], x: &mut [f64]) {
        for block in &sparsity.blocks {
            if block.augmented {
                let k = block.coordinates.len();
                let local = &mut self.gathered[..k];
                for (l, &j) in local.iter_mut().zip(&block.coordinates) {
                    *l = x[j];
                }
                cholesky_solve(k, &self.blocks[block.offset..block.offset + k * k], local);
                for (&l, &j) in local.iter().zip(&block.coordinates) {
                    x[j] = l;
                }
            } else {
                for &j in &block.coordinates {
                    x[j] /= mass[j];
                }
            }
        }
    }

    /// `F̃ = F − Σ_R w_i γ_i J_iᵀ`: the augmentation's share of the forces, into `force` (n).
    pub(crate) fn augment_force(&self, sparsity: &Sparsity, convective: &[f64], force: &mut [f64]) {
        for (&w, &i) in self.weights.iter().zip(&sparsity.augmented_rows) {
            let pull = w * convective[i];
            for e in sparsity.row_start[i]..sparsity.row_start[i + 1] {
                force[sparsity.column[e]] -= pull * self.jacobian[e];
            }
        }
    }

    /// `out = J_rᵀ x`, `J_r` the first `x.len()` rows (out: n).
    pub(crate) fn transpose_product(&self, sparsity: &Sparsity, x: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for (i, &xi) in x.iter().enumerate() {
            for e in sparsity.row_start[i]..sparsity.row_start[i + 1] {
                out[sparsity.column[e]] += self.jacobian[e] * xi;
            }
        }
    }

    /// `out = J_r x` (x: n), `J_r` the first `out.len()` rows; with `magnitude`, `|J_r| |x|`
    /// (the terms' magnitudes) into it.
    pub(crate) fn product(&self, sparsity: &Sparsity, x: &[f64], out: &mut [f64], mut magnitude: Option<&mut [f64]>) {
        for (i, o) in out.iter_mut().enumerate() {
            let (mut sum, mut size) = (0.0, 0.0);
            for e in sparsity.row_start[i]..sparsity.row_start[i + 1] {
                let term = self.jacobian[e] * x[sparsity.column[e]];
                sum += term;
                size += term.abs();
            }
            *o = sum;
            if let Some(m) = magnitude.as_deref_mut() {
                m[i] = size;
            }
        }
    }

    /// The size of each of the first `out.len()` constraint equations at `z`:
    /// `Σ_j |J_ij| s_j`, with `s_j = |z_j| + ℓ` for a position, `|z_j| + 1 rad` for an angle
    /// the row is linear in (a relative angle, a drive, a coupling), and 1 rad for an angle that
    /// turns a lever arm (`|J_ij|` is then the arm's length): the magnitudes of the positions,
    /// angles and lengths inside the equation, whose round-off bounds how well `Φ_i` can be
    /// evaluated and corrected. `ℓ`, the longest lever arm in `J`, is the mechanism's own length
    /// (and 1 rad an angle's): a rail `y_b = 0` at `y_b ≈ 0` has nothing else inside, yet its
    /// `y_b` is corrected by steps made of such lengths. Independent of each row's units; grows
    /// with the distance from the world's origin exactly as the round-off does.
    pub(crate) fn equation_sizes(&self, sparsity: &Sparsity, z: &[f64], out: &mut [f64]) {
        let arms = (0..self.jacobian.len()).filter(|&e| !sparsity.size_of_coordinate[e]);
        let lever = arms.fold(0.0_f64, |l, e| l.max(self.jacobian[e].abs()));
        for (i, o) in out.iter_mut().enumerate() {
            *o = (sparsity.row_start[i]..sparsity.row_start[i + 1])
                .map(|e| {
                    let j = sparsity.column[e];
                    let value = match (sparsity.size_of_coordinate[e], j % 3 == 2) {
                        (false, _) => 1.0,
                        (true, true) => z[j].abs() + 1.0,
                        (true, false) => z[j].abs() + lever,
                    };
                    self.jacobian[e].abs() * value
                })
                .sum();
        }
    }

    /// Assemble `S = J_r M̃⁻¹ J_rᵀ` over the first `rows` rows, scale it to unit diagonal, shift
    /// it by `μ` and factor it (unless already factored for this `J`).
    ///
    /// # Errors
    /// When the factorization fails, which only a non-finite `S` can make it do.
    pub(crate) fn factor_schur(&mut self, sparsity: &Sparsity, mass: &[f64], rows: usize) -> Result<(), ()> {
        let pattern = sparsity.pattern(rows);
        let Self { jacobian, blocks, mobility, all, holonomic, .. } = self;
        let work = match holonomic {
            Some(work) if work.scale.len() == rows => work,
            _ => all,
        };
        if work.valid {
            return Ok(());
        }
        let Some(symbolic) = &pattern.symbolic else {
            work.valid = true;
            return Ok(());
        };
        // S block by block: y_a = M̃_B⁻¹ J_(a,B)ᵀ, then S_ab += J_(a,B) · y_b.
        work.values.fill(0.0);
        for (block, scatter) in sparsity.blocks.iter().zip(&pattern.scatter) {
            let (k, p) = (block.coordinates.len(), block.rows.iter().take_while(|&&i| i < rows).count());
            for a in 0..p {
                let y = &mut mobility[a * k..(a + 1) * k];
                y.fill(0.0);
                for &(c, e) in &block.entries[a] {
                    y[c] = jacobian[e];
                }
                if block.augmented {
                    cholesky_solve(k, &blocks[block.offset..block.offset + k * k], y);
                } else {
                    for (v, &j) in y.iter_mut().zip(&block.coordinates) {
                        *v /= mass[j];
                    }
                }
            }
            for a in 0..p {
                for b in a..p {
                    let y = &mobility[b * k..(b + 1) * k];
                    let s: f64 = block.entries[a].iter().map(|&(c, e)| jacobian[e] * y[c]).sum();
                    work.values[scatter[a * p + b]] += s;
                }
            }
        }
        // Ŝ = D^(−1/2) S D^(−1/2); a row with S_ii = 0 (J_i = 0 here) keeps scale 1.
        for (scale, &d) in work.scale.iter_mut().zip(&pattern.diagonal) {
            let diagonal = work.values[d];
            *scale = if diagonal > 0.0 && diagonal.is_finite() { diagonal.sqrt().recip() } else { 1.0 };
        }
        for column in 0..rows {
            for e in pattern.column_start[column]..pattern.column_start[column + 1] {
                work.values[e] *= work.scale[pattern.row[e]] * work.scale[column];
            }
        }
        // Ŝ + μ I, factored (a pivot that round-off pushes below μ/2 is set to μ).
        work.shifted.copy_from_slice(&work.values);
        for &d in &pattern.diagonal {
            work.shifted[d] += REGULARIZATION;
        }
        let matrix = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(rows, rows, &pattern.column_start, None, &pattern.row),
            &work.shifted,
        );
        let regularization = LltRegularization {
            dynamic_regularization_delta: REGULARIZATION,
            dynamic_regularization_epsilon: 0.5 * REGULARIZATION,
        };
        let stack = MemStack::new(&mut work.scratch.buffer);
        symbolic
            .factorize_numeric_llt(
                &mut work.factor,
                matrix,
                Side::Upper,
                regularization,
                Par::Seq,
                stack,
                Default::default(),
            )
            .map_err(|_| ())?;
        work.valid = true;
        Ok(())
    }

    /// Solve `S_r λ = b` over the first `rows = b.len()` rows with the factor of
    /// [`factor_schur`](Self::factor_schur), refined [`REFINEMENTS`] times: `λ` replaces `b`.
    /// The scaled residual after refinement is left in [`SchurWork::residual`].
    pub(crate) fn solve_schur(&mut self, sparsity: &Sparsity, b: &mut [f64]) {
        let rows = b.len();
        let pattern = sparsity.pattern(rows);
        let work = match &mut self.holonomic {
            Some(work) if work.scale.len() == rows => work,
            _ => &mut self.all,
        };
        debug_assert!(work.valid, "solve_schur after factor_schur");
        let Some(symbolic) = &pattern.symbolic else {
            return;
        };
        let factor = LltRef::new(symbolic, &work.factor);
        let mut solve = |x: &mut [f64]| {
            let stack = MemStack::new(&mut work.scratch.buffer);
            factor.solve_in_place_with_conj(Conj::No, MatMut::from_column_major_slice_mut(x, rows, 1), Par::Seq, stack);
        };
        // x = (Ŝ + μI)⁻¹ D^(−1/2) b, then x += (Ŝ + μI)⁻¹ (D^(−1/2) b − Ŝ x).
        for ((t, x), &s) in work.target.iter_mut().zip(b.iter_mut()).zip(&work.scale) {
            *t = *x * s;
            *x = *t;
        }
        solve(b);
        for step in 0..=REFINEMENTS {
            residual(pattern, &work.values, &work.target, b, &mut work.residual);
            if step == REFINEMENTS {
                break;
            }
            solve(&mut work.residual);
            for (x, d) in b.iter_mut().zip(&work.residual) {
                *x += d;
            }
        }
        // λ = D^(−1/2) x.
        for (x, &s) in b.iter_mut().zip(&work.scale) {
            *x *= s;
        }
    }
}

/// `out = target − Ŝ x` with `Ŝ` stored as its upper triangle over `pattern`.
fn residual(pattern: &SchurPattern, values: &[f64], target: &[f64], x: &[f64], out: &mut [f64]) {
    out.copy_from_slice(target);
    for column in 0..pattern.rows {
        for e in pattern.column_start[column]..pattern.column_start[column + 1] {
            let row = pattern.row[e];
            out[row] -= values[e] * x[column];
            if row != column {
                out[column] -= values[e] * x[row];
            }
        }
    }
}

/// In-place Cholesky `A = L Lᵀ` of a symmetric matrix (k × k, row-major; `L` in the lower
/// triangle). Returns `Err((j, ratio))` at the first pivot `j` that is not positive relative
/// to its diagonal entry by more than [`PIVOT_RTOL`].
fn cholesky(k: usize, a: &mut [f64]) -> Result<(), (usize, f64)> {
    for j in 0..k {
        let diagonal = a[j * k + j];
        let pivot = diagonal - (0..j).map(|p| a[j * k + p] * a[j * k + p]).sum::<f64>();
        let ratio = if diagonal > 0.0 { pivot / diagonal } else { 0.0 };
        if ratio.is_nan() || ratio <= PIVOT_RTOL {
            return Err((j, ratio));
        }
        let root = pivot.sqrt();
        a[j * k + j] = root;
        for i in j + 1..k {
            let dot: f64 = (0..j).map(|p| a[i * k + p] * a[j * k + p]).sum();
            a[i * k + j] = (a[i * k + j] - dot) / root;
        }
    }
    Ok(())
}

/// Solve `L Lᵀ x = b` in place with the factor of [`cholesky`].
fn cholesky_solve(k: usize, factor: &[f64], b: &mut [f64]) {
    for i in 0..k {
        let dot: f64 = (0..i).map(|p| factor[i * k + p] * b[p]).sum();
        b[i] = (b[i] - dot) / factor[i * k + i];
    }
    for i in (0..k).rev() {
        let dot: f64 = (i + 1..k).map(|p| factor[p * k + i] * b[p]).sum();
        b[i] = (b[i] - dot) / factor[i * k + i];
    }
}
