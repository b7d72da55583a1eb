//! Seeding dual numbers, in one place: a state lifted to duals with zero derivative parts
//! ([`constant`]), or moving along a direction ([`along`], [`along2`]), or a chunk of its
//! coordinates seeded in the lanes of vector duals ([`chunk`]); and the seeded state of
//! the tangent passes of an acceleration Jacobian ([`Tangent`], [`Seeds`]).

use crate::error::{Error, Stage, all_finite, non_finite};
use crate::scalar::Scalar;
use num_dual::{Dual, Dual2, Dual64, DualSVec};

/// `out_i = x_i`, derivative parts zero.
pub(crate) fn constant<S: Scalar>(out: &mut [Dual<S>], x: &[S]) {
    for (d, &xi) in out.iter_mut().zip(x) {
        *d = Dual::from_re(xi);
    }
}

/// `out_i = x_i + ε dx_i`: first-order duals moving along `dx` (their `ε` parts are the
/// directional derivative along `dx`).
pub(crate) fn along<S: Scalar>(out: &mut [Dual<S>], x: &[S], dx: &[S]) {
    for ((d, &xi), &vi) in out.iter_mut().zip(x).zip(dx) {
        *d = Dual::new(xi, vi);
    }
}

/// `out_i = x_i + ε₁ dx_i`, second part zero: second-order duals moving along `dx` (`v1` is
/// the first directional derivative, `v2` the second).
pub(crate) fn along2<S: Scalar>(out: &mut [Dual2<S>], x: &[S], dx: &[S]) {
    for ((d, &xi), &vi) in out.iter_mut().zip(x).zip(dx) {
        *d = Dual2::new(xi, vi, S::zero());
    }
}

/// Lanes of the vector dual numbers of the chunked Jacobian passes: the columns of one pass.
pub(crate) const CHUNK: usize = 4;

/// A vector dual number carrying [`CHUNK`] derivative lanes.
pub(crate) type Lanes<S> = DualSVec<S, CHUNK>;

/// Lane `k` of a vector dual's derivative (0 where it carries none).
#[inline]
pub(crate) fn lane<S: Scalar>(v: &Lanes<S>, k: usize) -> S {
    v.eps.0.as_ref().map_or(S::zero(), |e| e[k])
}

/// Seed the chunk of coordinates starting at `j0` into `out`: `x_j` in every lane, with lane
/// `j − j0` carrying `∂/∂x_j` for the chunk's `j`; returns the chunk's width (at most
/// [`CHUNK`]).
pub(crate) fn chunk<S: Scalar>(out: &mut [Lanes<S>], x: &[S], j0: usize) -> usize {
    let width = CHUNK.min(x.len() - j0);
    for (j, (d, &xj)) in out.iter_mut().zip(x).enumerate() {
        *d = Lanes::from_re(xj);
        if (j0..j0 + width).contains(&j) {
            *d = d.derivative(j - j0);
        }
    }
    width
}

/// What the tangent passes of a Jacobian need besides the `f64` workspace: the workspace `W`
/// of the evaluation in `Dual64` and the seeded state. An `f64` workspace holds one (boxed),
/// allocated by [`Dynamics::workspace`] or by the first Jacobian.
#[derive(Clone, Debug)]
pub(crate) struct Tangent<W> {
    /// The evaluation's workspace in `Dual64`.
    pub(crate) workspace: W,
    /// The seeded state.
    pub(crate) seeds: Seeds,
}

impl<W> Tangent<W> {
    pub(crate) fn new(workspace: W, n: usize) -> Box<Self> {
        Box::new(Self { workspace, seeds: Seeds::new(n) })
    }
}

/// Seeded copies of the state for the tangent passes, allocated once.
#[derive(Clone, Debug)]
pub(crate) struct Seeds {
    /// Coordinates as duals (n); one of them (or of `qdot`) carries `ε = 1` during a pass.
    q: Vec<Dual64>,
    /// Velocities as duals (n).
    qdot: Vec<Dual64>,
    /// `∂q̈/∂x_j` of the current pass: column `j` of the Jacobian (n).
    column: Vec<f64>,
}

impl Seeds {
    pub(crate) fn new(n: usize) -> Self {
        let zero = Dual64::from_re(0.0);
        Self { q: vec![zero; n], qdot: vec![zero; n], column: vec![0.0; n] }
    }

    /// Fill `jacobian` (n × 2n, row-major) with `2n` tangent passes: pass `j` seeds
    /// `x_j = (q, q̇)_j` and `tangent(t, q, q̇, column)` writes the `ε` parts of `q̈` into `column`.
    pub(crate) fn jacobian(
        &mut self,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        jacobian: &mut [f64],
        mut tangent: impl FnMut(Dual64, &[Dual64], &[Dual64], &mut [f64]) -> Result<(), Error>,
    ) -> Result<(), Error> {
        let n = self.q.len();
        check_shape(n, q, qdot, jacobian)?;
        // Unseeded state.
        constant(&mut self.q, q);
        constant(&mut self.qdot, qdot);
        let t = Dual64::from_re(t);
        // One pass per column: seed, evaluate, unseed, scatter.
        for j in 0..2 * n {
            let seed = if j < n { &mut self.q[j] } else { &mut self.qdot[j - n] };
            seed.eps = 1.0;
            let result = tangent(t, &self.q, &self.qdot, &mut self.column);
            let seed = if j < n { &mut self.q[j] } else { &mut self.qdot[j - n] };
            seed.eps = 0.0;
            result?;
            for i in 0..n {
                jacobian[i * 2 * n + j] = self.column[i];
            }
        }
        check_finite(t.re, q, jacobian)
    }
}

pub(crate) fn check_shape(n: usize, q: &[f64], qdot: &[f64], jacobian: &[f64]) -> Result<(), Error> {
    if q.len() != n {
        return Err(Error::DimensionMismatch { what: "q", expected: n, got: q.len() });
    }
    if qdot.len() != n {
        return Err(Error::DimensionMismatch { what: "q̇", expected: n, got: qdot.len() });
    }
    if jacobian.len() != 2 * n * n {
        return Err(Error::DimensionMismatch {
            what: "acceleration Jacobian",
            expected: 2 * n * n,
            got: jacobian.len(),
        });
    }
    Ok(())
}

pub(crate) fn check_finite(t: f64, q: &[f64], jacobian: &[f64]) -> Result<(), Error> {
    if all_finite(jacobian) { Ok(()) } else { Err(non_finite(Stage::Jacobian, t, q)) }
}
