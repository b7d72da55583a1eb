//! What a user writes: coordinates, bodies and their poses ([`Mechanism`]), or a Lagrangian
//! ([`Lagrangian`]); below the probes and the [`Model`](crate::Model) that check and prepare them.

mod described;
mod lagrangian;
mod loads;
#[allow(clippy::module_inception)]
mod mechanism;
mod region;

pub use described::{Described, Poses};
pub use lagrangian::{Lagrangian, LagrangianFunction};
pub use loads::Loads;
pub(crate) use loads::project;
pub use mechanism::{Body, Coordinate, CoordinateKind, Mechanism};
pub use region::{Bounds, Side};
