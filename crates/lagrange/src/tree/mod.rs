//! Planar kinematic trees and their `O(n)` forward dynamics.
//!
//! A [`Tree`] describes bodies connected by revolute or prismatic [`Joint`]s to a parent body
//! or to the ground, one coordinate per joint. It is a [`Mechanism`](crate::Mechanism) by itself,
//! and any mechanism can declare one ([`Mechanism::tree`](crate::Mechanism::tree)); then
//! [`accelerations`](crate::accelerations) runs Featherstone's articulated-body algorithm
//! (planar spatial algebra) instead of assembling `M`.

mod joint;
pub(crate) mod spatial;
#[allow(clippy::module_inception)]
mod tree;

pub use joint::{AngleReference, Joint, JointKind, Parent, Sense};
pub(crate) use tree::Link;
pub use tree::Tree;
