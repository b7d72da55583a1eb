//! The rapier infrastructure for loops, point springs, torques and contact, on small hand-made
//! plans with closed-form or quadrature references: a parallelogram linkage closed by an impulse
//! joint (impulse joints throughout, and a multibody tree closed by an impulse joint), a rod
//! pulled by a spring and driven by a torque, and a disc rolling down an incline on colliders.

use super::plan::{BodySpec, ColliderSpec, JointKind, JointMode, JointSpec, Motion, Plan, Shape, StepForces};
use super::{double, single};
use crate::{BodyState, Engine, MaximalSimulation, Settings};
use lagrange_scenes::Params;

/// Tolerances and bounds, each with the reason for its size.
mod bound {
    /// First order in the substep: halving `h` must shrink the error by at least this factor
    /// (2 for an exactly first-order error; the margin admits the `O(h²)` terms at the coarse
    /// step).
    pub const HALVING: f64 = 1.6;
    /// f32 against f64 over the same run: every update rounds at ε = 6e-8 relative; a few
    /// hundred steps accumulate that (the impulse joints' velocity bias turns position round-off
    /// into velocities ≈ ε/h).
    pub const SINGLE_VS_DOUBLE: f64 = 1e-4;
}

fn dynamic(mass: f64, inertia: f64, pose: [f64; 3], velocity: [f64; 3], reduced: usize) -> BodySpec {
    BodySpec {
        motion: Motion::Dynamic,
        mass,
        inertia,
        initial: BodyState { pose, velocity },
        reduced: Some(reduced),
        collider: None,
    }
}

fn ground(pose: [f64; 3]) -> BodySpec {
    BodySpec {
        motion: Motion::Ground,
        mass: 0.0,
        inertia: 0.0,
        initial: BodyState { pose, velocity: [0.0; 3] },
        reduced: None,
        collider: None,
    }
}

fn revolute(parent: usize, child: usize, anchor_parent: [f64; 2], anchor_child: [f64; 2]) -> JointSpec {
    JointSpec { parent, child, anchor_parent, anchor_child, kind: JointKind::Revolute, closing: false }
}

fn plan(mode: JointMode, gravity: f64, bodies: Vec<BodySpec>, joints: Vec<JointSpec>, forces: StepForces) -> Plan {
    Plan {
        scene: "hand-made".into(),
        mode,
        params: Params::defaults(&[]),
        read_back: None,
        deviations: Vec::new(),
        gravity,
        reduced_bodies: bodies.iter().filter(|b| b.reduced.is_some()).count(),
        bodies,
        joints,
        graph: None,
        couplings: Vec::new(),
        forces,
        t0: 0.0,
    }
}

fn engine(mode: JointMode, f32: bool) -> Engine {
    match (mode, f32) {
        (JointMode::Impulse, false) => Engine::RapierImpulse,
        (JointMode::Impulse, true) => Engine::RapierImpulseF32,
        (JointMode::Multibody, false) => Engine::RapierMultibody,
        (JointMode::Multibody, true) => Engine::RapierMultibodyF32,
    }
}

/// The simulation of `plan` in f64 or f32.
fn simulation(plan: Plan, dt: f64, substeps: usize, f32: bool) -> Box<dyn MaximalSimulation> {
    let settings = Settings { dt, substeps, ..Settings::default() };
    let engine = engine(plan.mode, f32);
    let built: Result<Box<dyn MaximalSimulation>, _> = if f32 {
        single::world::RapierSimulation::new(engine, plan, &settings).map(|s| Box::new(s) as _)
    } else {
        double::world::RapierSimulation::new(engine, plan, &settings).map(|s| Box::new(s) as _)
    };
    built.unwrap_or_else(|e| panic!("{engine}: {e}"))
}

/// Fourth-order Runge–Kutta for `θ̈ = f(θ)` from rest or `(θ0, ω0)`, values at `times`.
fn quadrature(f: impl Fn(f64) -> f64, theta0: f64, omega0: f64, times: &[f64]) -> Vec<f64> {
    let (mut theta, mut omega, mut t) = (theta0, omega0, 0.0);
    let h = 1e-5;
    times
        .iter()
        .map(|&target| {
            while t < target - 0.5 * h {
                let k1 = (omega, f(theta));
                let k2 = (omega + 0.5 * h * k1.1, f(theta + 0.5 * h * k1.0));
                let k3 = (omega + 0.5 * h * k2.1, f(theta + 0.5 * h * k2.0));
                let k4 = (omega + h * k3.1, f(theta + h * k3.0));
                theta += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
                omega += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
                t += h;
            }
            theta
        })
        .collect()
}

/// Run `simulation` to each of `times`; the angle of reduced body 0 at each, and the largest
/// constraint violation seen.
fn angles(simulation: &mut dyn MaximalSimulation, times: &[f64]) -> (Vec<f64>, f64) {
    let mut violation: f64 = 0.0;
    let angles = times
        .iter()
        .map(|&t| {
            simulation.advance_to(t).unwrap_or_else(|e| panic!("{e}"));
            violation = violation.max(simulation.constraint_violation().unwrap_or(0.0));
            simulation.bodies()[0].pose[2]
        })
        .collect();
    (angles, violation)
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

fn times() -> Vec<f64> {
    (1..=120).map(|k| f64::from(k) / 120.0).collect()
}

/// Errors at the halving step sizes `dts` are each at least `bound::HALVING` times smaller than
/// the last.
fn assert_first_order(what: &str, dts: &[f64], errors: &[f64]) {
    for (pair, dt) in errors.windows(2).zip(dts.windows(2)) {
        let ratio = pair[0] / pair[1];
        let expected = bound::HALVING;
        assert!(
            ratio >= expected,
            "{what}: error ratio {ratio} from dt = {} to {} below {expected} ({:e} / {:e})",
            dt[0],
            dt[1],
            pair[0],
            pair[1]
        );
    }
}

/// The parallelogram: side links of length `l` (uniform rods, mass `m_l`) hung from `(0, 0)` and
/// `(w, 0)`, a coupler of width `w` (uniform rod, mass `m_c`) between their lower ends. The
/// coupler translates, and the linkage is the pendulum
/// `(2 m_l/3 + m_c) l θ̈ = −(m_l + m_c) g sin θ` in the side links' angle `θ` from the downward
/// vertical. Tree: ground → link 1 → coupler, ground → link 2; the pin link 2–coupler closes
/// the loop.
fn parallelogram(mode: JointMode, theta0: f64) -> (Plan, impl Fn(f64) -> f64) {
    let (l, w, m_l, m_c, g) = (1.0, 0.8, 1.0, 2.0, 9.81);
    let (sin, cos) = theta0.sin_cos();
    let link = |x0: f64, r| dynamic(m_l, m_l * l * l / 12.0, [x0 + 0.5 * l * sin, -0.5 * l * cos, theta0], [0.0; 3], r);
    let coupler = dynamic(m_c, m_c * w * w / 12.0, [0.5 * w + l * sin, -l * cos, 0.0], [0.0; 3], 2);
    let bodies = vec![ground([0.0; 3]), link(0.0, 0), link(w, 1), coupler];
    let mut closing = revolute(2, 3, [0.0, -0.5 * l], [0.5 * w, 0.0]);
    closing.closing = true;
    let joints = vec![
        revolute(0, 1, [0.0, 0.0], [0.0, 0.5 * l]),
        revolute(1, 3, [0.0, -0.5 * l], [-0.5 * w, 0.0]),
        revolute(0, 2, [w, 0.0], [0.0, 0.5 * l]),
        closing,
    ];
    let accel = move |theta: f64| -(m_l + m_c) * g * theta.sin() / ((2.0 * m_l / 3.0 + m_c) * l);
    (plan(mode, g, bodies, joints, StepForces::default()), accel)
}

/// A loop closed by an impulse joint, with impulse joints throughout and as a multibody tree
/// plus the closing impulse joint: first order in the substep towards the closed-form
/// pendulum, loop-closure violation shrinking with it, f32 following f64.
#[test]
fn a_loop_closed_by_an_impulse_joint_converges_at_first_order() {
    let theta0 = 0.5;
    let times = times();
    let dts = [1.0 / 120.0, 1.0 / 240.0, 1.0 / 480.0];
    for mode in [JointMode::Impulse, JointMode::Multibody] {
        let (_, accel) = parallelogram(mode, theta0);
        let reference = quadrature(accel, theta0, 0.0, &times);
        let mut errors = Vec::new();
        for dt in dts {
            let (angle, violation) = angles(&mut *simulation(parallelogram(mode, theta0).0, dt, 4, false), &times);
            let error = max_diff(&angle, &reference);
            println!(
                "parallelogram {mode:?}: dt = 1/{:.0}, 4 substeps: θ error {error:8.2e}, max loop violation {violation:8.2e} m",
                1.0 / dt
            );
            errors.push(error);
        }
        assert_first_order(&format!("parallelogram {mode:?}"), &dts, &errors);
        let (double, _) = angles(&mut *simulation(parallelogram(mode, theta0).0, dts[0], 4, false), &times);
        let (single, _) = angles(&mut *simulation(parallelogram(mode, theta0).0, dts[0], 4, true), &times);
        let gap = max_diff(&double, &single);
        println!("parallelogram {mode:?}: f32 vs f64 at dt = 1/120: {gap:8.2e}");
        assert!(gap <= bound::SINGLE_VS_DOUBLE, "{mode:?}: f32 vs f64 {gap:e}");
    }
}

/// With multibody joints the closing joint is an impulse joint between two links: the tree
/// alone (without it) is a different mechanism, whose coupler does not stay level.
#[test]
fn the_closing_joint_acts_in_multibody_mode() {
    let (mut open, _) = parallelogram(JointMode::Multibody, 0.5);
    open.joints.pop();
    let (closed, _) = parallelogram(JointMode::Multibody, 0.5);
    let tilt = |plan: Plan| {
        let mut simulation = simulation(plan, 1.0 / 240.0, 4, false);
        simulation.advance_to(0.5).unwrap_or_else(|e| panic!("{e}"));
        simulation.bodies()[2].pose[2].abs()
    };
    let (open, closed) = (tilt(open), tilt(closed));
    println!("coupler tilt at t = 0.5: open tree {open:8.2e} rad, closed loop {closed:8.2e} rad");
    assert!(open > 0.1, "the open tree's coupler swings: {open}");
    assert!(closed < 1e-3, "the closed loop's coupler stays level: {closed}");
}

/// A uniform rod of length `l` hanging from a pivot at the origin (no gravity), pulled by a
/// spring from the fixed point `C` to its lower end and driven by a constant torque:
/// `(m l²/3) θ̈ = τ + (D × F)(θ)` about the pivot.
fn sprung_rod(mode: JointMode) -> (Plan, impl Fn(f64) -> f64) {
    use lagrange::graph::{ForceElement, GROUND, GraphBody, GraphJoint, GraphMechanism, JointGraph, Point, Profile};
    let (m, l, k, l0, tau, c) = (0.5, 0.4, 30.0, 0.2, 0.3, [0.45, 0.1]);
    let graph = JointGraph::new("sprung rod", 0.0)
        .with_body(GraphBody::rigid("rod", m, m * l * l / 12.0))
        .with_joint(GraphJoint::revolute("θ", GROUND, [0.0, 0.0], "rod", [0.0, 0.5 * l]))
        .with_force(ForceElement::Spring {
            a: Point::world(c),
            b: Point::on("rod", [0.0, -0.5 * l]),
            stiffness: k,
            rest_length: l0,
        })
        .with_force(ForceElement::Torque { body: "rod".into(), torque: Profile::constant(tau) });
    let mechanism = GraphMechanism::new(graph).unwrap();
    let initial = lagrange::State::new(0.0, [0.0], [0.0]);
    let plan = super::graph::plan(engine(mode, false), mode, "sprung rod", &mechanism, &initial).unwrap().plan;
    let accel = move |theta: f64| {
        let d = [l * theta.sin(), -l * theta.cos()];
        let r = [d[0] - c[0], d[1] - c[1]];
        let length = r[0].hypot(r[1]);
        let f = [-k * (length - l0) * r[0] / length, -k * (length - l0) * r[1] / length];
        (tau + d[0] * f[1] - d[1] * f[0]) / (m * l * l / 3.0)
    };
    (plan, accel)
}

/// The spring and the torque applied each step: first order towards the quadrature, in both
/// joint modes, f32 following f64.
#[test]
fn point_spring_and_torque_converge_at_first_order() {
    let times = times();
    let dts = [1.0 / 480.0, 1.0 / 960.0, 1.0 / 1920.0];
    for mode in [JointMode::Impulse, JointMode::Multibody] {
        let (_, accel) = sprung_rod(mode);
        let reference = quadrature(accel, 0.0, 0.0, &times);
        let mut errors = Vec::new();
        for dt in dts {
            let (angle, _) = angles(&mut *simulation(sprung_rod(mode).0, dt, 4, false), &times);
            let error = max_diff(&angle, &reference);
            println!("sprung rod {mode:?}: dt = 1/{:.0}: θ error {error:8.2e}", 1.0 / dt);
            errors.push(error);
        }
        assert_first_order(&format!("sprung rod {mode:?}"), &dts, &errors);
        let (double, _) = angles(&mut *simulation(sprung_rod(mode).0, dts[0], 4, false), &times);
        let (single, _) = angles(&mut *simulation(sprung_rod(mode).0, dts[0], 4, true), &times);
        let gap = max_diff(&double, &single);
        println!("sprung rod {mode:?}: f32 vs f64 at dt = 1/480: {gap:8.2e}");
        assert!(gap <= bound::SINGLE_VS_DOUBLE, "{mode:?}: f32 vs f64 {gap:e}");
    }
}

/// A uniform disc (mass `m`, radius `R`, a ball collider, inertia `½ m R²` from the shape) on a
/// fixed cuboid inclined at `α`, both with friction `μ`, the disc's centre at the origin and
/// the surface exactly `R` below it along the normal: exact rolling is `s = ½ a t²` with
/// `a = g sin α / (1 + I/(m R²)) = ⅔ g sin α`, which needs `μ ≥ tan α / 3`.
fn disc_on_incline(mu: f64) -> (Plan, f64, f64) {
    let (m, r, alpha, g): (f64, f64, f64, f64) = (1.0, 0.1, 0.3, 9.81);
    let half = [20.0, 0.5];
    // The surface's upward normal n = (−sin α, cos α); the cuboid's centre lies R + h below the
    // disc's centre along it.
    let depth = r + half[1];
    let mut incline = ground([depth * alpha.sin(), -depth * alpha.cos(), alpha]);
    incline.collider = Some(ColliderSpec { shape: Shape::Cuboid { half_extents: half }, density: 0.0, friction: mu });
    let shape = Shape::Ball { radius: r };
    let mut disc = dynamic(m, 0.5 * m * r * r, [0.0; 3], [0.0; 3], 0);
    disc.collider = Some(ColliderSpec { shape, density: m / shape.area(), friction: mu });
    let plan = plan(JointMode::Impulse, g, vec![incline, disc], Vec::new(), StepForces::default());
    (plan, 2.0 / 3.0 * g * alpha.sin(), alpha)
}

/// Largest `|s − ½ a t²|` and slip `|ṡ − R φ̇|` over `[0, 1]` s, read every 1/100 s, and the
/// final acceleration estimate `ṡ(1)/1`.
fn rolling_errors(mu: f64, dt: f64, substeps: usize, f32: bool) -> (f64, f64, f64) {
    let (plan, a, alpha) = disc_on_incline(mu);
    let r = 0.1;
    let mut simulation = simulation(plan, dt, substeps, f32);
    let (mut position, mut slip, mut rate) = (0.0_f64, 0.0_f64, 0.0);
    for k in 1..=100 {
        let t = f64::from(k) / 100.0;
        simulation.advance_to(t).unwrap_or_else(|e| panic!("{e}"));
        let disc = simulation.bodies()[0];
        let along = |v: [f64; 3]| -(v[0] * alpha.cos() + v[1] * alpha.sin());
        let (s, s_dot) = (along(disc.pose), along(disc.velocity));
        position = position.max((s - 0.5 * a * t * t).abs());
        slip = slip.max((s_dot - r * disc.velocity[2]).abs());
        rate = s_dot / t;
    }
    (position, slip, rate)
}

/// A ball collider on an inclined cuboid with enough friction rolls: `s` converges at first
/// order in the step `dt` towards `½ a t²` and the slip vanishes with it. (Contacts are found
/// once per step, so substeps do not shrink the error: measured and printed.) Below
/// `μ = tan α / 3` the disc slides, with the sliding acceleration `g (sin α − μ cos α)`.
#[test]
fn disc_rolls_down_the_incline_at_first_order_in_the_step() {
    let dts = [1.0 / 240.0, 1.0 / 480.0, 1.0 / 960.0];
    for f32 in [false, true] {
        let mut errors = Vec::new();
        for dt in dts {
            let (position, slip, _) = rolling_errors(1.0, dt, 4, f32);
            println!(
                "disc μ = 1 (f32 {f32}): dt = 1/{:.0}, 4 substeps: max |s − ½at²| {position:8.2e}, max slip {slip:8.2e}",
                1.0 / dt
            );
            errors.push(position.max(slip));
        }
        assert_first_order(&format!("rolling disc (f32 {f32})"), &dts, &errors);
    }
    for substeps in [1, 16] {
        let (position, slip, _) = rolling_errors(1.0, 1.0 / 240.0, substeps, false);
        println!("disc μ = 1: dt = 1/240, {substeps} substeps: max |s − ½at²| {position:8.2e}, max slip {slip:8.2e}");
    }
    let (mu, alpha, g) = (0.05, 0.3_f64, 9.81);
    let (_, slip, rate) = rolling_errors(mu, 1.0 / 960.0, 4, false);
    let sliding = g * (alpha.sin() - mu * alpha.cos());
    println!("disc μ = {mu} < tan α/3: ṡ(1)/1 = {rate:.6} (sliding {sliding:.6}), slip {slip:8.2e}");
    assert!(slip > 1.0 && (rate - sliding).abs() < 1e-2 * sliding, "μ = {mu}: ṡ/t = {rate}, sliding {sliding}");
}

/// Largest coordinate error against the reduced model (adaptive, tolerance 1e-12) at `samples`
/// equally spaced times up to `t_end`, the largest constraint violation seen, and the energy
/// change `|E(t_end) − E(0)|` (with the work of a constant crank torque `τ β` removed).
fn scene_errors(scene: &str, engine: Engine, t_end: f64, dt: f64, substeps: usize, samples: u32) -> (f64, f64, f64) {
    use lagrange::{Method, Output, Tolerances};
    let found = lagrange_scenes::find(scene).unwrap_or_else(|| panic!("{scene}"));
    let params = found.default_params();
    let initial = found.default_state(&params).unwrap_or_else(|e| panic!("{scene}: {e}"));
    let settings = Settings { dt, substeps, ..Settings::default() };
    let mut built = crate::build(engine, crate::scene(scene), &params, &initial, &settings)
        .unwrap_or_else(|e| panic!("{scene}: {e}"));
    let times: Vec<f64> = (1..=samples).map(|k| t_end * f64::from(k) / f64::from(samples)).collect();
    let reference = found
        .build(&built.params)
        .and_then(|system| {
            system.simulate(
                &initial,
                t_end,
                Method::Dopri5 { tol: Tolerances::uniform(1e-12) },
                &Output::Times(times.clone()),
            )
        })
        .unwrap_or_else(|e| panic!("{scene}: reference: {e}"));
    let torque = ["torque", "mom"].iter().find(|p| built.params.spec(p).is_some()).map_or(0.0, |p| built.params.get(p));
    let energy = |simulation: &dyn MaximalSimulation, q0: f64| {
        built.read_back.energy(simulation.t(), &simulation.bodies()) - torque * q0
    };
    let e0 = energy(&*built.simulation, initial.q[0]);
    let (mut error, mut violation, mut previous) = (0.0_f64, 0.0_f64, initial.q.clone());
    for (k, &t) in times.iter().enumerate() {
        built.simulation.advance_to(t).unwrap_or_else(|e| panic!("{engine} {scene}: {e}"));
        violation = violation.max(built.simulation.constraint_violation().unwrap_or(0.0));
        let (q, _) = built.read_back.generalized(built.simulation.t(), &built.simulation.bodies(), &previous);
        error = error.max(max_diff(&q, reference.q(k)));
        previous = q;
    }
    let drift = (energy(&*built.simulation, previous[0]) - e0).abs();
    (error, violation, drift)
}

/// The closed-loop scenes in every rapier engine: impulse joints throughout, and a multibody
/// spanning tree closed by impulse joints. The coordinates converge at first order in the step
/// towards the reduced solution, and the loop-closure violation shrinks with it (printed with
/// the energy change). f32 follows at the steps where its round-off is below the error: the
/// squeezer's f32 multibody stops converging at dt = 2.5e-6 (measured 7.4e-3, 4.0e-3, 3.1e-3),
/// so f32 is checked on the first halving there.
#[test]
fn loops_converge_at_first_order() {
    let steps = [1.0 / 240.0, 1.0 / 480.0, 1.0 / 960.0];
    let cases: [(&str, f64, [f64; 3]); 3] =
        [("four_bar", 2.0, steps), ("slider_crank", 1.0, steps), ("andrews_squeezer", 0.03, [1e-5, 5e-6, 2.5e-6])];
    for (scene, t_end, dts) in cases {
        for engine in
            [Engine::RapierImpulse, Engine::RapierMultibody, Engine::RapierImpulseF32, Engine::RapierMultibodyF32]
        {
            let f32 = matches!(engine, Engine::RapierImpulseF32 | Engine::RapierMultibodyF32);
            let checked = if f32 && scene == "andrews_squeezer" { 2 } else { 3 };
            let (mut errors, mut violations) = (Vec::new(), Vec::new());
            for &dt in &dts[..checked] {
                let (error, violation, energy) = scene_errors(scene, engine, t_end, dt, 4, 30);
                println!(
                    "{scene:16} {engine:22} dt {dt:8.2e}: max coordinate error {error:8.2e}, max loop violation \
                     {violation:8.2e} m, |ΔE| {energy:8.2e} J over {t_end} s"
                );
                errors.push(error);
                violations.push(violation);
            }
            assert_first_order(&format!("{scene} {engine}"), &dts[..checked], &errors);
            assert_first_order(&format!("{scene} {engine} loop violation"), &dts[..checked], &violations);
        }
    }
}
