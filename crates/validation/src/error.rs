//! The validation library's errors: what can stop a report, a comparison or a stability case
//! from being set up or measured (a failing *run* is recorded in the report, not an error).

use lagrange_maximal::BuildError;

/// An error of the validation library.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Error {
    /// No scene is registered under this id.
    #[error("unknown scene `{0}`; known scenes: {known}", known = lagrange_scenes::ids().join(", "))]
    UnknownScene(String),
    /// The engine refused or failed (invalid parameters or state, a singular mass matrix, a
    /// non-finite value, a diverging run).
    #[error(transparent)]
    Engine(#[from] lagrange::Error),
    /// An engine error, with the scene it occurred on.
    #[error("{scene}: {source}")]
    Scene {
        /// The scene id.
        scene: String,
        /// The engine's error.
        source: lagrange::Error,
    },
    /// The reference trajectory of a scene could not be computed.
    #[error("{scene}: reference: {source}")]
    Reference {
        /// The scene id.
        scene: String,
        /// The engine's error.
        source: lagrange::Error,
    },
    /// A maximal engine could not build or run the scene.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// The report's horizon (`--t-end`) is not a positive multiple of the sample interval.
    #[error("--t-end must be a positive multiple of {interval} s, got {horizon}")]
    HorizonNotOnGrid {
        /// The requested horizon (s).
        horizon: f64,
        /// The sample interval (s).
        interval: f64,
    },
    /// The report's horizon is longer than a report's sample count allows.
    #[error("--t-end {horizon} s is too long for a report (at most {limit} s)")]
    HorizonTooLong {
        /// The requested horizon (s).
        horizon: f64,
        /// The longest horizon (s).
        limit: f64,
    },
    /// A method family was paired with a setting it does not take (a bug in the plan).
    #[error("{family} has no setting {setting}")]
    NoSuchSetting {
        /// The family's name.
        family: &'static str,
        /// The setting, described.
        setting: String,
    },
    /// A run returned non-finite errors instead of failing.
    #[error("the run blew up (non-finite error)")]
    NonFinite,
    /// A result the scene or the run should have produced is missing (`no closed form`,
    /// `empty run`, `unbound orbit`): a bug in a stability case's setup.
    #[error("{0}")]
    Missing(&'static str),
    /// A scene whose coordinates place no bodies (a raw Lagrangian without a maximal
    /// description) cannot be drawn.
    #[error("{scene} cannot be drawn: its coordinates place no bodies (a raw Lagrangian)")]
    Undrawable {
        /// The scene id.
        scene: String,
    },
    /// A normal mode that cannot be played: no such mode, or one that does not oscillate.
    #[error("mode {index}: {why}")]
    Mode {
        /// The mode's index (0: the lowest `ω²`).
        index: usize,
        /// Why, in one sentence.
        why: String,
    },
    /// A stability case could not be set up.
    #[error("stability case {case}: {source}")]
    Case {
        /// The case id.
        case: &'static str,
        /// What went wrong.
        source: Box<Error>,
    },
}

impl Error {
    /// An engine error on `scene`.
    pub fn scene(scene: &str, source: lagrange::Error) -> Error {
        Error::Scene { scene: scene.to_string(), source }
    }
}

/// The registered scene `id`: the one place the validation library (and through it the tests
/// and the command line) looks a scene up.
///
/// # Errors
/// [`Error::UnknownScene`].
pub fn scene(id: &str) -> Result<&'static dyn lagrange_scenes::Scene, Error> {
    lagrange_scenes::find(id).ok_or_else(|| Error::UnknownScene(id.to_string()))
}
