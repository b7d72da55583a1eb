//! Normal modes: the small oscillations of a mechanism about an equilibrium.
//!
//! An equilibrium `q*` is a configuration where the system rests, `q̈(t, q*, 0) = 0`. Near it,
//! `δq̈ = A δq` with `A = ∂q̈/∂q` (the engine's exact acceleration Jacobian), and the motion obeys
//! `M δq̈ + K δq = 0` with `K = −M A`. On a mechanism with constraints the motion stays in the
//! tangent space `G δq = 0`: with a basis `N` of it, `M_r = Nᵀ M N`, `K_r = Nᵀ K N` (the
//! constraint forces `Gᵀλ` drop out of `Nᵀ`). The modes solve `K_r y = ω² M_r y`, a symmetric
//! generalized eigenproblem (Cholesky of `M_r`, then nalgebra's symmetric eigensolver); each mode
//! shape is `δq = N y`. `ω² > 0` oscillates at `ω`, `ω² = 0` is a zero mode (a free cart, a
//! cyclic coordinate), `ω² < 0` an unstable direction, reported with its imaginary frequency.
//!
//! The equilibrium is found by Newton's method from a given configuration, in the tangent space
//! and in the metric of `M` (`Nᵀ M A N Δy = −Nᵀ M q̈`), a minimum-norm step along the zero
//! modes, each iterate projected back onto the constraints.
//!
//! ```
//! use lagrange::{Description, Mechanism, Model, Pose, Scalar};
//!
//! /// A pendulum of length 2 m.
//! #[derive(Clone)]
//! struct Pendulum(Description);
//!
//! impl Mechanism for Pendulum {
//!     fn description(&self) -> &Description {
//!         &self.0
//!     }
//!     fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
//!         p[0] = Pose::point(q[0].sin() * 2.0, -q[0].cos() * 2.0);
//!     }
//! }
//!
//! let pendulum = Pendulum(Description::new().angle("θ").point("bob", 1.0).gravity(9.81));
//! let mut system = lagrange::Buffered::new(Model::new(pendulum)?);
//! let modes = lagrange::modes::normal_modes(&mut system, 0.0, &[0.3])?;
//! assert!(modes.equilibrium[0].abs() < 1e-12);
//! // ω² = g/l.
//! approx::assert_relative_eq!(modes.modes[0].omega_squared, 9.81 / 2.0, max_relative = 1e-12);
//! # Ok::<(), lagrange::Error>(())
//! ```

use crate::{Error, State, System};
use nalgebra::{DMatrix, DVector};

/// Newton iterations allowed to find the equilibrium.
const ITERATIONS: usize = 60;

/// Singular values below this fraction of the largest are zero (directions in which `q̈` does
/// not change: the zero modes' and the constraints'). The matrices come from exact derivatives,
/// so their round-off is about ε times their size; 1e-10 leaves five orders of margin.
const SINGULAR: f64 = 1e-10;

/// An eigenvalue `ω²` within this fraction of the largest `|ω²|` is a zero mode: exact
/// derivatives give the spectrum to round-off (≈ 1e-15 relative), 1e-9 leaves a wide margin
/// for the conditioning of `M_r`.
const ZERO: f64 = 1e-9;

/// What a mode does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModeKind {
    /// `ω² > 0`: an oscillation at `ω`.
    Oscillating,
    /// `ω² = 0` (to round-off): a free motion without restoring force.
    Zero,
    /// `ω² < 0`: an unstable direction, growing as `e^{√(−ω²) t}`.
    Unstable,
}

/// One normal mode.
#[derive(Clone, Debug, PartialEq)]
pub struct Mode {
    /// `ω²` (rad²/s²).
    pub omega_squared: f64,
    /// What it does.
    pub kind: ModeKind,
    /// The mode shape `δq`, scaled to a largest entry of 1 (positive).
    pub shape: Vec<f64>,
}

impl Mode {
    /// The angular frequency `ω = √ω²` (rad/s) of an oscillating mode; `√|ω²|`, the growth
    /// rate, of an unstable one (its frequency is imaginary); 0 for a zero mode.
    pub fn omega(&self) -> f64 {
        match self.kind {
            ModeKind::Zero => 0.0,
            _ => self.omega_squared.abs().sqrt(),
        }
    }
}

/// The normal modes about an equilibrium.
#[derive(Clone, Debug, PartialEq)]
pub struct Modes {
    /// The equilibrium `q*`.
    pub equilibrium: Vec<f64>,
    /// The mass matrix there (n × n, row-major).
    pub mass: Vec<f64>,
    /// The stiffness matrix there, `K = −M ∂q̈/∂q` (n × n, row-major). On a mechanism with
    /// constraints only its restriction to their tangent space is symmetric (the rest carries
    /// the constraint forces' change).
    pub stiffness: Vec<f64>,
    /// The largest entry of `K_r − K_rᵀ` relative to the largest of `K_r = Nᵀ K N`: round-off
    /// for forces with a potential; more means circulatory forces, and the modes shown are those
    /// of its symmetric part.
    pub asymmetry: f64,
    /// Whether `q̈` depends on `q̇` at rest to first order (damping): the frequencies are the
    /// undamped ones.
    pub damped: bool,
    /// The modes, by increasing `ω²`, as many as the tangent space has dimensions.
    pub modes: Vec<Mode>,
}

fn no_equilibrium(q: &[f64], why: String) -> Error {
    Error::NoEquilibrium { q: q.to_vec(), why }
}

/// A basis of the null space of the `rows × n` matrix `g` (row-major): right singular vectors
/// whose singular values are below [`SINGULAR`] of the largest. The identity without rows.
fn tangent_basis(g: &[f64], rows: usize, n: usize) -> DMatrix<f64> {
    if rows == 0 {
        return DMatrix::identity(n, n);
    }
    // Pad to a square matrix so that the SVD returns every right singular vector.
    let mut square = DMatrix::zeros(n.max(rows), n);
    for r in 0..rows {
        for c in 0..n {
            square[(r, c)] = g[r * n + c];
        }
    }
    let svd = square.svd(false, true);
    let v_t = svd.v_t.expect("requested");
    let largest = svd.singular_values.max();
    let columns: Vec<DVector<f64>> = svd
        .singular_values
        .iter()
        .enumerate()
        .filter(|(_, s)| **s <= SINGULAR * largest)
        .map(|(k, _)| v_t.row(k).transpose())
        .collect();
    if columns.is_empty() { DMatrix::zeros(n, 0) } else { DMatrix::from_columns(&columns) }
}

/// `Δy` minimizing `|a y − b|` with the smallest norm: the SVD's pseudo-inverse, singular values
/// below [`SINGULAR`] of the largest dropped.
fn least_squares(a: &DMatrix<f64>, b: &DVector<f64>) -> DVector<f64> {
    let svd = a.clone().svd(true, true);
    let largest = svd.singular_values.max();
    svd.solve(b, SINGULAR * largest).unwrap_or_else(|_| DVector::zeros(a.ncols()))
}

/// The system's matrices at rest at `(t, q)`: `M`, `A = ∂q̈/∂q`, `∂q̈/∂q̇`, `q̈` and the tangent
/// basis of its constraints.
struct AtRest {
    mass: DMatrix<f64>,
    jacobian: DMatrix<f64>,
    velocity_jacobian: DMatrix<f64>,
    accelerations: DVector<f64>,
    tangent: DMatrix<f64>,
}

fn at_rest(system: &mut dyn System, t: f64, q: &[f64]) -> Result<AtRest, Error> {
    let n = q.len();
    let rest = vec![0.0; n];
    let accelerations = DVector::from_column_slice(system.accelerations(t, q, &rest)?);
    let full = system.acceleration_jacobian(t, q, &rest)?;
    let jacobian = DMatrix::from_fn(n, n, |i, j| full[i * 2 * n + j]);
    let velocity_jacobian = DMatrix::from_fn(n, n, |i, j| full[i * 2 * n + n + j]);
    let mass = DMatrix::from_row_slice(n, n, system.mass_matrix(t, q, &rest)?);
    let (m, k) = system.constraint_counts();
    let tangent = match system.constraint_jacobian(t, q, &rest)? {
        Some(g) => tangent_basis(g, m + k, n),
        None => DMatrix::identity(n, n),
    };
    Ok(AtRest { mass, jacobian, velocity_jacobian, accelerations, tangent })
}

/// The equilibrium nearest `q` (Newton's method in the tangent space of the constraints) and the
/// normal modes about it, at time `t`.
///
/// # Errors
/// [`Error::NoEquilibrium`] when Newton's method does not bring `q̈` to zero from `q` (Kepler's
/// problem, a block sliding down a wedge), or when the equilibrium does not stay one as time
/// passes (a driven pendulum); [`Error::IndefiniteMassMatrix`] if `M` on the tangent space is not
/// positive definite; any error of the system's evaluations or of its projection onto the
/// constraints.
pub fn normal_modes(system: &mut dyn System, t: f64, q: &[f64]) -> Result<Modes, Error> {
    let n = system.coordinates().len();
    if q.len() != n {
        return Err(Error::DimensionMismatch { what: "q", expected: n, got: q.len() });
    }
    let project = |system: &mut dyn System, q: &[f64]| -> Result<Vec<f64>, Error> {
        if system.constraint_counts() == (0, 0) {
            return Ok(q.to_vec());
        }
        Ok(system.assemble(&State::new(t, q.to_vec(), vec![0.0; n]), &vec![false; n])?.q)
    };
    let mut x = project(system, q)?;
    let scale = 1.0 + x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let mut residual = f64::INFINITY;
    let mut equilibrium = None;
    for _ in 0..ITERATIONS {
        let r = at_rest(system, t, &x)?;
        let metric = r.tangent.transpose() * &r.mass;
        let force = &metric * &r.accelerations;
        let reduced = &metric * &r.jacobian * &r.tangent;
        // The size q̈ is measured against: how much it changes over the configuration's scale.
        residual = force.amax() / (reduced.amax() * scale + f64::MIN_POSITIVE);
        if residual <= 16.0 * f64::EPSILON {
            equilibrium = Some(r);
            break;
        }
        let step = &r.tangent * least_squares(&reduced, &(-force));
        if step.amax() == 0.0 {
            break;
        }
        let next: Vec<f64> = x.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
        x = project(system, &next)?;
        if x.iter().zip(q).any(|(a, b)| !a.is_finite() || (a - b).abs() > 1e3 * scale) {
            return Err(no_equilibrium(q, "Newton's method runs away from it (q̈ does not vanish nearby)".into()));
        }
    }
    let Some(r) = equilibrium else {
        return Err(no_equilibrium(
            q,
            format!(
                "q̈ at rest does not vanish nearby (relative residual {residual:.1e} after Newton's method; a mechanism that cannot rest, or a force that does not depend on q)"
            ),
        ));
    };
    // An equilibrium holds at every time: a drive or a time-varying force moves it.
    let metric = r.tangent.transpose() * &r.mass;
    let reference = (&metric * &r.jacobian * &r.tangent).amax() * scale;
    let rest = vec![0.0; n];
    for dt in [0.37, 1.3, 2.9] {
        let later = DVector::from_column_slice(system.accelerations(t + dt, &x, &rest)?);
        if (&metric * later).amax() > 1e-8 * reference {
            return Err(no_equilibrium(
                q,
                format!(
                    "the configuration at rest at t = {t} does not stay at rest at t = {} (the equations depend on time)",
                    t + dt
                ),
            ));
        }
    }

    let stiffness = -(&r.mass * &r.jacobian);
    let damped = r.velocity_jacobian.amax() > 1e-12 * (r.jacobian.amax() + 1.0);
    let mass_r = r.tangent.transpose() * &r.mass * &r.tangent;
    let stiffness_r = r.tangent.transpose() * &stiffness * &r.tangent;
    let largest = stiffness_r.amax();
    let asymmetry = if largest > 0.0 { (&stiffness_r - stiffness_r.transpose()).amax() / largest } else { 0.0 };
    let mass_r = (&mass_r + mass_r.transpose()) * 0.5;
    let stiffness_r = (&stiffness_r + stiffness_r.transpose()) * 0.5;
    let indefinite = || Error::IndefiniteMassMatrix {
        t,
        q: x.clone(),
        coordinate: "(the constraints' tangent space)".into(),
        pivot: mass_r.symmetric_eigenvalues().min(),
        diagonal: mass_r.diagonal().min(),
    };
    let cholesky = mass_r.clone().cholesky().ok_or_else(indefinite)?;
    let l_inv = cholesky.l().try_inverse().ok_or_else(indefinite)?;
    let c = &l_inv * &stiffness_r * l_inv.transpose();
    let c = (&c + c.transpose()) * 0.5;
    let eigen = c.symmetric_eigen();
    let biggest = eigen.eigenvalues.amax();
    let mut modes: Vec<Mode> = eigen
        .eigenvalues
        .iter()
        .enumerate()
        .map(|(k, &w2)| {
            let y = l_inv.transpose() * eigen.eigenvectors.column(k);
            let mut shape: Vec<f64> = (&r.tangent * y).iter().copied().collect();
            let peak = shape.iter().copied().fold(0.0_f64, |m, v| if v.abs() > m.abs() { v } else { m });
            if peak != 0.0 {
                shape.iter_mut().for_each(|v| *v /= peak);
            }
            let kind = if w2.abs() <= ZERO * biggest || biggest == 0.0 {
                ModeKind::Zero
            } else if w2 > 0.0 {
                ModeKind::Oscillating
            } else {
                ModeKind::Unstable
            };
            Mode { omega_squared: if kind == ModeKind::Zero { 0.0 } else { w2 }, kind, shape }
        })
        .collect();
    modes.sort_by(|a, b| a.omega_squared.total_cmp(&b.omega_squared));
    Ok(Modes {
        equilibrium: x,
        mass: r.mass.transpose().iter().copied().collect(),
        stiffness: stiffness.transpose().iter().copied().collect(),
        asymmetry,
        damped,
        modes,
    })
}
