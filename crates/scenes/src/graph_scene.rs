//! A user's own mechanism as a scene: a joint graph with a default state, registered at run
//! time so that everything that takes a scene id (the maximal builds, `compare`, the report's
//! runs) takes it.

use crate::{Conserved, Domain, ParamSpec, Params, Scene};
use lagrange::graph::{GraphMechanism, JointGraph};
use lagrange::{Buffered, Coordinate, Error, Model, State, System};
use std::sync::RwLock;

/// A [`JointGraph`] with a default state, as a [`Scene`]: its id is the graph's name, its
/// parameters are gravity and every body's mass and inertia (`gravity`, `<body>.mass`,
/// `<body>.inertia`, defaults from the graph), its model the graph's reduced model
/// ([`GraphMechanism`]). It has no closed form and no exact solution; register it
/// ([`register`]) to make its id known to [`find`](crate::find).
///
/// ```
/// use lagrange::graph::{GROUND, GraphBody, GraphJoint, JointGraph};
/// use lagrange::State;
/// use lagrange_scenes::{GraphScene, register};
///
/// let graph = JointGraph::new("my_pendulum", 9.81)
///     .with_body(GraphBody::rigid("rod", 1.0, 1.0 / 12.0))
///     .with_joint(GraphJoint::revolute("θ", GROUND, [0.0, 0.0], "rod", [0.0, 0.5]));
/// let scene = register(GraphScene::new(graph, State::new(0.0, [0.4], [0.0]))?)?;
/// assert_eq!(lagrange_scenes::find("my_pendulum").map(|s| s.id()), Some("my_pendulum"));
/// let mut params = scene.default_params();
/// params.set("rod.mass", 2.0)?;
/// let mut system = scene.build(&params)?;
/// let qddot = system.accelerations(0.0, &[0.4], &[0.0])?.to_vec();
/// // About its end, (I + m l²/4) θ̈ = −m g (l/2) sin θ with l = 1, m = 2, I = 1/12.
/// let expected = -2.0 * 9.81 * 0.5 * 0.4_f64.sin() / (1.0 / 12.0 + 2.0 * 0.25);
/// approx::assert_relative_eq!(qddot[0], expected, max_relative = 1e-12);
/// # Ok::<(), lagrange::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct GraphScene {
    id: &'static str,
    title: &'static str,
    graph: JointGraph,
    initial: State,
    coordinates: Vec<Coordinate>,
    params: &'static [ParamSpec],
    horizon: Option<f64>,
}

/// A string that lives as long as the program (a registered scene's names).
fn leak(s: String) -> &'static str {
    Box::leak(s.into_boxed_str())
}

impl GraphScene {
    /// The scene of `graph` starting from `initial` (brought onto the loop constraints with
    /// the first coordinate held, if the graph has loops and the coordinate is free).
    ///
    /// # Errors
    /// [`Error::InvalidGraph`] for a graph that is not a mechanism; whatever
    /// [`Model::new`] rejects; [`Error::DimensionMismatch`] for a state of the wrong size;
    /// [`Error::AssemblyFailed`] when the state cannot be brought onto the constraints. A
    /// graph whose loops fix every coordinate (a truss, a fully driven linkage) is a scene.
    pub fn new(graph: JointGraph, initial: State) -> Result<Self, Error> {
        let model = Model::new(GraphMechanism::new(graph.clone())?)?;
        let n = model.dof();
        if initial.q.len() != n || initial.qdot.len() != n {
            return Err(Error::DimensionMismatch { what: "initial state", expected: n, got: initial.q.len() });
        }
        let initial = if !model.description().constraints.is_empty() {
            // The first coordinate is held where it is free to be; where the loops fix every
            // coordinate (a structure, a mechanism its drives move) none is.
            let mut held = vec![false; n];
            held[0] = model.mechanism().degrees_of_freedom(initial.t, &initial.q) > 0;
            lagrange::Dynamics::assemble(&model, &initial, &held).map_err(|error| match error {
                // Named by the loop, not by one of its rows: what does not close is the links.
                Error::AssemblyFailed { constraint, residual, .. } => Error::InvalidGraph {
                    element: format!("the loop closed by {}", constraint.split(" (").next().unwrap_or(&constraint)),
                    why: format!(
                        "does not close from the initial state (still {residual:.3e} m apart): the lengths along \
                         it may admit no closed configuration, or the initial angles are far from one"
                    ),
                },
                other => other,
            })?
        } else {
            initial
        };
        // A body that moves no mass along a coordinate leaves the reduced model without
        // accelerations: said here, not at the first step.
        let mut probe = Buffered::new(model.clone());
        probe.check_admissible(initial.t, &initial.q, &initial.qdot)?;
        probe.accelerations(initial.t, &initial.q, &initial.qdot)?;
        let mut specs = vec![ParamSpec {
            name: "gravity",
            symbol: "g",
            unit: "m/s²",
            default: graph.gravity,
            domain: Domain::Finite,
            description: "gravitational acceleration along −y",
        }];
        for body in &graph.bodies {
            for (what, unit, value) in [("mass", "kg", body.mass), ("inertia", "kg m²", body.inertia)] {
                let name = leak(format!("{}.{what}", body.name));
                specs.push(ParamSpec {
                    name,
                    symbol: name,
                    unit,
                    default: value,
                    domain: Domain::NonNegative,
                    description: leak(format!("{what} of body `{}`", body.name)),
                });
            }
        }
        Ok(Self {
            id: leak(graph.name.clone()),
            title: leak(format!("{} (joint graph)", graph.name)),
            coordinates: model.coordinates().to_vec(),
            graph,
            initial,
            params: Box::leak(specs.into_boxed_slice()),
            horizon: None,
        })
    }

    /// The same scene meant to be run over `horizon` seconds ([`Scene::horizon`]).
    pub fn with_horizon(mut self, horizon: f64) -> Self {
        self.horizon = Some(horizon);
        self
    }

    /// The graph with the masses, inertias and gravity of `params`.
    fn graph_with(&self, params: &Params) -> Result<JointGraph, Error> {
        if params.specs() != self.params {
            return Err(Error::InvalidParameter {
                name: "parameters".into(),
                value: f64::NAN,
                why: format!("were made for another scene than `{}`", self.id),
            });
        }
        let mut graph = self.graph.clone();
        graph.gravity = params.get("gravity");
        for body in &mut graph.bodies {
            body.mass = params.get(&format!("{}.mass", body.name));
            body.inertia = params.get(&format!("{}.inertia", body.name));
        }
        Ok(graph)
    }

    fn model(&self, params: &Params) -> Result<Model<GraphMechanism>, Error> {
        Model::new(GraphMechanism::new(self.graph_with(params)?)?)
    }
}

impl Scene for GraphScene {
    fn id(&self) -> &'static str {
        self.id
    }

    fn title(&self) -> &'static str {
        self.title
    }

    fn reference(&self) -> &'static str {
        "a joint graph (docs/graphs.md)"
    }

    fn horizon(&self) -> Option<f64> {
        self.horizon
    }

    fn params(&self) -> &'static [ParamSpec] {
        self.params
    }

    fn coordinates(&self, params: &Params) -> Result<Vec<Coordinate>, Error> {
        self.graph_with(params)?;
        Ok(self.coordinates.clone())
    }

    fn default_state(&self, params: &Params) -> Result<State, Error> {
        self.graph_with(params)?;
        Ok(self.initial.clone())
    }

    fn build(&self, params: &Params) -> Result<Box<dyn System>, Error> {
        Ok(Box::new(Buffered::new(self.model(params)?)))
    }

    fn closed_form_accelerations(
        &self,
        params: &Params,
        _t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<Option<Vec<f64>>, Error> {
        crate::checks::check_dimensions(self.coordinates.len(), q, qdot)?;
        self.graph_with(params)?;
        Ok(None)
    }

    fn exact_solution(&self, params: &Params, initial: &State, _t: f64) -> Result<Option<State>, Error> {
        crate::checks::check_state(self.coordinates.len(), initial)?;
        self.graph_with(params)?;
        Ok(None)
    }

    fn conserved_quantities(&self, params: &Params) -> Result<Vec<Conserved>, Error> {
        self.graph_with(params)?;
        Ok(Vec::new())
    }

    fn joint_graph(&self, params: &Params) -> Result<Option<JointGraph>, Error> {
        self.graph_with(params).map(Some)
    }

    /// None: a registered graph's own deviations are its bodies' (`build_graph` names them).
    fn rapier_deviations(&self, _multibody: bool) -> &'static [crate::RapierDeviation] {
        &[]
    }
}

/// The scenes registered at run time, after the built-in ones.
static REGISTERED: RwLock<Vec<&'static dyn Scene>> = RwLock::new(Vec::new());

/// Make `scene` known to [`find`](crate::find) by its id, for the rest of the program (the
/// scene is kept for good).
///
/// # Errors
/// [`Error::Registered`] when a scene with the same id is known already.
pub fn register(scene: impl Scene + 'static) -> Result<&'static dyn Scene, Error> {
    if crate::find(scene.id()).is_some() {
        return Err(Error::Registered { id: scene.id().to_string() });
    }
    let scene: &'static dyn Scene = Box::leak(Box::new(scene));
    let mut registered = REGISTERED.write().unwrap_or_else(std::sync::PoisonError::into_inner);
    registered.push(scene);
    Ok(scene)
}

/// The registered scene with id `id`.
pub(crate) fn registered(id: &str) -> Option<&'static dyn Scene> {
    let registered = REGISTERED.read().unwrap_or_else(std::sync::PoisonError::into_inner);
    registered.iter().copied().find(|s| s.id() == id)
}
