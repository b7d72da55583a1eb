//! Integration checks of the reduced-coordinate solver against closed forms, identities,
//! finite differences, its own second (raw-Lagrangian) path and the maximal-coordinate
//! formulations; scene files, joint graphs and the allocation-free steps. One module per kind of
//! check, all in one test binary so that the workspace and both rapier builds are linked once
//! (`cargo test -p lagrange-tests --test checks -- MODULE::` runs one module).

mod allocation;
mod analytic;
mod animation;
mod bad_input;
mod constant_mass;
mod constraints;
mod derivatives;
mod files;
mod graphs;
mod health;
mod identities;
mod integrators;
mod layering;
mod maximal;
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
