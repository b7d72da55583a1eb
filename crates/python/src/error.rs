//! Rust errors as Python exceptions: every failure is a [`Failure`] — the class of
//! `lagrange.errors` it raises and the message the command line prints for it — converted to
//! the Python exception at the boundary. No panic crosses it: the bindings return every error.

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyType;

/// A failure on its way to Python: the exception class (by name, in `lagrange.errors`) and the
/// message.
#[derive(Debug)]
pub struct Failure {
    /// The class: `ArgumentError`, `FileError`, `GraphError`, `SingularMassMatrixError`,
    /// `NonFiniteError`, `ConstraintError`, `IntegrationError`, `EquilibriumError`,
    /// `UnhealthyRunError`, `EngineError`.
    pub class: &'static str,
    /// What the command line prints for the same failure.
    pub message: String,
}

impl Failure {
    /// A bad argument (the command line's usage errors).
    pub fn argument(message: impl Into<String>) -> Self {
        Self { class: "ArgumentError", message: message.into() }
    }
}

/// The class of an engine error: what kind of failure it is, as Python users catch it.
fn class_of(error: &lagrange::Error) -> &'static str {
    use lagrange::Error as E;
    match error {
        E::InvalidParameter { .. } | E::DimensionMismatch { .. } | E::InvalidSetting { .. } | E::Registered { .. } => {
            "ArgumentError"
        }
        E::InvalidGraph { .. } => "GraphError",
        E::SingularMassMatrix { .. } | E::IndefiniteMassMatrix { .. } => "SingularMassMatrixError",
        E::NonFinite { .. } => "NonFiniteError",
        E::InconsistentConstraints { .. }
        | E::AssemblyFailed { .. }
        | E::Inconsistent { .. }
        | E::Inadmissible { .. } => "ConstraintError",
        E::Diverged { .. }
        | E::StepSizeUnderflow { .. }
        | E::TooManySteps { .. }
        | E::Stiff { .. }
        | E::NewtonFailed { .. }
        | E::Stopped { .. } => "IntegrationError",
        E::NoEquilibrium { .. } => "EquilibriumError",
        _ => "EngineError",
    }
}

impl From<lagrange::Error> for Failure {
    fn from(error: lagrange::Error) -> Self {
        Self { class: class_of(&error), message: error.to_string() }
    }
}

impl From<lagrange_validation::Error> for Failure {
    fn from(error: lagrange_validation::Error) -> Self {
        use lagrange_validation::Error as V;
        let class = match &error {
            V::UnknownScene(_) | V::HorizonNotOnGrid { .. } | V::HorizonTooLong { .. } => "ArgumentError",
            V::Engine(e) | V::Reference { source: e, .. } => class_of(e),
            V::Build(lagrange_maximal::BuildError::Invalid(e)) => class_of(e),
            _ => "EngineError",
        };
        Self { class, message: error.to_string() }
    }
}

impl From<lagrange_file::FileError> for Failure {
    fn from(error: lagrange_file::FileError) -> Self {
        use lagrange_file::FileError as F;
        let class = match &error {
            F::Registered(e) => class_of(e),
            _ => "FileError",
        };
        // Drawn on the file's text, as the command line draws it (without its `error: `).
        let rendered = error.render();
        let message = rendered.trim_end().strip_prefix("error: ").unwrap_or(rendered.trim_end()).to_string();
        Self { class, message }
    }
}

impl From<lagrange_validation::start::HoldError> for Failure {
    fn from(error: lagrange_validation::start::HoldError) -> Self {
        use lagrange_validation::start::HoldError;
        match error {
            HoldError::Refused(why) => Failure::argument(format!("hold: {why}")),
            HoldError::Engine(error) => error.into(),
        }
    }
}

impl From<serde_json::Error> for Failure {
    fn from(error: serde_json::Error) -> Self {
        Self { class: "EngineError", message: format!("cannot serialize the result as JSON: {error}") }
    }
}

impl From<Failure> for PyErr {
    fn from(failure: Failure) -> PyErr {
        Python::attach(|py| {
            let class = py
                .import("lagrange.errors")
                .and_then(|module| module.getattr(failure.class))
                .and_then(|class| class.cast_into::<PyType>().map_err(PyErr::from));
            match class {
                Ok(class) => PyErr::from_type(class, failure.message),
                // The package's Python side is missing: the message still reaches the user.
                Err(_) => PyRuntimeError::new_err(format!("{}: {}", failure.class, failure.message)),
            }
        })
    }
}

/// The bindings' result.
pub type Result<T> = std::result::Result<T, Failure>;
