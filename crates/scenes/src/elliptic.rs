//! Jacobi elliptic functions and the incomplete elliptic integral of the first kind, in the
//! parameter `m = k²` (Abramowitz & Stegun, ch. 16–17), `0 ≤ m < 1`: the amplitude `am(u|m)`
//! by the descending Landen (arithmetic–geometric mean) recurrence (A&S 16.4), and `F(φ|m)`
//! and `K(m)` by Carlson's symmetric integral `R_F` (Carlson 1995, Numer. Algorithms 10, 13–26;
//! DLMF 19.25.5), both extended to every real argument by their quasi-periodicity
//! `F(φ + jπ|m) = F(φ|m) + 2j K(m)`, `am(u + 2jK|m) = am(u|m) + jπ`. For the exact motion of
//! the pendulum (`pendulum.rs`); no other crate is needed.

/// `R_F`'s duplication stops when every argument is within this fraction of their mean: the
/// fifth-order series that finishes it then leaves a relative error below `r⁶/(4(1 − r))`
/// ≈ 2.5e-19 (Carlson 1995, eq. 2.2), far below round-off.
const RF_SPREAD: f64 = 1e-3;

/// At most this many duplications: each one divides the spread by 4 (Carlson 1995), so ~30
/// reach `RF_SPREAD` from any spread of finite, non-negative arguments; NaN input runs out.
const RF_STEPS: usize = 64;

/// The AGM stops once `c_n ≤ ε a_n`: `c` squares at every step (`c_{n+1} = c_n²/(4 a_{n+1})`),
/// so from `m < 1 − 1e-16` it takes at most ~8 steps.
const AGM_STEPS: usize = 32;

/// Carlson's symmetric elliptic integral of the first kind,
/// `R_F(x, y, z) = ½ ∫₀^∞ dt / √((t + x)(t + y)(t + z))`, for `x, y, z ≥ 0` with at most one
/// of them zero; NaN otherwise.
pub(crate) fn carlson_rf(x: f64, y: f64, z: f64) -> f64 {
    if !(x >= 0.0 && y >= 0.0 && z >= 0.0 && x + y + z > 0.0 && x.is_finite() && y.is_finite() && z.is_finite()) {
        return f64::NAN;
    }
    let (mut x, mut y, mut z) = (x, y, z);
    for _ in 0..RF_STEPS {
        // Relative distances of the arguments from their mean.
        let mean = (x + y + z) / 3.0;
        let (dx, dy) = (1.0 - x / mean, 1.0 - y / mean);
        let dz = -(dx + dy);
        if dx.abs().max(dy.abs()).max(dz.abs()) <= RF_SPREAD {
            // Close together: the series of R_F about the mean, through fifth order
            // (E2 = dx dy − dz², E3 = dx dy dz; DLMF 19.36.1).
            let (e2, e3) = (dx * dy - dz * dz, dx * dy * dz);
            return (1.0 + e2 * (e2 / 24.0 - 0.1 - 3.0 * e3 / 44.0) + e3 / 14.0) / mean.sqrt();
        }
        // Duplication: R_F(x, y, z) = R_F((x + λ)/4, (y + λ)/4, (z + λ)/4) (DLMF 19.26.18).
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * sy + sx * sz + sy * sz;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
    }
    f64::NAN
}

/// The complete elliptic integral of the first kind `K(m) = R_F(0, 1 − m, 1)` (DLMF 19.25.1),
/// `0 ≤ m < 1`.
pub(crate) fn complete_first_kind(m: f64) -> f64 {
    carlson_rf(0.0, 1.0 - m, 1.0)
}

/// The incomplete elliptic integral of the first kind `F(φ|m) = ∫₀^φ dθ / √(1 − m sin²θ)`
/// for every real `φ`, `0 ≤ m < 1`: `sin φ R_F(cos² φ, 1 − m sin² φ, 1)` on `|φ| ≤ π/2`
/// (DLMF 19.25.5), extended by `F(φ + jπ) = F(φ) + 2jK`.
pub(crate) fn incomplete_first_kind(phi: f64, m: f64) -> f64 {
    // Reduce to |φ| ≤ π/2.
    let turns = (phi / std::f64::consts::PI).round();
    let reduced = phi - turns * std::f64::consts::PI;
    let (s, c) = reduced.sin_cos();
    let principal = s * carlson_rf(c * c, 1.0 - m * s * s, 1.0);
    if turns == 0.0 { principal } else { principal + 2.0 * turns * complete_first_kind(m) }
}

/// The Jacobi amplitude `am(u|m)`, the inverse of `F(·|m)`, for every real `u`, `0 ≤ m < 1`:
/// `u` is reduced to `|u| ≤ K` (`am(u + 2jK) = am(u) + jπ`), then the descending Landen
/// recurrence (A&S 16.4.2–3): `a₀ = 1`, `b₀ = √(1 − m)`, `c₀ = √m`, `a_{n+1} = (a_n + b_n)/2`,
/// `b_{n+1} = √(a_n b_n)`, `c_{n+1} = c_n²/(4 a_{n+1})` until `c_N` is negligible; then
/// `φ_N = 2^N a_N u` and `φ_{n−1} = (φ_n + asin(c_n sin φ_n / a_n))/2`, `am = φ₀`.
pub(crate) fn amplitude(u: f64, m: f64) -> f64 {
    if !(0.0..1.0).contains(&m) || !u.is_finite() {
        return f64::NAN;
    }
    // Reduce to |u| ≤ K.
    let quarter = complete_first_kind(m);
    let turns = (u / (2.0 * quarter)).round();
    let reduced = u - 2.0 * turns * quarter;
    // The AGM, keeping a_n and c_n.
    let (mut a, mut b, mut c) = ([1.0; AGM_STEPS + 1], (1.0 - m).sqrt(), [m.sqrt(); AGM_STEPS + 1]);
    let mut n = 0;
    while n < AGM_STEPS && c[n] > f64::EPSILON * a[n] {
        a[n + 1] = 0.5 * (a[n] + b);
        b = (a[n] * b).sqrt();
        c[n + 1] = c[n] * c[n] / (4.0 * a[n + 1]);
        n += 1;
    }
    // Back down from φ_N = 2^N a_N u.
    let mut phi = 2f64.powi(n as i32) * a[n] * reduced;
    for k in (1..=n).rev() {
        phi = 0.5 * (phi + (c[k] / a[k] * phi.sin()).asin());
    }
    phi + turns * std::f64::consts::PI
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    /// Values by mpmath 1.3.0 at 34 significant digits for the arguments' exact double values,
    /// rounded to the nearest double (`ellipk`, `ellipf`; `am` by solving `ellipf(φ) = u`,
    /// checked against `ellipfun`'s `sn`); each is compared to 4 ε relative: the routines are a
    /// few dozen well-conditioned operations (the duplication and the AGM converge without
    /// cancellation), and a wrong step or constant shows as an error many orders larger.
    #[test]
    fn values_match_mpmath() {
        const K: [(f64, f64); 4] =
            [(0.0, FRAC_PI_2), (0.5, 1.8540746773013719), (0.9, 2.5780921133481733), (0.999_999, 8.294051463601063)];
        const F: [(f64, f64, f64); 4] = [
            (1.2, 0.7, 1.4294484330227633),
            (-0.4, 0.3, -0.40316499194713923),
            (5.0, 0.9, 8.558511085027694),
            (-11.0, 0.2, -11.622313283163042),
        ];
        const AM: [(f64, f64, f64); 4] = [
            (2.3, 0.9, 1.4818337945150486),
            (-0.7, 0.25, -0.687094025355835),
            (13.0, 0.6, 10.569649627326202),
            (40.0, 0.999, 13.590341639714719),
        ];
        let close = |what: String, expected: f64, got: f64| {
            let bound = 4.0 * f64::EPSILON * expected.abs();
            assert!((got - expected).abs() <= bound, "{what}: expected {expected}, got {got}, bound {bound:e}");
        };
        for (m, k) in K {
            close(format!("K({m})"), k, complete_first_kind(m));
        }
        for (phi, m, f) in F {
            close(format!("F({phi}|{m})"), f, incomplete_first_kind(phi, m));
        }
        for (u, m, am) in AM {
            close(format!("am({u}|{m})"), am, amplitude(u, m));
        }
    }

    /// `am` inverts `F` over several periods and close to `m = 1`, to 8 ε of the angle (each
    /// routine contributes a few ε; the reduction by `2K` adds `ε` per period).
    #[test]
    fn amplitude_inverts_the_integral() {
        for m in [0.0, 0.1, 0.5, 0.9, 0.999_9, 1.0 - 1e-12] {
            for phi in [-7.0, -1.5, -0.2, 0.0, 0.3, FRAC_PI_2, 2.0, 3.0 * PI + 0.1, 20.0] {
                let back = amplitude(incomplete_first_kind(phi, m), m);
                let bound = 8.0 * f64::EPSILON * phi.abs().max(1.0);
                assert!((back - phi).abs() <= bound, "m = {m}, φ = {phi}: am(F(φ)) = {back}");
            }
        }
    }

    #[test]
    fn invalid_arguments_are_nan_not_a_hang() {
        assert!(carlson_rf(f64::NAN, 1.0, 1.0).is_nan());
        assert!(carlson_rf(0.0, 0.0, 1.0).is_nan());
        assert!(carlson_rf(-1.0, 1.0, 1.0).is_nan());
        assert!(amplitude(1.0, 1.0).is_nan());
        assert!(amplitude(f64::INFINITY, 0.5).is_nan());
        assert!(incomplete_first_kind(f64::NAN, 0.5).is_nan());
    }
}
