//! The validated, immutable model built from a user's [`Mechanism`].

use crate::error::Error;
use crate::mechanism::{Body, Bounds, Coordinate, Description, Loads, Mechanism};
use crate::pose::Pose;
use crate::probe::{self, ConstantTerms, ProbeStates};
use crate::tree::Tree;
use std::sync::OnceLock;

/// A [`Mechanism`] checked and prepared for evaluation: the *model* of the model/workspace split.
///
/// Construction validates the bodies (finite, non-negative masses and inertias), asks once
/// which optional terms the mechanism has (potential, generalized forces, admissible region), checks a declared
/// constant mass matrix or kinematic tree at probe states (and factors the constant matrix),
/// and whether the equations are autonomous; the cyclic coordinates are found on first request.
/// Evaluations never re-check any of this.
///
/// # Which algorithm computes `q̈`
///
/// [`accelerations`](crate::accelerations) picks, once and for all at construction:
/// 1. a declared constant mass matrix ([`Description::constant_mass_matrix`]): the stored factor;
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
    /// Whether the mechanism lists forces applied at points of bodies.
    pub(crate) has_applied: bool,
    /// Whether the mechanism declares an admissible region.
    pub(crate) has_region: bool,
    pub(crate) constant: Option<ConstantTerms>,
    /// The cyclic coordinates, found on first request ([`cyclic_coordinates`](Self::cyclic_coordinates)).
    pub(crate) cyclic: OnceLock<Vec<bool>>,
    pub(crate) autonomous: bool,
    /// Whether accelerations run the articulated-body algorithm on the mechanism's declared
    /// tree ([`declared_tree`](Self::declared_tree)).
    pub(crate) uses_tree: bool,
    /// Numbers of holonomic and velocity constraints among the coordinates.
    pub(crate) constraint_counts: (usize, usize),
    /// The structure of the sparse constrained solve of a tree with many holonomic
    /// constraints (`None`: the dense solve).
    pub(crate) sparse: Option<Box<crate::eom::sparse::SparseStructure>>,
}

impl<M: Mechanism> Model<M> {
    /// Validate and prepare a mechanism.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-finite or negative mass or inertia, non-finite
    /// gravity (negative `g` is allowed: gravity along +y), or a
    /// mechanism without coordinates or bodies, or whose applied forces name a body it does not
    /// have; [`Error::UnwrittenPose`] if the poses leave a
    /// body's pose (or a component of it) unwritten at a probe state; [`Error::LostDerivative`]
    /// if an exact derivative of the poses disagrees with finite differences (the poses read
    /// `t.re()` or `q[i].re()`); [`Error::Inconsistent`] if a declared constant
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
        let description = mechanism.description();
        check_description(description)?;
        let (n, bodies, gravity) = (description.coordinates.len(), &description.bodies, description.gravity);
        let mut model = Model {
            n,
            mass: bodies.iter().map(|b| b.mass).collect(),
            inertia: bodies.iter().map(|b| b.inertia).collect(),
            gravity,
            has_potential: false,
            has_force: false,
            has_applied: false,
            has_region: false,
            constant: None,
            cyclic: OnceLock::new(),
            autonomous: false,
            uses_tree: false,
            constraint_counts: description.constraint_counts(),
            sparse: None,
            mechanism,
        };
        let probes = ProbeStates::new(n);
        probe::check_poses(&model.mechanism, &probes)?;
        model.ask_optional_terms(&probes)?;
        let constraints_autonomous = if model.is_constrained() {
            probe::check_constraints(&model.mechanism, model.constraint_counts, &probes)?
        } else {
            true
        };
        if model.mechanism.description().constant_mass_matrix {
            model.constant = Some(probe::constant_terms(&model.mechanism, &probes)?);
        }
        if use_tree && let Some(tree) = model.mechanism.tree() {
            probe::check_tree(&model.mechanism, tree, &probes)?;
            // A constant mass matrix is cheaper still: the tree is checked but not used.
            if model.constant.is_none() {
                model.uses_tree = true;
            }
        }
        if let Some(tree) = model.declared_tree()
            && let (m @ 1.., 0) = model.constraint_counts
            && n >= crate::eom::sparse::SPARSE_FROM
        {
            model.sparse = crate::eom::sparse::SparseStructure::new(&model.mechanism, tree, m, &probes).map(Box::new);
        }
        // A moving constraint does work.
        model.autonomous = probes.autonomous(&model) && constraints_autonomous;
        Ok(model)
    }

    /// Ask once, at the first probe state, which optional terms the mechanism has: a potential,
    /// generalized forces, applied forces (on bodies it has), an admissible region.
    fn ask_optional_terms(&mut self, probes: &ProbeStates) -> Result<(), Error> {
        let (q, qdot, t) = probes.state(0);
        let mut poses = vec![Pose::<f64>::default(); self.description().bodies.len()];
        self.mechanism.poses(t, q, &mut poses);
        self.has_potential = self.mechanism.potential(t, q, &poses).is_some();
        let mut force = vec![0.0; self.n];
        self.has_force = self.mechanism.generalized_force(t, q, qdot, &mut force);
        let mut wrench = vec![0.0; 3 * self.description().bodies.len()];
        let mut loads = Loads::new(&poses, &mut wrench);
        self.has_applied = self.mechanism.applied_forces(t, q, qdot, &poses, &mut loads);
        if let Some(body) = loads.bad_body() {
            return Err(invalid("applied force", body as f64, "names a body the mechanism does not have"));
        }
        self.has_region = self.mechanism.admissible(t, q, qdot, &mut Bounds::new());
        Ok(())
    }

    /// The user's mechanism.
    pub fn mechanism(&self) -> &M {
        &self.mechanism
    }

    /// Number of generalized coordinates `n`.
    pub fn dof(&self) -> usize {
        self.n
    }

    /// The bodies, in the order of the poses (`bodies().len()` is `B`).
    pub fn bodies(&self) -> &[Body] {
        &self.mechanism.description().bodies
    }

    /// The generalized coordinates.
    pub fn coordinates(&self) -> &[Coordinate] {
        &self.mechanism.description().coordinates
    }

    /// The mechanism's data: coordinates, bodies, gravity, constraint names.
    pub fn description(&self) -> &Description {
        self.mechanism.description()
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

    /// Whether the mechanism lists forces applied at points of bodies
    /// ([`Mechanism::applied_forces`]).
    pub fn has_applied_forces(&self) -> bool {
        self.has_applied
    }

    /// Whether the mechanism declares an admissible region ([`Mechanism::admissible`]).
    pub fn has_admissible_region(&self) -> bool {
        self.has_region
    }

    /// Whether `M` is constant (declared, and checked at construction).
    pub fn has_constant_mass_matrix(&self) -> bool {
        self.constant.is_some()
    }

    /// A consistent state from an approximate one, the coordinates marked in `held` kept:
    /// [`assemble`](crate::assemble), callable as a method without importing
    /// [`Dynamics`](crate::Dynamics).
    ///
    /// # Errors
    /// As [`assemble`](crate::assemble).
    pub fn assemble(&self, approximate: &crate::State, held: &[bool]) -> Result<crate::State, Error> {
        crate::assemble(self, approximate, held)
    }

    /// Whether [`accelerations`](crate::accelerations) runs the articulated-body algorithm on
    /// the mechanism's declared [`Tree`] (built with [`new`](Self::new), a tree declared, no
    /// constant mass matrix).
    pub fn uses_tree_path(&self) -> bool {
        self.uses_tree
    }

    /// The mechanism's declared tree when accelerations run the articulated-body algorithm on
    /// it, `None` otherwise.
    pub(crate) fn declared_tree(&self) -> Option<&Tree> {
        if self.uses_tree { self.mechanism.tree() } else { None }
    }

    /// Whether the coordinates are related by constraints ([`Description::constraints`],
    /// [`Description::velocity_constraints`]).
    pub fn is_constrained(&self) -> bool {
        self.constraint_counts != (0, 0)
    }

    /// The numbers of holonomic and of velocity constraints `(m, k)`.
    pub fn constraint_counts(&self) -> (usize, usize) {
        self.constraint_counts
    }

    /// Which coordinates are cyclic (`∂L/∂q_j = 0`): their momenta `p_j` are conserved when
    /// no generalized force acts on them. Found at construction by evaluating `∂L/∂q_j`
    /// exactly (AD) at probe states: a coordinate is cyclic when it is exactly zero at all.
    ///
    /// Asked of the mechanism on the first call (one dual pass per coordinate at each probe
    /// state, `O(n²)` for a chain) and kept: construction does not pay for it.
    pub fn cyclic_coordinates(&self) -> &[bool] {
        self.cyclic.get_or_init(|| {
            let probes = ProbeStates::new(self.n);
            let mut cyclic = probes.cyclic(self);
            if self.is_constrained() {
                // A constraint force along q_j moves p_j.
                let involves = probe::constraint_involvement(&self.mechanism, self.constraint_counts, &probes);
                for (c, involved) in cyclic.iter_mut().zip(involves) {
                    *c &= !involved;
                }
            }
            cyclic
        })
    }

    /// Whether the Lagrangian does not depend on time explicitly (`∂L/∂t = 0` exactly at the
    /// probe states); then, without generalized forces, the energy function `h` is conserved.
    pub fn is_autonomous(&self) -> bool {
        self.autonomous
    }

    /// Whether the energy function `h` is a constant of the motion: autonomous, no `Q`, no
    /// applied forces.
    pub fn conserves_energy(&self) -> bool {
        self.autonomous && !self.has_force && !self.has_applied
    }
}

/// The description's own checks: at least one coordinate and one body, finite non-negative
/// masses and inertias, finite gravity.
fn check_description(description: &Description) -> Result<(), Error> {
    if description.coordinates.is_empty() {
        return Err(invalid("coordinates", 0.0, "a mechanism needs at least one coordinate"));
    }
    if description.bodies.is_empty() {
        return Err(invalid("bodies", 0.0, "a mechanism needs at least one body"));
    }
    for Body { name, mass, inertia } in &description.bodies {
        check_non_negative(&format!("mass of {name}"), *mass)?;
        check_non_negative(&format!("inertia of {name}"), *inertia)?;
    }
    if !description.gravity.is_finite() {
        return Err(invalid("g", description.gravity, "must be finite"));
    }
    Ok(())
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
