//! The raw-Lagrangian path (`∂²L/∂q̇² q̈ = ∂L/∂q − ∂²L/∂q̇∂q q̇ − ∂²L/∂q̇∂t`) against the body
//! path (`M q̈ = Σ J_bᵀ(F_b − D_b γ_b) − ∂V/∂q + Q`) on every scene: two independent assemblies
//! of the same equations must agree to round-off.

use lagrange::{Dynamics, Mechanism, Model, RawModel, State};
use lagrange_scenes::{ClosedForm, MechanismVisitor, all, visit_mechanism};
use lagrange_tests::{condition_number, max_abs, max_abs_diff, rng, sampling, tolerance};

struct RawVsBody<'a> {
    states: &'a [State],
}

impl MechanismVisitor for RawVsBody<'_> {
    type Output = usize;

    fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) -> usize {
        let body = Model::new(mechanism.clone()).expect("valid");
        if body.constraint_counts() != (0, 0) {
            // The raw path takes no constraints among the coordinates: it refuses them, by name,
            // rather than dropping them.
            let refused = RawModel::new(Model::new(mechanism).expect("valid"));
            assert!(
                matches!(refused, Err(lagrange::Error::InvalidParameter { ref name, .. }) if name == "constraints")
            );
            return 0;
        }
        let raw = RawModel::new(Model::new(mechanism).expect("valid")).expect("valid");
        let (mut ws, mut rws) = (body.workspace(), raw.workspace());
        let n = body.dof();
        let (mut a, mut b, mut m) = (vec![0.0; n], vec![0.0; n], vec![0.0; n * n]);
        for s in self.states {
            body.accelerations(&mut ws, s.t, &s.q, &s.qdot, &mut a).expect("body path");
            Dynamics::accelerations(&raw, &mut rws, s.t, &s.q, &s.qdot, &mut b).expect("raw path");
            body.mass_matrix(&mut ws, s.t, &s.q, &s.qdot, &mut m).expect("valid");
            let bound = tolerance::conditioned(condition_number(n, &m));
            let relative = max_abs_diff(&a, &b) / max_abs(&a).max(f64::MIN_POSITIVE);
            assert!(
                relative <= bound || max_abs_diff(&a, &b) == 0.0,
                "q̈ body {a:?} vs raw {b:?}: {relative:e} > {bound:e}"
            );
            // The energy function and the momenta, also assembled independently.
            let (h_body, h_raw) = (
                body.energy_function(&mut ws, s.t, &s.q, &s.qdot).unwrap(),
                Dynamics::energy_function(&raw, &mut rws, s.t, &s.q, &s.qdot).unwrap(),
            );
            let scale =
                body.momenta(&mut ws, s.t, &s.q, &s.qdot, &mut a).map(|_| max_abs(&a) * max_abs(&s.qdot)).unwrap()
                    + h_body.abs();
            assert!(
                (h_body - h_raw).abs() <= tolerance::ROUNDOFF * scale.max(1e-300),
                "h body {h_body} vs raw {h_raw}"
            );
            Dynamics::momenta(&raw, &mut rws, s.t, &s.q, &s.qdot, &mut b).unwrap();
            assert!(max_abs_diff(&a, &b) <= tolerance::ROUNDOFF * max_abs(&a).max(1e-300), "p body {a:?} vs raw {b:?}");
        }
        self.states.len()
    }
}

#[test]
fn raw_lagrangian_path_equals_body_path_on_every_scene() {
    let mut compared = 0;
    for (index, scene) in all().iter().enumerate() {
        let mut rng = rng(4000 + index as u64);
        for set in 0..4 {
            let params = if set == 0 { scene.default_params() } else { sampling::regular_params(*scene, &mut rng) };
            let states: Vec<State> = (0..6).map(|k| sampling::state(*scene, &params, &mut rng, k)).collect();
            if let Some(count) = visit_mechanism(scene.id(), &params, RawVsBody { states: &states }).expect("valid") {
                compared += count;
            }
        }
    }
    // Every body scene (all but the raw charged particle) without constraints was compared.
    let constrained = all().iter().filter(|s| s.build(&s.default_params()).unwrap().constraint_counts() != (0, 0));
    assert!(compared >= 24 * (all().len() - 1 - constrained.count()), "only {compared} states compared");
}

/// Tells body scenes (a mechanism) from raw ones (`None`).
struct IsBody;

impl MechanismVisitor for IsBody {
    type Output = ();

    fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, _mechanism: M) {}
}

/// `RawModel::new` checks a raw Lagrangian at probe states (finite, no derivative lost to
/// `.re()`, `∂²L/∂q̇²` positive definite): every raw scene passes, at its defaults and at
/// sampled parameters.
#[test]
fn every_raw_scene_passes_the_construction_checks() {
    let mut built = 0;
    for (index, scene) in all().iter().enumerate() {
        let mut rng = rng(4100 + index as u64);
        for set in 0..4 {
            let params = if set == 0 { scene.default_params() } else { sampling::regular_params(*scene, &mut rng) };
            if visit_mechanism(scene.id(), &params, IsBody).expect("valid").is_none() {
                scene.build(&params).unwrap_or_else(|error| panic!("{}: {error}", scene.id()));
                built += 1;
            }
        }
    }
    assert!(built >= 4, "only {built} raw scenes built");
}
