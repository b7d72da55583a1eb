//! The simplified-Newton linear algebra shared by the implicit Runge–Kutta integrators
//! ([`Sdirk4`](super::Sdirk4), [`Gauss4`](super::Gauss4)), reduced to the velocities.
//!
//! `s` coupled stages with coefficient matrix `C` (s × s) on `y = (q, q̇)`, `y' = (q̇, a)`,
//! linearized with the frozen Jacobian `∂f/∂y = [[0, I], [A_q, A_v]]`
//! (`A_q = ∂q̈/∂q`, `A_v = ∂q̈/∂q̇`), give for the updates `(δq, δv)` of the stage increments
//!
//! ```text
//! δq − h (C ⊗ I) δv           = r_q
//! δv − h (C ⊗ A_q) δq − h (C ⊗ A_v) δv = r_v.
//! ```
//!
//! Eliminating `δq = r_q + h (C ⊗ I) δv` leaves one `sn × sn` system,
//!
//! ```text
//! (I − h C ⊗ A_v − h² C² ⊗ A_q) δv = r_v + h (C ⊗ A_q) r_q,
//! ```
//!
//! the Schur complement of `I − h C ⊗ ∂f/∂y` (Hairer & Wanner, *Solving ODE II*, §IV.8 and
//! §IV.10, on second-order problems): the same Newton step for a quarter of the factorization
//! work. For SDIRK (`s = 1`, `C = γ`) it is `I − γh A_v − (γh)² A_q`, i.e. `I − γh ∂f/∂y`.

use crate::linalg as solve;

/// The Jacobian, the factored reduced Newton matrix and scratch, for `s` stages of `n`
/// coordinates.
#[derive(Clone, Debug)]
pub(crate) struct StageSystem {
    n: usize,
    s: usize,
    /// `∂q̈/∂(q, q̇) = [A_q | A_v]` (n × 2n), filled by the integrator.
    pub jacobian: Vec<f64>,
    /// LU factor of `I − h C ⊗ A_v − h² C² ⊗ A_q` (sn × sn).
    matrix: Vec<f64>,
    /// Row pivots of the factor (sn).
    pivots: Vec<usize>,
    /// Right-hand side of the reduced system (sn).
    rhs: Vec<f64>,
}

impl StageSystem {
    pub(crate) fn new(n: usize, s: usize) -> Self {
        Self {
            n,
            s,
            jacobian: vec![0.0; 2 * n * n],
            matrix: vec![0.0; s * s * n * n],
            pivots: vec![0; s * n],
            rhs: vec![0.0; s * n],
        }
    }

    /// Assemble and factor `I − h C ⊗ A_v − h² C² ⊗ A_q` from `jacobian`; `c` and `c2 = C²`
    /// are `s × s`, row-major. Returns `false` if the matrix is singular.
    pub(crate) fn factor(&mut self, h: f64, c: &[f64], c2: &[f64]) -> bool {
        let (n, s) = (self.n, self.s);
        let m = s * n;
        for i in 0..s {
            for j in 0..s {
                let (hc, h2c2) = (h * c[i * s + j], h * h * c2[i * s + j]);
                for a in 0..n {
                    let row = &self.jacobian[a * 2 * n..(a + 1) * 2 * n];
                    for b in 0..n {
                        let identity = if i == j && a == b { 1.0 } else { 0.0 };
                        self.matrix[(i * n + a) * m + j * n + b] = identity - hc * row[n + b] - h2c2 * row[b];
                    }
                }
            }
        }
        solve::lu_factor(m, &mut self.matrix, &mut self.pivots).is_ok()
    }

    /// Solve for the Newton update in place: `rq`, `rv` (sn each, stage-major) hold the
    /// residuals on entry and `δq`, `δv` on return.
    pub(crate) fn solve(&mut self, h: f64, c: &[f64], rq: &mut [f64], rv: &mut [f64]) {
        let (n, s) = (self.n, self.s);
        // Right-hand side r_v + h (C ⊗ A_q) r_q.
        for i in 0..s {
            for a in 0..n {
                let row = &self.jacobian[a * 2 * n..a * 2 * n + n];
                let mut sum = rv[i * n + a];
                for j in 0..s {
                    let hc = h * c[i * s + j];
                    if hc != 0.0 {
                        let r = &rq[j * n..(j + 1) * n];
                        sum += hc * row.iter().zip(r).map(|(x, y)| x * y).sum::<f64>();
                    }
                }
                self.rhs[i * n + a] = sum;
            }
        }
        // δv from the factor.
        solve::lu_solve(s * n, &self.matrix, &self.pivots, &mut self.rhs);
        rv.copy_from_slice(&self.rhs);
        // δq = r_q + h (C ⊗ I) δv.
        for i in 0..s {
            for j in 0..s {
                let hc = h * c[i * s + j];
                for a in 0..n {
                    rq[i * n + a] += hc * rv[j * n + a];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::assert_relative;
    use nalgebra::{DMatrix, DVector};

    /// The reduced solve gives the same update as the full system `(I − h C ⊗ ∂f/∂y) δ = r`.
    #[test]
    fn reduced_solve_matches_the_full_newton_system() {
        let (n, s, h) = (3, 2, 0.37);
        let c = [0.25, 0.25 - 3f64.sqrt() / 6.0, 0.25 + 3f64.sqrt() / 6.0, 0.25];
        let c2: Vec<f64> = (0..4).map(|k| (0..2).map(|l| c[(k / 2) * 2 + l] * c[l * 2 + k % 2]).sum()).collect();
        let mut system = StageSystem::new(n, s);
        for (k, x) in system.jacobian.iter_mut().enumerate() {
            *x = ((k * 7 + 3) % 11) as f64 - 5.0 + 0.1 * k as f64;
        }
        assert!(system.factor(h, &c, &c2));
        let rq0: Vec<f64> = (0..s * n).map(|k| 0.3 * k as f64 - 1.0).collect();
        let rv0: Vec<f64> = (0..s * n).map(|k| 1.0 / (k as f64 + 1.5)).collect();
        let (mut rq, mut rv) = (rq0.clone(), rv0.clone());
        system.solve(h, &c, &mut rq, &mut rv);
        // Full system in y = (q, v) per stage: ∂f/∂y = [[0, I], [A_q, A_v]].
        let dim = 2 * n;
        let df = DMatrix::from_fn(dim, dim, |r, col| match (r < n, col < n) {
            (true, true) => 0.0,
            (true, false) => f64::from(u8::from(col - n == r)),
            (false, _) => system.jacobian[(r - n) * 2 * n + col],
        });
        let full = DMatrix::from_fn(s * dim, s * dim, |r, col| {
            let (i, j) = (r / dim, col / dim);
            f64::from(u8::from(r == col)) - h * c[i * s + j] * df[(r % dim, col % dim)]
        });
        let rhs = DVector::from_fn(s * dim, |r, _| {
            let (i, k) = (r / dim, r % dim);
            if k < n { rq0[i * n + k] } else { rv0[i * n + k - n] }
        });
        let expected = full.lu().solve(&rhs).expect("regular");
        for i in 0..s {
            for a in 0..n {
                assert_relative(rq[i * n + a], expected[i * dim + a], 1e-12);
                assert_relative(rv[i * n + a], expected[i * dim + n + a], 1e-12);
            }
        }
    }
}
