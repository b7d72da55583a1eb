//! No heap allocation per step (Pinocchio's malloc tests): a counting global allocator around
//! the equations of motion, the AD Jacobian and one step of every integrator (RK4,
//! Dormand–Prince, variational, SDIRK4, Gauss–Legendre) and the projection onto the constraints,
//! for every scene, on the tree path, the assembled-mass-matrix path and (for scenes without
//! constraints among their coordinates) the raw-Lagrangian path. The counts are per thread, so
//! the other modules of this test binary, running beside it, do not enter them.
#![allow(unsafe_code)] // a global allocator is necessarily `unsafe impl`

use lagrange::integrate::{Dopri5, Gauss4, Rk4, Sdirk4, Variational};
use lagrange::{Description, Dynamics, Loads, Mechanism, Model, Pose, RawModel, Scalar, State, Tolerances};
use lagrange_scenes::SceneType;
use lagrange_scenes::{ClosedForm, MechanismVisitor, all, visit_mechanism};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

thread_local! {
    /// Allocations made by this thread (tests run in parallel threads).
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

struct Counting;

fn count() {
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

// SAFETY: forwards every call unchanged to the system allocator; only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn allocations(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    f();
    ALLOCATIONS.with(Cell::get) - before
}

/// Every per-step entry point of `system`, after its buffers exist, allocates nothing.
fn assert_no_allocation_per_step<D: Dynamics>(name: &str, system: &D, initial: &State) {
    let n = system.dof();
    let mut ws = system.workspace();
    let mut qddot = vec![0.0; n];
    let mut rk4 = Rk4::new(n);
    let mut state = initial.clone();
    let mut dopri = Dopri5::new(n, Tolerances::uniform(1e-8)).expect("valid");
    dopri.start(system, &mut ws, initial.t, &initial.q, &initial.qdot, 1.0).expect("valid");
    let mut variational = Variational::new(system);
    variational.start(system, initial.t, &initial.q, &initial.qdot).expect("valid");
    let mut sdirk = Sdirk4::new(n, Tolerances::uniform(1e-8)).expect("valid");
    sdirk.start(system, &mut ws, initial.t, &initial.q, &initial.qdot, 1.0).expect("valid");
    let mut gauss = Gauss4::new(n);
    let mut gauss_state = initial.clone();
    let mut qdot = vec![0.0; n];
    let mut jacobian = vec![0.0; 2 * n * n];
    // Warm-up: anything lazily initialised happens here, outside the count.
    system.accelerations(&mut ws, initial.t, &initial.q, &initial.qdot, &mut qddot).expect("valid");
    system.acceleration_jacobian(&mut ws, initial.t, &initial.q, &initial.qdot, &mut jacobian).expect("valid");
    // A scene file's evaluation buffers are per thread and per scalar type, made at a type's
    // first use: the variational integrator's first step is the first hyper-dual pass here (it
    // builds the Newton matrix that later steps keep), so a throwaway one takes it.
    let mut warm_up = Variational::new(system);
    warm_up.start(system, initial.t, &initial.q, &initial.qdot).expect("valid");
    warm_up.step(system, 1e-3).expect("valid");
    let counted = allocations(|| {
        for _ in 0..10 {
            system.accelerations(&mut ws, initial.t, &initial.q, &initial.qdot, &mut qddot).expect("valid");
            system.acceleration_jacobian(&mut ws, initial.t, &initial.q, &initial.qdot, &mut jacobian).expect("valid");
            rk4.step(system, &mut ws, &mut state, 1e-3).expect("valid");
            // A constrained run projects after every step (a no-op without constraints).
            system.project(&mut ws, state.t, &mut state.q, &mut state.qdot).expect("valid");
            dopri.step(system, &mut ws, 1e9).expect("valid");
            variational.step(system, 1e-3).expect("valid");
            sdirk.step(system, &mut ws, 1e9).expect("valid");
            gauss.step(system, &mut ws, &mut gauss_state, 1e-3).expect("valid");
        }
        variational.velocities(system, &mut qdot).expect("valid");
    });
    assert_eq!(counted, 0, "{name}: {counted} heap allocations in 10 steps");
    assert!(gauss.stats().jacobians > 0 && sdirk.stats().jacobians > 0 && sdirk.stats().steps == 10, "{name}");
}

struct NoAllocation<'a> {
    id: &'a str,
    initial: &'a State,
}

impl MechanismVisitor for NoAllocation<'_> {
    type Output = ();

    fn visit<M: Mechanism + ClosedForm + Clone + Send + Sync + 'static>(self, mechanism: M) {
        let model = Model::new(mechanism.clone()).expect("valid");
        assert_no_allocation_per_step(self.id, &model, self.initial);
        if model.mechanism().tree().is_some() {
            let generic = Model::new_generic(mechanism.clone()).expect("valid");
            assert_no_allocation_per_step(&format!("{} (assembled M)", self.id), &generic, self.initial);
        }
        // The raw path takes no constraints among the coordinates (`RawModel::new` refuses them).
        if !model.is_constrained() {
            let raw = RawModel::new(Model::new(mechanism).expect("valid")).expect("valid");
            assert_no_allocation_per_step(&format!("{} (raw path)", self.id), &raw, self.initial);
        }
    }
}

#[test]
fn the_counter_counts() {
    let counted = allocations(|| {
        std::hint::black_box(vec![1.0_f64; 8]);
    });
    assert_eq!(counted, 1);
}

#[test]
fn no_heap_allocation_per_step_in_any_scene() {
    let mut visited = 0;
    for scene in all() {
        let params = scene.default_params();
        let initial = scene.default_state(&params).expect("valid");
        if visit_mechanism(scene.id(), &params, NoAllocation { id: scene.id(), initial: &initial })
            .expect("valid")
            .is_some()
        {
            visited += 1;
        }
    }
    assert_eq!(visited, all().len() - 1, "every body scene checked");
    // The raw Lagrangian scene.
    let scene = lagrange_scenes::find("charged_particle").expect("registered");
    let params = scene.default_params();
    let particle = lagrange_scenes::charged_particle::ChargedParticle::from_params(&params).expect("valid");
    let raw = RawModel::new(particle).expect("valid");
    assert_no_allocation_per_step("charged_particle", &raw, &scene.default_state(&params).expect("valid"));
}

/// A rod pendulum pushed sideways at its tip: the applied forces' pass.
struct PushedRod {
    description: Description,
}

impl Mechanism for PushedRod {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (s, c) = (q[0].sin(), q[0].cos());
        world_from_body[0] = Pose::new(s * 0.5, -c * 0.5, q[0]);
    }

    fn applied_forces<S: Scalar>(&self, t: S, _: &[S], qdot: &[S], _: &[Pose<S>], loads: &mut Loads<'_, S>) -> bool {
        // A force at the tip (0, −0.5) in the rod's frame, depending on time and velocity.
        loads.force(0, [S::zero(), S::from(-0.5)], [t.cos() - qdot[0], S::zero()]);
        true
    }
}

#[test]
fn no_heap_allocation_per_step_with_applied_forces() {
    let rod = || PushedRod { description: Description::new().angle("θ").rigid("rod", 1.0, 1.0 / 12.0).gravity(9.81) };
    let initial = State::new(0.0, vec![0.4], vec![0.1]);
    let model = Model::new(rod()).expect("valid");
    assert!(model.has_applied_forces());
    assert_no_allocation_per_step("pushed rod", &model, &initial);
    let raw = RawModel::new(Model::new(rod()).expect("valid")).expect("valid");
    assert_no_allocation_per_step("pushed rod (raw path)", &raw, &initial);
}

/// Models built from joint graphs step without allocating either: every scene's graph (loops,
/// couplings, springs, torques), and a random tree and loop with dampers and a time-varying
/// torque added (the loads' dual pass of the forward kinematics).
#[test]
fn no_heap_allocation_per_step_for_joint_graphs() {
    use lagrange::graph::{ForceElement, GraphMechanism, Point, Profile};
    use lagrange_testing::rng;
    use lagrange_validation::graphs::{random_loop, random_tree};
    let mut checked = 0;
    for scene in all() {
        let params = scene.default_params();
        let Some(graph) = scene.joint_graph(&params).expect("valid") else { continue };
        let model = Model::new(GraphMechanism::new(graph).expect("a mechanism")).expect("valid");
        assert_no_allocation_per_step(
            &format!("{} (graph)", scene.id()),
            &model,
            &scene.default_state(&params).expect("valid"),
        );
        checked += 1;
    }
    assert_eq!(checked, 14, "the joint-graph scenes");
    for (graph, state) in [random_tree(&mut rng(3), 6), random_loop(&mut rng(12), 5)] {
        let graph = graph
            .with_force(ForceElement::Damper {
                a: Point::on("b0", [0.1, 0.0]),
                b: Point::on("b2", [0.0, 0.2]),
                coefficient: 0.5,
            })
            .with_force(ForceElement::JointDamper { joint: "q1".into(), coefficient: 0.3 })
            .with_force(ForceElement::Torque { body: "b1".into(), torque: Profile::harmonic(0.5, 2.0) });
        let name = graph.name.clone();
        let model = Model::new(GraphMechanism::new(graph).expect("a mechanism")).expect("valid");
        assert_no_allocation_per_step(&name, &model, &state);
    }
}

/// Scene files: the tapes evaluate into a per-thread buffer kept for the thread's life, so a
/// file scene steps without allocating, as the scene it writes again.
#[test]
fn no_heap_allocation_per_step_for_scene_files() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/scenes");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).expect("examples/scenes") {
        let path = entry.expect("an entry").path();
        let name = path.display().to_string();
        if !name.ends_with(".toml") || name.ends_with(".graph.toml") {
            continue;
        }
        let scene = lagrange_file::load_coordinates(&path).unwrap_or_else(|e| panic!("{}", e.render()));
        let params = lagrange_scenes::Scene::default_params(&scene);
        let initial = lagrange_scenes::Scene::default_state(&scene, &params).expect("valid");
        match scene.model(&params).expect("valid") {
            lagrange_file::FileModel::Bodies(model) => assert_no_allocation_per_step(&name, &*model, &initial),
            lagrange_file::FileModel::Raw(model) => assert_no_allocation_per_step(&name, &*model, &initial),
        }
        checked += 1;
    }
    assert!(checked >= 22, "{checked} coordinates-form files");
}
