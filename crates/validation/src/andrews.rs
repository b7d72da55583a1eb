//! Andrews' squeezing mechanism as the CWI/Bari IVP test set writes it (problem "andrews";
//! Hairer & Wanner, *Solving ODEs II*, §VII.7): its hand-derived mass matrix `M(q)`, force
//! vector `f(q, q̇)`, constraints `g(q)` and their Jacobian `G(q)`, in the test set's seven
//! angles `(β, Θ, γ, Φ, δ, Ω, ε)`, at the test set's parameters.
//!
//! This is the independent side of two checks: the scene `andrews_squeezer` derives the same
//! equations from its seven bodies' poses by automatic differentiation
//! (docs/scenes.md#andrews_squeezer), and the benches time its constrained `q̈` and `λ` against
//! [`kkt`], the dense solve of these formulas. Nothing here is used by the engine.

use nalgebra::{SMatrix, SVector};

/// Masses `m1 … m7` (kg).
const M: [f64; 7] = [0.04325, 0.00365, 0.02373, 0.00706, 0.07050, 0.00706, 0.05498];
/// Inertias about the centres of mass `i1 … i7` (kg m²).
const I: [f64; 7] = [2.194e-6, 4.410e-7, 5.255e-6, 5.667e-7, 1.169e-5, 5.667e-7, 1.912e-5];
/// Fixed points `A`, `B`, `C` (m).
const XA: f64 = -0.06934;
const YA: f64 = -0.00227;
const XB: f64 = -0.03635;
const YB: f64 = 0.03273;
const XC: f64 = 0.014;
const YC: f64 = 0.072;
/// Spring stiffness (N/m) and natural length (m); driving torque (N m).
const C0: f64 = 4530.0;
const L0: f64 = 0.07785;
const MOM: f64 = 0.033;
/// Body geometry (m).
const D: f64 = 28e-3;
const DA: f64 = 115e-4;
const E: f64 = 2e-2;
const EA: f64 = 1421e-5;
const RR: f64 = 7e-3;
const RA: f64 = 92e-5;
const SS: f64 = 35e-3;
const SA: f64 = 1874e-5;
const SB: f64 = 1043e-5;
const SC: f64 = 18e-3;
const SD: f64 = 2e-2;
const TA: f64 = 2308e-5;
const TB: f64 = 916e-5;
const U: f64 = 4e-2;
const UA: f64 = 1228e-5;
const UB: f64 = 449e-5;
const ZF: f64 = 2e-2;
const ZT: f64 = 4e-2;
const FA: f64 = 1421e-5;

/// The test set's equations at one state: `M` (7 × 7), `f` (7), `G` (6 × 7), `g` (6).
#[derive(Clone, Debug, PartialEq)]
pub struct Equations {
    /// Mass matrix `M(q)`.
    pub mass: SMatrix<f64, 7, 7>,
    /// Force vector `f(q, q̇)`: driving torque, spring, and the velocity-dependent terms.
    pub force: SVector<f64, 7>,
    /// Constraint Jacobian `G = ∂g/∂q`.
    pub jacobian: SMatrix<f64, 6, 7>,
    /// Constraints `g(q)` (the loop closures at the joint point `E`).
    pub constraints: SVector<f64, 6>,
}

/// `M`, `f`, `G` and `g` at `(q, q̇)` from the test set's formulas, with its sign convention
/// `M q̈ = f − Gᵀ λ`.
pub fn equations(q: &[f64; 7], qdot: &[f64; 7]) -> Equations {
    let [beta, theta, gamma, phi, delta, omega, epsilon] = *q;
    let (sibe, cobe) = beta.sin_cos();
    let (sith, coth) = theta.sin_cos();
    let (siga, coga) = gamma.sin_cos();
    let (siph, coph) = phi.sin_cos();
    let (side, code) = delta.sin_cos();
    let (siom, coom) = omega.sin_cos();
    let (siep, coep) = epsilon.sin_cos();
    let (sibeth, cobeth) = (beta + theta).sin_cos();
    let (siphde, cophde) = (phi + delta).sin_cos();
    let (siomep, coomep) = (omega + epsilon).sin_cos();
    let [bep, thp, _, php, dep, omp, epp] = *qdot;
    let [m1, m2, m3, m4, m5, m6, m7] = M;
    let [i1, i2, i3, i4, i5, i6, i7] = I;

    let mut mass = SMatrix::<f64, 7, 7>::zeros();
    mass[(0, 0)] = m1 * RA * RA + m2 * (RR * RR - 2.0 * DA * RR * coth + DA * DA) + i1 + i2;
    mass[(1, 0)] = m2 * (DA * DA - DA * RR * coth) + i2;
    mass[(1, 1)] = m2 * DA * DA + i2;
    mass[(2, 2)] = m3 * (SA * SA + SB * SB) + i3;
    mass[(3, 3)] = m4 * (E - EA).powi(2) + i4;
    mass[(4, 3)] = m4 * ((E - EA).powi(2) + ZT * (E - EA) * siph) + i4;
    mass[(4, 4)] = m4 * (ZT * ZT + 2.0 * ZT * (E - EA) * siph + (E - EA).powi(2)) + m5 * (TA * TA + TB * TB) + i4 + i5;
    mass[(5, 5)] = m6 * (ZF - FA).powi(2) + i6;
    mass[(6, 5)] = m6 * ((ZF - FA).powi(2) - U * (ZF - FA) * siom) + i6;
    mass[(6, 6)] = m6 * ((ZF - FA).powi(2) - 2.0 * U * (ZF - FA) * siom + U * U) + m7 * (UA * UA + UB * UB) + i6 + i7;
    for j in 1..7 {
        for i in 0..j {
            mass[(i, j)] = mass[(j, i)];
        }
    }

    // The spring from C to the point D of body K3.
    let xd = SD * coga + SC * siga + XB;
    let yd = SD * siga - SC * coga + YB;
    let length = ((xd - XC).powi(2) + (yd - YC).powi(2)).sqrt();
    let tension = -C0 * (length - L0) / length;
    let (fx, fy) = (tension * (xd - XC), tension * (yd - YC));
    let force = SVector::<f64, 7>::from([
        MOM - m2 * DA * RR * thp * (thp + 2.0 * bep) * sith,
        m2 * DA * RR * bep * bep * sith,
        fx * (SC * coga - SD * siga) + fy * (SD * coga + SC * siga),
        m4 * ZT * (E - EA) * dep * dep * coph,
        -m4 * ZT * (E - EA) * php * (php + 2.0 * dep) * coph,
        -m6 * U * (ZF - FA) * epp * epp * coom,
        m6 * U * (ZF - FA) * omp * (omp + 2.0 * epp) * coom,
    ]);

    let mut jacobian = SMatrix::<f64, 6, 7>::zeros();
    for row in [0, 2, 4] {
        jacobian[(row, 0)] = -RR * sibe + D * sibeth;
        jacobian[(row, 1)] = D * sibeth;
        jacobian[(row + 1, 0)] = RR * cobe - D * cobeth;
        jacobian[(row + 1, 1)] = -D * cobeth;
    }
    jacobian[(0, 2)] = -SS * coga;
    jacobian[(1, 2)] = -SS * siga;
    jacobian[(2, 3)] = -E * cophde;
    jacobian[(2, 4)] = -E * cophde + ZT * side;
    jacobian[(3, 3)] = -E * siphde;
    jacobian[(3, 4)] = -E * siphde - ZT * code;
    jacobian[(4, 5)] = ZF * siomep;
    jacobian[(4, 6)] = ZF * siomep - U * coep;
    jacobian[(5, 5)] = -ZF * coomep;
    jacobian[(5, 6)] = -ZF * coomep - U * siep;

    let constraints = SVector::<f64, 6>::from([
        RR * cobe - D * cobeth - SS * siga - XB,
        RR * sibe - D * sibeth + SS * coga - YB,
        RR * cobe - D * cobeth - E * siphde - ZT * code - XA,
        RR * sibe - D * sibeth + E * cophde - ZT * side - YA,
        RR * cobe - D * cobeth - ZF * coomep - U * siep - XA,
        RR * sibe - D * sibeth - ZF * siomep + U * coep - YA,
    ]);
    Equations { mass, force, jacobian, constraints }
}

/// The convective term `γ = (d/dt G) q̇ = Σ_jk ∂²g/∂q_j∂q_k q̇_j q̇_k` of the test set's
/// constraints, differentiated by hand: `G q̈ = −γ` on the motion.
pub fn convective(q: &[f64; 7], qdot: &[f64; 7]) -> SVector<f64, 6> {
    let [beta, theta, gamma, phi, delta, omega, epsilon] = *q;
    let [bep, thp, gap, php, dep, omp, epp] = *qdot;
    let (bt, pd, oe) = (bep + thp, php + dep, omp + epp);
    // d/dt of (rr cos β − d cos(β + Θ)) is (−rr sin β β̇ + d sin(β+Θ)(β̇+Θ̇)); its derivative
    // along q̇ again gives the γ of the common part E(β, Θ).
    let ex = -RR * beta.cos() * bep * bep + D * (beta + theta).cos() * bt * bt;
    let ey = -RR * beta.sin() * bep * bep + D * (beta + theta).sin() * bt * bt;
    SVector::<f64, 6>::from([
        ex + SS * gamma.sin() * gap * gap,
        ey - SS * gamma.cos() * gap * gap,
        ex + E * (phi + delta).sin() * pd * pd + ZT * delta.cos() * dep * dep,
        ey - E * (phi + delta).cos() * pd * pd + ZT * delta.sin() * dep * dep,
        ex + ZF * (omega + epsilon).cos() * oe * oe + U * epsilon.sin() * epp * epp,
        ey + ZF * (omega + epsilon).sin() * oe * oe - U * epsilon.cos() * epp * epp,
    ])
}

/// `q̈` and `λ` at `(q, q̇)` from one dense LU solve of the KKT system
/// `[[M, Gᵀ], [G, 0]] (q̈, λ) = (f, −γ)` built from the test set's formulas: the hand-coded
/// solve the engine's constrained accelerations are compared and timed against. `None` when
/// the KKT matrix is singular.
pub fn kkt(q: &[f64; 7], qdot: &[f64; 7]) -> Option<([f64; 7], [f64; 6])> {
    let Equations { mass, force, jacobian, .. } = equations(q, qdot);
    let gamma = convective(q, qdot);
    let mut matrix = SMatrix::<f64, 13, 13>::zeros();
    matrix.fixed_view_mut::<7, 7>(0, 0).copy_from(&mass);
    matrix.fixed_view_mut::<7, 6>(0, 7).copy_from(&jacobian.transpose());
    matrix.fixed_view_mut::<6, 7>(7, 0).copy_from(&jacobian);
    let mut rhs = SVector::<f64, 13>::zeros();
    rhs.fixed_rows_mut::<7>(0).copy_from(&force);
    rhs.fixed_rows_mut::<6>(7).copy_from(&(-gamma));
    let solution = matrix.lu().solve(&rhs)?;
    Some((std::array::from_fn(|i| solution[i]), std::array::from_fn(|i| solution[7 + i])))
}

pub use lagrange_scenes::andrews_squeezer::{
    INITIAL_ANGLES, PUBLISHED_AT_0_03, PUBLISHED_INITIAL_ACCELERATIONS, PUBLISHED_INITIAL_MULTIPLIERS,
};

/// End of the test set's interval (s).
pub const T_END: f64 = 0.03;

#[cfg(test)]
mod tests {
    use super::*;

    /// The hand-coded KKT solve reproduces the test set's consistent initial values: `q̈` and `λ`
    /// to 1e-12 relative to their largest entry (a 13 × 13 LU of condition ~1e6 in these units
    /// loses ~1e-10 at worst; measured 5e-16 and 9e-16), and `g(q₀)` vanishes to 1e-16 m (the positions
    /// are given to 30 digits).
    #[test]
    fn the_kkt_solve_reproduces_the_published_initial_values() {
        let (qddot, lambda) = kkt(&INITIAL_ANGLES, &[0.0; 7]).expect("regular");
        let worst = |got: &[f64], want: &[f64]| {
            got.iter().zip(want).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / want[0].abs()
        };
        eprintln!(
            "q̈ to {:.1e}, λ to {:.1e} relative",
            worst(&qddot, &PUBLISHED_INITIAL_ACCELERATIONS),
            worst(&lambda, &PUBLISHED_INITIAL_MULTIPLIERS)
        );
        let scale = PUBLISHED_INITIAL_ACCELERATIONS[0].abs();
        for (got, want) in qddot.iter().zip(PUBLISHED_INITIAL_ACCELERATIONS) {
            assert!((got - want).abs() <= 1e-12 * scale, "q̈: {qddot:?}");
        }
        let scale = PUBLISHED_INITIAL_MULTIPLIERS[0].abs();
        for (got, want) in lambda.iter().zip(PUBLISHED_INITIAL_MULTIPLIERS) {
            assert!((got - want).abs() <= 1e-12 * scale, "λ: {lambda:?}");
        }
        let g = equations(&INITIAL_ANGLES, &[0.0; 7]).constraints;
        assert!(g.amax() <= 1e-16, "g(q₀) = {g:?}");
    }

    /// `γ` is the second derivative of `g` along the motion: `g(q + s q̇)` differentiated twice
    /// by central differences agrees with it (step 1e-4: truncation ~1e-8 relative, round-off
    /// ~1e-16/1e-8 = 1e-8 relative, bound 1e-6).
    #[test]
    fn the_convective_term_is_the_second_derivative_of_the_constraints() {
        let q = [0.3, -0.2, 0.5, 0.1, 0.4, -0.3, 1.1];
        let qdot = [2.0, -1.5, 0.7, 1.1, -0.4, 0.9, -0.6];
        let at = |s: f64| {
            let shifted: [f64; 7] = std::array::from_fn(|i| q[i] + s * qdot[i]);
            equations(&shifted, &qdot).constraints
        };
        let h = 1e-4;
        let second = (at(h) - 2.0 * at(0.0) + at(-h)) / (h * h);
        let gamma = convective(&q, &qdot);
        assert!((second - gamma).amax() <= 1e-6 * gamma.amax(), "{second:?} vs {gamma:?}");
    }
}
