//! Constants of the motion: what each scene conserves, in closed form, and why.

use crate::SceneType;
use crate::checks::check_dimensions;
use lagrange::Error;
use std::fmt;

/// What the engine can tell about a constant of the motion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Invariant {
    /// The energy function `h = q̇·∂L/∂q̇ − L` (here `T + V`): conserved when `L` does not depend
    /// on `t` and no generalized force acts, which the engine derives
    /// ([`System::conserves_energy`](lagrange::System::conserves_energy)).
    Energy,
    /// The momentum `p_j = ∂L/∂q̇_j` of coordinate `j`, which `L` does not contain: the engine
    /// finds it cyclic ([`System::cyclic_coordinates`](lagrange::System::cyclic_coordinates)).
    /// Where `q_j`'s terms in `L` cancel only for some parameter values (`m1 = m2` in the
    /// Atwood machine, `e B = 0`), the engine may find it cyclic too (exactly, or not, by
    /// round-off); the scene declares that momentum as [`Other`](Self::Other) (`p_x − F_x t`
    /// with `F_x = 0`, `K_x`).
    CyclicMomentum(usize),
    /// Any other constant (a hidden symmetry such as the Runge–Lenz vector, or an integral
    /// that depends on `t`); the engine does not derive it.
    Other,
}

/// The value of a constant of the motion at `(t, q, q̇)`.
type Value = Box<dyn Fn(f64, &[f64], &[f64]) -> f64 + Send + Sync>;

/// A constant of the motion of a scene with given parameters, in closed form
/// ([`SceneType::conserves_energy`], [`Scene::conserved_quantities`](crate::Scene::conserved_quantities)).
pub struct Conserved {
    /// Its symbol (`E`, `p_X`, `A_x`, `p_x − F_x t`), as in docs/scenes.md.
    pub symbol: String,
    /// Why it is conserved, in a few words (`X is cyclic`).
    pub why: &'static str,
    /// What the engine derives of it.
    pub invariant: Invariant,
    /// Number of coordinates of the scene.
    n: usize,
    value: Value,
}

impl Conserved {
    /// The quantity `value(scene, t, q, q̇)` of `scene` (a copy of which it keeps), named
    /// `symbol`, conserved because `why`; the closed form must hold for the scene's
    /// parameters (a scene lists only what it conserves with them).
    pub fn new<T: SceneType>(
        scene: &T,
        symbol: impl Into<String>,
        why: &'static str,
        invariant: Invariant,
        value: impl Fn(&T, f64, &[f64], &[f64]) -> f64 + Send + Sync + 'static,
    ) -> Self {
        let (n, scene) = (scene.generalized_coordinates().len(), scene.clone());
        Self { symbol: symbol.into(), why, invariant, n, value: Box::new(move |t, q, qdot| value(&scene, t, q, qdot)) }
    }

    /// The energy `E = T + V` of a scene whose `L` does not depend on `t` and on which no
    /// generalized force acts.
    pub fn energy<T: SceneType>(scene: &T, value: impl Fn(&T, &[f64], &[f64]) -> f64 + Send + Sync + 'static) -> Self {
        Self::new(scene, "E", "h = T + V: L does not depend on t", Invariant::Energy, move |s, _, q, qdot| {
            value(s, q, qdot)
        })
    }

    /// The value at `(t, q, q̇)`.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for a state of the wrong size.
    pub fn value(&self, t: f64, q: &[f64], qdot: &[f64]) -> Result<f64, Error> {
        check_dimensions(self.n, q, qdot)?;
        Ok((self.value)(t, q, qdot))
    }
}

impl fmt::Debug for Conserved {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Conserved")
            .field("symbol", &self.symbol)
            .field("why", &self.why)
            .field("invariant", &self.invariant)
            .finish_non_exhaustive()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SINGULAR_DEFAULT_MOTION;
    use crate::all;
    use crate::testing::{ENGINE_VS_CLOSED_FORM, assert_close, max_abs};
    use lagrange::{Method, Output, Tolerances};

    /// Relative and absolute tolerance of the runs.
    const TOL: f64 = 1e-12;

    /// `Σ_i |∂I/∂y_i| (1 + Y_i)` at `y = (q, q̇)`, with `Y_i` the largest `|y_i|` of the run: how
    /// much errors of size `1 + Y_i` in each component move `I` (central differences).
    fn sensitivity(quantity: &Conserved, t: f64, q: &[f64], qdot: &[f64], largest: &[f64]) -> f64 {
        let y: Vec<f64> = q.iter().chain(qdot).copied().collect();
        let at = |i: usize, h: f64| {
            let mut z = y.clone();
            z[i] += h;
            quantity.value(t, &z[..q.len()], &z[q.len()..]).unwrap()
        };
        let step = |i: usize| 1e-6 * (1.0 + y[i].abs());
        (0..y.len()).map(|i| ((at(i, step(i)) - at(i, -step(i))) / (2.0 * step(i))).abs() * (1.0 + largest[i])).sum()
    }

    /// Every scene, from its default state, run for 3 s (or over its own horizon where it
    /// declares a shorter one: Andrews' squeezer's 0.03 s, the span of its published solution,
    /// a hundredth of 3 s, which took 150 s at this tolerance) by
    /// Dormand–Prince at `rtol = atol = TOL`: each declared quantity `I` stays constant to the
    /// bound below, and the energy and the cyclic momenta the engine derives are exactly those
    /// declared, with the same values.
    ///
    /// The bound: `I` is constant along the exact flow, so its drift is the sum over the steps
    /// of `∇I · e`, `e` the step's local error; no error propagates into it. Each accepted step
    /// has a scaled error estimate `‖e_i / (TOL (1 + |y_i|))‖_rms ≤ 1`, so `|e_i| ≤ √(2n) TOL
    /// (1 + |y_i|)`, and the state is rounded to `ε |y_i|` per step; over `N` steps
    /// `|ΔI| ≤ N (√(2n) TOL + ε) S` with `S = Σ_i |∂I/∂y_i| (1 + Y_i)`, plus `100 ε S` for
    /// evaluating `I`. The estimate is that of the 4th-order solution while the 5th-order one is
    /// propagated, so it over-states the error; `S` is the largest over the recorded samples,
    /// a sixtieth of the run apart (0.05 s over 3 s), and a factor 2 covers its growth between them.
    #[test]
    fn declared_constants_of_the_motion_are_conserved_and_agree_with_the_engine() {
        for scene in all().iter().filter(|s| !SINGULAR_DEFAULT_MOTION.contains(&s.id())) {
            check_declared_constants(*scene);
        }
    }

    /// The same for the scenes whose default motion passes a configuration where the loop
    /// constraints lose rank.
    // needs the singular-configuration solver
    #[test]
    #[ignore = "needs the singular-configuration solver"]
    fn declared_constants_are_conserved_through_singular_configurations() {
        for id in SINGULAR_DEFAULT_MOTION {
            check_declared_constants(crate::find(id).expect("registered"));
        }
    }

    /// The check of [`declared_constants_of_the_motion_are_conserved_and_agree_with_the_engine`]
    /// for one scene.
    fn check_declared_constants(scene: &dyn crate::Scene) {
        let (id, params) = (scene.id(), scene.default_params());
        let initial = scene.default_state(&params).unwrap();
        let mut system = scene.build(&params).unwrap();
        let conserved = scene.conserved_quantities(&params).unwrap();
        let n = initial.q.len();
        let energy = conserved.iter().any(|c| c.invariant == Invariant::Energy);
        assert_eq!(energy, system.conserves_energy(), "{id}: energy declared iff the engine conserves h");
        let cyclic: Vec<bool> =
            (0..n).map(|j| conserved.iter().any(|c| c.invariant == Invariant::CyclicMomentum(j))).collect();
        assert_eq!(cyclic, system.cyclic_coordinates(), "{id}: declared momenta vs the engine's cyclic coordinates");

        let method = Method::Dopri5 { tol: Tolerances::uniform(TOL) };
        let horizon = scene.horizon().map_or(3.0, |h| h.min(3.0));
        let run = system.simulate(&initial, horizon, method, &Output::Every(horizon / 60.0)).unwrap();
        let samples: Vec<_> = (0..run.len()).map(|k| (run.t[k], run.q(k), run.qdot(k))).collect();
        let largest: Vec<f64> = (0..2 * n)
            .map(|i| {
                max_abs(&samples.iter().map(|(_, q, qdot)| if i < n { q[i] } else { qdot[i - n] }).collect::<Vec<_>>())
            })
            .collect();
        let steps = run.stats.steps as f64;
        let per_unit = 2.0 * (steps * (((2 * n) as f64).sqrt() * TOL + f64::EPSILON) + 100.0 * f64::EPSILON);
        for c in &conserved {
            let what = format!("{id}: {}", c.symbol);
            let values: Vec<f64> = samples.iter().map(|&(t, q, qdot)| c.value(t, q, qdot).unwrap()).collect();
            let scale =
                max_abs(&samples.iter().map(|&(t, q, qdot)| sensitivity(c, t, q, qdot, &largest)).collect::<Vec<_>>());
            assert_close(&format!("{what}: drift"), &vec![values[0]; values.len()], &values, per_unit * scale);
            for (&(t, q, qdot), &value) in samples.iter().zip(&values) {
                let engine = match c.invariant {
                    Invariant::Energy => system.energy_function(t, q, qdot).unwrap(),
                    Invariant::CyclicMomentum(j) => system.momenta(t, q, qdot).unwrap()[j],
                    Invariant::Other => break,
                };
                assert_close(
                    &format!("{what} vs the engine at t = {t}"),
                    &[engine],
                    &[value],
                    ENGINE_VS_CLOSED_FORM * scale,
                );
            }
        }
    }
}
