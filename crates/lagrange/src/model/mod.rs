//! The model: a user's mechanism, validated and immutable.

mod lagrangian;
#[allow(clippy::module_inception)]
mod model;
#[cfg(test)]
mod tests;

pub use model::Model;
