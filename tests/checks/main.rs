//! Integration checks of the reduced-coordinate solver against closed forms, identities,
//! finite differences and its own second (raw-Lagrangian) path. One module per kind of check.

mod analytic;
mod animation;
mod bad_input;
mod constant_mass;
mod constraints;
mod derivatives;
mod health;
mod identities;
mod integrators;
mod layering;
mod modes;
mod properties;
mod raw_path;
mod reactions;
mod readme;
mod region;
mod singular;
mod stability;
mod variational;
mod variational_constraints;
