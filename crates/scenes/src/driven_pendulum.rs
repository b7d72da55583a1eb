//! Pendulum whose support is driven horizontally: a rheonomic constraint (beyond the lecture).

use crate::checks::{check_dimensions, fixed};
use crate::params::{GRAVITY, check_all};
use crate::{Domain, ParamSpec, Params, Scene};
use lagrange::{Body, Coordinate, Error, Mechanism, Model, Pose, Scalar, Simulation, State, System};

/// Parameters: mass `m`, rod length `l`, drive amplitude `A`, drive frequency `ω`, `g`.
pub const PARAMS: &[ParamSpec] = &[
    ParamSpec::new("mass", "m", "kg", 1.0, Domain::Positive, "mass of the bob"),
    ParamSpec::new("length", "l", "m", 1.0, Domain::Positive, "length of the massless rod"),
    ParamSpec::new("amplitude", "A", "m", 0.1, Domain::Finite, "amplitude of the support's horizontal motion"),
    ParamSpec::new("drive_frequency", "ω", "rad/s", 3.0, Domain::NonNegative, "angular frequency of the drive"),
    GRAVITY,
];

/// A bob of mass `m` on a massless rod of length `l` whose support moves as `(A sin ωt, 0)`:
/// bob at `(A sin ωt + l sinθ, −l cosθ)`; `q = (θ)`, from the downward vertical,
/// counter-clockwise. The pose depends on time (rheonomic), so energy is not conserved.
///
/// Construct with [`new`](Self::new) or [`from_params`](Self::from_params); the fields are public
/// for reading (changing one afterwards does not update the bodies the engine sees).
#[derive(Clone, Debug, PartialEq)]
pub struct DrivenPendulum {
    /// Bob mass `m` (kg).
    pub mass: f64,
    /// Rod length `l` (m).
    pub length: f64,
    /// Drive amplitude `A` (m).
    pub amplitude: f64,
    /// Drive angular frequency `ω` (rad/s).
    pub drive_frequency: f64,
    /// Gravitational acceleration `g` (m/s²).
    pub gravity: f64,
    coordinates: [Coordinate; 1],
    bodies: [Body; 1],
}

impl DrivenPendulum {
    /// A driven pendulum with mass `m`, length `l`, drive amplitude `A`, drive frequency `ω` and
    /// gravity `g`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first parameter outside its domain ([`PARAMS`]).
    pub fn new(mass: f64, length: f64, amplitude: f64, drive_frequency: f64, gravity: f64) -> Result<Self, Error> {
        check_all(PARAMS, &[mass, length, amplitude, drive_frequency, gravity])?;
        Ok(Self {
            mass,
            length,
            amplitude,
            drive_frequency,
            gravity,
            coordinates: [Coordinate::angle("θ")],
            bodies: [Body::point("bob", mass)],
        })
    }

    /// The driven pendulum with the values in `params`.
    ///
    /// # Errors
    /// As [`new`](Self::new), or a parameter missing from `params`.
    pub fn from_params(params: &Params) -> Result<Self, Error> {
        let [mass, length, amplitude, drive_frequency, gravity] = params.values_of(PARAMS)?;
        Self::new(mass, length, amplitude, drive_frequency, gravity)
    }

    /// `θ̈ = −(g/l) sinθ + (A ω² sin ωt / l) cosθ`: from
    /// `L = ½ m (A² ω² cos² ωt + 2 A ω cos ωt l θ̇ cosθ + l² θ̇²) + m g l cosθ`, the support's
    /// acceleration `−A ω² sin ωt` acts on the bob as the inertial force `m A ω² sin ωt` along x
    /// (derived as SYSTEMS.md §1 with the cart's motion prescribed).
    ///
    /// # Panics
    /// If `q` or `qdot` does not have 1 entry.
    pub fn closed_form_accelerations(&self, t: f64, q: &[f64], qdot: &[f64]) -> [f64; 1] {
        let [theta] = fixed(q, "q");
        let _: [f64; 1] = fixed(qdot, "q̇");
        let (l, a, omega) = (self.length, self.amplitude, self.drive_frequency);
        let drive = a * omega * omega * (omega * t).sin() / l;
        [-(self.gravity / l) * theta.sin() + drive * theta.cos()]
    }
}

impl Mechanism for DrivenPendulum {
    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }

    fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    fn gravity(&self) -> f64 {
        self.gravity
    }

    fn poses<S: Scalar>(&self, q: &[S], t: S, world_from_body: &mut [Pose<S>]) {
        let theta = q[0];
        // Support at (A sin ωt, 0); bob at the end of the rod.
        let support = (t * self.drive_frequency).sin() * self.amplitude;
        let (sin, cos) = theta.sin_cos();
        world_from_body[0] = Pose::point(support + sin * self.length, -cos * self.length);
    }
}

/// The [`DrivenPendulum`] as a [`Scene`] (`driven_pendulum`).
#[derive(Clone, Copy, Debug, Default)]
pub struct DrivenPendulumScene;

impl Scene for DrivenPendulumScene {
    fn id(&self) -> &'static str {
        "driven_pendulum"
    }

    fn title(&self) -> &'static str {
        "Pendulum with a horizontally driven support"
    }

    fn reference(&self) -> &'static str {
        "beyond the lecture (rheonomic constraint); closed form derived in driven_pendulum.rs"
    }

    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }

    fn coordinates(&self, params: &Params) -> Result<Vec<Coordinate>, Error> {
        Ok(DrivenPendulum::from_params(params)?.coordinates.to_vec())
    }

    /// `θ = 0.2`, at rest.
    fn default_state(&self, _params: &Params) -> Result<State, Error> {
        Ok(State::new(0.0, [0.2], [0.0]))
    }

    fn build(&self, params: &Params) -> Result<Box<dyn System>, Error> {
        Ok(Box::new(Simulation::new(Model::new(DrivenPendulum::from_params(params)?)?)))
    }

    fn closed_form_accelerations(
        &self,
        params: &Params,
        t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<Option<Vec<f64>>, Error> {
        let scene = DrivenPendulum::from_params(params)?;
        check_dimensions(1, q, qdot)?;
        Ok(Some(scene.closed_form_accelerations(t, q, qdot).to_vec()))
    }

    /// None: the motion has no closed form.
    fn exact_solution(&self, params: &Params, _initial: &State, _t: f64) -> Result<Option<State>, Error> {
        DrivenPendulum::from_params(params)?;
        Ok(None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::assert_engine_matches_closed_form;

    fn states() -> Vec<State> {
        vec![
            State::new(0.0, [0.2], [0.0]),
            State::new(0.37, [-0.4], [1.2]),
            State::new(1.1, [2.0], [-3.0]),
            State::new(3.9, [3.0], [0.7]),
            State::new(7.3, [-1.5], [-0.2]),
        ]
    }

    #[test]
    fn engine_matches_closed_form() {
        let mut params = DrivenPendulumScene.default_params();
        assert_engine_matches_closed_form(&DrivenPendulumScene, &params, &states());
        for (key, value) in [("A", -0.5), ("ω", 7.0), ("l", 0.3), ("ω", 0.0)] {
            params.set(key, value).unwrap();
            assert_engine_matches_closed_form(&DrivenPendulumScene, &params, &states());
        }
    }

    #[test]
    fn the_drive_makes_the_system_non_autonomous() {
        let system = DrivenPendulumScene.build(&DrivenPendulumScene.default_params()).unwrap();
        assert!(!system.conserves_energy());
        let mut still = DrivenPendulumScene.default_params();
        still.set("A", 0.0).unwrap();
        assert!(DrivenPendulumScene.build(&still).unwrap().conserves_energy());
    }
}
