//! What a user writes: the data ([`Description`]) and the poses ([`Mechanism`]), or a Lagrangian
//! ([`Lagrangian`]); below the probes and the [`Model`](crate::Model) that check and prepare them.

mod description;
mod lagrangian;
mod loads;
#[allow(clippy::module_inception)]
mod mechanism;
mod region;

pub use description::Description;
pub use lagrangian::{Lagrangian, LagrangianFunction};
pub use loads::Loads;
pub(crate) use loads::project;
pub use mechanism::{Body, Coordinate, CoordinateKind, Mechanism};
pub use region::{Bounds, Side};
