//! AD derivatives against central finite differences: the pose Jacobian `J`, the convective
//! term `γ`, the potential gradient `∂V/∂q` and the momenta `∂L/∂q̇`.

use lagrange::{Mechanism, Model, Pose, State};
use lagrange_scenes::{ClosedForm, MechanismVisitor, all, visit_mechanism};
use lagrange_testing as fixtures;
use lagrange_tests::{max_abs, rng, sampling, tolerance};

fn poses<M: Mechanism>(model: &Model<M>, t: f64, q: &[f64]) -> Vec<f64> {
    let mut out = vec![Pose::<f64>::default(); model.bodies().len()];
    model.mechanism().poses(t, q, &mut out);
    out.iter().flat_map(|p| [p.x, p.y, p.angle]).collect()
}

/// AD (`expected`) against FD (`got`) to `tol` relative to the larger of both and 1.
fn assert_close(what: &str, ad: &[f64], fd: &[f64], tol: f64) {
    let scale = max_abs(ad).max(max_abs(fd)).max(1.0);
    fixtures::assert_close(what, ad, fd, tol * scale);
}

/// Central differences of `f: ℝⁿ → ℝᵐ` in every entry of `x` (step `FD_STEP · max(|x_j|, 1)`):
/// its m × n Jacobian, row-major.
fn central_differences(x: &[f64], mut f: impl FnMut(&[f64]) -> Vec<f64>) -> Vec<f64> {
    let n = x.len();
    let columns: Vec<Vec<f64>> = (0..n)
        .map(|j| {
            let step = tolerance::FD_STEP * x[j].abs().max(1.0);
            let (mut plus, mut minus) = (x.to_vec(), x.to_vec());
            plus[j] += step;
            minus[j] -= step;
            let (fp, fm) = (f(&plus), f(&minus));
            fp.iter().zip(&fm).map(|(p, m)| (p - m) / (2.0 * step)).collect()
        })
        .collect();
    let m = columns.first().map_or(0, Vec::len);
    (0..m * n).map(|k| columns[k % n][k / n]).collect()
}

struct FiniteDifferences<'a> {
    states: &'a [State],
}

impl MechanismVisitor for FiniteDifferences<'_> {
    type Output = ();

    fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) {
        let model = Model::new(mechanism).expect("valid");
        let rows = 3 * model.bodies().len();
        let mut ws = model.workspace();
        for s in self.states {
            // J and γ from the engine (the momenta call runs both passes).
            lagrange::momenta(&model, &mut ws, s.t, &s.q, &s.qdot).expect("valid");
            let (jacobian, convective) = (ws.jacobian.clone(), ws.convective.clone());
            // J by central differences.
            let fd = central_differences(&s.q, |q| poses(&model, s.t, q));
            assert_close("J", &jacobian, &fd, tolerance::FINITE_DIFFERENCE);
            // γ = d²/ds² p(q + s q̇, t + s): second central difference with a larger step
            // (h = 1e-4: truncation h² p''''/12 ~ 1e-9, cancellation 4ε/h² ~ 1e-7 of the pose scale).
            let h2 = 1e-4;
            let moved = |sign: f64| {
                let q: Vec<f64> = s.q.iter().zip(&s.qdot).map(|(q, v)| q + sign * h2 * v).collect();
                poses(&model, s.t + sign * h2, &q)
            };
            let (pp, p0, pm) = (moved(1.0), poses(&model, s.t, &s.q), moved(-1.0));
            let fd_gamma: Vec<f64> = (0..rows).map(|r| (pp[r] - 2.0 * p0[r] + pm[r]) / (h2 * h2)).collect();
            assert_close("γ", &convective, &fd_gamma, 1e-6);
            // ∂V/∂q (filled by the acceleration pass) against differences of V.
            if model.has_potential() {
                lagrange::accelerations(&model, &mut ws, s.t, &s.q, &s.qdot).expect("valid");
                let gradient = ws.potential_gradient.clone();
                // Gravity is part of potential_energy; subtract it so that only V remains.
                let extra = |q: &[f64], ws: &mut lagrange::Workspace<f64>| {
                    let total = lagrange::potential_energy(&model, ws, s.t, q).expect("valid");
                    let p = poses(&model, s.t, q);
                    let gravity: f64 = (0..model.bodies().len())
                        .map(|b| model.mechanism().description().bodies[b].mass * model.gravity() * p[3 * b + 1])
                        .sum();
                    total - gravity
                };
                let fd_v = central_differences(&s.q, |q| vec![extra(q, &mut ws)]);
                assert_close("∂V/∂q", &gradient, &fd_v, tolerance::FINITE_DIFFERENCE);
            }
            // p = ∂L/∂q̇ against differences of L in q̇.
            let momenta = lagrange::momenta(&model, &mut ws, s.t, &s.q, &s.qdot).expect("valid").to_vec();
            let fd_p = central_differences(&s.qdot, |v| {
                vec![lagrange::lagrangian(&model, &mut ws, s.t, &s.q, v).expect("valid")]
            });
            assert_close("∂L/∂q̇", &momenta, &fd_p, tolerance::FINITE_DIFFERENCE);
        }
    }
}

#[test]
fn automatic_derivatives_match_finite_differences_on_every_scene() {
    for (index, scene) in all().iter().enumerate() {
        let mut rng = rng(6000 + index as u64);
        let params = sampling::regular_params(*scene, &mut rng);
        let states: Vec<State> = (0..4).map(|k| sampling::state(*scene, &params, &mut rng, k)).collect();
        visit_mechanism(scene.id(), &params, FiniteDifferences { states: &states }).expect("valid");
    }
}
