//! The motion of a material point of a body: where it is, how fast it moves, how it
//! accelerates — what a linkage designer asks of a coupler point.

use crate::eom::equations::accelerations;
use crate::{Error, Mechanism, Model, Pose, Workspace};
use num_dual::{Dual2_64, DualNum};

/// The world position, velocity and acceleration of a material point of a body at one state
/// ([`point_motion`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointMotion {
    /// Position `p` (m).
    pub position: [f64; 2],
    /// Velocity `ṗ` (m/s).
    pub velocity: [f64; 2],
    /// Acceleration `p̈` (m/s²).
    pub acceleration: [f64; 2],
}

/// The motion of the point `at` (m, in the frame of the body named `body`) of a body [`Model`]
/// at `(t, q, q̇)`: `p = x_b + R(φ_b) at`, `ṗ = J q̇ + ∂p/∂t` and `p̈ = J q̈ + (d/dt J) q̇ + …`,
/// all from one second-order dual pass of the poses along the motion `q(s) = q + s q̇ + ½ s² q̈`,
/// `t(s) = t + s`, with `q̈` the model's accelerations (constraints included).
///
/// ```
/// use lagrange::{Description, Mechanism, Model, Pose, Scalar, point_motion};
///
/// // A pendulum of length 1 m: its bob at θ = 0 (hanging), swinging at 2 rad/s.
/// struct Pendulum(Description);
/// impl Mechanism for Pendulum {
///     fn description(&self) -> &Description { &self.0 }
///     fn poses<S: Scalar>(&self, _t: S, q: &[S], out: &mut [Pose<S>]) {
///         out[0] = Pose::point(q[0].sin(), -q[0].cos());
///     }
/// }
/// let model = Model::new(Pendulum(Description::new().angle("θ").point("bob", 1.0).gravity(9.81)))?;
/// let mut ws = model.workspace();
/// let bob = point_motion(&model, &mut ws, "bob", [0.0, 0.0], 0.0, &[0.0], &[2.0])?;
/// assert!((bob.velocity[0] - 2.0).abs() < 1e-15); // v = ℓ θ̇
/// assert!((bob.acceleration[1] - 4.0).abs() < 1e-15); // centripetal ℓ θ̇², upwards
/// # Ok::<(), lagrange::Error>(())
/// ```
///
/// # Errors
/// [`Error::InvalidParameter`] naming a body the model does not have; as
/// [`accelerations`](crate::accelerations) otherwise.
pub fn point_motion<M: Mechanism>(
    model: &Model<M>,
    ws: &mut Workspace<f64>,
    body: &str,
    at: [f64; 2],
    t: f64,
    q: &[f64],
    qdot: &[f64],
) -> Result<PointMotion, Error> {
    let bodies = model.bodies();
    let Some(b) = bodies.iter().position(|candidate| candidate.name == body) else {
        let names: Vec<&str> = bodies.iter().map(|candidate| candidate.name.as_ref()).collect();
        return Err(Error::InvalidParameter {
            name: "body".into(),
            value: f64::NAN,
            why: format!("no body `{body}`; the bodies are {}", names.join(", ")),
        });
    };
    if !(at[0].is_finite() && at[1].is_finite()) {
        return Err(Error::InvalidParameter {
            name: "point".into(),
            value: at[0] + at[1],
            why: "must be finite".into(),
        });
    }
    let qddot = accelerations(model, ws, t, q, qdot)?.to_vec();
    let jet: Vec<Dual2_64> = (0..q.len()).map(|i| Dual2_64::new(q[i], qdot[i], qddot[i])).collect();
    let mut poses = vec![Pose::new(Dual2_64::from(0.0), Dual2_64::from(0.0), Dual2_64::from(0.0)); bodies.len()];
    model.mechanism().poses(Dual2_64::new(t, 1.0, 0.0), &jet, &mut poses);
    let pose = poses[b];
    let (sin, cos) = (pose.angle.sin(), pose.angle.cos());
    let x = pose.x + cos * at[0] - sin * at[1];
    let y = pose.y + sin * at[0] + cos * at[1];
    let motion = PointMotion { position: [x.re, y.re], velocity: [x.v1, y.v1], acceleration: [x.v2, y.v2] };
    let values = [motion.position, motion.velocity, motion.acceleration];
    if values.iter().flatten().all(|v| v.is_finite()) {
        Ok(motion)
    } else {
        Err(crate::eom::non_finite(crate::error::Stage::Kinematics, t, q))
    }
}
