//! The acceleration Jacobian against central finite differences on every evaluation path.

use super::Dynamics;
use crate::test_support::{Charge, Range, RodChain, Spring, cart, driven, rng};
use crate::{Coordinate, Error, LagrangianFunction, Model, RawModel, Scalar};

/// Central differences of `q̈` with step `h max(|x_j|, 1)`, `h = 1e-6`.
fn finite_differences<D: Dynamics>(system: &D, ws: &mut D::Workspace, t: f64, q: &[f64], qdot: &[f64]) -> Vec<f64> {
    let n = system.dof();
    let mut jacobian = vec![0.0; 2 * n * n];
    let (mut plus, mut minus) = (vec![0.0; n], vec![0.0; n]);
    for j in 0..2 * n {
        let (mut qp, mut vp, mut qm, mut vm) = (q.to_vec(), qdot.to_vec(), q.to_vec(), qdot.to_vec());
        let x = if j < n { q[j] } else { qdot[j - n] };
        let step = 1e-6 * x.abs().max(1.0);
        if j < n {
            qp[j] += step;
            qm[j] -= step;
        } else {
            vp[j - n] += step;
            vm[j - n] -= step;
        }
        system.accelerations(ws, t, &qp, &vp, &mut plus).unwrap();
        system.accelerations(ws, t, &qm, &vm, &mut minus).unwrap();
        for i in 0..n {
            jacobian[i * 2 * n + j] = (plus[i] - minus[i]) / (2.0 * step);
        }
    }
    jacobian
}

/// Seeded random states: `q` and `q̇` in `[−1.2, 1.2]`, `t` in `[0, 2]`.
fn states(n: usize) -> Vec<(f64, Vec<f64>, Vec<f64>)> {
    let mut rng = rng(0x1AC0_B1A2);
    (0..4)
        .map(|_| {
            let t = rng.range(0.0, 2.0);
            let q = (0..n).map(|_| rng.range(-1.2, 1.2)).collect();
            let v = (0..n).map(|_| rng.range(-1.2, 1.2)).collect();
            (t, q, v)
        })
        .collect()
}

/// `∂q̈/∂(q, q̇)` by AD agrees with central differences: truncation `h² q̈'''/6 ~ 1e-12` and
/// cancellation `ε |q̈| / h ~ 2e-10 |q̈|` bound the difference; 1e-8 of the scale leaves a
/// margin of 50.
fn check<D: Dynamics>(name: &str, system: &D) {
    let n = system.dof();
    let mut ws = system.workspace();
    let mut jacobian = vec![0.0; 2 * n * n];
    let mut qddot = vec![0.0; n];
    for (t, q, v) in states(n) {
        system.acceleration_jacobian(&mut ws, t, &q, &v, &mut jacobian).unwrap();
        let expected = finite_differences(system, &mut ws, t, &q, &v);
        system.accelerations(&mut ws, t, &q, &v, &mut qddot).unwrap();
        let scale = 1.0 + expected.iter().chain(&qddot).fold(0.0_f64, |m, x| m.max(x.abs()));
        for (k, (got, want)) in jacobian.iter().zip(&expected).enumerate() {
            let residual = (got - want).abs();
            assert!(
                residual <= 1e-8 * scale,
                "{name}: ∂q̈_{}/∂x_{} at t = {t}, q = {q:?}, q̇ = {v:?}: expected {want}, got {got}, residual {residual:e}",
                k / (2 * n),
                k % (2 * n)
            );
        }
    }
}

#[test]
fn jacobian_matches_finite_differences_on_the_assembled_body_path() {
    let cart = Model::new(cart(2.0, 1.0, 1.3)).unwrap();
    assert!(!cart.uses_tree_path() && !cart.has_constant_mass_matrix());
    check("cart pendulum", &cart);
    let chain = Model::new_generic(RodChain::new(&[1.0, 0.7, 1.4], &[1.0, 0.8, 0.6], 9.81)).unwrap();
    check("rod chain, assembled", &chain);
    // Time-dependent poses, a potential and a velocity-dependent force.
    let driven = Model::new(driven()).unwrap();
    assert!(driven.has_potential() && driven.has_generalized_force() && !driven.is_autonomous());
    check("driven pendulum", &driven);
}

#[test]
fn jacobian_matches_finite_differences_on_the_tree_path() {
    let chain = Model::new(RodChain::new(&[1.0, 0.7, 1.4], &[1.0, 0.8, 0.6], 9.81)).unwrap();
    assert!(chain.uses_tree_path());
    check("rod chain, articulated", &chain);
}

#[test]
fn jacobian_matches_finite_differences_on_the_constant_mass_path() {
    let spring = Model::new(Spring::new(1.5, 7.0, 0.3)).unwrap();
    assert!(spring.has_constant_mass_matrix());
    check("damped oscillator", &spring);
    // Exact: ∂ẍ/∂x = −k/m, ∂ẍ/∂ẋ = −c/m.
    let mut ws = spring.workspace();
    let mut jacobian = [0.0; 2];
    spring.acceleration_jacobian(&mut ws, 0.0, &[0.3], &[-0.2], &mut jacobian).unwrap();
    assert!((jacobian[0] + 7.0 / 1.5).abs() < 1e-14 && (jacobian[1] + 0.3 / 1.5).abs() < 1e-15, "{jacobian:?}");
}

#[test]
fn jacobian_matches_finite_differences_on_the_raw_path() {
    let charge = RawModel::new(Charge::new(2.0, 3.0)).unwrap();
    check("charge in a magnetic field (raw)", &charge);
    check("cart pendulum (raw)", &RawModel::new(Model::new(cart(2.0, 1.0, 1.3)).unwrap()).unwrap());
    check("driven pendulum (raw)", &RawModel::new(Model::new(driven()).unwrap()).unwrap());
    check("damped oscillator (raw)", &RawModel::new(Model::new(Spring::new(1.5, 7.0, 0.3)).unwrap()).unwrap());
}

/// Two exact derivatives of the same equations: equal to round-off.
#[test]
fn body_and_raw_jacobians_agree_to_round_off() {
    let body = Model::new(cart(2.0, 1.0, 1.3)).unwrap();
    let raw = RawModel::new(Model::new(cart(2.0, 1.0, 1.3)).unwrap()).unwrap();
    let (mut wb, mut wr) = (body.workspace(), raw.workspace());
    let (mut a, mut b) = ([0.0; 8], [0.0; 8]);
    for (t, q, v) in states(2) {
        body.acceleration_jacobian(&mut wb, t, &q, &v, &mut a).unwrap();
        raw.acceleration_jacobian(&mut wr, t, &q, &v, &mut b).unwrap();
        let scale = a.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        for k in 0..8 {
            assert!((a[k] - b[k]).abs() <= 1e-12 * scale, "entry {k}: body {} raw {}", a[k], b[k]);
        }
    }
}

#[test]
fn jacobian_rejects_a_wrong_shape_and_a_non_finite_state() {
    let cart = Model::new(cart(2.0, 1.0, 1.3)).unwrap();
    let mut ws = cart.workspace();
    let mut short = [0.0; 7];
    let error = cart.acceleration_jacobian(&mut ws, 0.0, &[0.1, 0.2], &[0.0, 0.0], &mut short).unwrap_err();
    assert!(matches!(error, Error::DimensionMismatch { expected: 8, got: 7, .. }), "{error}");
    let mut jacobian = [0.0; 8];
    let error = cart.acceleration_jacobian(&mut ws, 0.0, &[f64::NAN, 0.2], &[0.0, 0.0], &mut jacobian).unwrap_err();
    assert!(matches!(error, Error::NonFinite { .. }), "{error}");
}

/// A system that provides only `f64` accelerations: the trait's default Jacobian.
pub(crate) struct WithoutJacobian<D>(pub D);

impl<D: Dynamics> LagrangianFunction for WithoutJacobian<D> {
    type Scratch<S: Scalar> = D::Scratch<S>;
    fn coordinates(&self) -> &[Coordinate] {
        self.0.coordinates()
    }
    fn scratch<S: Scalar>(&self) -> D::Scratch<S> {
        self.0.scratch()
    }
    fn lagrangian_with<S: Scalar>(&self, scratch: &mut D::Scratch<S>, t: S, q: &[S], qdot: &[S]) -> S {
        self.0.lagrangian_with(scratch, t, q, qdot)
    }
    fn generalized_force_with<S: Scalar>(
        &self,
        scratch: &mut D::Scratch<S>,
        t: S,
        q: &[S],
        qdot: &[S],
        force: &mut [S],
    ) -> bool {
        self.0.generalized_force_with(scratch, t, q, qdot, force)
    }
}

impl<D: Dynamics> Dynamics for WithoutJacobian<D> {
    type Workspace = D::Workspace;
    fn workspace(&self) -> D::Workspace {
        self.0.workspace()
    }
    fn accelerations(&self, ws: &mut D::Workspace, t: f64, q: &[f64], v: &[f64], a: &mut [f64]) -> Result<(), Error> {
        self.0.accelerations(ws, t, q, v, a)
    }
    fn energy_function(&self, ws: &mut D::Workspace, t: f64, q: &[f64], qdot: &[f64]) -> Result<f64, Error> {
        self.0.energy_function(ws, t, q, qdot)
    }
    fn mass_matrix(&self, ws: &mut D::Workspace, t: f64, q: &[f64], v: &[f64], m: &mut [f64]) -> Result<(), Error> {
        self.0.mass_matrix(ws, t, q, v, m)
    }
    fn momenta(&self, ws: &mut D::Workspace, t: f64, q: &[f64], v: &[f64], p: &mut [f64]) -> Result<(), Error> {
        self.0.momenta(ws, t, q, v, p)
    }
    fn cyclic_coordinates(&self) -> &[bool] {
        self.0.cyclic_coordinates()
    }
    fn has_external_forces(&self) -> bool {
        self.0.has_external_forces()
    }
    fn conserves_energy(&self) -> bool {
        self.0.conserves_energy()
    }
}

/// The default (central differences, step `ε^{1/3}`) agrees with AD to its own accuracy:
/// truncation and cancellation both `~ε^{2/3} ≈ 4e-11` of the scale; 1e-8 leaves a wide margin.
#[test]
fn default_jacobian_is_finite_differences_close_to_ad() {
    let exact = Model::new(driven()).unwrap();
    let fallback = WithoutJacobian(Model::new(driven()).unwrap());
    let (mut we, mut wf) = (exact.workspace(), fallback.workspace());
    let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
    for (t, q, v) in states(1) {
        exact.acceleration_jacobian(&mut we, t, &q, &v, &mut a).unwrap();
        fallback.acceleration_jacobian(&mut wf, t, &q, &v, &mut b).unwrap();
        let scale = 1.0 + a.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        assert!((a[0] - b[0]).abs() <= 1e-8 * scale && (a[1] - b[1]).abs() <= 1e-8 * scale, "{a:?} vs {b:?}");
    }
}
