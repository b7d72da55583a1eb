//! The minimal integrated state.

/// Time, generalized coordinates and generalized velocities: `(t, q, q̇)`.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Time `t` (s).
    pub t: f64,
    /// Generalized coordinates `q` (n).
    pub q: Vec<f64>,
    /// Generalized velocities `q̇` (n).
    pub qdot: Vec<f64>,
}

impl State {
    /// A state from its parts.
    pub fn new(t: f64, q: impl Into<Vec<f64>>, qdot: impl Into<Vec<f64>>) -> Self {
        Self { t, q: q.into(), qdot: qdot.into() }
    }

    /// Number of coordinates.
    pub fn dof(&self) -> usize {
        self.q.len()
    }
}
