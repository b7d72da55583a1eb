//! Which scene a Python object names, and how it travels: a built-in scene by id, a scene file
//! by its text, a joint graph by its serde form with its initial state. That description (the
//! *spec*, a JSON text) is what a pickled `Scene` carries to a Dask worker, which resolves it
//! again ([`resolve`]); resolving the same spec twice in one process gives the same scene.

use crate::error::{Failure, Result};
use lagrange::State;
use lagrange_scenes::Scene;
use serde::{Deserialize, Serialize};
use std::sync::Mutex;

/// A scene's description.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Spec {
    /// A built-in scene (or one registered before in this process) by id.
    Builtin(String),
    /// A scene file: its path (for messages) and its text.
    File {
        /// Where it was read from; only messages show it.
        path: String,
        /// The file's text.
        text: String,
    },
    /// A joint graph (`lagrange::graph::JointGraph` in its serde form) and where it starts.
    Graph {
        /// The graph.
        graph: serde_json::Value,
        /// Initial time.
        t: f64,
        /// Initial coordinates.
        q: Vec<f64>,
        /// Initial velocities.
        qdot: Vec<f64>,
    },
}

/// The scenes this process resolved, by spec: a file or graph is registered once (its id then
/// names it everywhere, as for the command line), and asked again it is the same scene.
static RESOLVED: Mutex<Vec<(String, &'static dyn Scene)>> = Mutex::new(Vec::new());

/// The scene a spec describes.
///
/// # Errors
/// An unknown id, a file that is not a scene (with the file's diagnostic), a graph that is not
/// a mechanism or does not close, an id taken by another scene.
pub fn resolve(spec: &Spec) -> Result<&'static dyn Scene> {
    if let Spec::Builtin(id) = spec {
        return Ok(lagrange_validation::scene(id)?);
    }
    let key = serde_json::to_string(spec)?;
    let mut resolved = RESOLVED.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some((_, scene)) = resolved.iter().find(|(k, _)| *k == key) {
        return Ok(*scene);
    }
    let scene = match spec {
        Spec::Builtin(_) => unreachable!("resolved above"),
        Spec::File { path, text } => lagrange_file::register_source(path, text)?,
        Spec::Graph { graph, t, q, qdot } => {
            let graph: lagrange::graph::JointGraph = serde_json::from_value(graph.clone())
                .map_err(|e| Failure { class: "GraphError", message: format!("not a joint graph: {e}") })?;
            let scene = lagrange_scenes::GraphScene::new(graph, State::new(*t, q.clone(), qdot.clone()))?;
            lagrange_scenes::register(scene)?
        }
    };
    resolved.push((key, scene));
    Ok(scene)
}
