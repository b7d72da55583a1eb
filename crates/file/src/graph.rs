//! The joint-graph form: a serialized [`JointGraph`] and its initial state, read into a
//! [`GraphScene`] (which gets the Cartesian and rapier builds as the built-in graphs do).

use crate::coordinates::Reader;
use crate::diagnostic::Diagnostic;
use crate::read::find_string;
use crate::schema::SceneFile;
use lagrange::graph::JointGraph;
use lagrange::{Error, State};
use lagrange_scenes::{GraphScene, Scene};
use toml::Spanned;

/// Read the joint-graph form of `file`.
pub(crate) fn read(
    reader: &Reader<'_>,
    file: &SceneFile,
    graph: &Spanned<JointGraph>,
) -> Result<Box<dyn Scene>, Diagnostic> {
    // The first key of the coordinates form, where it is written.
    let expression = |e: &Option<Spanned<crate::schema::Expr>>| e.as_ref().map(Spanned::span);
    let coordinates_form = [
        ("parameters", file.parameters.first().map(|p| p.name.span())),
        ("coordinates", file.coordinates.first().map(|c| c.name.span())),
        ("bodies", file.bodies.first().map(|b| b.name.span())),
        ("gravity", expression(&file.gravity)),
        ("potential", expression(&file.potential)),
        ("forces", file.forces.first().map(|f| f.coordinate.span())),
        ("constraints", file.constraints.first().map(|c| c.name.span())),
        ("velocity_constraints", file.velocity_constraints.first().map(|c| c.name.span())),
        ("lagrangian", expression(&file.lagrangian)),
        ("region", file.region.first().map(|r| r.quantity.span())),
    ];
    if let Some((key, Some(span))) = coordinates_form.iter().find(|(_, span)| span.is_some()) {
        return Err(reader
            .error(span.clone(), format!("a joint-graph file has no `{key}`: that belongs to the coordinates form"))
            .label("this file is a joint graph ([graph])")
            .with_hint(Some("the graph names its bodies, joints, forces and gravity; its parameters are gravity and each body's mass and inertia".into())));
    }
    let Some(initial) = &file.initial else {
        return Err(reader
            .error(graph.span(), "a joint-graph file needs its initial state")
            .label("this graph")
            .with_hint(Some(
                "add [initial] with q = [...] (one value per free joint, in the order listed) and qdot = [...]".into(),
            )));
    };
    // The scene's id is the file's (a graph's own name, if it gives one, is replaced).
    let mut graph_value = graph.get_ref().clone();
    graph_value.name = file.id.get_ref().clone();
    let state = initial.get_ref();
    let n = state.q.len();
    let qdot = state.qdot.clone().unwrap_or_else(|| vec![0.0; n]);
    if let Some(bad) = state.q.iter().chain(&qdot).find(|v| !v.is_finite()) {
        return Err(reader
            .error(initial.span(), format!("the initial state holds {bad}, not a finite number"))
            .label("here"));
    }
    if qdot.len() != n {
        return Err(reader
            .error(initial.span(), format!("`q` has {n} values and `qdot` {}", qdot.len()))
            .label("one rate per coordinate"));
    }
    let point = |error: Error| -> Diagnostic {
        let span = match &error {
            Error::InvalidGraph { element, why } => {
                // The most precise name first: the one the reason gives (`refers to a body
                // `rodd``), then the element's; searched from the graph on (its tables follow it).
                let rest = graph.span().start..reader.source.len();
                let names = [why.as_str(), element.as_str()].map(|text| text.split('`').nth(1));
                names
                    .into_iter()
                    .flatten()
                    .map(|name| find_string(reader.source, rest.clone(), name))
                    .find(|span| *span != rest)
                    .unwrap_or_else(|| graph.span())
            }
            Error::DimensionMismatch { .. } => initial.span(),
            _ => graph.span(),
        };
        reader.error(span, error.to_string()).label("here")
    };
    let mut scene = GraphScene::new(graph_value, State::new(state.t, state.q.clone(), qdot)).map_err(point)?;
    if let Some(h) = &file.horizon {
        scene = scene.with_horizon(*h.get_ref());
    }
    Ok(Box::new(scene))
}
