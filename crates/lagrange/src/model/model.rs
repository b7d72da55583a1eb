//! The validated, immutable model built from a user's [`Mechanism`].

use crate::eom::{kinematics, mass_matrix, solve};
use crate::model::probe::ProbeStates;
use crate::{Body, Coordinate, Error, Mechanism, Pose, Tree, Workspace};
use num_dual::Dual2;

/// Terms computed once for a mechanism that declares a constant mass matrix.
#[derive(Clone, Debug)]
pub(crate) struct ConstantTerms {
    /// `J` (3B × n), body-major rows.
    pub jacobian: Vec<f64>,
    /// `M` (n × n).
    pub mass_matrix: Vec<f64>,
    /// LDLᵀ factor of `M` (n × n): unit lower triangle below the diagonal, `D` on it.
    pub factor: Vec<f64>,
    /// `Σ_b J_bᵀ (0, −m_b g, 0)` (n).
    pub gravity_force: Vec<f64>,
}

/// A [`Mechanism`] checked and prepared for evaluation: the *model* of the model/workspace split.
///
/// Construction validates the bodies (finite, non-negative masses and inertias), asks once
/// which optional terms the mechanism has (potential, generalized forces), checks a declared
/// constant mass matrix or kinematic tree at probe states (and factors the constant matrix),
/// and finds the cyclic coordinates. Evaluations never re-check any of this.
///
/// # Which algorithm computes `q̈`
///
/// [`accelerations`](crate::accelerations) picks, once and for all at construction:
/// 1. a declared constant mass matrix ([`Mechanism::constant_mass_matrix`]): the stored factor;
/// 2. a declared kinematic tree ([`Mechanism::tree`]): the articulated-body algorithm, `O(n)`
///    ([`uses_tree_path`](Self::uses_tree_path));
/// 3. otherwise: assembly of `M` and `f` from the pose Jacobian and an LDLᵀ solve, `O(n³)`.
///
/// [`Model::new_generic`] ignores a declared tree and always takes path 3 — the independent
/// reference the tree path is validated against. The mass matrix, energies, momenta, reaction
/// forces and the raw-Lagrangian path use the pose passes whatever the choice.
#[derive(Clone, Debug)]
pub struct Model<M> {
    pub(crate) mechanism: M,
    pub(crate) n: usize,
    /// Body masses `m_b` (B).
    pub(crate) mass: Vec<f64>,
    /// Body inertias `I_b` (B).
    pub(crate) inertia: Vec<f64>,
    pub(crate) gravity: f64,
    pub(crate) has_potential: bool,
    pub(crate) has_force: bool,
    pub(crate) constant: Option<ConstantTerms>,
    pub(crate) cyclic: Vec<bool>,
    pub(crate) autonomous: bool,
    /// The declared kinematic tree, when accelerations run the articulated-body algorithm.
    pub(crate) tree: Option<Tree>,
}

impl<M: Mechanism> Model<M> {
    /// Validate and prepare a mechanism.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-finite or negative mass or inertia, non-finite
    /// gravity (negative `g` is allowed: gravity along +y), or a
    /// mechanism without coordinates or bodies; [`Error::Inconsistent`] if a declared constant
    /// mass matrix or a declared tree is contradicted by the poses; [`Error::SingularMassMatrix`]
    /// if that constant matrix is singular.
    pub fn new(mechanism: M) -> Result<Self, Error> {
        Self::build(mechanism, true)
    }

    /// As [`new`](Self::new), but ignoring a declared [`tree`](Mechanism::tree): accelerations
    /// always assemble and factor `M` from the pose Jacobian. For validating the tree path
    /// against an independent algorithm on the same mechanism, and for benchmarks.
    ///
    /// # Errors
    /// As [`new`](Self::new) (a declared tree is not checked).
    pub fn new_generic(mechanism: M) -> Result<Self, Error> {
        Self::build(mechanism, false)
    }

    fn build(mechanism: M, use_tree: bool) -> Result<Self, Error> {
        let n = mechanism.coordinates().len();
        let bodies = mechanism.bodies();
        if n == 0 {
            return Err(invalid("coordinates", 0.0, "a mechanism needs at least one coordinate"));
        }
        if bodies.is_empty() {
            return Err(invalid("bodies", 0.0, "a mechanism needs at least one body"));
        }
        for Body { name, mass, inertia } in bodies {
            check_non_negative(&format!("mass of {name}"), *mass)?;
            check_non_negative(&format!("inertia of {name}"), *inertia)?;
        }
        let gravity = mechanism.gravity();
        if !gravity.is_finite() {
            return Err(invalid("g", gravity, "must be finite"));
        }
        let mut model = Model {
            n,
            mass: bodies.iter().map(|b| b.mass).collect(),
            inertia: bodies.iter().map(|b| b.inertia).collect(),
            gravity,
            has_potential: false,
            has_force: false,
            constant: None,
            cyclic: vec![false; n],
            autonomous: false,
            tree: None,
            mechanism,
        };
        let probes = ProbeStates::new(n);
        // Ask once which optional terms exist.
        let (q, qdot, t) = probes.state(0);
        let mut poses = vec![Pose::<f64>::default(); model.bodies()];
        model.mechanism.poses(q, t, &mut poses);
        model.has_potential = model.mechanism.potential(q, &poses, t).is_some();
        let mut force = vec![0.0; n];
        model.has_force = model.mechanism.generalized_force(t, q, qdot, &mut force);
        if model.mechanism.constant_mass_matrix() {
            model.constant = Some(constant_terms(&model, &probes)?);
        }
        if use_tree && let Some(tree) = model.mechanism.tree() {
            check_tree(&model, tree, &probes)?;
            // A constant mass matrix is cheaper still: the tree is checked but not used.
            if model.constant.is_none() {
                model.tree = Some(tree.clone());
            }
        }
        let (cyclic, autonomous) = probes.lagrangian_structure(&model);
        model.cyclic = cyclic;
        model.autonomous = autonomous;
        Ok(model)
    }

    /// The user's mechanism.
    pub fn mechanism(&self) -> &M {
        &self.mechanism
    }

    /// Number of generalized coordinates `n`.
    pub fn dof(&self) -> usize {
        self.n
    }

    /// Number of bodies `B`.
    pub fn bodies(&self) -> usize {
        self.mass.len()
    }

    /// The generalized coordinates.
    pub fn coordinates(&self) -> &[Coordinate] {
        self.mechanism.coordinates()
    }

    /// Gravitational acceleration along −y.
    pub fn gravity(&self) -> f64 {
        self.gravity
    }

    /// Whether the mechanism has a potential beyond gravity.
    pub fn has_potential(&self) -> bool {
        self.has_potential
    }

    /// Whether the mechanism has non-conservative generalized forces.
    pub fn has_generalized_force(&self) -> bool {
        self.has_force
    }

    /// Whether `M` is constant (declared, and checked at construction).
    pub fn has_constant_mass_matrix(&self) -> bool {
        self.constant.is_some()
    }

    /// Whether [`accelerations`](crate::accelerations) runs the articulated-body algorithm on
    /// the mechanism's declared [`Tree`] (built with [`new`](Self::new), a tree declared, no
    /// constant mass matrix).
    pub fn uses_tree_path(&self) -> bool {
        self.tree.is_some()
    }

    /// Which coordinates are cyclic (`∂L/∂q_j = 0`): their momenta `p_j` are conserved when
    /// no generalized force acts on them. Found at construction by evaluating `∂L/∂q_j`
    /// exactly (AD) at probe states: a coordinate is cyclic when it is exactly zero at all.
    pub fn cyclic_coordinates(&self) -> &[bool] {
        &self.cyclic
    }

    /// Whether the Lagrangian does not depend on time explicitly (`∂L/∂t = 0` exactly at the
    /// probe states); then, without generalized forces, the energy function `h` is conserved.
    pub fn is_autonomous(&self) -> bool {
        self.autonomous
    }

    /// Whether the energy function `h` is a constant of the motion: autonomous, no `Q`.
    pub fn conserves_energy(&self) -> bool {
        self.autonomous && !self.has_force
    }

    /// A workspace for evaluations in scalar `S` (allocate once, reuse for every step).
    pub fn workspace<S: crate::Scalar>(&self) -> Workspace<S> {
        Workspace::new(self)
    }
}

fn invalid(name: &str, value: f64, why: &str) -> Error {
    Error::InvalidParameter { name: name.to_string(), value, why: why.to_string() }
}

fn check_non_negative(name: &str, value: f64) -> Result<(), Error> {
    if !value.is_finite() {
        Err(invalid(name, value, "must be finite"))
    } else if value < 0.0 {
        Err(invalid(name, value, "must be non-negative"))
    } else {
        Ok(())
    }
}

/// Check a declared constant mass matrix at the probe states and compute its terms.
fn constant_terms<M: Mechanism>(model: &Model<M>, probes: &ProbeStates) -> Result<ConstantTerms, Error> {
    let n = model.n;
    let mut ws = Workspace::<f64>::new(model);
    let mut reference: Option<Vec<f64>> = None;
    for k in 0..probes.len() {
        let (q, qdot, t) = probes.state(k);
        kinematics::jacobian_pass(model, &mut ws, t, q, false);
        kinematics::velocity_pass(model, &mut ws, t, q, qdot);
        match &reference {
            None => reference = Some(ws.jacobian.clone()),
            Some(j0) => {
                let scale = j0.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
                if j0.iter().zip(&ws.jacobian).any(|(a, b)| (a - b).abs() > 1e-12 * scale) {
                    return Err(Error::Inconsistent {
                        what: "declared a constant mass matrix, but the pose Jacobian changes with q or t".into(),
                    });
                }
            }
        }
        let scale = ws.velocity.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        if ws.convective.iter().any(|g| g.abs() > 1e-12 * scale) {
            return Err(Error::Inconsistent {
                what: "declared a constant mass matrix, but the convective term p̈ − J q̈ is not zero".into(),
            });
        }
    }
    // Probe 0 again, with q̇ = 0: a time-dependent pose would show a velocity.
    let (q, _, t) = probes.state(0);
    let zero = vec![0.0; n];
    kinematics::velocity_pass(model, &mut ws, t, q, &zero);
    if ws.velocity.iter().any(|v| *v != 0.0) {
        return Err(Error::Inconsistent {
            what: "declared a constant mass matrix, but the poses depend on time".into(),
        });
    }
    kinematics::jacobian_pass(model, &mut ws, t, q, false);
    mass_matrix::assemble(model, &mut ws, crate::eom::size::Dynamic(n));
    let mut factor = ws.mass_matrix.clone();
    solve::ldlt_factor(n, &mut factor).map_err(|(j, pivot)| Error::SingularMassMatrix {
        t,
        q: q.to_vec(),
        coordinate: model.coordinates()[j].name.clone(),
        pivot,
    })?;
    let mut gravity_force = vec![0.0; n];
    for (b, m) in model.mass.iter().enumerate() {
        for j in 0..n {
            gravity_force[j] -= ws.jacobian[(3 * b + 1) * n + j] * m * model.gravity;
        }
    }
    Ok(ConstantTerms { jacobian: ws.jacobian.clone(), mass_matrix: ws.mass_matrix.clone(), factor, gravity_force })
}

/// Check a declared tree against the mechanism: bodies, gravity, and — at every probe state —
/// poses, velocities and convective accelerations from one second-order dual pass of each.
fn check_tree<M: Mechanism>(model: &Model<M>, tree: &Tree, probes: &ProbeStates) -> Result<(), Error> {
    let inconsistent =
        |what: String| Err(Error::Inconsistent { what: format!("declared a kinematic tree, but {what}") });
    let bodies = model.mechanism.bodies();
    if tree.len() != bodies.len() || tree.len() != model.n {
        return inconsistent(format!(
            "it has {} bodies and coordinates where the mechanism has {} bodies and {} coordinates",
            tree.len(),
            bodies.len(),
            model.n
        ));
    }
    for (mine, theirs) in bodies.iter().zip(tree.bodies()) {
        if (mine.mass, mine.inertia) != (theirs.mass, theirs.inertia) {
            return inconsistent(format!("its body `{}` differs from the mechanism's `{}`", theirs.name, mine.name));
        }
    }
    if tree.gravity() != model.gravity {
        return inconsistent(format!("its g = {} differs from the mechanism's {}", tree.gravity(), model.gravity));
    }
    let b = bodies.len();
    let (mut mine, mut theirs) = (vec![Pose::<Dual2<f64>>::default(); b], vec![Pose::<Dual2<f64>>::default(); b]);
    let mut seeded = vec![Dual2::from_re(0.0); model.n];
    for k in 0..probes.len() {
        let (q, qdot, t) = probes.state(k);
        for ((d, &qi), &vi) in seeded.iter_mut().zip(q).zip(qdot) {
            *d = Dual2::new(qi, vi, 0.0);
        }
        let t_dual = Dual2::new(t, 1.0, 0.0);
        model.mechanism.poses(&seeded, t_dual, &mut mine);
        tree.poses(&seeded, t_dual, &mut theirs);
        // Components: x and y of bodies with mass, the angle of bodies with inertia.
        let components = |poses: &[Pose<Dual2<f64>>]| {
            poses
                .iter()
                .zip(bodies)
                .flat_map(|(p, body)| {
                    let translation = if body.mass != 0.0 { [Some(p.x), Some(p.y)] } else { [None, None] };
                    translation.into_iter().chain([(body.inertia != 0.0).then_some(p.angle)]).flatten()
                })
                .collect::<Vec<_>>()
        };
        let (a, b) = (components(&mine), components(&theirs));
        for (order, part) in [("poses", 0), ("velocities", 1), ("convective accelerations", 2)] {
            let get = |d: &Dual2<f64>| [d.re, d.v1, d.v2][part];
            let scale = a.iter().chain(&b).fold(1.0_f64, |m, d| m.max(get(d).abs()));
            // A NaN difference fails too.
            if !a.iter().zip(&b).all(|(x, y)| (get(x) - get(y)).abs() <= 1e-12 * scale) {
                return inconsistent(format!(
                    "its forward kinematics differ from the mechanism's {order} at q = {q:?}"
                ));
            }
        }
    }
    Ok(())
}
