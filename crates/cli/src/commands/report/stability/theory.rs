//! Linear stability theory: the boundaries of the methods' stability regions on the axes where
//! the test problems put their eigenvalues.
//!
//! A one-step method applied to `y' = λ y` multiplies `y` by its stability function `R(z)`,
//! `z = λ h`, each step, and is stable where `|R(z)| ≤ 1`. An undamped oscillator has `λ = ±iω`
//! (imaginary axis); a strongly over-damped one has a fast real `λ ≈ −c/m` (negative real axis).

/// RK4 on the imaginary axis: `|R(iy)|² = 1 − y⁶/72 + y⁸/576` is 1 at `y² = 8`: `2√2 = 2.8284…`
/// (Hairer & Wanner, *Solving ODEs II*, §IV.2). The limit of an undamped oscillator.
pub fn rk4_imaginary_axis() -> f64 {
    2.0 * std::f64::consts::SQRT_2
}

/// RK4 on the negative real axis: `R(−x) = 1` ⇔ `x³ − 4x² + 12x − 24 = 0`, `x = 2.7853…` (the
/// often-quoted constant; `R(−x) > −1` everywhere). The limit of a strongly damped oscillator.
pub fn rk4_real_axis() -> f64 {
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

/// Dormand–Prince 5(4) on the negative real axis: `R(z) = Σ_{k≤5} z^k/k! + z⁶/600` (Hairer,
/// Nørsett & Wanner I, §IV.2), `R(−x) = 1` between 3 and 3.5: `x = 3.3066…`.
pub fn dopri5_real_axis() -> f64 {
    let r = |x: f64| {
        let (mut sum, mut power, mut factorial) = (1.0, 1.0, 1.0);
        for k in 1..=5 {
            power *= -x;
            factorial *= f64::from(k);
            sum += power / factorial;
        }
        sum + power * -x / 600.0
    };
    let (mut low, mut high) = (3.0, 3.5);
    for _ in 0..100 {
        let mid = 0.5 * (low + high);
        if r(mid) < 1.0 {
            low = mid;
        } else {
            high = mid;
        }
    }
    0.5 * (low + high)
}

/// rapier with one substep and a per-step spring force is symplectic Euler (`v ← v − h ω² x`,
/// `x ← x + h v`): the step matrix has determinant 1 and trace `2 − h²ω²`, stable iff `ω h < 2`.
pub fn symplectic_euler() -> f64 {
    2.0
}

/// Symplectic Euler with the damping force `−c v` applied from the start of the step
/// (`v ← (1 − hc) v − h k x`, `x ← x + h v`, m = 1): determinant `D = 1 − hc`, trace
/// `T = 2 − h²k − hc`; both eigenvalues lie in the unit disc iff `|D| ≤ 1` and `|T| ≤ 1 + D`,
/// i.e. `k h² + 2 c h ≤ 4`: `h ≤ 4 / (c + √(c² + 4k))` — explicit Euler's `2/c` when `c² ≫ k`.
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

/// `(λ_fast, λ_slow)` of `ẍ + c ẋ + k x = 0` (m = 1), over-damped, each without cancellation.
pub fn damped_roots(k: f64, c: f64) -> (f64, f64) {
    let fast = -(c + (c * c - 4.0 * k).sqrt()) / 2.0;
    (fast, k / fast)
}

/// Free fall from rest at `r₀` to the centre under `μ/r²`: `t = (π/2) √(r₀³/(2μ))` (the
/// degenerate Kepler ellipse, half its period).
pub fn radial_infall_time(r0: f64, mu: f64) -> f64 {
    std::f64::consts::FRAC_PI_2 * (r0 * r0 * r0 / (2.0 * mu)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boundaries() {
        assert!((rk4_real_axis() - 2.785_293_563_405_282).abs() < 1e-14);
        assert!((dopri5_real_axis() - 3.306_567_892_634_946).abs() < 1e-12);
        // k h² + 2 c h = 4 at the damped limit.
        let (k, c) = (1e6, 3e3);
        let h = damped_symplectic_euler_step(k, c);
        assert!((k * h * h + 2.0 * c * h - 4.0).abs() < 1e-12);
    }
}
