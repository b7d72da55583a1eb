//! Typed errors: bad input, singular configurations, diverging integrations.

use crate::scalar::Scalar;
use std::fmt;

/// The stage of an evaluation at which a non-finite value appeared
/// (MuJoCo's `mj_checkPos` / `mj_checkVel` / `mj_checkAcc`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// The state handed to the engine (`t`, `q`, `q̇`).
    State,
    /// Body poses and their derivatives.
    Kinematics,
    /// The user potential or its gradient.
    Potential,
    /// The non-conservative generalized forces.
    GeneralizedForce,
    /// The Lagrangian or its derivatives (raw-Lagrangian path, variational integrator).
    Lagrangian,
    /// The solved accelerations.
    Accelerations,
    /// The derivatives of the accelerations, `∂q̈/∂(q, q̇)` (implicit integrators).
    Jacobian,
}

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Stage::State => "state",
            Stage::Kinematics => "kinematics",
            Stage::Potential => "potential",
            Stage::GeneralizedForce => "generalized force",
            Stage::Lagrangian => "Lagrangian",
            Stage::Accelerations => "accelerations",
            Stage::Jacobian => "acceleration Jacobian",
        })
    }
}

/// Everything that can go wrong, as data.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Error {
    /// A physical or numerical parameter is out of its domain.
    #[error("invalid parameter `{name}` = {value}: {why}")]
    InvalidParameter {
        /// Name of the parameter.
        name: String,
        /// The rejected value.
        value: f64,
        /// What it must be.
        why: String,
    },
    /// A slice has the wrong length.
    #[error("dimension mismatch for {what}: expected {expected}, got {got}")]
    DimensionMismatch {
        /// Which input.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Length received.
        got: usize,
    },
    /// The mass matrix (or `∂²L/∂q̇²`) is singular or indefinite at this configuration.
    #[error(
        "singular mass matrix at t = {t}, q = {q:?}: pivot {pivot:e} for coordinate `{coordinate}` \
         (the coordinates are not independent here, or this coordinate moves no mass)"
    )]
    SingularMassMatrix {
        /// Time.
        t: f64,
        /// Configuration.
        q: Vec<f64>,
        /// The coordinate whose pivot vanished.
        coordinate: String,
        /// The pivot, relative to the coordinate's own diagonal entry.
        pivot: f64,
    },
    /// A stage of an evaluation produced NaN or infinity.
    #[error("non-finite {stage} at t = {t}, q = {q:?}")]
    NonFinite {
        /// Where it appeared.
        stage: Stage,
        /// Time.
        t: f64,
        /// Configuration.
        q: Vec<f64>,
    },
    /// An integration blew up.
    #[error("integration diverged at t = {t} after {step} steps: {quantity}")]
    Diverged {
        /// Time of the last finite state.
        t: f64,
        /// Number of steps taken.
        step: usize,
        /// Which quantity became non-finite or exceeded its bound.
        quantity: String,
    },
    /// A step size or tolerance is not usable.
    #[error("invalid {what} = {value}: {why}")]
    InvalidSetting {
        /// `step`, `tolerance`, `horizon`, …
        what: &'static str,
        /// The value.
        value: f64,
        /// What it must be.
        why: &'static str,
    },
    /// The adaptive integrator's step collapsed.
    #[error(
        "step size underflow at t = {t}: h = {h:e} cannot meet the tolerance \
         (the problem may be stiff or singular here)"
    )]
    StepSizeUnderflow {
        /// Time.
        t: f64,
        /// The rejected step.
        h: f64,
    },
    /// The adaptive integrator needed more steps than allowed.
    #[error("too many steps: {steps} steps reached t = {t} of {t_end}")]
    TooManySteps {
        /// Steps taken.
        steps: usize,
        /// Time reached.
        t: f64,
        /// Requested end.
        t_end: f64,
    },
    /// The explicit adaptive integrator failed (its step collapsed, or it ran out of steps)
    /// after its stiffness test had fired: the problem is stiff, and an L-stable implicit
    /// method takes steps the explicit one cannot.
    #[error(
        "the problem looks stiff at t = {t} (the explicit step fell to h = {h:e}): use the implicit integrator \
         (Method::Implicit / --integrator implicit)"
    )]
    Stiff {
        /// Time reached.
        t: f64,
        /// The last step tried.
        h: f64,
    },
    /// Newton's method in an implicit integrator did not converge.
    #[error("Newton iteration did not converge at t = {t} ({iterations} iterations, residual {residual:e})")]
    NewtonFailed {
        /// Time at the start of the step.
        t: f64,
        /// Iterations done.
        iterations: usize,
        /// Final residual norm.
        residual: f64,
    },
    /// [`Mechanism::poses`](crate::Mechanism::poses) left a component of a body's pose
    /// unwritten (or wrote NaN) at a probe state: the engine fills the poses with NaN first,
    /// so that a forgotten body is an error instead of a body at the origin.
    #[error(
        "the poses do not write the {component} of body `{body}` at t = {t}, q = {q:?} \
         (it is still NaN): every body's pose must be written"
    )]
    UnwrittenPose {
        /// The body.
        body: String,
        /// `x`, `y` or `angle`.
        component: &'static str,
        /// Time of the probe state.
        t: f64,
        /// Configuration of the probe state.
        q: Vec<f64>,
    },
    /// An exact derivative of a body's pose (by automatic differentiation) disagrees with
    /// central differences of the poses: [`Mechanism::poses`](crate::Mechanism::poses) reads
    /// the real part of the time or of a coordinate (`t.re()`), which drops its derivative.
    #[error(
        "the {component} of body `{body}`: ∂/∂{variable} = {exact} by automatic differentiation but \
         {finite_difference} by finite differences — do the poses read `{variable}.re()`? Use the \
         scalar argument itself"
    )]
    LostDerivative {
        /// The body.
        body: String,
        /// `x`, `y` or `angle`.
        component: &'static str,
        /// The coordinate's name, or `t`.
        variable: String,
        /// The derivative by automatic differentiation.
        exact: f64,
        /// The central difference.
        finite_difference: f64,
    },
    /// A mechanism declared a property that its functions contradict.
    #[error("inconsistent mechanism: {what}")]
    Inconsistent {
        /// What is contradicted.
        what: String,
    },
}

/// Check that every entry is finite (its real part, for dual numbers).
pub(crate) fn all_finite<S: Scalar>(values: &[S]) -> bool {
    values.iter().all(|v| v.re().is_finite())
}

/// The [`Error::NonFinite`] of `stage` at `(t, q)`.
pub(crate) fn non_finite<S: Scalar>(stage: Stage, t: S, q: &[S]) -> Error {
    Error::NonFinite { stage, t: t.re(), q: q.iter().map(|v| v.re()).collect() }
}
