//! Linear stability theory of the integrators, and the bisection that measures a stability limit.
//!
//! Applied to `y' = λ y`, a one-step method multiplies `y` by its stability function `R(z)`,
//! `z = λ h`, every step: it is stable where `|R(z)| ≤ 1`. An undamped oscillator has `λ = ±iω`
//! (the imaginary axis), a strongly over-damped one a fast real `λ ≈ −c/m` (the negative real
//! axis), so each needs the boundary of the stability region on its own axis.

/// `R(z) = 1 + z + z²/2 + z³/6 + z⁴/24` of the classical RK4 at `z = x + iy`, as `|R|²`.
pub fn rk4_amplification_squared(x: f64, y: f64) -> f64 {
    // Powers of z = x + iy, accumulated with the Taylor coefficients 1/k!.
    let (mut re, mut im) = (1.0, 0.0);
    let (mut power_re, mut power_im) = (1.0, 0.0);
    let mut factorial = 1.0;
    for k in 1..=4 {
        (power_re, power_im) = (power_re * x - power_im * y, power_re * y + power_im * x);
        factorial *= k as f64;
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
/// boundary is `R(−x) = 1`, i.e. `x (−1 + x/2 − x²/6 + x³/24) = 0`, the real root of
/// `x³ − 4x² + 12x − 24 = 0`: `x = 2.7852935…` (Newton from 3). The limit of a strongly
/// damped oscillator's fast real mode: `|λ| dt ≤ 2.785` — the constant.
pub fn rk4_real_axis_limit() -> f64 {
    newton(|x| (x * x * x - 4.0 * x * x + 12.0 * x - 24.0, 3.0 * x * x - 8.0 * x + 12.0), 3.0)
}

/// Dormand–Prince 5(4)'s stability function (the propagated fifth-order solution):
/// `R(z) = Σ_{k≤5} z^k/k! + z⁶/600` (Hairer, Nørsett & Wanner, *Solving ODEs I*, §IV.2 / II §IV.2).
fn dopri5_stability(x: f64) -> f64 {
    let mut sum = 1.0;
    let (mut power, mut factorial) = (1.0, 1.0);
    for k in 1..=5 {
        power *= x;
        factorial *= k as f64;
        sum += power / factorial;
    }
    sum + power * x / 600.0
}

/// Dormand–Prince 5(4)'s boundary on the negative real axis: `0 < R(−x) < 1` up to the root of
/// `R(−x) = 1` between 3 and 3.5 (bisection; `R(−3) = 0.565`, `R(−3.5) = 1.42`): `x = 3.3066…`.
/// The adaptive explicit method's step on a problem with a fast real mode `λ` cannot stay
/// above `3.31/|λ|`.
pub fn dopri5_real_axis_limit() -> f64 {
    let (mut low, mut high) = (3.0, 3.5);
    debug_assert!(dopri5_stability(-low) < 1.0 && dopri5_stability(-high) > 1.0);
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

/// Symplectic Euler (`v ← v − h ω² x`, then `x ← x + h v`; rapier with one substep and a per-step
/// force): the step matrix `[[1 − h²ω², h], [−hω², 1]]` has determinant 1 and trace `2 − h²ω²`,
/// so it is stable (eigenvalues on the unit circle) iff `|2 − h²ω²| < 2`: `ω h < 2`.
pub fn symplectic_euler_limit() -> f64 {
    2.0
}

fn newton(f: impl Fn(f64) -> (f64, f64), mut x: f64) -> f64 {
    for _ in 0..50 {
        let (value, slope) = f(x);
        let step = value / slope;
        x -= step;
        if step.abs() <= 1e-16 * x.abs() {
            break;
        }
    }
    x
}

/// The boundary between stable and unstable steps, by bisection on `dt` in `[stable, unstable]`
/// (which must bracket it) until the bracket is `relative` wide; returns its midpoint.
pub fn bisect_limit(mut stable: f64, mut unstable: f64, relative: f64, mut is_stable: impl FnMut(f64) -> bool) -> f64 {
    assert!(is_stable(stable) && !is_stable(unstable), "[{stable}, {unstable}] does not bracket the limit");
    while (unstable - stable) > relative * stable {
        let mid = 0.5 * (stable + unstable);
        if is_stable(mid) {
            stable = mid;
        } else {
            unstable = mid;
        }
    }
    0.5 * (stable + unstable)
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
    }
}
