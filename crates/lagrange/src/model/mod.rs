//! The model: what the user describes, validated and immutable.

mod lagrangian;
mod mechanism;
#[allow(clippy::module_inception)]
mod model;
pub(crate) mod probe;

pub use lagrangian::{Lagrangian, LagrangianFunction};
pub use mechanism::{Body, Coordinate, CoordinateKind, Mechanism};
pub use model::Model;
