//! # lagrange-validation — how the engine is checked, as a library
//!
//! The validation report's machinery, reusable by the `lagrange` command line, the tests and
//! the benches: the scenes as a catalogue ([`catalogue`]), what runs ([`plan`]), the references every run is measured against
//! ([`reference`](mod@reference)), the measurement of one run ([`measure`], whose loop also serves [`compare`], which sets the reduced solver beside a maximal engine and tabulates the engines), what a run costs before and while it runs ([`cost`]), a run's check of itself ([`health`]), the sweeps of a scene
//! ([`runs`]), the work-precision fronts and their comparison ([`pareto`]), the assembly of a
//! scene's report ([`assemble`]) into the serialized [`schema`], and the stability suite with
//! its theory ([`stability`]); random joint graphs ([`graphs`]) and the tolerances with their
//! reasons ([`tolerance`]). The numeric helpers every check shares (seeded generator, NaN-aware
//! maxima, closeness, condition number) are the leaf crate `lagrange-testing`'s. The report's rendering — Markdown, the SVG plots, the terminal
//! summary — is here too ([`render`]), as text: any front end produces the same report, and
//! writes the files itself.

pub mod andrews;
pub mod animation;
pub mod assemble;
pub mod catalogue;
pub mod compare;
pub mod cost;
mod error;
pub mod graphs;
pub mod health;
pub mod measure;
pub mod pareto;
pub mod plan;
pub mod reference;
pub mod render;
pub mod runs;
pub mod schema;
pub mod stability;
pub mod start;
pub mod tolerance;

pub use error::{Error, scene};
