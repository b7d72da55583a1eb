//! Writing a scene as a file: any scene that is a joint graph, in the joint-graph form (a
//! built-in scene to start one's own from).

use lagrange::Error;
use lagrange::graph::JointGraph;
use lagrange_scenes::{Params, Scene};
use serde::Serialize;

#[derive(Serialize)]
struct GraphFile<'a> {
    version: i64,
    id: &'a str,
    title: &'a str,
    reference: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    horizon: Option<f64>,
    graph: JointGraph,
    initial: Initial<'a>,
}

#[derive(Serialize)]
struct Initial<'a> {
    t: f64,
    q: &'a [f64],
    qdot: &'a [f64],
}

/// The joint-graph form of `scene` with `params`, under the id `id`: a file [`parse`](crate::parse)
/// reads back into the same graph and default state, to the bit. `None` for a scene that is not
/// a joint graph.
///
/// # Errors
/// [`Error::InvalidParameter`] for parameters that are not the scene's.
pub fn graph_file(scene: &dyn Scene, params: &Params, id: &str) -> Result<Option<String>, Error> {
    let Some(mut graph) = scene.joint_graph(params)? else { return Ok(None) };
    graph.name = id.to_string();
    let state = scene.default_state(params)?;
    let file = GraphFile {
        version: crate::schema::VERSION,
        id,
        title: scene.title(),
        reference: scene.reference(),
        horizon: scene.horizon(),
        graph,
        initial: Initial { t: state.t, q: &state.q, qdot: &state.qdot },
    };
    let text = toml::to_string(&file).map_err(|e| Error::InvalidParameter {
        name: "scene".into(),
        value: f64::NAN,
        why: format!("cannot be written as TOML: {e}"),
    })?;
    Ok(Some(format!(
        "# `{}` as a joint-graph scene file (docs/files.md), written by `lagrange scenes --export {}`.\n{text}",
        scene.id(),
        scene.id()
    )))
}
