//! Joint graphs: a mechanism described once as bodies and joints.
//!
//! A [`JointGraph`] lists bodies (mass, inertia about the centre of mass, optionally a shape),
//! joints between two bodies or a body and the ground (revolute, prismatic, fixed; any of the
//! first two driven by a prescribed function of time), couplings between joint coordinates
//! (`q_j = k q_i + c`), force elements (springs and dampers between points, springs and
//! dampers on joints, torques and forces) and gravity. Loops are allowed.
//!
//! [`GraphMechanism`] resolves it into the reduced model: a spanning tree chosen from the graph
//! (joints marked [`Role::Tree`] first, then the others in the order listed, each unless it
//! would close a loop) gives one coordinate per free tree joint and the poses by forward
//! kinematics; every loop-closing joint gives holonomic constraints `Φ(q, t) = 0`, so that the
//! equations solved are
//!
//! ```text
//! M(q, t) q̈ + Gᵀ λ = f(q, q̇, t),      G q̈ = −γ,      G = ∂Φ/∂q,
//! ```
//!
//! with `f` from gravity, the springs' potential and the dampers', torques' and forces' loads
//! (docs/graphs.md). The crate `lagrange-maximal` builds the same graph as Cartesian bodies
//! with multipliers and in rapier, and reads the bodies back into these coordinates with
//! [`GraphMechanism::coordinates_of`].
//!
//! ```
//! use lagrange::graph::{GraphBody, GraphJoint, GraphMechanism, JointGraph};
//! use lagrange::{Model, accelerations};
//!
//! // A four-bar linkage: crank, coupler and rocker as uniform rods on pins; the pin between
//! // coupler and rocker closes the loop.
//! let rod = |name: &str, length: f64| GraphBody::rigid(name, 1.0, length * length / 12.0);
//! let graph = JointGraph::new("four-bar", 9.81)
//!     .with_body(rod("crank", 1.0))
//!     .with_body(rod("coupler", 2.0))
//!     .with_body(rod("rocker", 2.0))
//!     .with_joint(GraphJoint::revolute("θ2", "ground", [0.0, 0.0], "crank", [-0.5, 0.0]))
//!     .with_joint(GraphJoint::revolute("θ3", "crank", [0.5, 0.0], "coupler", [-1.0, 0.0]).absolute())
//!     .with_joint(GraphJoint::revolute("θ4", "ground", [2.0, 0.0], "rocker", [-1.0, 0.0]))
//!     .with_joint(GraphJoint::revolute("B", "coupler", [1.0, 0.0], "rocker", [1.0, 0.0]).closing());
//! let mechanism = GraphMechanism::new(graph)?;
//! let model = Model::new(mechanism)?;
//! assert_eq!(model.dof(), 3);
//! // Assemble a consistent state with the crank held at 1 rad, then solve.
//! use lagrange::{Dynamics, State};
//! let state = Dynamics::assemble(&model, &State::new(0.0, [1.0, 0.5, 1.5], [1.0, 0.0, 0.0]), &[true, false, false])?;
//! let mut ws = model.workspace();
//! let qddot = accelerations(&model, &mut ws, 0.0, &state.q, &state.qdot)?;
//! assert!(qddot.iter().all(|a| a.is_finite()));
//! # Ok::<(), lagrange::Error>(())
//! ```

mod description;
mod forces;
mod mechanism;
mod spanning;
#[cfg(test)]
mod tests;

pub use description::{
    Coupling, ForceElement, GROUND, GraphBody, GraphJoint, JointGraph, JointType, Point, Profile, Role, Shape,
};
pub use mechanism::GraphMechanism;

use crate::Error;

/// The error for an element of a graph that is not a mechanism.
pub(crate) fn invalid(element: &str, why: String) -> Error {
    Error::InvalidGraph { element: element.to_string(), why }
}
