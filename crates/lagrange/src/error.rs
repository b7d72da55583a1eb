//! Typed errors: bad input, singular configurations, diverging integrations — [`Error`] (also
//! at the crate root) and the details some of its variants carry ([`Stage`], [`Derived`]).

use crate::scalar::Scalar;
use std::fmt;

/// The stage of an evaluation at which a non-finite value appeared
/// (MuJoCo's `mj_checkPos` / `mj_checkVel` / `mj_checkAcc`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// The state handed to the engine (`t`, `q`).
    State,
    /// The velocities `q̇` handed to the engine (the message shows `q`, which is finite).
    Velocities,
    /// Body poses and their derivatives.
    Kinematics,
    /// The user potential or its gradient.
    Potential,
    /// The non-conservative generalized forces.
    GeneralizedForce,
    /// The forces and torques applied at points of bodies
    /// ([`Mechanism::applied_forces`](crate::Mechanism::applied_forces)).
    AppliedForce,
    /// The Lagrangian or its derivatives (raw-Lagrangian path, variational integrator).
    Lagrangian,
    /// The solved accelerations.
    Accelerations,
    /// The derivatives of the accelerations, `∂q̈/∂(q, q̇)` (implicit integrators).
    Jacobian,
    /// The constraints among the coordinates, their Jacobian or convective terms
    /// ([`Mechanism::constraints`](crate::Mechanism::constraints)).
    Constraints,
}

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Stage::State => "state",
            Stage::Velocities => "velocities q̇",
            Stage::Kinematics => "kinematics",
            Stage::Potential => "potential",
            Stage::GeneralizedForce => "generalized force",
            Stage::AppliedForce => "applied force",
            Stage::Lagrangian => "Lagrangian",
            Stage::Accelerations => "accelerations",
            Stage::Jacobian => "acceleration Jacobian",
            Stage::Constraints => "constraints",
        })
    }
}

/// Everything that can go wrong, as data.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Error {
    /// A physical or numerical parameter is out of its domain.
    #[error("invalid parameter `{name}` = {}: {why}", compact(.value))]
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
    /// The mass matrix (or `∂²L/∂q̇²`) is singular at this configuration (positive
    /// semidefinite, a pivot of zero to within 1e-12 of its diagonal entry).
    #[error(
        "singular mass matrix at t = {}, q = {}: pivot {} for coordinate `{coordinate}` \
         (the coordinates are not independent here, or this coordinate moves no mass)",
        compact(.t),
        compact_all(.q),
        compact(.pivot)
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
    /// The mass matrix (or `∂²L/∂q̇²`) is indefinite or negative definite at this
    /// configuration: the kinetic energy is negative along some velocity.
    ///
    /// A negative-definite raw Lagrangian is refused too, although `L` and `−L` have the same
    /// equations of motion: `−L` flips the signs of the momenta `p = ∂L/∂q̇` and of the energy
    /// function `h` that the engine reports, and writing `V − T` for `T − V` is a sign slip far
    /// more often than a choice. [`RawModel::new`](crate::RawModel::new) checks it at probe
    /// states; write `L = T − V` with `T` positive definite in `q̇`.
    #[error(
        "indefinite mass matrix at t = {}, q = {}: pivot {} for coordinate `{coordinate}` (its diagonal \
         entry is {}): the kinetic energy is not positive along it — check the signs of the \
         velocity terms",
        compact(.t),
        compact_all(.q),
        compact(.pivot),
        compact(.diagonal)
    )]
    IndefiniteMassMatrix {
        /// Time.
        t: f64,
        /// Configuration.
        q: Vec<f64>,
        /// The coordinate whose pivot is negative.
        coordinate: String,
        /// The pivot (`D_j` of the LDLᵀ factorization).
        pivot: f64,
        /// The coordinate's diagonal entry.
        diagonal: f64,
    },
    /// A stage of an evaluation produced NaN or infinity.
    #[error("non-finite {stage} at t = {}, q = {}", compact(.t), compact_all(.q))]
    NonFinite {
        /// Where it appeared.
        stage: Stage,
        /// Time.
        t: f64,
        /// Configuration.
        q: Vec<f64>,
    },
    /// An integration blew up.
    #[error("integration diverged at t = {} after {step} steps: {quantity}", compact(.t))]
    Diverged {
        /// Time of the last finite state.
        t: f64,
        /// Number of steps taken.
        step: usize,
        /// Which quantity became non-finite or exceeded its bound.
        quantity: String,
    },
    /// The state lies outside the region where the mechanism's model holds, as the mechanism
    /// declares it ([`Mechanism::admissible`](crate::Mechanism::admissible)): a polar radius
    /// through zero, a mass pulled through its pulley, a block past the end of its incline.
    /// The integrators check the initial state and the state after every accepted step, so
    /// the boundary was crossed between `inside_until` and `t`.
    #[error(
        "{quantity} = {} is outside the admissible region {bound} at t = {} s{}",
        compact(.value),
        compact(.t),
        InsideUntil(*.inside_until)
    )]
    Inadmissible {
        /// Time of the state.
        t: f64,
        /// The last time at which the run found the state inside (the previous accepted step
        /// or sample): the boundary was crossed in `(inside_until, t]`. `None` for a single
        /// state or an initial state outside.
        inside_until: Option<f64>,
        /// The bounded quantity, as the mechanism names it (`r`, `rope length l − x`).
        quantity: String,
        /// The bound that failed, written out (`r > 0`).
        bound: String,
        /// The quantity's value at the state.
        value: f64,
        /// The limit of the bound.
        limit: f64,
    },
    /// A step size or tolerance is not usable.
    #[error("invalid {what} = {}: {why}", compact(.value))]
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
        "step size underflow at t = {}: h = {} cannot meet the tolerance \
         (the problem may be stiff or singular here)",
        compact(.t),
        compact(.h)
    )]
    StepSizeUnderflow {
        /// Time.
        t: f64,
        /// The rejected step.
        h: f64,
    },
    /// The adaptive integrator needed more steps than allowed.
    #[error("too many steps: {steps} steps reached t = {} of {}", compact(.t), compact(.t_end))]
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
        "the problem looks stiff at t = {} (the explicit step fell to h = {}): use the implicit integrator \
         (Method::Sdirk4 / --integrator sdirk4)",
        compact(.t),
        compact(.h)
    )]
    Stiff {
        /// Time reached.
        t: f64,
        /// The last step tried.
        h: f64,
    },
    /// Newton's method in an implicit integrator did not converge. (A value that stops being
    /// finite inside a Newton iteration is an [`Error::Diverged`] naming it instead.)
    #[error("Newton iteration did not converge at t = {} ({iterations} iterations, {})", compact(.t), NewtonResidual(*.residual))]
    NewtonFailed {
        /// Time at the start of the step.
        t: f64,
        /// Iterations done.
        iterations: usize,
        /// Final residual norm (finite), or `None` when the Newton matrix was singular before a
        /// residual was evaluated.
        residual: Option<f64>,
    },
    /// [`Mechanism::poses`](crate::Mechanism::poses) left a component of a body's pose
    /// unwritten (or wrote NaN) at a probe state: the engine fills the poses with NaN first,
    /// so that a forgotten body is an error instead of a body at the origin.
    #[error(
        "the poses leave the {component} of body `{body}` NaN at t = {}, q = {} \
         (unwritten, or written as NaN): every body's pose must be written, finite",
        compact(.t),
        compact_all(.q)
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
    /// An exact derivative (by automatic differentiation) of a body's pose or of a raw
    /// Lagrangian disagrees with central differences at a probe state: the user's function
    /// reads the real part of the time, a coordinate or a velocity (`t.re()`), which drops its
    /// derivative. [`Model::new`](crate::Model::new) and [`RawModel::new`](crate::RawModel::new)
    /// check it.
    #[error(
        "{of}: ∂/∂{variable} = {} by automatic differentiation but {} by finite differences — \
         {} read `{variable}.re()`? Use the scalar argument itself",
        compact(.exact),
        compact(.finite_difference),
        .of.reader()
    )]
    LostDerivative {
        /// What was differentiated: a component of a body's pose, or the Lagrangian.
        of: Derived,
        /// The variable: a coordinate's name, `t`, or (raw Lagrangian) a coordinate's name
        /// with a dot for its velocity (`ẋ`).
        variable: String,
        /// The derivative by automatic differentiation.
        exact: f64,
        /// The central difference.
        finite_difference: f64,
    },
    /// Constraints among the coordinates that contradict each other here: a row of
    /// `G q̈ = −γ` that depends on the rows before it but asks for a different `q̈`.
    #[error(
        "inconsistent constraints at t = {}, q = {}: {} cannot all hold (residual {} after elimination)",
        compact(.t), compact_all(.q), .constraints.join(", "), compact(.residual)
    )]
    InconsistentConstraints {
        /// Time.
        t: f64,
        /// Coordinates.
        q: Vec<f64>,
        /// The names of the contradicting constraints ([`Description::constraint_name`](crate::Description::constraint_name)).
        constraints: Vec<String>,
        /// The dependent row's residual after elimination.
        residual: f64,
    },
    /// A consistent state could not be found: Gauss–Newton on `Φ(t, q) = 0` (with the held
    /// coordinates fixed) did not converge, e.g. a four-bar whose links cannot close.
    #[error(
        "cannot assemble at t = {}: {} = {} after {iterations} Gauss–Newton iterations (the constraints cannot be met from this guess: links that cannot close, coordinates held where no closed configuration has them, or a guess outside the basin)",
        compact(.t), .constraint, compact(.residual)
    )]
    AssemblyFailed {
        /// Time.
        t: f64,
        /// The constraint with the largest residual.
        constraint: String,
        /// Its residual.
        residual: f64,
        /// Iterations taken.
        iterations: usize,
    },
    /// A joint graph that is not a mechanism (`lagrange::graph`), naming the element at fault.
    #[error("invalid joint graph: {element} {why}")]
    InvalidGraph {
        /// The body, joint, coupling or force element (`body `arm``).
        element: String,
        /// What is wrong with it.
        why: String,
    },
    /// The run's sink asked it to stop ([`Sink::keep_going`](crate::integrate::Sink::keep_going)):
    /// a deadline or an interrupt, not a failure of the integration.
    #[error("stopped by its caller at t = {} after {steps} steps", compact(.t))]
    Stopped {
        /// Time reached.
        t: f64,
        /// Steps taken.
        steps: usize,
    },
    /// A scene registered under an id that is taken (`lagrange_scenes::register`).
    #[error("a scene with id `{id}` exists already: register it under another id")]
    Registered {
        /// The id.
        id: String,
    },
    /// No configuration at rest near the one given ([`normal_modes`](crate::modes::normal_modes)):
    /// a mechanism that cannot rest there (Kepler's problem, a block sliding down a wedge) or
    /// whose equations move its rest with time (a driven pendulum).
    #[error("no equilibrium near q = {}: {why}", compact_all(.q))]
    NoEquilibrium {
        /// The configuration the search started from.
        q: Vec<f64>,
        /// Why.
        why: String,
    },
    /// A mechanism declared a property that its functions contradict.
    #[error("inconsistent mechanism: {what}")]
    Inconsistent {
        /// What is contradicted.
        what: String,
    },
}

/// What an [`Error::LostDerivative`] was found in.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Derived {
    /// A component of a body's pose ([`Mechanism::poses`](crate::Mechanism::poses)).
    Pose {
        /// The body.
        body: String,
        /// `x`, `y` or `angle`.
        component: &'static str,
    },
    /// A raw Lagrangian ([`Lagrangian::lagrangian`](crate::Lagrangian::lagrangian)).
    Lagrangian,
}

impl Derived {
    /// Whose code the message asks about.
    fn reader(&self) -> &'static str {
        match self {
            Derived::Pose { .. } => "do the poses",
            Derived::Lagrangian => "does the Lagrangian",
        }
    }
}

impl fmt::Display for Derived {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Derived::Pose { body, component } => write!(f, "the {component} of body `{body}`"),
            Derived::Lagrangian => f.write_str("the Lagrangian"),
        }
    }
}

/// Check that every entry is finite (its real part, for dual numbers).
pub(crate) fn all_finite<S: Scalar>(values: &[S]) -> bool {
    values.iter().all(|v| v.re().is_finite())
}

/// The [`Error::NonFinite`] of `stage` at `(t, q)`.
pub(crate) fn non_finite<S: Scalar>(stage: Stage, t: S, q: &[S]) -> Error {
    Error::NonFinite { stage, t: t.re(), q: q.iter().map(|v| v.re()).collect() }
}

/// A failed pivot of an LDLᵀ factorization (`linalg::ldlt_factor`) at `(t, q)`, for the
/// coordinate named `coordinate`: [`Error::IndefiniteMassMatrix`] when the pivot or the diagonal
/// entry is negative beyond round-off, otherwise [`Error::SingularMassMatrix`] (pivot relative
/// to the diagonal entry, or the pivot itself where that ratio is not finite).
pub(crate) fn bad_pivot<S: Scalar>(t: S, q: &[S], coordinate: &str, pivot: f64, diagonal: f64) -> Error {
    let (t, q, coordinate) = (t.re(), q.iter().map(|v| v.re()).collect(), coordinate.to_string());
    let ratio = pivot / diagonal;
    if diagonal < 0.0 || (diagonal > 0.0 && ratio < -crate::linalg::PIVOT_RTOL) {
        Error::IndefiniteMassMatrix { t, q, coordinate, pivot, diagonal }
    } else {
        Error::SingularMassMatrix { t, q, coordinate, pivot: if ratio.is_finite() { ratio } else { pivot } }
    }
}

/// A value for a message, in its shortest exact form: plain between 1e-4 and 1e6, in
/// scientific notation outside (`1e-16`, not `0.0000000000000001`).
pub(crate) struct Compact(f64);

impl fmt::Display for Compact {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0;
        if v == 0.0 || !v.is_finite() || (1e-4..1e6).contains(&v.abs()) { write!(f, "{v}") } else { write!(f, "{v:e}") }
    }
}

/// Where an [`Error::Inadmissible`] run was last inside, for its message.
struct InsideUntil(Option<f64>);

impl fmt::Display for InsideUntil {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(t) => write!(f, " (inside at t = {} s)", Compact(t)),
            None => Ok(()),
        }
    }
}

/// The residual of an [`Error::NewtonFailed`] for its message.
struct NewtonResidual(Option<f64>);

impl fmt::Display for NewtonResidual {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(r) if r.is_finite() => write!(f, "residual {}", Compact(r)),
            // Never constructed (a non-finite value inside Newton is `Diverged`), never printed.
            Some(_) => f.write_str("a non-finite residual"),
            None => f.write_str("the Newton matrix is singular"),
        }
    }
}

pub(crate) fn compact(v: &f64) -> Compact {
    Compact(*v)
}

/// A list of values for a message, each [`Compact`].
struct CompactAll<'a>(&'a [f64]);

impl fmt::Display for CompactAll<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("[")?;
        for (i, v) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            write!(f, "{}", Compact(*v))?;
        }
        f.write_str("]")
    }
}

fn compact_all(v: &[f64]) -> CompactAll<'_> {
    CompactAll(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_print_compactly() {
        assert_eq!(Compact(1e-16).to_string(), "1e-16");
        assert_eq!(Compact(0.25).to_string(), "0.25");
        assert_eq!(Compact(-3.0).to_string(), "-3");
        assert_eq!(Compact(1.5e7).to_string(), "1.5e7");
        assert_eq!(CompactAll(&[0.0, 1e-16, 2.5]).to_string(), "[0, 1e-16, 2.5]");
        let error = Error::NonFinite { stage: Stage::State, t: 1e-16, q: vec![0.1, 1e-20] };
        assert_eq!(error.to_string(), "non-finite state at t = 1e-16, q = [0.1, 1e-20]");
    }

    #[test]
    fn a_newton_failure_prints_its_residual_or_a_singular_matrix_never_nan() {
        let failed = Error::NewtonFailed { t: 4.15, iterations: 50, residual: Some(5.5e-17) };
        assert_eq!(
            failed.to_string(),
            "Newton iteration did not converge at t = 4.15 (50 iterations, residual 5.5e-17)"
        );
        let singular = Error::NewtonFailed { t: 0.5, iterations: 0, residual: None };
        assert_eq!(
            singular.to_string(),
            "Newton iteration did not converge at t = 0.5 (0 iterations, the Newton matrix is singular)"
        );
        let never = Error::NewtonFailed { t: 0.5, iterations: 3, residual: Some(f64::NAN) }.to_string();
        assert!(!never.contains("NaN"), "{never}");
    }

    #[test]
    fn a_negative_pivot_is_indefinite_and_a_vanishing_one_singular() {
        // Negative definite: the first pivot is its own (negative) diagonal entry.
        let e = bad_pivot(0.0, &[1.0], "x", -1.0, -1.0);
        assert!(matches!(e, Error::IndefiniteMassMatrix { .. }), "{e}");
        assert!(e.to_string().contains("indefinite") && !e.to_string().contains("not independent"), "{e}");
        // Indefinite: a positive diagonal entry, a negative pivot.
        assert!(matches!(bad_pivot(0.0, &[1.0], "x", -0.5, 2.0), Error::IndefiniteMassMatrix { .. }));
        // Singular: a pivot zero to round-off, or a coordinate that moves no mass.
        let e = bad_pivot(0.0, &[1.0], "x", -1e-17, 1.0);
        assert!(matches!(e, Error::SingularMassMatrix { pivot, .. } if pivot == -1e-17), "{e}");
        assert!(matches!(bad_pivot(0.0, &[1.0], "x", 0.0, 0.0), Error::SingularMassMatrix { pivot: 0.0, .. }));
    }
}
