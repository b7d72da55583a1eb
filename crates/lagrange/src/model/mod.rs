//! The model: a user's mechanism, validated and immutable.

mod lagrangian;
#[allow(clippy::module_inception)]
mod model;

pub use model::Model;
