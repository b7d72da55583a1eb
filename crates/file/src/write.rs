//! Writing a scene as a file: any scene that is a joint graph, in the joint-graph form (a
//! built-in scene to start one's own from).

use lagrange::graph::JointGraph;
use lagrange::{Error, State};
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

/// The coordinates form of `scene` with `params`, under the id `id`: the joint graph's
/// coordinates, each body's pose as an expression in them, the loop-closing joints as
/// constraints, springs as the potential and the other force elements as generalized forces
/// (the conventions of [`GraphMechanism`](lagrange::graph::GraphMechanism), so the file gives the
/// graph's `q̈` and multipliers). `None` for a scene that is not a joint graph.
///
/// # Errors
/// [`Error::InvalidParameter`] for parameters that are not the scene's or an initial time other
/// than 0 (the coordinates form starts at `t = 0`); the graph's own errors.
pub fn coordinates_file(scene: &dyn Scene, params: &Params, id: &str) -> Result<Option<String>, Error> {
    coordinates_from(scene, params, id, |state| state)
}

/// [`coordinates_file`] from the initial state `start` makes of the scene's.
pub(crate) fn coordinates_from(
    scene: &dyn Scene,
    params: &Params,
    id: &str,
    start: impl FnOnce(State) -> State,
) -> Result<Option<String>, Error> {
    let Some(graph) = scene.joint_graph(params)? else { return Ok(None) };
    let state = start(scene.default_state(params)?);
    let quoted = |s: &str| toml::Value::String(s.to_string()).to_string();
    let mut header = format!(
        "# `{}` in the coordinates form (docs/files.md), written by `lagrange scenes --export {} --form coordinates`:\n\
         # the joint graph's coordinates and the body poses they give.\nversion = {}\nid = {}\ntitle = {}\nreference = {}\n",
        scene.id(),
        scene.id(),
        crate::schema::VERSION,
        quoted(id),
        quoted(scene.title()),
        quoted(scene.reference()),
    );
    if let Some(h) = scene.horizon() {
        header.push_str(&format!("horizon = {}\n", toml::Value::Float(h)));
    }
    crate::unfold::coordinates_text(&graph, &state, &header).map(Some)
}
