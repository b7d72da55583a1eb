//! Your own mechanism, described once as bodies and joints, through every engine: a four-bar
//! linkage whose rocker carries a swinging pendulum, pulled by a spring and driven by a torque.
//! The reduced model (a spanning tree with the loop closed by a constraint), the Cartesian
//! model and the four rapier builds all follow from the one description; `compare` measures
//! each against the reduced solution, and the report's work-precision sweeps run on it too.
//!
//! `cargo run --release -p lagrange-examples --example own_mechanism`

use lagrange::State;
use lagrange::graph::{ForceElement, GROUND, GraphBody, GraphJoint, JointGraph, Point, Profile};
use lagrange_maximal::{BuildError, Engine, Settings};
use lagrange_scenes::{GraphScene, register};
use lagrange_validation::Error;
use lagrange_validation::compare::compare;
use lagrange_validation::plan::Plan;
use lagrange_validation::runs::{ScenePlan, SceneRuns};

fn rod(name: &str, mass: f64, length: f64) -> GraphBody {
    GraphBody::rigid(name, mass, mass * length * length / 12.0)
}

/// The mechanism: crank (1 m), coupler (2.2 m) and rocker (2 m) on pins, the ground pins 2 m
/// apart; a 0.8 m pendulum rod hung from the rocker's tip; a spring from the ground to the
/// coupler's middle; a torque on the crank.
fn mechanism() -> JointGraph {
    JointGraph::new("pumpjack", 9.81)
        .with_body(rod("crank", 1.0, 1.0))
        .with_body(rod("coupler", 1.5, 2.2))
        .with_body(rod("rocker", 1.2, 2.0))
        .with_body(rod("pendulum", 0.5, 0.8))
        .with_joint(GraphJoint::revolute("crank angle", GROUND, [0.0, 0.0], "crank", [-0.5, 0.0]))
        .with_joint(GraphJoint::revolute("coupler angle", "crank", [0.5, 0.0], "coupler", [-1.1, 0.0]))
        .with_joint(GraphJoint::revolute("rocker angle", GROUND, [2.0, 0.0], "rocker", [-1.0, 0.0]))
        .with_joint(GraphJoint::revolute("swing", "rocker", [1.0, 0.0], "pendulum", [0.0, 0.4]))
        // The pin between coupler and rocker closes the loop.
        .with_joint(GraphJoint::revolute("pin B", "coupler", [1.1, 0.0], "rocker", [1.0, 0.0]).closing())
        .with_force(ForceElement::Spring {
            a: Point::world([1.0, -1.0]),
            b: Point::on("coupler", [0.0, 0.0]),
            stiffness: 20.0,
            rest_length: 1.5,
        })
        .with_force(ForceElement::Torque { body: "crank".into(), torque: Profile::constant(0.5) })
}

fn main() -> Result<(), Error> {
    // An approximate start (angles: crank 1 rad, the others guessed); the scene brings it onto
    // the loop with the crank angle held.
    let approximate = State::new(0.0, [1.0, -0.3, 1.2, 0.0], [2.0, 0.0, 0.0, 0.5]);
    let scene = register(GraphScene::new(mechanism(), approximate)?)?;
    let params = scene.default_params();
    let initial = scene.default_state(&params)?;
    println!("{}: coordinates {:?}, assembled start q = {:.4?}", scene.id(), scene.coordinates(&params)?, initial.q);

    println!(
        "\nmax ‖q − q_ref‖∞ over 2 s against the reduced solution (rapier at dt = 1/960, one substep; its quick sweeps below go finer)\n"
    );
    println!("{:<21} {:>10} {:>12}  notes", "engine", "max error", "violation");
    for engine in Engine::ALL {
        let settings = Settings { dt: 1.0 / 960.0, substeps: 1, tolerance: 1e-12 };
        match compare(engine, scene, &params, &initial, &settings, 2.0, 0.02) {
            Ok(c) => {
                let violation = c.constraint_violation.map_or("—".into(), |v| format!("{v:.1e}"));
                println!("{:<21} {:>10.1e} {:>12}  {}", engine.name(), c.max_error, violation, c.deviations.join("; "));
            }
            Err(Error::Build(BuildError::Unbuildable { reason, .. })) => {
                println!("{:<21} {:>10} {:>12}  not buildable: {reason}", engine.name(), "—", "—");
            }
            Err(e) => return Err(e),
        }
    }

    // The report's sweeps (quick plan): every method's work-precision runs on this mechanism.
    println!("\nthe report's quick sweeps: best error reached and its run time, per method\n");
    let plan = ScenePlan::new(scene, &Plan::new(true, None)?)?;
    let runs = SceneRuns::execute(&plan, |_| {})?;
    for family in &runs.families {
        let best = family
            .runs
            .iter()
            .filter_map(|run| run.outcome.as_ref().ok())
            .map(|m| (m.errors.iter().copied().fold(0.0, f64::max), m.wall_time))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match best {
            Some((error, time)) => println!("{:<24} {error:>10.1e} in {:>9.3} ms", family.family.name(), time * 1e3),
            None => println!("{:<24} {:>10}", family.family.name(), "—"),
        }
    }
    Ok(())
}
