//! Scene files: a mechanism written in a TOML file instead of Rust, read into a
//! [`Scene`](lagrange_scenes::Scene) that every command of the `lagrange` CLI and every
//! function of the validation crate takes.
//!
//! Two forms share one schema (docs/files.md):
//! - the **coordinates form**, the lecture's method: parameters, generalized coordinates `q`,
//!   and every body's mass, inertia and pose `(x, y, φ)` as expressions in `q`, `t` and the
//!   parameters; optionally a potential `V(t, q)`, generalized forces `Q(t, q, q̇)`, holonomic
//!   constraints `Φ(t, q) = 0`, velocity constraints, a raw Lagrangian `L(t, q, q̇)` in place of
//!   bodies, and bounds of the admissible region. The engine then derives, exactly,
//!   `T = ½ Σ_b (m_b |ṗ_b|² + I_b φ̇_b²)`, `L = T − V − Σ_b m_b g y_b` and Lagrange's equations
//!   `d/dt ∂L/∂q̇ − ∂L/∂q = Q + Gᵀλ`, as for a mechanism written in Rust;
//! - the **joint-graph form**: a [`JointGraph`](lagrange::graph::JointGraph) (bodies, joints,
//!   couplings, force elements) and its initial state, which also gets the Cartesian and the
//!   rapier builds.
//!
//! Expressions are parsed once and compiled into a tape per function (each repeated
//! subexpression evaluated once, constants folded), evaluated over the engine's scalar types
//! without allocating. Every error points into the file ([`Diagnostic`]).
//!
//! ```
//! let text = r#"
//! version = 1
//! id = "file_pendulum"
//! gravity = "g"
//!
//! [[parameters]]
//! name = "g"
//! value = 9.81
//! unit = "m/s²"
//!
//! [[parameters]]
//! name = "l"
//! value = 2.0
//! domain = "positive"
//!
//! [[coordinates]]
//! name = "theta"
//! kind = "angle"
//! initial = 0.3
//!
//! [[bodies]]
//! name = "bob"
//! mass = 1.0
//! x = "l*sin(theta)"
//! y = "-l*cos(theta)"
//! "#;
//! let scene = lagrange_file::parse("pendulum.toml", text)?;
//! let mut system = scene.build(&scene.default_params())?;
//! let qddot = system.accelerations(0.0, &[0.3], &[0.0])?[0];
//! approx::assert_relative_eq!(qddot, -9.81 / 2.0 * 0.3_f64.sin(), max_relative = 1e-14);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod coordinates;
mod diagnostic;
pub mod expr;
mod graph;
mod mechanism;
mod names;
mod read;
mod scene;
pub mod schema;
pub mod symbolic;
pub mod tape;
mod unfold;
mod write;

pub use diagnostic::Diagnostic;
pub use mechanism::{FileLagrangian, FileMechanism};
pub use read::{FileError, eom, eom_source, load, load_coordinates, parse, register, register_source, scene_equations};
pub use scene::{FileModel, FileScene};
pub use write::{coordinates_file, graph_file};
