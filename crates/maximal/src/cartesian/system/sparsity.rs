//! The fixed sparsity of a Cartesian system, found once when the system is built: which
//! coordinates each constraint row touches, the blocks of the mass matrix the solve inverts,
//! and the pattern of the Schur complement `S = J M̃⁻¹ Jᵀ` with its symbolic Cholesky
//! factorization (a fill-reducing AMD ordering and the elimination tree).
//!
//! A row's pattern is probed: `Φ_z` (and `∂(A ż)/∂ż` for a velocity row) by dual passes at two
//! generic configurations, a coordinate counting as touched where either derivative is nonzero.
//! `J` then stores, for each row, the three coordinates of every body its constraint touches
//! (so that an entry that happens to vanish at both probes is still stored), and `S_ik` is
//! structurally nonzero when rows `i` and `k` touch a common block.
//!
//! **Blocks.** `M = diag(m_b, m_b, I_b)` may have zero entries (point masses' orientations,
//! massless pulleys): those coordinates move no mass and are fixed by constraints alone, so
//! `M⁻¹` does not exist. The rows that touch such a coordinate (the augmented rows `R`) are
//! added to the mass matrix, `M̃ = M + Σ_{i∈R} w_i J_iᵀ J_i`, which is exact: along every motion
//! `J_i z̈ = −γ_i`, so `M̃ z̈ + Jᵀ λ = F − Σ_{i∈R} w_i γ_i J_iᵀ` has the same `(z̈, λ)`
//! ([`super::schur`]). `M̃` is block diagonal with one block per set of bodies joined by
//! augmented rows — one body per block in every scene but those with massless pulleys — and is
//! positive definite exactly when every massless coordinate is fixed by the constraints.

use crate::cartesian::constraints::{Constraint, VelocityConstraint, evaluate_all};
use faer::Side;
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky};
use lagrange::num_dual::Dual64;

/// Coordinate `k` of probe configuration `p` (0 or 1): generic values in about `[−1.2, 1.2]`
/// (m and rad) that put no two anchors at the same point and no angle at a multiple of `π/2`.
fn probe_value(k: usize, p: usize) -> f64 {
    let k = k as f64;
    if p == 0 { 0.31 + 0.83 * (1.37 * k + 0.41).sin() } else { -0.23 + 0.97 * (0.73 * k + 1.19).cos() }
}

/// The times of the two probes (s).
const PROBE_TIMES: [f64; 2] = [0.23, 0.61];

/// The bodies of the mass matrix's block `M̃_B` and the constraint rows that touch them.
#[derive(Debug)]
pub(crate) struct Block {
    /// Global coordinates of the block, three per body, bodies ascending (k).
    pub(crate) coordinates: Vec<usize>,
    /// Offset of the block's `k × k` factor in the workspace's block storage.
    pub(crate) offset: usize,
    /// Whether an augmented row touches the block (then `M̃_B` is dense; else `M_B`, diagonal).
    pub(crate) augmented: bool,
    /// The rows touching the block, ascending (p).
    pub(crate) rows: Vec<usize>,
    /// For each of [`rows`](Self::rows): its entries on the block, as (local coordinate, index
    /// into `J`'s values).
    pub(crate) entries: Vec<Vec<(usize, usize)>>,
    /// The augmented rows among [`rows`](Self::rows): (local row, index into
    /// [`Sparsity::augmented_rows`]).
    pub(crate) augmenting: Vec<(usize, usize)>,
}

/// The pattern of `S = J_r M̃⁻¹ J_rᵀ` over the first `rows` constraint rows (upper triangle,
/// compressed columns), with its symbolic factorization.
#[derive(Debug)]
pub(crate) struct SchurPattern {
    /// Number of rows `r` (all `m` rows, or the `h` holonomic ones for the position projection).
    pub(crate) rows: usize,
    /// Column starts (r + 1).
    pub(crate) column_start: Vec<usize>,
    /// Row of each stored entry, ascending within a column (nnz).
    pub(crate) row: Vec<usize>,
    /// Position of each diagonal entry `S_ii` (r).
    pub(crate) diagonal: Vec<usize>,
    /// For each block, the positions of `S_(a,b)` for the block's rows `a, b < r`
    /// (`p_r × p_r`, row-major; both orders give the one stored upper entry).
    pub(crate) scatter: Vec<Vec<usize>>,
    /// AMD ordering and elimination tree, computed once (`None` when `r = 0`).
    pub(crate) symbolic: Option<SymbolicCholesky<usize>>,
}

/// Everything about the system's equations that does not change with the configuration.
#[derive(Debug)]
pub(crate) struct Sparsity {
    /// Start of each row's entries in `J`'s values (m + 1).
    pub(crate) row_start: Vec<usize>,
    /// Coordinate of each entry of `J` (nnz(J)): the three coordinates of each body the row's
    /// constraint touches, body by body.
    pub(crate) column: Vec<usize>,
    /// Whether an entry of `J` (nnz(J)) weighs its coordinate's value in the equation's size
    /// (a position, or an angle the row is linear in: relative angles, drives, couplings) or
    /// counts 1 rad (an angle that turns a lever arm, whose `|J_ij|` is the arm's length).
    pub(crate) size_of_coordinate: Vec<bool>,
    /// The bodies each holonomic constraint touches, ascending (one list per constraint).
    pub(crate) constraint_bodies: Vec<Vec<usize>>,
    /// The rows touching a coordinate without mass (augmented into `M̃`), ascending.
    pub(crate) augmented_rows: Vec<usize>,
    /// A coordinate without mass that no constraint row touches, if any: `M̃` is singular.
    pub(crate) unfixed: Option<usize>,
    /// The blocks of `M̃`, covering every coordinate once.
    pub(crate) blocks: Vec<Block>,
    /// Total size of the blocks' factors (`Σ k_B²`).
    pub(crate) block_storage: usize,
    /// Largest block: rows (p) and coordinates (k).
    pub(crate) largest_block: (usize, usize),
    /// The pattern over all `m` rows: accelerations, velocity projection.
    pub(crate) all: SchurPattern,
    /// The pattern over the `h` holonomic rows, when velocity rows follow them: the position
    /// projection. `None` when every row is holonomic (then [`all`](Self::all) serves).
    pub(crate) holonomic: Option<SchurPattern>,
    /// Inverse mass used in the augmentation weights `w_i = 1 / Σ_j J_ij² / m̄_j` (n): `1/M_jj`,
    /// or for a coordinate without mass `1 /` the largest mass of its kind (translation or
    /// rotation; 1 if the system has none), so that `w_i J_iᵀ J_i` is of the size of the
    /// masses it joins.
    pub(crate) weight_inverse_mass: Vec<f64>,
}

impl Sparsity {
    /// Probe the constraints (`holonomic` equations, then the velocity rows) of a system with
    /// mass diagonal `mass` (n) and lay out `J`, the blocks and the Schur patterns.
    pub(crate) fn new(
        constraints: &[Constraint],
        velocity: &[VelocityConstraint],
        mass: &[f64],
        holonomic: usize,
    ) -> Self {
        let n = mass.len();
        let m = holonomic + velocity.len();
        let probed = probe(constraints, velocity, n, holonomic);
        let touches = |i: usize, j: usize| probed[i].iter().any(|&(k, _)| k == j);
        let (row_bodies, constraint_bodies) = row_bodies(constraints, velocity, &probed, n);
        // J in compressed rows: three coordinates per body.
        let mut row_start = vec![0];
        let mut column = Vec::new();
        for bodies in &row_bodies {
            column.extend(bodies.iter().flat_map(|&b| [3 * b, 3 * b + 1, 3 * b + 2]));
            row_start.push(column.len());
        }
        let size_of_coordinate: Vec<bool> = (0..m)
            .flat_map(|i| row_start[i]..row_start[i + 1])
            .map(|e| {
                let (i, j) = (row_start.partition_point(|&s| s <= e) - 1, column[e]);
                j % 3 != 2 || probed[i].iter().any(|&(k, linear)| k == j && linear)
            })
            .collect();
        // Coordinates without mass, the rows that fix them, and one left unfixed.
        let massless: Vec<bool> = mass.iter().map(|&v| v == 0.0).collect();
        let augmented_rows: Vec<usize> = (0..m).filter(|&i| probed[i].iter().any(|&(j, _)| massless[j])).collect();
        let unfixed = (0..n).find(|&j| massless[j] && !(0..m).any(|i| touches(i, j)));
        let (blocks, block_storage) = blocks(&row_bodies, &augmented_rows, (&row_start, &column), n);
        let largest_block = blocks.iter().fold((0, 0), |(p, k), b| (p.max(b.rows.len()), k.max(b.coordinates.len())));
        let all = SchurPattern::new(&blocks, m);
        let holonomic_pattern = (!velocity.is_empty()).then(|| SchurPattern::new(&blocks, holonomic));
        let weight_inverse_mass = weight_inverse_mass(mass);
        Self {
            row_start,
            column,
            size_of_coordinate,
            constraint_bodies,
            augmented_rows,
            unfixed,
            blocks,
            block_storage,
            largest_block,
            all,
            holonomic: holonomic_pattern,
            weight_inverse_mass,
        }
    }

    /// The pattern for the first `rows` rows: [`all`](Self::all) or [`holonomic`](Self::holonomic).
    pub(crate) fn pattern(&self, rows: usize) -> &SchurPattern {
        match &self.holonomic {
            Some(pattern) if pattern.rows == rows => pattern,
            _ => &self.all,
        }
    }
}

/// The bodies of every row of `J` (those of its constraint's rows together, ascending; a
/// velocity row's one body), and those of every holonomic constraint, from the `probed` rows.
fn row_bodies(
    constraints: &[Constraint],
    velocity: &[VelocityConstraint],
    probed: &[Vec<(usize, bool)>],
    n: usize,
) -> (Vec<Vec<usize>>, Vec<Vec<usize>>) {
    let mut row_bodies: Vec<Vec<usize>> = Vec::with_capacity(probed.len());
    let mut constraint_bodies = Vec::with_capacity(constraints.len());
    let mut first = 0;
    for constraint in constraints {
        let rows = first..first + constraint.equations();
        let bodies: Vec<usize> =
            (0..n / 3).filter(|&b| rows.clone().any(|i| probed[i].iter().any(|&(j, _)| j / 3 == b))).collect();
        row_bodies.extend(rows.map(|_| bodies.clone()));
        constraint_bodies.push(bodies);
        first += constraint.equations();
    }
    row_bodies.extend(velocity.iter().map(|v| vec![v.body]));
    (row_bodies, constraint_bodies)
}

/// The blocks of `M̃`: bodies joined by the `augmented_rows` (union–find), each with its
/// coordinates, its offset in the factors' storage, the rows touching it with their entries in
/// `J = (row_start, column)`, and which of its rows augment it; and the factors' total storage.
fn blocks(
    row_bodies: &[Vec<usize>],
    augmented_rows: &[usize],
    (row_start, column): (&[usize], &[usize]),
    n: usize,
) -> (Vec<Block>, usize) {
    let mut parent: Vec<usize> = (0..n / 3).collect();
    for &i in augmented_rows {
        for pair in row_bodies[i].windows(2) {
            let (a, b) = (root(&mut parent, pair[0]), root(&mut parent, pair[1]));
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut blocks: Vec<Block> = Vec::new();
    let mut block_of = vec![usize::MAX; n / 3];
    let mut offset = 0;
    for b in 0..n / 3 {
        let r = root(&mut parent, b);
        if block_of[r] == usize::MAX {
            block_of[r] = blocks.len();
            blocks.push(Block {
                coordinates: Vec::new(),
                offset: 0,
                augmented: false,
                rows: Vec::new(),
                entries: Vec::new(),
                augmenting: Vec::new(),
            });
        }
        block_of[b] = block_of[r];
        blocks[block_of[b]].coordinates.extend([3 * b, 3 * b + 1, 3 * b + 2]);
    }
    let mut local = vec![0; n];
    for block in &mut blocks {
        for (l, &j) in block.coordinates.iter().enumerate() {
            local[j] = l;
        }
        block.offset = offset;
        offset += block.coordinates.len().pow(2);
    }
    for (i, bodies) in row_bodies.iter().enumerate() {
        let mut seen: Vec<usize> = bodies.iter().map(|&b| block_of[b]).collect();
        seen.sort_unstable();
        seen.dedup();
        for k in seen {
            let block = &mut blocks[k];
            block.rows.push(i);
            block.entries.push(
                (row_start[i]..row_start[i + 1])
                    .filter(|&e| block_of[column[e] / 3] == k)
                    .map(|e| (local[column[e]], e))
                    .collect(),
            );
        }
    }
    for (r, &i) in augmented_rows.iter().enumerate() {
        if let Some(&b) = row_bodies[i].first() {
            let block = &mut blocks[block_of[b]];
            let a = block.rows.binary_search(&i).unwrap_or_else(|_| unreachable!("row {i} touches its block"));
            block.augmenting.push((a, r));
            block.augmented = true;
        }
    }
    (blocks, offset)
}

/// Inverse masses for the augmentation weights: `1/M_jj`, or for a coordinate without mass `1 /`
/// the largest mass of its kind (translation or rotation; 1 if the system has none).
fn weight_inverse_mass(mass: &[f64]) -> Vec<f64> {
    let n = mass.len();
    let largest = |kind: fn(usize) -> bool| {
        let largest = (0..n).filter(|&j| kind(j)).fold(0.0_f64, |w, j| w.max(mass[j]));
        if largest > 0.0 { largest } else { 1.0 }
    };
    let (translation, rotation) = (largest(|j| j % 3 != 2), largest(|j| j % 3 == 2));
    (0..n)
        .map(|j| if mass[j] > 0.0 { 1.0 / mass[j] } else { 1.0 / if j % 3 == 2 { rotation } else { translation } })
        .collect()
}

/// What the probes found about row `i`: the coordinates `j` where `∂Φ_i/∂z_j` (or `∂(A ż)_i/∂ż_j`)
/// is nonzero at either probe configuration (row `i` touches `j`), each with whether it is the
/// same number at both (`Φ_i` is linear in `z_j`: a position, a relative angle or a drive, rather
/// than an angle turning a lever arm). A NaN derivative counts as touching, and as not linear.
/// One dual pass per coordinate and probe: `O(n m)` once per system, memory `O(nnz(J))`.
fn probe(
    constraints: &[Constraint],
    velocity: &[VelocityConstraint],
    n: usize,
    holonomic: usize,
) -> Vec<Vec<(usize, bool)>> {
    let m = holonomic + velocity.len();
    let mut rows = vec![Vec::new(); m];
    let point = |p: usize, shift: usize| (0..n).map(|k| Dual64::from(probe_value(k + shift, p))).collect::<Vec<_>>();
    let (mut z, mut zdot) = ([point(0, 0), point(1, 0)], [point(0, n), point(1, n)]);
    let mut phi = [vec![Dual64::from(0.0); holonomic], vec![Dual64::from(0.0); holonomic]];
    let mut rates = [vec![0.0; velocity.len()], vec![0.0; velocity.len()]];
    for j in 0..n {
        for p in 0..2 {
            // Φ_z column j, and ∂(A ż)/∂ż column j.
            z[p][j].eps = 1.0;
            evaluate_all(constraints, &z[p], Dual64::from(PROBE_TIMES[p]), &mut phi[p]);
            z[p][j].eps = 0.0;
            zdot[p][j].eps = 1.0;
            for (rate, constraint) in rates[p].iter_mut().zip(velocity) {
                *rate = constraint.evaluate(&z[p], &zdot[p]).eps;
            }
            zdot[p][j].eps = 0.0;
        }
        let derivative = |p: usize, i: usize| if i < holonomic { phi[p][i].eps } else { rates[p][i - holonomic] };
        for (i, row) in rows.iter_mut().enumerate() {
            let (a, b) = (derivative(0, i), derivative(1, i));
            if a != 0.0 || b != 0.0 {
                row.push((j, a != 0.0 && a == b));
            }
        }
    }
    rows
}

/// The representative of `b`'s set (union–find with path halving).
fn root(parent: &mut [usize], mut b: usize) -> usize {
    while parent[b] != b {
        parent[b] = parent[parent[b]];
        b = parent[b];
    }
    b
}

impl SchurPattern {
    /// The pattern of `S` over rows `0..rows`: `S_ik` for every pair of rows touching a common
    /// block, and every diagonal entry.
    fn new(blocks: &[Block], rows: usize) -> Self {
        let mut columns: Vec<Vec<usize>> = (0..rows).map(|i| vec![i]).collect();
        for block in blocks {
            let kept = block.rows.iter().take_while(|&&i| i < rows);
            for (a, &i) in kept.clone().enumerate() {
                columns[i].extend(kept.clone().take(a).copied());
            }
        }
        let mut column_start = vec![0];
        let mut row = Vec::new();
        for entries in &mut columns {
            entries.sort_unstable();
            entries.dedup();
            row.extend_from_slice(entries);
            column_start.push(row.len());
        }
        let position = |i: usize, k: usize| {
            let (i, k) = (i.min(k), i.max(k));
            let found = row[column_start[k]..column_start[k + 1]].binary_search(&i);
            column_start[k] + found.unwrap_or_else(|_| unreachable!("S_({i},{k}) is in the pattern by construction"))
        };
        let diagonal = (0..rows).map(|i| position(i, i)).collect();
        let scatter = blocks
            .iter()
            .map(|block| {
                let kept: Vec<usize> = block.rows.iter().copied().take_while(|&i| i < rows).collect();
                kept.iter().flat_map(|&a| kept.iter().map(move |&b| (a, b))).map(|(a, b)| position(a, b)).collect()
            })
            .collect();
        let symbolic = (rows > 0).then(|| {
            let pattern = SymbolicSparseColMatRef::new_checked(rows, rows, &column_start, None, &row);
            factorize_symbolic_cholesky(pattern, Side::Upper, SymmetricOrdering::Amd, Default::default())
                .unwrap_or_else(|error| panic!("symbolic Cholesky of a {rows} × {rows} pattern: {error:?}"))
        });
        Self { rows, column_start, row, diagonal, scatter, symbolic }
    }
}
