//! Reading a scene file: text → TOML → schema → checked scene, every failure a [`Diagnostic`].

use crate::coordinates::{CoordinateForm, Reader};
use crate::diagnostic::Diagnostic;
use crate::scene::{FileScene, leak};
use crate::schema::{self, SceneFile};
use lagrange::Error;
use lagrange_scenes::{Domain, ParamSpec, Scene};
use std::ops::Range;
use std::path::Path;

/// Why a scene file could not be used.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    /// The file could not be read.
    #[error("cannot read `{path}`: {source}")]
    Read {
        /// The path as given.
        path: String,
        /// What the system said.
        source: std::io::Error,
    },
    /// The file is not a valid scene: where and why.
    #[error("{0}")]
    Invalid(Box<Diagnostic>),
    /// A scene with the file's id is known already (a built-in scene, or a file loaded before).
    #[error("{0}")]
    Registered(Error),
    /// A coordinates-form file was asked for and the file is a joint graph.
    #[error("`{path}` is a joint-graph file, not the coordinates form")]
    NotCoordinates {
        /// The path as given.
        path: String,
    },
    /// The file's equations cannot be printed.
    #[error("cannot print the equations of `{path}`: {why}")]
    NoEquations {
        /// The path as given.
        path: String,
        /// Why.
        why: String,
    },
}

impl From<Diagnostic> for FileError {
    fn from(d: Diagnostic) -> Self {
        FileError::Invalid(Box::new(d))
    }
}

impl FileError {
    /// The error as the command line prints it: a file's error drawn on its source, as rustc
    /// draws one.
    pub fn render(&self) -> String {
        match self {
            FileError::Invalid(d) => d.render(),
            other => format!("error: {other}\n"),
        }
    }
}

/// Read the scene file at `path`.
///
/// # Errors
/// [`FileError::Read`] if it cannot be read, [`FileError::Invalid`] with the place and reason
/// if it is not a valid scene (syntax, unknown names, a mechanism the engine refuses at its
/// initial state).
pub fn load(path: impl AsRef<Path>) -> Result<Box<dyn Scene>, FileError> {
    let path = path.as_ref();
    let shown = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| FileError::Read { path: shown.clone(), source })?;
    let source = match String::from_utf8(bytes) {
        Ok(text) => text,
        Err(e) => {
            let at = e.utf8_error().valid_up_to();
            let text = String::from_utf8_lossy(e.as_bytes()).into_owned();
            return Err(Diagnostic::new(&shown, &text, at..at + 1, "not a text file: the bytes are not UTF-8")
                .label("first byte that is not UTF-8")
                .with_hint(Some("a scene file is TOML text (docs/files.md)".into()))
                .into());
        }
    };
    Ok(parse(&shown, &source)?)
}

/// Read a scene file and make its id known to [`lagrange_scenes::find`], so that everything
/// that takes a scene id takes it.
///
/// # Errors
/// As [`load`]; [`FileError::Registered`] if a scene with the same id is known already.
pub fn register(path: impl AsRef<Path>) -> Result<&'static dyn Scene, FileError> {
    let scene = load(path)?;
    lagrange_scenes::register(BoxedScene(scene)).map_err(FileError::Registered)
}

/// [`register`] for the text of a scene file already read (`path` names it in messages): how a
/// scene file travels to another process (the Python package's sweeps send the text, not the
/// path).
///
/// # Errors
/// As [`parse`]; [`FileError::Registered`] if a scene with the same id is known already.
pub fn register_source(path: &str, source: &str) -> Result<&'static dyn Scene, FileError> {
    let scene = parse(path, source)?;
    lagrange_scenes::register(BoxedScene(scene)).map_err(FileError::Registered)
}

/// A boxed scene as a scene (what [`lagrange_scenes::register`] keeps).
struct BoxedScene(Box<dyn Scene>);

macro_rules! forward {
    ($($name:ident($($arg:ident: $ty:ty),*) -> $out:ty;)*) => {
        $(fn $name(&self, $($arg: $ty),*) -> $out { self.0.$name($($arg),*) })*
    };
}

impl Scene for BoxedScene {
    forward! {
        id() -> &'static str;
        title() -> &'static str;
        reference() -> &'static str;
        horizon() -> Option<f64>;
        params() -> &'static [ParamSpec];
        coordinates(params: &lagrange_scenes::Params) -> Result<Vec<lagrange::Coordinate>, Error>;
        default_state(params: &lagrange_scenes::Params) -> Result<lagrange::State, Error>;
        build(params: &lagrange_scenes::Params) -> Result<Box<dyn lagrange::System>, Error>;
        closed_form_accelerations(params: &lagrange_scenes::Params, t: f64, q: &[f64], qdot: &[f64]) -> Result<Option<Vec<f64>>, Error>;
        exact_solution(params: &lagrange_scenes::Params, initial: &lagrange::State, t: f64) -> Result<Option<lagrange::State>, Error>;
        conserved_quantities(params: &lagrange_scenes::Params) -> Result<Vec<lagrange_scenes::Conserved>, Error>;
        joint_graph(params: &lagrange_scenes::Params) -> Result<Option<lagrange::graph::JointGraph>, Error>;
        rapier_deviations(multibody: bool) -> &'static [lagrange_scenes::RapierDeviation];
        body_poses(params: &lagrange_scenes::Params, states: &[(f64, &[f64])]) -> Result<Option<Vec<Vec<[f64; 3]>>>, Error>;
    }
}

/// Read a scene from `source`, the text of the file at `path` (used in messages only).
///
/// # Errors
/// A [`Diagnostic`] with the place and reason if the text is not a valid scene.
pub fn parse(path: &str, source: &str) -> Result<Box<dyn Scene>, Diagnostic> {
    Ok(match read(path, source, true)? {
        Parsed::Coordinates(scene) => scene,
        Parsed::Graph(scene) => scene,
    })
}

/// A file read: a coordinates-form scene (whose expressions [`eom`] can print), or a joint graph.
pub(crate) enum Parsed {
    Coordinates(Box<FileScene>),
    Graph(Box<dyn Scene>),
}

/// The equations of the scene file at `path`, derived symbolically and written as a textbook
/// writes them ([`Equations`](crate::symbolic::Equations)); for a joint-graph file, those of its
/// coordinates form ([`coordinates_file`](crate::coordinates_file)), with the body poses its
/// coordinates give.
///
/// # Errors
/// As [`load`]; [`FileError::NoEquations`] for an expression the symbolic derivation does not
/// take (`abs`, a variable exponent, a coefficient beyond exact 128-bit rationals).
pub fn eom(path: impl AsRef<Path>) -> Result<crate::symbolic::Equations, FileError> {
    let path = path.as_ref();
    let shown = path.display().to_string();
    let source = std::fs::read_to_string(path).map_err(|source| FileError::Read { path: shown.clone(), source })?;
    eom_source(&shown, &source)
}

/// [`eom`] for the text of a scene file already read (`path` names it in messages).
///
/// # Errors
/// As [`eom`], but for reading the file.
pub fn eom_source(path: &str, source: &str) -> Result<crate::symbolic::Equations, FileError> {
    match read(path, source, false)? {
        Parsed::Coordinates(scene) => {
            scene.equations().map_err(|e| FileError::NoEquations { path: path.to_string(), why: e.0 })
        }
        Parsed::Graph(scene) => graph_equations(scene.as_ref(), &scene.default_params(), path),
    }
}

/// The equations of a joint-graph scene (a built-in one, or one read from a file) with
/// `params`: those of its coordinates form, with the body poses its coordinates give. `None`
/// for a scene that is not a joint graph (a built-in scene written in Rust: its coordinates-form
/// file is in examples/scenes).
///
/// # Errors
/// [`FileError::NoEquations`] if the graph cannot be written in the coordinates form or its
/// derivation fails.
pub fn scene_equations(
    scene: &dyn Scene,
    params: &lagrange_scenes::Params,
) -> Result<Option<crate::symbolic::Equations>, FileError> {
    match scene.joint_graph(params) {
        Ok(None) => Ok(None),
        _ => graph_equations(scene, params, scene.id()).map(Some),
    }
}

fn graph_equations(
    scene: &dyn Scene,
    params: &lagrange_scenes::Params,
    shown: &str,
) -> Result<crate::symbolic::Equations, FileError> {
    let fail = |why: String| FileError::NoEquations { path: shown.to_string(), why };
    let id = format!("{}_coordinates", scene.id());
    // The equations do not depend on when the motion starts: the form starts at t = 0.
    let text = crate::write::coordinates_from(scene, params, &id, |state| lagrange::State { t: 0.0, ..state })
        .map_err(|e| fail(e.to_string()))?
        .ok_or_else(|| fail("it is not a joint graph".into()))?;
    let Parsed::Coordinates(form) =
        read(&format!("{shown} (coordinates form)"), &text, false).map_err(|d| fail(d.render()))?
    else {
        return Err(fail("its coordinates form did not read as one".into()));
    };
    let mut equations = form.equations().map_err(|e| fail(e.0))?;
    equations.poses = form.poses().map_err(|e| fail(e.0))?;
    Ok(equations)
}

/// Read the coordinates-form scene file at `path` as its typed scene.
///
/// # Errors
/// As [`load`]; [`FileError::NotCoordinates`] for a joint-graph file.
pub fn load_coordinates(path: impl AsRef<Path>) -> Result<FileScene, FileError> {
    let path = path.as_ref();
    let shown = path.display().to_string();
    let source = std::fs::read_to_string(path).map_err(|source| FileError::Read { path: shown.clone(), source })?;
    match read(&shown, &source, true)? {
        Parsed::Coordinates(scene) => Ok(*scene),
        Parsed::Graph(_) => Err(FileError::NotCoordinates { path: shown }),
    }
}

/// Read a file's text; `new_id`: refuse an id a known scene has (every read but
/// [`eom_source`]'s, whose file may be the registered scene itself).
fn read(path: &str, source: &str, new_id: bool) -> Result<Parsed, Diagnostic> {
    let reader = Reader { path, source };
    let file: SceneFile = toml::from_str(source).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        let message = e.message().trim().to_string();
        let hint = if source.trim().is_empty() {
            Some("a scene file starts with `version = 1` and `id = \"...\"` (docs/files.md)".into())
        } else {
            None
        };
        reader.error(span, message).label("here").with_hint(hint)
    })?;
    check_header(&reader, &file, new_id)?;
    if let Some(graph) = &file.graph {
        return crate::graph::read(&reader, &file, graph).map(Parsed::Graph);
    }
    if let Some(initial) = &file.initial {
        return Err(reader
            .error(initial.span(), "`initial` belongs to the joint-graph form")
            .label("no [graph] in this file")
            .with_hint(Some("in the coordinates form each coordinate gives its `initial` and `rate`".into())));
    }
    let (specs, names, values) = parameters(&reader, &file)?;
    let form = CoordinateForm::read(&reader, &file, names)?;
    form.compile(&values).map_err(|(span, message, hint)| reader.error(span, message).label("here").with_hint(hint))?;
    let scene = FileScene::new(
        file.id.get_ref().clone(),
        file.title.clone().unwrap_or_else(|| file.id.get_ref().clone()),
        file.reference.clone().unwrap_or_else(|| format!("the scene file {path}")),
        file.horizon.as_ref().map(|h| *h.get_ref()),
        specs,
        form,
    );
    check_initial_state(&reader, &file, &scene)?;
    Ok(Parsed::Coordinates(Box::new(scene)))
}

/// The version, the id and the horizon.
fn check_header(reader: &Reader<'_>, file: &SceneFile, new_id: bool) -> Result<(), Diagnostic> {
    if *file.version.get_ref() != schema::VERSION {
        return Err(reader
            .error(
                file.version.span(),
                format!(
                    "this is version {} of the format; lagrange reads version {}",
                    file.version.get_ref(),
                    schema::VERSION
                ),
            )
            .label("unknown version"));
    }
    let id = file.id.get_ref();
    if id.is_empty() || !id.chars().all(|c| c.is_alphanumeric() || c == '_' || c == '-') {
        return Err(reader
            .error(file.id.span(), format!("`{id}` cannot be a scene id"))
            .label("letters, digits, `_` and `-` only")
            .with_hint(Some("the id names the scene on the command line and in reports".into())));
    }
    if new_id && lagrange_scenes::find(id).is_some() {
        return Err(reader
            .error(file.id.span(), format!("a scene called `{id}` exists already"))
            .label("taken")
            .with_hint(Some(format!("give the file's scene its own id (e.g. `my_{id}`)"))));
    }
    if let Some(h) = &file.horizon
        && !(h.get_ref().is_finite() && *h.get_ref() > 0.0)
    {
        return Err(reader.error(h.span(), "the horizon must be a positive number of seconds").label("here"));
    }
    Ok(())
}

/// The parameter table: specifications (leaked, as a scene's are static), names, defaults.
/// A file's parameter table: the specifications, the names, the defaults.
type Table = (Vec<ParamSpec>, Vec<String>, Vec<f64>);

fn parameters(reader: &Reader<'_>, file: &SceneFile) -> Result<Table, Diagnostic> {
    let (mut specs, mut names, mut values) = (Vec::new(), Vec::new(), Vec::new());
    for p in &file.parameters {
        let domain = match (&p.domain, &p.between) {
            (Some(_), Some(b)) => {
                return Err(reader.error(b.span(), "give `domain` or `between`, not both").label("here"));
            }
            (None, Some(b)) => {
                let [low, high] = *b.get_ref();
                if low.partial_cmp(&high) != Some(std::cmp::Ordering::Less) {
                    return Err(reader.error(b.span(), format!("[{low}, {high}] is not an interval")).label("here"));
                }
                Domain::OpenInterval(low, high)
            }
            (Some(d), None) => match d.get_ref().as_str() {
                "positive" => Domain::Positive,
                "non_negative" => Domain::NonNegative,
                "finite" => Domain::Finite,
                other => {
                    let known = ["positive", "non_negative", "finite"];
                    return Err(reader.error(d.span(), format!("unknown domain `{other}`")).label("here").with_hint(
                        Some(crate::names::suggest(other, known).map_or_else(
                            || "one of positive, non_negative, finite; or between = [low, high]".into(),
                            |s| format!("did you mean `{s}`?"),
                        )),
                    ));
                }
            },
            (None, None) => Domain::Finite,
        };
        let value = *p.value.get_ref();
        let name = leak(p.name.get_ref().clone());
        let spec = ParamSpec {
            name,
            symbol: leak(p.symbol.clone().unwrap_or_else(|| p.name.get_ref().clone())),
            unit: leak(p.unit.clone().unwrap_or_default()),
            default: value,
            domain,
            description: leak(p.description.clone().unwrap_or_else(|| "a parameter of the scene file".into())),
        };
        specs.push(spec);
        names.push(name.to_string());
        values.push(value);
    }
    // Each default checked against its domain, as a value given on the command line is.
    let table: &'static [ParamSpec] = Box::leak(specs.clone().into_boxed_slice());
    let mut params = lagrange_scenes::Params::defaults(table);
    for (p, spec) in file.parameters.iter().zip(table) {
        if let Err(e) = params.set(spec.name, spec.default) {
            return Err(reader.error(p.value.span(), e.to_string()).label(format!("outside {}", spec.domain)));
        }
    }
    Ok((specs, names, values))
}

/// Build the engine's model at the defaults and evaluate it at the initial state, so that a
/// mechanism the engine refuses is refused here, pointing at its cause.
fn check_initial_state(reader: &Reader<'_>, file: &SceneFile, scene: &FileScene) -> Result<(), Diagnostic> {
    let params = scene.default_params();
    let at = |error: Error| -> Diagnostic {
        let form = scene.form();
        let span = match &error {
            Error::SingularMassMatrix { coordinate, .. } | Error::IndefiniteMassMatrix { coordinate, .. } => {
                form.coordinates.iter().position(|c| &c.name == coordinate).map(|i| form.coordinate_spans[i].clone())
            }
            Error::AssemblyFailed { constraint, .. } => form
                .constraint_spans
                .iter()
                .zip(file.constraints.iter().chain(&file.velocity_constraints))
                .find(|(_, c)| c.name.get_ref() == constraint)
                .map(|(span, _)| span.clone()),
            Error::InconsistentConstraints { constraints, .. } => form
                .constraint_spans
                .iter()
                .zip(file.constraints.iter().chain(&file.velocity_constraints))
                .find(|(_, c)| constraints.first() == Some(c.name.get_ref()))
                .map(|(span, _)| span.clone()),
            _ => None,
        };
        reader
            .error(span.unwrap_or_else(|| file.id.span()), format!("the mechanism fails at its initial state: {error}"))
            .label("here")
    };
    let (mut system, state) = scene.system_and_state(&params).map_err(at)?;
    system.check_admissible(state.t, &state.q, &state.qdot).map_err(at)?;
    system.accelerations(state.t, &state.q, &state.qdot).map_err(at)?;
    Ok(())
}

/// The span of the first `"text"` or `'text'` string inside `within` (to point at a named
/// element of a joint graph), else `within`.
pub(crate) fn find_string(source: &str, within: Range<usize>, text: &str) -> Range<usize> {
    let region = &source[within.clone()];
    for quote in ['"', '\''] {
        let needle = format!("{quote}{text}{quote}");
        if let Some(i) = region.find(&needle) {
            return within.start + i..within.start + i + needle.len();
        }
    }
    within
}
