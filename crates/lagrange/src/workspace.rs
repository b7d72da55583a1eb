//! Every buffer an evaluation of a body model needs, allocated once.

use crate::eom::articulated::ArticulatedBody;
pub use crate::eom::constraints::ConstraintBuffers;
use crate::mechanism::Mechanism;
use crate::model::Model;
use crate::pose::Pose;
use crate::scalar::Scalar;
use crate::seed::Lanes;
use crate::seed::Tangent;
use num_dual::{Dual, Dual2, Dual64};

/// Scratch space for evaluating a [`Model`] in scalar `S` (the *data* of Pinocchio's
/// model/data split). Allocate it once with [`Model::workspace`] (`f64`) or
/// [`Model::workspace_in`] (any scalar); no evaluation allocates.
///
/// Results are borrowed from it: the fields below are public for reading (shapes in
/// parentheses; `n` coordinates, `B` bodies; matrices row-major).
#[derive(Clone, Debug)]
pub struct Workspace<S: Scalar> {
    /// Coordinates seeded for one Jacobian column (n), filled by `jacobian_pass`.
    pub(crate) q_dual: Vec<Dual<S>>,
    /// Poses of one Jacobian pass (B).
    pub(crate) poses_dual: Vec<Pose<Dual<S>>>,
    /// Coordinates seeded for one chunk of Jacobian columns (n), filled by `jacobian_pass`.
    pub(crate) q_lanes: Vec<Lanes<S>>,
    /// Poses of one chunk pass (B).
    pub(crate) poses_lanes: Vec<Pose<Lanes<S>>>,
    /// Coordinates as second-order duals along `(q̇, 1)` (n), filled by `velocity_pass`.
    pub(crate) q_dual2: Vec<Dual2<S>>,
    /// Poses of the velocity pass (B).
    pub(crate) poses_dual2: Vec<Pose<Dual2<S>>>,
    /// Body poses `p_b = (x, y, φ)` (3B), filled by `jacobian_pass`.
    pub position: Vec<S>,
    /// Pose Jacobian `J = ∂p/∂q` (3B × n), body-major rows, filled by `jacobian_pass`.
    pub jacobian: Vec<S>,
    /// Body velocities `ṗ_b = J_b q̇ + ∂p_b/∂t` (3B), filled by `velocity_pass`.
    pub velocity: Vec<S>,
    /// Convective accelerations `γ_b = p̈_b − J_b q̈` (3B), filled by `velocity_pass`.
    pub convective: Vec<S>,
    /// Extra potential `V` (without gravity), filled by `jacobian_pass` when the model has one.
    pub potential: S,
    /// `∂V/∂q` (n), filled by `jacobian_pass` when the model has a potential.
    pub potential_gradient: Vec<S>,
    /// Generalized forces `Q` (n), filled by the bias stage.
    pub generalized_force: Vec<S>,
    /// Applied wrenches `w_b = (F_x, F_y, τ)` about each centre of mass (3B; empty unless the
    /// model has [applied forces](crate::Mechanism::applied_forces)), filled by the bias stage.
    pub applied_wrench: Vec<S>,
    /// Their generalized forces `Σ_b J_bᵀ w_b` (n; empty unless the model has applied forces),
    /// filled by the bias stage.
    pub applied_force: Vec<S>,
    /// Body poses handed to [`Mechanism::applied_forces`] (B; empty unless the model has them).
    pub(crate) applied_poses: Vec<Pose<S>>,
    /// Mass matrix `M = Σ_b J_bᵀ D_b J_b` (n × n), filled by `mass_matrix::assemble`.
    pub mass_matrix: Vec<S>,
    /// LDLᵀ factor of `M` (n × n): unit lower triangle below the diagonal, `D` on it.
    pub factor: Vec<S>,
    /// Column indices (n): scratch of the sparse mass-matrix assembly.
    pub(crate) columns: Vec<usize>,
    /// Right-hand side `f = Σ_b J_bᵀ (F_b − D_b γ_b) − ∂V/∂q + Q` (n), filled by the bias stage;
    /// on the tree path only `Q − ∂V/∂q` (when the model has either).
    pub rhs: Vec<S>,
    /// Generalized accelerations `q̈` (n), filled by [`accelerations`](crate::accelerations).
    pub qddot: Vec<S>,
    /// Generalized momenta `p = ∂L/∂q̇` (n), filled by [`momenta`](crate::momenta).
    pub momenta: Vec<S>,
    /// Constraint forces on the bodies `(F_x, F_y, τ)` (3B), filled by
    /// [`reaction_forces`](crate::reaction_forces).
    pub reaction: Vec<S>,
    /// `∂V/∂p_b`: the potential's force on each body, negated (3B), filled by `reaction_forces`.
    pub(crate) potential_pose_gradient: Vec<S>,
    /// Constant terms of the model in `S` (empty unless `M` is constant): `J`, LDLᵀ of `M`,
    /// generalized gravity.
    pub(crate) constant_jacobian: Vec<S>,
    pub(crate) constant_factor: Vec<S>,
    pub(crate) constant_gravity: Vec<S>,
    /// Per-body scratch of the articulated-body algorithm (B; empty unless the model uses the
    /// tree path), filled by `articulated::solve`.
    pub(crate) articulated: Vec<ArticulatedBody<S>>,
    /// The `Dual64` workspace and seeds of the tangent passes of
    /// [`Dynamics::acceleration_jacobian`](crate::Dynamics::acceleration_jacobian): allocated
    /// up front by [`Dynamics::workspace`](crate::Dynamics::workspace), otherwise by the
    /// first Jacobian (`None` until then).
    pub(crate) tangent: Option<Box<Tangent<Workspace<Dual64>>>>,
    /// The constrained solve's buffers (`None` for a model without constraints): `G`, `γ`,
    /// the residuals and the multipliers `λ`, filled by [`accelerations`](crate::accelerations).
    pub constraints: Option<ConstraintBuffers<S>>,
    /// The sparse constrained solve's buffers (`None` unless the model has a
    /// [`SparseStructure`](crate::eom::sparse::SparseStructure)).
    pub(crate) sparse: Option<crate::eom::sparse::SparseBuffers<S>>,
}

impl<S: Scalar> Workspace<S> {
    /// Allocate every buffer for `model` (users call [`Model::workspace`] / [`Model::workspace_in`]).
    pub(crate) fn new<M: Mechanism>(model: &Model<M>) -> Self {
        let n = model.dof();
        let b = model.bodies().len();
        let zero = S::zero();
        let lift = |v: &Vec<f64>| v.iter().map(|&x| S::from(x)).collect::<Vec<S>>();
        let (constant_jacobian, constant_factor, constant_gravity) = match &model.constant {
            Some(c) => (lift(&c.jacobian), lift(&c.factor), lift(&c.gravity_force)),
            None => (Vec::new(), Vec::new(), Vec::new()),
        };
        Self {
            q_dual: vec![Dual::from_re(zero); n],
            poses_dual: vec![Pose::default(); b],
            q_lanes: vec![Lanes::from_re(zero); n],
            poses_lanes: vec![Pose::default(); b],
            q_dual2: vec![Dual2::from_re(zero); n],
            poses_dual2: vec![Pose::default(); b],
            position: vec![zero; 3 * b],
            jacobian: vec![zero; 3 * b * n],
            velocity: vec![zero; 3 * b],
            convective: vec![zero; 3 * b],
            potential: zero,
            potential_gradient: vec![zero; n],
            generalized_force: vec![zero; n],
            applied_wrench: if model.has_applied { vec![zero; 3 * b] } else { Vec::new() },
            applied_force: if model.has_applied { vec![zero; n] } else { Vec::new() },
            applied_poses: if model.has_applied { vec![Pose::default(); b] } else { Vec::new() },
            mass_matrix: vec![zero; n * n],
            factor: vec![zero; n * n],
            columns: vec![0; n],
            rhs: vec![zero; n],
            qddot: vec![zero; n],
            momenta: vec![zero; n],
            reaction: vec![zero; 3 * b],
            potential_pose_gradient: vec![zero; 3 * b],
            constant_jacobian,
            constant_factor,
            constant_gravity,
            articulated: if model.uses_tree { vec![ArticulatedBody::zero(); b] } else { Vec::new() },
            tangent: None,
            constraints: model.is_constrained().then(|| {
                let (m, k) = model.constraint_counts();
                ConstraintBuffers::new(n, b, m, k)
            }),
            sparse: model.sparse.as_ref().map(|s| crate::eom::sparse::SparseBuffers::new(s)),
        }
    }
}

impl<M: Mechanism> Model<M> {
    /// A workspace for `f64` evaluations (allocate once, reuse for every step).
    pub fn workspace(&self) -> Workspace<f64> {
        Workspace::new(self)
    }

    /// A workspace for evaluations in scalar `S` (e.g. `Dual64`, to differentiate the
    /// accelerations).
    pub fn workspace_in<S: Scalar>(&self) -> Workspace<S> {
        Workspace::new(self)
    }
}
