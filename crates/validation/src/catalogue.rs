//! The scenes as a catalogue, for any front end: each scene's id, title, source, coordinates,
//! parameters, constants of the motion and default initial state ([`entries`]). Serialized, it
//! is `lagrange scenes --json` (docs/cli-json.md, field by field);
//! [`render::terminal::catalogue`](crate::render::terminal::catalogue) prints it.

use lagrange_scenes::Scene;
use serde::Serialize;

/// One parameter of a scene.
#[derive(Clone, Debug, Serialize)]
pub struct ParamEntry {
    /// Its name (`mass_1`).
    pub name: &'static str,
    /// Its symbol (`m₁`, `α`).
    pub symbol: &'static str,
    /// The symbol in ASCII (`alpha` for `α`), also accepted where parameters are named.
    pub ascii_symbol: String,
    /// Its SI unit (empty when dimensionless).
    pub unit: &'static str,
    /// Its default value.
    pub default: f64,
    /// What it is.
    pub description: &'static str,
}

/// One generalized coordinate of a scene.
#[derive(Clone, Debug, Serialize)]
pub struct CoordinateEntry {
    /// Its name (`θ1`).
    pub name: String,
    /// Its SI unit (`rad`, `m`).
    pub unit: &'static str,
}

/// The state a run starts from when none is given.
#[derive(Clone, Debug, Serialize)]
pub struct StateEntry {
    /// The initial time.
    pub t: f64,
    /// The coordinates, in the order of the scene's.
    pub q: Vec<f64>,
    /// Their rates.
    pub qdot: Vec<f64>,
}

/// One scene of the catalogue.
#[derive(Clone, Debug, Serialize)]
pub struct SceneEntry {
    /// The scene's id.
    pub id: &'static str,
    /// Its title.
    pub title: &'static str,
    /// Where it comes from.
    pub reference: &'static str,
    /// Its coordinates at the default parameters.
    pub coordinates: Vec<CoordinateEntry>,
    /// Its parameters.
    pub parameters: Vec<ParamEntry>,
    /// The symbols of its constants of the motion at the default parameters.
    pub conserved: Vec<String>,
    /// The default initial state, at the default parameters.
    pub initial_state: StateEntry,
}

impl SceneEntry {
    /// The entry of `scene`, at its default parameters.
    ///
    /// # Errors
    /// The scene's, when its default parameters give no coordinates or no default state.
    pub fn of(scene: &dyn Scene) -> Result<SceneEntry, lagrange::Error> {
        let params = scene.default_params();
        let coordinates = scene.coordinates(&params)?;
        let initial = scene.default_state(&params)?;
        Ok(SceneEntry {
            id: scene.id(),
            title: scene.title(),
            reference: scene.reference(),
            coordinates: coordinates.iter().map(|c| CoordinateEntry { name: c.name.clone(), unit: c.unit() }).collect(),
            parameters: scene
                .params()
                .iter()
                .map(|p| ParamEntry {
                    name: p.name,
                    symbol: p.symbol,
                    ascii_symbol: p.ascii_symbol(),
                    unit: p.unit,
                    default: p.default,
                    description: p.description,
                })
                .collect(),
            // Valid parameters: `coordinates` took them.
            conserved: scene.conserved_quantities(&params).unwrap_or_default().into_iter().map(|c| c.symbol).collect(),
            initial_state: StateEntry { t: initial.t, q: initial.q, qdot: initial.qdot },
        })
    }
}

/// Every registered scene's entry, in registry order.
///
/// # Errors
/// As [`SceneEntry::of`].
pub fn entries() -> Result<Vec<SceneEntry>, lagrange::Error> {
    lagrange_scenes::all().iter().map(|&scene| SceneEntry::of(scene)).collect()
}
