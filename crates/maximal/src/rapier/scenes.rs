//! One rapier construction per scene and joint mode (RAPIER-NOTES §3), written as a [`Plan`]:
//! which bodies, which joints with which anchors, which couplings and per-step forces, and the
//! deviations from the requested scene that rapier needs.

use super::plan::{BodySpec, Coupling, JointKind, JointMode, JointSpec, Motion, Plan, RopePulley, StepForces};
use crate::{BodyState, BuildError, Engine, maps};
use lagrange::{Body, Error, State};
use lagrange_scenes::Params;

/// Relative inertia `I_b = 1e-2 m r²` given to point bobs on impulse revolute joints, which
/// freeze the rotation of a body with zero inertia (RAPIER-NOTES §1.3).
const COMPOUND_BOB: f64 = 1e-2;

/// Mass given to massless movable pulleys of multibody Atwood machines, whose coordinate would
/// otherwise move no mass (a singular mass matrix, RAPIER-NOTES §2.4).
const MASSIVE_PULLEY: f64 = 0.5;

/// Why the Atwood family has no impulse-joint build.
const NO_PULLEY_JOINT: &str = "impulse joints have no pulley or gear constraint (rapier has no gear, \
     rack-and-pinion or pulley joint, and the lever-and-pin-slot substitute adds its own inertia)";

/// Why the driven pendulum has no multibody build.
const NO_RHEONOMIC_MULTIBODY: &str = "a rapier multibody propagates neither the velocity nor the \
     acceleration of a kinematic root to its links, so the bob would miss the support's motion \
     (measured: an error of 0.28 rad that does not shrink with the step)";

/// The plan of `scene` in `mode`, starting from the reduced `initial` state.
///
/// # Errors
/// [`BuildError::Invalid`] for an unknown scene, invalid parameters or a state of the wrong
/// size; [`BuildError::Unbuildable`] when `mode` cannot express the scene.
pub(crate) fn plan(
    engine: Engine,
    mode: JointMode,
    scene: &str,
    params: &Params,
    initial: &State,
) -> Result<Plan, BuildError> {
    check_input(scene, params, initial)?;
    let unbuildable =
        |reason: &str| Err(BuildError::Unbuildable { engine, scene: scene.into(), reason: reason.into() });
    match (scene, mode) {
        ("atwood" | "double_atwood" | "double_double_atwood", JointMode::Impulse) => {
            return unbuildable(NO_PULLEY_JOINT);
        }
        ("driven_pendulum", JointMode::Multibody) => return unbuildable(NO_RHEONOMIC_MULTIBODY),
        _ => {}
    }
    let (params, deviations) = with_deviations(mode, scene, params)?;
    let mut draft = Draft::new(mode, scene, &params, initial)?;
    let p = |name: &str| params.get(name);
    match scene {
        "cart_pendulum" => {
            let (ground, cart, bob) = (draft.ground(), draft.reduced(0), draft.reduced(1));
            draft.prismatic(ground, cart, [1.0, 0.0], [0.0, 0.0], [0.0, 0.0]);
            draft.revolute(cart, bob, [0.0, 0.0], [0.0, p("rod_length")]);
        }
        "harmonic_oscillator" => {
            let (ground, mass) = (draft.ground(), draft.reduced(0));
            draft.prismatic(ground, mass, [1.0, 0.0], [0.0, 0.0], [0.0, 0.0]);
            draft.forces = StepForces { potential: true, damping: p("damping"), lorentz: 0.0 };
        }
        "kepler" | "isotropic_oscillator" => {
            // Polar coordinates: an arm turning by θ, the particle sliding along it by r.
            polar(&mut draft, initial, [1.0, 0.0]);
            draft.forces.potential = true;
        }
        "spring_pendulum" => {
            // θ from the downward vertical: the arm's slide axis is its local −y.
            polar(&mut draft, initial, [0.0, -1.0]);
            draft.forces.potential = true;
        }
        "charged_particle" => {
            if mode == JointMode::Multibody {
                // Cartesian coordinates: a massless slider along x carrying the particle along y.
                let ground = draft.ground();
                let [x, _, _] = draft.states[0].pose;
                let [vx, _, _] = draft.states[0].velocity;
                let slider = draft.massless(BodyState { pose: [x, 0.0, 0.0], velocity: [vx, 0.0, 0.0] });
                let particle = draft.reduced(0);
                draft.prismatic(ground, slider, [1.0, 0.0], [0.0, 0.0], [0.0, 0.0]);
                draft.prismatic(slider, particle, [0.0, 1.0], [0.0, 0.0], [0.0, 0.0]);
            } else {
                draft.reduced(0);
            }
            draft.forces.lorentz = p("charge") * p("field");
        }
        "atwood" => {
            // Depths below the axle on vertical slides; the rope keeps x₁ + x₂ = l − πa and the
            // pulley turns by φ = x₁/a.
            let (ground, m1, m2) = (draft.ground(), draft.reduced(0), draft.reduced(1));
            let a = p("pulley_radius");
            let rope1 = draft.prismatic(ground, m1, DOWN, [-a, 0.0], [0.0, 0.0]);
            let rope2 = draft.prismatic(ground, m2, DOWN, [a, 0.0], [0.0, 0.0]);
            draft.couple(rope1, rope2, -1.0);
            if p("pulley_inertia") > 0.0 {
                let pulley = draft.reduced(2);
                let turn = draft.revolute(ground, pulley, [0.0, 0.0], [0.0, 0.0]);
                draft.couple(rope1, turn, 1.0 / a);
            } else {
                // A pulley link without inertia would move no mass: leave it out.
                draft.rope_pulleys.push(RopePulley { reduced: 2, source: m1, radius: a });
            }
        }
        "double_atwood" => {
            // Bodies m1, m2, m3, P: m1 and P on the upper rope, m2 and m3 hang from P.
            let ground = draft.ground();
            let [m1, m2, m3, pulley] = [0, 1, 2, 3].map(|r| draft.reduced(r));
            let upper1 = draft.prismatic(ground, m1, DOWN, [0.0, 0.0], [0.0, 0.0]);
            let upper2 = draft.prismatic(ground, pulley, DOWN, [0.0, 0.0], [0.0, 0.0]);
            let lower2 = draft.prismatic(pulley, m2, DOWN, [0.0, 0.0], [0.0, 0.0]);
            let lower3 = draft.prismatic(pulley, m3, DOWN, [0.0, 0.0], [0.0, 0.0]);
            draft.couple(upper1, upper2, -1.0);
            draft.couple(lower2, lower3, -1.0);
        }
        "double_double_atwood" => {
            // Bodies A, B, m2, m3, m4, m5: A and B on the upper rope, m2, m3 hang from B and
            // m4, m5 from A.
            let ground = draft.ground();
            let [a, b, m2, m3, m4, m5] = [0, 1, 2, 3, 4, 5].map(|r| draft.reduced(r));
            let upper_a = draft.prismatic(ground, a, DOWN, [0.0, 0.0], [0.0, 0.0]);
            let upper_b = draft.prismatic(ground, b, DOWN, [0.0, 0.0], [0.0, 0.0]);
            let rope_b2 = draft.prismatic(b, m2, DOWN, [0.0, 0.0], [0.0, 0.0]);
            let rope_b3 = draft.prismatic(b, m3, DOWN, [0.0, 0.0], [0.0, 0.0]);
            let rope_a4 = draft.prismatic(a, m4, DOWN, [0.0, 0.0], [0.0, 0.0]);
            let rope_a5 = draft.prismatic(a, m5, DOWN, [0.0, 0.0], [0.0, 0.0]);
            draft.couple(upper_a, upper_b, -1.0);
            draft.couple(rope_b2, rope_b3, -1.0);
            draft.couple(rope_a4, rope_a5, -1.0);
        }
        "wedge" => {
            // The block slides down the incline from the top corner (0, L sinα) of the wedge.
            let (ground, wedge, block) = (draft.ground(), draft.reduced(0), draft.reduced(1));
            let (sin, cos) = p("angle").sin_cos();
            draft.prismatic(ground, wedge, [1.0, 0.0], [0.0, 0.0], [0.0, 0.0]);
            draft.prismatic(wedge, block, [cos, -sin], [0.0, p("incline_length") * sin], [0.0, 0.0]);
        }
        "double_pendulum" => {
            let (ground, bob1, bob2) = (draft.ground(), draft.reduced(0), draft.reduced(1));
            draft.revolute(ground, bob1, [0.0, 0.0], [0.0, p("length_1")]);
            draft.revolute(bob1, bob2, [0.0, 0.0], [0.0, p("length_2")]);
        }
        "chain" => {
            // Rods hinged at their ends: pivot i at the top of rod i, the bottom of rod i − 1.
            let half = 0.5 * p("link_length");
            let mut parent = draft.ground();
            let mut anchor = [0.0, 0.0];
            for r in 0..draft.states.len() {
                let link = draft.reduced(r);
                draft.revolute(parent, link, anchor, [0.0, half]);
                (parent, anchor) = (link, [0.0, -half]);
            }
        }
        "driven_pendulum" => {
            // A rope from the moving support to the point bob's centre: the rod of a point bob
            // without inertia, exact while the rod is in tension.
            let support = draft.support(p("amplitude"), p("drive_frequency"), initial.t);
            let bob = draft.reduced(0);
            draft.rope(support, bob, p("length"));
        }
        other => {
            return Err(BuildError::Invalid(Error::InvalidParameter {
                name: "scene".into(),
                value: f64::NAN,
                why: format!("no rapier construction for scene `{other}`"),
            }));
        }
    }
    Ok(draft.finish(scene, params, deviations, initial.t))
}

/// The downward slide axis: coordinates are depths.
const DOWN: [f64; 2] = [0.0, -1.0];

/// Scene, parameters and state are valid and fit together (before any `Params::get`).
fn check_input(scene: &str, params: &Params, initial: &State) -> Result<(), BuildError> {
    let Some(found) = lagrange_scenes::find(scene) else {
        return Err(Error::InvalidParameter {
            name: "scene".into(),
            value: f64::NAN,
            why: format!("unknown scene id `{scene}`; known: {}", lagrange_scenes::ids().join(", ")),
        }
        .into());
    };
    let n = found.coordinates(params)?.len();
    for (what, values) in [("q", &initial.q), ("q̇", &initial.qdot)] {
        if values.len() != n {
            return Err(Error::DimensionMismatch { what, expected: n, got: values.len() }.into());
        }
    }
    if !(initial.t.is_finite() && initial.q.iter().chain(&initial.qdot).all(|v| v.is_finite())) {
        return Err(Error::NonFinite { stage: lagrange::Stage::State, t: initial.t, q: initial.q.clone() }.into());
    }
    Ok(())
}

/// The parameters rapier simulates, and one sentence per change: compound bobs for impulse
/// revolute joints, massive movable pulleys for multibody couplings.
fn with_deviations(mode: JointMode, scene: &str, params: &Params) -> Result<(Params, Vec<String>), Error> {
    let mut params = params.clone();
    let mut deviations = Vec::new();
    let changes: &[(&str, &str, &str)] = match (scene, mode) {
        ("cart_pendulum", JointMode::Impulse) => &[("bob_inertia", "bob_mass", "rod_length")],
        ("double_pendulum", JointMode::Impulse) => {
            &[("inertia_1", "mass_1", "length_1"), ("inertia_2", "mass_2", "length_2")]
        }
        ("double_atwood", JointMode::Multibody) => &[("lower_pulley_mass", "", "")],
        ("double_double_atwood", JointMode::Multibody) => &[("pulley_a_mass", "", ""), ("pulley_b_mass", "", "")],
        _ => &[],
    };
    for &(name, mass, length) in changes {
        if params.get(name) != 0.0 {
            continue;
        }
        if mass.is_empty() {
            params.set(name, MASSIVE_PULLEY)?;
            deviations.push(format!(
                "{name} = {MASSIVE_PULLEY} kg instead of 0: a massless movable pulley's coordinate moves \
                 no mass and makes the multibody mass matrix singular (RAPIER-NOTES §2.4)"
            ));
        } else {
            let value = COMPOUND_BOB * params.get(mass) * params.get(length).powi(2);
            params.set(name, value)?;
            deviations.push(format!(
                "{name} = {COMPOUND_BOB:e} {mass} {length}² = {value:e} kg m² instead of 0: an impulse \
                 revolute joint freezes the rotation of a body without inertia, so the bob is a compound bob"
            ));
        }
    }
    Ok((params, deviations))
}

/// Polar coordinates for a multibody (`ground → revolute → massless arm → prismatic → particle`,
/// the arm turned by `θ = q[1]` and the particle at `q[0]` along `axis` in the arm's frame), or
/// the free particle for impulse joints.
fn polar(draft: &mut Draft, initial: &State, axis: [f64; 2]) {
    if draft.mode == JointMode::Impulse {
        draft.reduced(0);
        return;
    }
    let ground = draft.ground();
    let arm = draft.massless(BodyState { pose: [0.0, 0.0, initial.q[1]], velocity: [0.0, 0.0, initial.qdot[1]] });
    let particle = draft.reduced(0);
    draft.revolute(ground, arm, [0.0, 0.0], [0.0, 0.0]);
    draft.prismatic(arm, particle, axis, [0.0, 0.0], [0.0, 0.0]);
}

/// A plan being written.
struct Draft {
    mode: JointMode,
    /// The reduced model's bodies (masses, inertias).
    reduced_bodies: Vec<Body>,
    /// The reduced model's body states at the initial state.
    states: Vec<BodyState>,
    bodies: Vec<BodySpec>,
    joints: Vec<JointSpec>,
    /// `(from, to, coeff)`; offsets are filled in by [`Draft::finish`].
    couplings: Vec<(usize, usize, f64)>,
    rope_pulleys: Vec<RopePulley>,
    forces: StepForces,
    gravity: f64,
}

impl Draft {
    fn new(mode: JointMode, scene: &str, params: &Params, initial: &State) -> Result<Self, Error> {
        Ok(Self {
            mode,
            reduced_bodies: maps::bodies(scene, params)?,
            states: maps::body_states(scene, params, initial)?,
            bodies: Vec::new(),
            joints: Vec::new(),
            couplings: Vec::new(),
            rope_pulleys: Vec::new(),
            forces: StepForces::default(),
            gravity: maps::gravity(params),
        })
    }

    fn push(&mut self, body: BodySpec) -> usize {
        self.bodies.push(body);
        self.bodies.len() - 1
    }

    /// The fixed ground at the origin.
    fn ground(&mut self) -> usize {
        self.push(BodySpec {
            motion: Motion::Ground,
            mass: 0.0,
            inertia: 0.0,
            initial: BodyState::default(),
            reduced: None,
        })
    }

    /// Reduced body `r`, with its mass, inertia and initial state.
    fn reduced(&mut self, r: usize) -> usize {
        let (body, initial) = (&self.reduced_bodies[r], self.states[r]);
        let spec =
            BodySpec { motion: Motion::Dynamic, mass: body.mass, inertia: body.inertia, initial, reduced: Some(r) };
        self.push(spec)
    }

    /// A massless, inertia-free link of a multibody (an arm, a slider).
    fn massless(&mut self, initial: BodyState) -> usize {
        self.push(BodySpec { motion: Motion::Dynamic, mass: 0.0, inertia: 0.0, initial, reduced: None })
    }

    /// The kinematic support of a driven pendulum at its place at `t`.
    fn support(&mut self, amplitude: f64, frequency: f64, t: f64) -> usize {
        let motion = Motion::Support { amplitude, frequency };
        let (sin, cos) = (frequency * t).sin_cos();
        let initial =
            BodyState { pose: [amplitude * sin, 0.0, 0.0], velocity: [amplitude * frequency * cos, 0.0, 0.0] };
        self.push(BodySpec { motion, mass: 0.0, inertia: 0.0, initial, reduced: None })
    }

    fn joint(
        &mut self,
        parent: usize,
        child: usize,
        kind: JointKind,
        anchor_parent: [f64; 2],
        anchor_child: [f64; 2],
    ) -> usize {
        self.joints.push(JointSpec { parent, child, anchor_parent, anchor_child, kind });
        self.joints.len() - 1
    }

    fn revolute(&mut self, parent: usize, child: usize, anchor_parent: [f64; 2], anchor_child: [f64; 2]) -> usize {
        self.joint(parent, child, JointKind::Revolute, anchor_parent, anchor_child)
    }

    fn prismatic(
        &mut self,
        parent: usize,
        child: usize,
        axis: [f64; 2],
        anchor_parent: [f64; 2],
        anchor_child: [f64; 2],
    ) -> usize {
        self.joint(parent, child, JointKind::Prismatic { axis }, anchor_parent, anchor_child)
    }

    /// A rope between the two bodies' centres.
    fn rope(&mut self, parent: usize, child: usize, length: f64) -> usize {
        self.joint(parent, child, JointKind::Rope { length }, [0.0, 0.0], [0.0, 0.0])
    }

    /// `q_to = coeff · q_from + offset`, the offset taken from the initial state.
    fn couple(&mut self, from: usize, to: usize, coeff: f64) {
        self.couplings.push((from, to, coeff));
    }

    fn finish(self, scene: &str, params: Params, deviations: Vec<String>, t0: f64) -> Plan {
        let coordinate = |j: usize| {
            let joint = &self.joints[j];
            joint.coordinate(&self.bodies[joint.parent].initial, &self.bodies[joint.child].initial).0
        };
        let couplings = self
            .couplings
            .iter()
            .map(|&(from, to, coeff)| Coupling { from, to, coeff, offset: coordinate(to) - coeff * coordinate(from) })
            .collect();
        Plan {
            scene: scene.into(),
            mode: self.mode,
            params,
            deviations,
            gravity: self.gravity,
            reduced_bodies: self.states.len(),
            bodies: self.bodies,
            joints: self.joints,
            couplings,
            rope_pulleys: self.rope_pulleys,
            forces: self.forces,
            t0,
        }
    }
}
