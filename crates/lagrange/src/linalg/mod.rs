//! Dense linear algebra for the small systems of the engine, below every other module: the
//! in-place LDLᵀ and LU factorizations, the mass-matrix product `Σ_b J_bᵀ D_b J_b`, and the
//! number of coordinates as a type ([`size`]).
//!
//! Generic over the scalar (so that accelerations can be differentiated), which is why the
//! engine does not call nalgebra's decompositions (they require `RealField`).

pub(crate) mod size;

use crate::scalar::Scalar;
use size::{Size, with_size};

/// Relative pivot below which a symmetric positive definite factorization is declared
/// singular: the pivot of coordinate `j` (its diagonal entry after eliminating the coordinates
/// before it) is compared with that coordinate's own diagonal entry. A ratio of 1e-12 means
/// the coordinate is dependent on the others to within ~1e4 ulps — a configuration where the
/// accelerations lose all digits. Extreme but regular scenes (mass ratios 1e6, angles 1e-8)
/// keep ratios ≥ 1e-7.
pub(crate) const PIVOT_RTOL: f64 = 1e-12;

/// A pivot of [`ldlt_factor`] that is not positive relative to its diagonal entry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BadPivot {
    /// Its row (the coordinate).
    pub index: usize,
    /// The pivot `D_j`.
    pub pivot: f64,
    /// The diagonal entry `A_jj`.
    pub diagonal: f64,
}

/// Factor the symmetric matrix `a` (n × n, row-major, both triangles filled) in place as
/// `L D Lᵀ`: `L` unit lower triangular below the diagonal, `D` on the diagonal; the strict
/// upper triangle is left untouched.
///
/// Returns the [`BadPivot`] `j` if that pivot is not positive relative to its diagonal entry
/// (singular or indefinite matrix).
pub(crate) fn ldlt_factor<S: Scalar>(n: usize, a: &mut [S]) -> Result<(), BadPivot> {
    debug_assert_eq!(a.len(), n * n);
    with_size!(n, size => ldlt_factor_sized(size, a))
}

/// [`ldlt_factor`] compiled for a size.
#[inline]
pub(crate) fn ldlt_factor_sized<S: Scalar, N: Size>(size: N, a: &mut [S]) -> Result<(), BadPivot> {
    let n = size.get();
    let a = &mut a[..n * n];
    for j in 0..n {
        // D_j = A_jj − Σ_k L_jk² D_k.
        let diagonal = a[j * n + j];
        let mut d = diagonal;
        for k in 0..j {
            let l = a[j * n + k];
            d -= l * l * a[k * n + k];
        }
        let ratio = d.re() / diagonal.re();
        if !(diagonal.re() > 0.0 && ratio > PIVOT_RTOL) {
            return Err(BadPivot { index: j, pivot: d.re(), diagonal: diagonal.re() });
        }
        a[j * n + j] = d;
        // L_ij = (A_ij − Σ_k L_ik L_jk D_k) / D_j.
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k] * a[k * n + k];
            }
            a[i * n + j] = s / d;
        }
    }
    Ok(())
}

/// Solve `L D Lᵀ x = b` in place (`b` becomes `x`) with a factor from [`ldlt_factor`].
pub(crate) fn ldlt_solve<S: Scalar>(n: usize, factor: &[S], b: &mut [S]) {
    with_size!(n, size => ldlt_solve_sized(size, factor, b))
}

/// [`ldlt_solve`] compiled for a size.
#[inline]
pub(crate) fn ldlt_solve_sized<S: Scalar, N: Size>(size: N, factor: &[S], b: &mut [S]) {
    let n = size.get();
    let (factor, b) = (&factor[..n * n], &mut b[..n]);
    // Forward substitution L y = b.
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= factor[i * n + k] * b[k];
        }
        b[i] = s;
    }
    // Diagonal D z = y.
    for i in 0..n {
        b[i] /= factor[i * n + i];
    }
    // Back substitution Lᵀ x = z.
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= factor[k * n + i] * b[k];
        }
        b[i] = s;
    }
}

/// Solve `L y = b` in place with the unit lower triangle of a factor from [`ldlt_factor`].
pub(crate) fn ldlt_forward<S: Scalar>(n: usize, factor: &[S], b: &mut [S]) {
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= factor[i * n + k] * b[k];
        }
        b[i] = s;
    }
}

/// Solve `Lᵀ x = b` in place with the unit lower triangle of a factor from [`ldlt_factor`].
pub(crate) fn ldlt_backward<S: Scalar>(n: usize, factor: &[S], b: &mut [S]) {
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= factor[k * n + i] * b[k];
        }
        b[i] = s;
    }
}

/// Factor a general matrix `a` (n × n, row-major) in place as `P A = L U` with partial pivoting;
/// `pivots[i]` is the row swapped into row `i`. Returns `Err(j)` at an exactly zero or
/// non-finite pivot.
pub(crate) fn lu_factor(n: usize, a: &mut [f64], pivots: &mut [usize]) -> Result<(), usize> {
    for j in 0..n {
        // Pivot: the largest entry of column j at or below the diagonal.
        let mut p = j;
        for i in j + 1..n {
            if a[i * n + j].abs() > a[p * n + j].abs() {
                p = i;
            }
        }
        pivots[j] = p;
        let pivot = a[p * n + j];
        if pivot == 0.0 || !pivot.is_finite() {
            return Err(j);
        }
        if p != j {
            for k in 0..n {
                a.swap(j * n + k, p * n + k);
            }
        }
        // Eliminate below the pivot.
        for i in j + 1..n {
            let l = a[i * n + j] / pivot;
            a[i * n + j] = l;
            for k in j + 1..n {
                a[i * n + k] -= l * a[j * n + k];
            }
        }
    }
    Ok(())
}

/// Solve `A x = b` in place with a factor from [`lu_factor`].
pub(crate) fn lu_solve(n: usize, factor: &[f64], pivots: &[usize], b: &mut [f64]) {
    for j in 0..n {
        b.swap(j, pivots[j]);
    }
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= factor[i * n + k] * b[k];
        }
        b[i] = s;
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= factor[i * n + k] * b[k];
        }
        b[i] = s / factor[i * n + i];
    }
}

/// The mass matrix `M = Σ_b J_bᵀ D_b J_b`, `D_b = diag(m_b, m_b, I_b)`, from the pose Jacobian
/// `jacobian` (3B × n, body-major rows) into `out` (n × n): upper triangle, mirrored.
pub(crate) fn mass_matrix_sized<S: Scalar, N: Size>(
    size: N,
    mass: &[f64],
    inertia: &[f64],
    jacobian: &[S],
    out: &mut [S],
) {
    let n = size.get();
    let (mm, jac) = (&mut out[..n * n], jacobian);
    mm.fill(S::zero());
    for (b, (&m, &inertia)) in mass.iter().zip(inertia).enumerate() {
        let rows = &jac[3 * b * n..3 * (b + 1) * n];
        // Translational part m (Jxᵀ Jx + Jyᵀ Jy), upper triangle.
        if m != 0.0 {
            for i in 0..n {
                let (xi, yi) = (rows[i] * m, rows[n + i] * m);
                for j in i..n {
                    mm[i * n + j] += xi * rows[j] + yi * rows[n + j];
                }
            }
        }
        // Rotational part I Jφᵀ Jφ.
        if inertia != 0.0 {
            for i in 0..n {
                let ai = rows[2 * n + i] * inertia;
                for j in i..n {
                    mm[i * n + j] += ai * rows[2 * n + j];
                }
            }
        }
    }
    // Mirror the upper triangle.
    for i in 1..n {
        for j in 0..i {
            mm[i * n + j] = mm[j * n + i];
        }
    }
}

/// [`mass_matrix_sized`] for real numbers, skipping the columns of `J` that are exactly zero for
/// a body: each body of a mechanism of many coordinates usually moves with a few of them (a
/// link of a loop with its own angle and its neighbour's), so its outer products touch a few
/// entries of `M` instead of `n²`. `columns` (n) is scratch. Exact zeros only, so the result is
/// the dense one bit for bit.
pub(crate) fn mass_matrix_sparse(
    n: usize,
    mass: &[f64],
    inertia: &[f64],
    jacobian: &[f64],
    out: &mut [f64],
    columns: &mut [usize],
) {
    let mm = &mut out[..n * n];
    mm.fill(0.0);
    for (b, (&m, &inertia)) in mass.iter().zip(inertia).enumerate() {
        let rows = &jacobian[3 * b * n..3 * (b + 1) * n];
        // The body's columns with a nonzero entry, in increasing order.
        let mut count = 0;
        for j in 0..n {
            if rows[j] != 0.0 || rows[n + j] != 0.0 || rows[2 * n + j] != 0.0 {
                columns[count] = j;
                count += 1;
            }
        }
        let columns = &columns[..count];
        // The same operations as the dense assembly on these columns (the others add zeros).
        if m != 0.0 {
            for (a, &i) in columns.iter().enumerate() {
                let (xi, yi) = (rows[i] * m, rows[n + i] * m);
                for &j in &columns[a..] {
                    mm[i * n + j] += xi * rows[j] + yi * rows[n + j];
                }
            }
        }
        if inertia != 0.0 {
            for (a, &i) in columns.iter().enumerate() {
                let ai = rows[2 * n + i] * inertia;
                for &j in &columns[a..] {
                    mm[i * n + j] += ai * rows[2 * n + j];
                }
            }
        }
    }
    // Mirror the upper triangle.
    for i in 1..n {
        for j in 0..i {
            mm[i * n + j] = mm[j * n + i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    #[test]
    fn the_sparse_mass_matrix_is_the_dense_one() {
        let (n, mass, inertia) = (5, [1.0, 2.0, 0.5], [0.1, 0.0, 0.3]);
        // Each body moves with two or three of the five coordinates.
        let mut jacobian = vec![0.0; 9 * n];
        for (r, row) in jacobian.chunks_mut(n).enumerate() {
            for j in [r % 5, (r + 2) % 5, (r / 3 + 4) % 5] {
                row[j] = 0.3 + (r * 7 + j * 3) as f64 * 0.11;
            }
        }
        let (mut dense, mut sparse, mut columns) = (vec![0.0; n * n], vec![0.0; n * n], vec![0; n]);
        mass_matrix_sized(size::Dynamic(n), &mass, &inertia, &jacobian, &mut dense);
        mass_matrix_sparse(n, &mass, &inertia, &jacobian, &mut sparse, &mut columns);
        assert_eq!(dense, sparse);
    }

    fn spd(n: usize) -> DMatrix<f64> {
        let b = DMatrix::from_fn(n, n, |i, j| ((i * 7 + j * 3) % 5) as f64 * 0.3 + if i == j { 1.0 } else { 0.1 });
        &b * b.transpose() + DMatrix::identity(n, n)
    }

    #[test]
    fn ldlt_solves_like_nalgebra_cholesky() {
        for n in 1..7 {
            let a = spd(n);
            let rhs = DVector::from_fn(n, |i, _| i as f64 - 1.5);
            let expected = a.clone().cholesky().unwrap().solve(&rhs);
            let mut f: Vec<f64> = a.transpose().as_slice().to_vec();
            ldlt_factor(n, &mut f).unwrap();
            let mut x = rhs.as_slice().to_vec();
            ldlt_solve(n, &f, &mut x);
            for i in 0..n {
                assert!((x[i] - expected[i]).abs() <= 1e-12 * expected.amax().max(1.0), "n={n} i={i}");
            }
        }
    }

    #[test]
    fn ldlt_rejects_singular_and_indefinite() {
        // Rank one: second coordinate dependent on the first.
        let mut a = vec![1.0, 2.0, 2.0, 4.0];
        assert_eq!(ldlt_factor(2, &mut a).unwrap_err().index, 1);
        let mut a = vec![1.0, 0.0, 0.0, -1.0];
        assert!(ldlt_factor(2, &mut a).is_err());
        let mut a = vec![0.0];
        assert!(ldlt_factor(1, &mut a).is_err());
    }

    #[test]
    fn lu_solves_like_nalgebra() {
        let n = 4;
        let a = DMatrix::from_fn(n, n, |i, j| ((i * 5 + j * 11) % 7) as f64 - 3.0 + if i == j { 0.5 } else { 0.0 });
        let rhs = DVector::from_fn(n, |i, _| 1.0 + i as f64);
        let expected = a.clone().lu().solve(&rhs).unwrap();
        let mut f: Vec<f64> = a.transpose().as_slice().to_vec();
        let mut p = vec![0; n];
        lu_factor(n, &mut f, &mut p).unwrap();
        let mut x = rhs.as_slice().to_vec();
        lu_solve(n, &f, &p, &mut x);
        for i in 0..n {
            assert!((x[i] - expected[i]).abs() <= 1e-12 * expected.amax(), "i={i}");
        }
    }
}
