//! The TOML schema of a scene file, as serde reads it: every table refuses keys it does not
//! know, and every value an error can be about keeps its place in the file.

use serde::Deserialize;
use toml::Spanned;

/// The version of the format this crate reads.
pub const VERSION: i64 = 1;

/// A whole scene file: its identity, then either the coordinates form (parameters,
/// coordinates, bodies, …) or the joint-graph form (`graph` and `initial`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// The format's version ([`VERSION`]).
    pub version: Spanned<i64>,
    /// The scene's id (as a built-in scene's `cart_pendulum`).
    pub id: Spanned<String>,
    /// A title in words.
    #[serde(default)]
    pub title: Option<String>,
    /// Where the system comes from (a book, a lecture).
    #[serde(default)]
    pub reference: Option<String>,
    /// The span of time the scene is meant to be run over (s).
    #[serde(default)]
    pub horizon: Option<Spanned<f64>>,

    /// Parameters the expressions name (coordinates form).
    #[serde(default)]
    pub parameters: Vec<Parameter>,
    /// Gravity along −y (an expression in the parameters; default 0).
    #[serde(default)]
    pub gravity: Option<Spanned<Expr>>,
    /// The generalized coordinates, in order.
    #[serde(default)]
    pub coordinates: Vec<CoordinateEntry>,
    /// The bodies and where they are.
    #[serde(default)]
    pub bodies: Vec<BodyEntry>,
    /// An extra potential energy `V(t, q)` beyond gravity.
    #[serde(default)]
    pub potential: Option<Spanned<Expr>>,
    /// Non-conservative generalized forces `Q_i(t, q, q̇)`, by coordinate.
    #[serde(default)]
    pub forces: Vec<ForceEntry>,
    /// Holonomic constraints `Φ(t, q) = 0`.
    #[serde(default)]
    pub constraints: Vec<ConstraintEntry>,
    /// Velocity constraints `a(t, q) · q̇ + b(t, q) = 0`.
    #[serde(default)]
    pub velocity_constraints: Vec<ConstraintEntry>,
    /// A raw Lagrangian `L(t, q, q̇)` in place of bodies.
    #[serde(default)]
    pub lagrangian: Option<Spanned<Expr>>,
    /// The admissible region: bounds on functions of the state.
    #[serde(default)]
    pub region: Vec<BoundEntry>,

    /// The joint graph (joint-graph form; docs/graphs.md).
    #[serde(default)]
    pub graph: Option<Spanned<lagrange::graph::JointGraph>>,
    /// The initial state of a joint graph's coordinates.
    #[serde(default)]
    pub initial: Option<Spanned<InitialEntry>>,
}

/// An expression: a TOML number, or a string in the expression language (docs/files.md).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum Expr {
    /// A number.
    Number(f64),
    /// An expression's text.
    Text(String),
}

/// One parameter.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Parameter {
    /// The name expressions use (`m1`, `theta0`, `l`).
    pub name: Spanned<String>,
    /// The symbol as printed (`m₁`); default the name.
    #[serde(default)]
    pub symbol: Option<String>,
    /// Its value.
    pub value: Spanned<f64>,
    /// Its SI unit (`kg`, `m`).
    #[serde(default)]
    pub unit: Option<String>,
    /// The values it may take: `positive`, `non_negative` or `finite` (the default).
    #[serde(default)]
    pub domain: Option<Spanned<String>>,
    /// Or: strictly between two values.
    #[serde(default)]
    pub between: Option<Spanned<[f64; 2]>>,
    /// One line on what it is.
    #[serde(default)]
    pub description: Option<String>,
}

/// What a coordinate measures.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// An angle (rad).
    Angle,
    /// A length (m).
    Length,
}

/// One generalized coordinate.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoordinateEntry {
    /// Its name (`theta`); its rate is `<name>_dot`.
    pub name: Spanned<String>,
    /// Angle or length.
    pub kind: Kind,
    /// Its value at `t = 0` (an expression in the parameters; default 0).
    #[serde(default)]
    pub initial: Option<Spanned<Expr>>,
    /// Its rate at `t = 0` (an expression in the parameters; default 0).
    #[serde(default)]
    pub rate: Option<Spanned<Expr>>,
}

/// One body: its mass, its inertia and where it is.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyEntry {
    /// Its name.
    pub name: Spanned<String>,
    /// Mass (kg; an expression in the parameters).
    pub mass: Spanned<Expr>,
    /// Moment of inertia about the centre of mass (kg m²; default 0, a point mass).
    #[serde(default)]
    pub inertia: Option<Spanned<Expr>>,
    /// The centre of mass's `x(t, q)`.
    pub x: Spanned<Expr>,
    /// The centre of mass's `y(t, q)` (gravity acts along −y).
    pub y: Spanned<Expr>,
    /// The body's angle `φ(t, q)`, counter-clockwise (default 0).
    #[serde(default)]
    pub angle: Option<Spanned<Expr>>,
}

/// A generalized force on one coordinate.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForceEntry {
    /// The coordinate it acts along.
    pub coordinate: Spanned<String>,
    /// `Q(t, q, q̇)`.
    pub force: Spanned<Expr>,
}

/// A constraint row.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConstraintEntry {
    /// Its name (for reaction forces and errors).
    pub name: Spanned<String>,
    /// The residual that must vanish.
    pub residual: Spanned<Expr>,
}

/// A bound of the admissible region.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundEntry {
    /// A function of `(t, q, q̇)`.
    pub quantity: Spanned<Expr>,
    /// The quantity must stay strictly above this.
    #[serde(default)]
    pub above: Option<f64>,
    /// The quantity must stay strictly below this.
    #[serde(default)]
    pub below: Option<f64>,
}

/// The initial state of a joint graph.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialEntry {
    /// Time (default 0).
    #[serde(default)]
    pub t: f64,
    /// The coordinates, in the graph's order.
    pub q: Vec<f64>,
    /// Their rates (default 0).
    #[serde(default)]
    pub qdot: Option<Vec<f64>>,
}
