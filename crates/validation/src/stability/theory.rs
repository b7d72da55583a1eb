//! Linear stability theory of the explicit schemes, and the bisection that measures a stability
//! limit: what the stability suite (`lagrange report`, the `stability` tests) checks its
//! measurements against.
//!
//! Applied to `y' = λ y`, a one-step method multiplies `y` by its stability function `R(z)`,
//! `z = λ h`, every step: it is stable where `|R(z)| ≤ 1`. An undamped oscillator has `λ = ±iω`
//! (the imaginary axis), a strongly over-damped one a fast real `λ ≈ −c/m` (the negative real
//! axis), so each needs the boundary of the stability region on its own axis.
//!
//! ```
//! use lagrange_validation::stability::theory;
//! // An undamped spring of ω = 1e3 rad/s: RK4 is stable up to dt = 2√2 / ω.
//! let dt_max = theory::rk4_imaginary_axis_limit() / 1e3;
//! assert!((dt_max - 2.828e-3).abs() < 1e-6);
//! ```

/// `|R(z)|²` of the classical RK4, `R(z) = 1 + z + z²/2 + z³/6 + z⁴/24`, at `z = x + iy`.
pub fn rk4_amplification_squared(x: f64, y: f64) -> f64 {
    // Powers of z = x + iy, accumulated with the Taylor coefficients 1/k!.
    let (mut re, mut im) = (1.0, 0.0);
    let (mut power_re, mut power_im) = (1.0, 0.0);
    let mut factorial = 1.0;
    for k in 1..=4 {
        (power_re, power_im) = (power_re * x - power_im * y, power_re * y + power_im * x);
        factorial *= f64::from(k);
        re += power_re / factorial;
        im += power_im / factorial;
    }
    re * re + im * im
}

/// RK4's stability boundary on the imaginary axis: `|R(iy)|² = 1 − y⁶/72 + y⁸/576`, which is 1
/// at `y² = 8`: `y = 2√2 = 2.8284…` (Hairer & Wanner, *Solving ODEs II*, §IV.2, Fig. 2.1).
/// The limit of an undamped oscillator: `ω dt ≤ 2√2`.
pub fn rk4_imaginary_axis_limit() -> f64 {
    2.0 * std::f64::consts::SQRT_2
}

/// RK4's stability boundary on the negative real axis: `R(−x) = −1` has no real root, so the
/// boundary is `R(−x) = 1`, i.e. the real root of `x³ − 4x² + 12x − 24 = 0`: `x = 2.7852935…`
/// (Newton from 3). The limit of a strongly damped oscillator's fast real mode:
/// `|λ| dt ≤ 2.785`.
pub fn rk4_real_axis_limit() -> f64 {
    let mut x: f64 = 3.0;
    for _ in 0..50 {
        let step = (x * x * x - 4.0 * x * x + 12.0 * x - 24.0) / (3.0 * x * x - 8.0 * x + 12.0);
        x -= step;
        if step.abs() <= 1e-16 * x {
            break;
        }
    }
    x
}

/// Dormand–Prince 5(4)'s stability function on the real axis (the propagated fifth-order
/// solution): `R(x) = Σ_{k≤5} x^k/k! + x⁶/600` (Hairer, Nørsett & Wanner, *Solving ODEs I*, §IV.2).
fn dopri5_stability(x: f64) -> f64 {
    let (mut sum, mut power, mut factorial) = (1.0, 1.0, 1.0);
    for k in 1..=5 {
        power *= x;
        factorial *= f64::from(k);
        sum += power / factorial;
    }
    sum + power * x / 600.0
}

/// Dormand–Prince 5(4)'s boundary on the negative real axis: `0 < R(−x) < 1` up to the root of
/// `R(−x) = 1` between 3 and 3.5 (bisection; `R(−3) = 0.565`, `R(−3.5) = 1.42`): `x = 3.3066…`.
/// On a problem with a fast real mode `λ`, the explicit adaptive step cannot stay above
/// `3.31/|λ|`, whatever the tolerance.
pub fn dopri5_real_axis_limit() -> f64 {
    let (mut low, mut high) = (3.0, 3.5);
    for _ in 0..100 {
        let mid = 0.5 * (low + high);
        if dopri5_stability(-mid) < 1.0 {
            low = mid;
        } else {
            high = mid;
        }
    }
    0.5 * (low + high)
}

/// Symplectic Euler (`v ← v − h ω² x`, then `x ← x + h v`; rapier with one substep and a
/// per-step force): the step matrix `[[1 − h²ω², h], [−hω², 1]]` has determinant 1 and trace
/// `2 − h²ω²`, so it is stable (eigenvalues on the unit circle) iff `|2 − h²ω²| < 2`: `ω h < 2`.
pub fn symplectic_euler_limit() -> f64 {
    2.0
}

/// Symplectic Euler with the damping force `−c v` applied from the start of the step
/// (`v ← (1 − hc) v − h k x`, `x ← x + h v`, m = 1): determinant `D = 1 − hc`, trace
/// `T = 2 − h²k − hc`; both eigenvalues lie in the unit disc iff `|D| ≤ 1` and `|T| ≤ 1 + D`,
/// i.e. `k h² + 2 c h ≤ 4`: the largest stable step `h = 4 / (c + √(c² + 4k))` — explicit
/// Euler's `2/c` when `c² ≫ k`.
pub fn damped_symplectic_euler_step(k: f64, c: f64) -> f64 {
    4.0 / (c + (c * c + 4.0 * k).sqrt())
}

/// Symplectic Euler's energy band on the oscillator: it conserves `I = v² + ω²x² − hω² x v`
/// exactly and `|hω² x v| ≤ (hω/2)(v² + ω²x²)`, so from a turning point the relative energy
/// error never exceeds `(hω/2)/(1 − hω/2)`.
pub fn symplectic_euler_energy_band(h_omega: f64) -> f64 {
    let half = 0.5 * h_omega;
    half / (1.0 - half)
}

/// `(λ_fast, λ_slow)` of the over-damped oscillator `ẍ + c ẋ + k x = 0` (m = 1, `c² > 4k`),
/// each without cancellation (`λ_slow = k / λ_fast`).
pub fn damped_roots(k: f64, c: f64) -> (f64, f64) {
    let fast = -(c + (c * c - 4.0 * k).sqrt()) / 2.0;
    (fast, k / fast)
}

/// The boundary between stable and unstable steps, by bisection on `dt` in `[stable, unstable]`
/// until the bracket is `relative` wide: `(midpoint, probes)`, or `None` if the interval does
/// not bracket it (`is_stable(stable)` false or `is_stable(unstable)` true).
pub fn bisect_limit(
    mut stable: f64,
    mut unstable: f64,
    relative: f64,
    mut is_stable: impl FnMut(f64) -> bool,
) -> Option<(f64, usize)> {
    if !is_stable(stable) || is_stable(unstable) {
        return None;
    }
    let mut probes = 2;
    while unstable - stable > relative * stable {
        let mid = 0.5 * (stable + unstable);
        probes += 1;
        if is_stable(mid) {
            stable = mid;
        } else {
            unstable = mid;
        }
    }
    Some((0.5 * (stable + unstable), probes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boundaries_are_on_the_unit_circle() {
        let y = rk4_imaginary_axis_limit();
        assert!((rk4_amplification_squared(0.0, y) - 1.0).abs() < 1e-14);
        assert!(rk4_amplification_squared(0.0, 0.99 * y) < 1.0 && rk4_amplification_squared(0.0, 1.01 * y) > 1.0);
        let x = rk4_real_axis_limit();
        assert!((x - 2.785_293_563_405_282).abs() < 1e-14, "{x}");
        assert!((rk4_amplification_squared(-x, 0.0) - 1.0).abs() < 1e-14);
        let d = dopri5_real_axis_limit();
        assert!((d - 3.306_567_892_634_946).abs() < 1e-12, "{d}");
        assert!((dopri5_stability(-d) - 1.0).abs() < 1e-12);
        // k h² + 2 c h = 4 at the damped symplectic Euler limit.
        let (k, c) = (1e6, 3e3);
        let h = damped_symplectic_euler_step(k, c);
        assert!((k * h * h + 2.0 * c * h - 4.0).abs() < 1e-12);
        // The roots of the damped oscillator satisfy λ² + c λ + k = 0.
        let (fast, slow) = damped_roots(1e6, 1e6);
        for l in [fast, slow] {
            assert!((l * l + 1e6 * l + 1e6).abs() <= 1e-9 * (l * l).max(1e6), "{l}");
        }
    }

    #[test]
    fn bisection_brackets_and_counts_its_probes() {
        let (limit, probes) = bisect_limit(1.0, 4.0, 1e-12, |dt| dt < 2.5).expect("brackets");
        assert!((limit - 2.5).abs() <= 1e-11, "{limit}");
        assert!(probes > 30, "{probes}");
        assert!(bisect_limit(3.0, 4.0, 1e-6, |dt| dt < 2.5).is_none());
    }
}
