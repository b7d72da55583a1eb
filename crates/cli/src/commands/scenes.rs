//! `lagrange scenes`: every scene with its coordinates, parameters and default initial state
//! ([`lagrange_validation::catalogue`]).

use crate::error::CliError;
use crate::output::{outln, print};
use lagrange_validation::catalogue;
use lagrange_validation::render::terminal;

/// Arguments of `lagrange scenes`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
    /// Print the scene (a built-in id or a file) as a scene file, to start one's own from
    /// (scenes that are joint graphs).
    #[arg(long, value_name = "ID|FILE", conflicts_with = "json")]
    export: Option<String>,
    /// The form `--export` writes: the joint graph itself, or its coordinates form (the
    /// coordinates the graph chose, each body's pose as an expression in them, the loop
    /// closures as constraints).
    #[arg(long, value_enum, default_value_t = Form::Graph, requires = "export")]
    form: Form,
    /// What the engine understood of a scene (a built-in id or a file): its parameters,
    /// coordinates, bodies, optional terms, constraints and joint graph.
    #[arg(long, value_name = "ID|FILE", conflicts_with_all = ["json", "export"])]
    describe: Option<String>,
}

/// The two forms of a scene file.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// `[graph]`: bodies, joints, force elements.
    Graph,
    /// Coordinates, bodies' poses, constraints.
    Coordinates,
}

/// Print the scene list, one scene as a file, or what the engine understood of one.
pub fn run(args: &Args) -> Result<(), CliError> {
    if let Some(id) = &args.describe {
        // A coordinates-form file is read as one before it is registered as a scene.
        let file = std::path::Path::new(id).is_file().then(|| lagrange_file::load_coordinates(id).ok()).flatten();
        return print(&describe(file.as_ref(), crate::args::scene(id)?)?);
    }
    if let Some(id) = &args.export {
        let scene = crate::args::scene(id)?;
        let params = scene.default_params();
        let id = format!("my_{}", scene.id());
        let text = match args.form {
            Form::Graph => lagrange_file::graph_file(scene, &params, &id)?,
            Form::Coordinates => lagrange_file::coordinates_file(scene, &params, &id)?,
        }
        .ok_or_else(|| CliError::NotAGraph(scene.id().to_string()))?;
        return print(&text);
    }
    let scenes = catalogue::entries()?;
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&scenes)?)?;
    } else {
        print(&terminal::catalogue(&scenes))?;
    }
    Ok(())
}

/// How the engine computes `q̈` for a model: the articulated-body tree, a constant mass matrix,
/// or `M(q)` assembled; and whether it checks an admissible region.
fn path<M: lagrange::Mechanism>(model: &lagrange::Model<M>) -> String {
    let solve = if model.uses_tree_path() {
        "the articulated-body algorithm on the mechanism's joint tree (O(n), no mass matrix)"
    } else if model.has_constant_mass_matrix() {
        "a constant mass matrix, factored once"
    } else {
        "M(q) assembled from the poses' Jacobians and factored at every evaluation"
    };
    let constraints = if model.is_constrained() { ", the constraints through their multipliers" } else { "" };
    let region = if model.has_admissible_region() { "checked" } else { "none (every state is admissible)" };
    format!("q̈ by {solve}{constraints}; admissible region: {region}")
}

/// How a raw Lagrangian's `q̈` is computed.
const RAW: &str =
    "q̈ from the raw Lagrangian: M = ∂²L/∂q̇² and the rest of Lagrange's equations by automatic differentiation";

/// The built-in mechanism's [`path`].
struct Path;

impl lagrange_scenes::MechanismVisitor for Path {
    type Output = Result<String, lagrange::Error>;

    fn visit<M: lagrange::Mechanism + lagrange_scenes::ClosedForm + Clone + Send + Sync + 'static>(
        self,
        mechanism: M,
    ) -> Self::Output {
        lagrange::Model::new(mechanism).map(|model| path(&model))
    }
}

/// How `scene` computes its equations (`file`: the scene as its coordinates-form file).
fn equations_path(
    file: Option<&lagrange_file::FileScene>,
    scene: &dyn lagrange_scenes::Scene,
) -> Result<Option<String>, CliError> {
    let params = scene.default_params();
    if let Some(graph) = scene.joint_graph(&params)? {
        let mechanism = lagrange::graph::GraphMechanism::new(graph)?;
        let joints = |tree: bool| -> Vec<String> {
            let graph = mechanism.graph();
            (0..graph.joints.len())
                .filter(|&j| mechanism.in_tree(j) == tree)
                .map(|j| graph.joints[j].name.clone())
                .collect()
        };
        let (tree, closing) = (joints(true), joints(false));
        let model = lagrange::Model::new(mechanism)?;
        let closing = if closing.is_empty() { "none".to_string() } else { closing.join(", ") };
        return Ok(Some(format!(
            "{}
spanning tree: {}; loop-closing: {closing}",
            path(&model),
            tree.join(", ")
        )));
    }
    if let Some(file) = file {
        let mut text = match file.model(&params)? {
            lagrange_file::FileModel::Bodies(model) => path(&model),
            lagrange_file::FileModel::Raw(_) => RAW.to_string(),
        };
        let region = file.region();
        if !region.is_empty() {
            text.push_str(&format!("\nregion: {}", region.join(", ")));
        }
        return Ok(Some(text));
    }
    match lagrange_scenes::visit_mechanism(scene.id(), &params, Path) {
        Ok(Some(text)) => Ok(Some(text?)),
        Ok(None) => Ok(Some(RAW.to_string())),
        Err(_) => Ok(None),
    }
}

/// What the engine understood of `scene` at its default parameters, in words.
fn describe(file: Option<&lagrange_file::FileScene>, scene: &dyn lagrange_scenes::Scene) -> Result<String, CliError> {
    use std::fmt::Write as _;
    let params = scene.default_params();
    let system = scene.build(&params)?;
    let state = scene.default_state(&params)?;
    let mut out = String::new();
    let w = &mut out;
    let _ = writeln!(w, "{} — {}\n  from: {}", scene.id(), scene.title(), scene.reference());
    let _ = writeln!(w, "parameters:");
    for (spec, value) in params.iter() {
        let _ = writeln!(w, "  {} ({}) = {value} {} [{}]", spec.name, spec.symbol, spec.unit, spec.domain);
    }
    let _ = writeln!(w, "coordinates (initial value, rate):");
    let cyclic = system.cyclic_coordinates();
    for (i, c) in system.coordinates().iter().enumerate() {
        let note = if cyclic.get(i).copied().unwrap_or(false) { "  (cyclic)" } else { "" };
        let _ = writeln!(w, "  {} [{}] = {}, {}{note}", c.name, c.unit(), state.q[i], state.qdot[i]);
    }
    let _ = writeln!(w, "bodies:");
    for b in system.bodies() {
        let _ = writeln!(w, "  {}: mass {} kg, inertia {} kg m²", b.name, b.mass, b.inertia);
    }
    let (m, k) = system.constraint_counts();
    let _ = writeln!(w, "constraints: {m} holonomic, {k} velocity");
    let _ = writeln!(
        w,
        "terms: {}; energy {}",
        if system.has_external_forces() {
            "forces that do work (generalized or applied)"
        } else {
            "no external forces"
        },
        if system.conserves_energy() { "conserved (L does not depend on t)" } else { "not conserved" }
    );
    if let Some(text) = equations_path(file, scene)? {
        let _ = writeln!(w, "{text}");
    }
    match scene.joint_graph(&params)? {
        Some(graph) => {
            let closing = graph.joints.iter().filter(|j| j.role == lagrange::graph::Role::Closing).count();
            let _ = writeln!(
                w,
                "joint graph: {} bodies, {} joints ({} marked closing), {} couplings, {} force elements; Cartesian and rapier builds",
                graph.bodies.len(),
                graph.joints.len(),
                closing,
                graph.couplings.len(),
                graph.forces.len()
            );
        }
        None => {
            let _ = writeln!(w, "joint graph: none (no maximal-coordinate builds; its check is the engine's own)");
        }
    }
    Ok(out)
}
