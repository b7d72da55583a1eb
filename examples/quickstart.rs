//! A double pendulum in a few lines: name the coordinates and bodies, write where the bodies are, simulate.
use lagrange::{Description, Mechanism, Method, Model, Output, Pose, Scalar, State, accelerations, simulate};

/// Two point masses on massless rods of lengths l1, l2; θ1, θ2 from the downward vertical.
struct DoublePendulum {
    description: Description,
    l1: f64,
    l2: f64,
}

impl Mechanism for DoublePendulum {
    // The data: coordinates, bodies, gravity.
    fn description(&self) -> &Description {
        &self.description
    }
    // Where each body is, as a function of q: written once, differentiated exactly.
    fn poses<S: Scalar>(&self, _t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        let (x1, y1) = (q[0].sin() * self.l1, -q[0].cos() * self.l1);
        world_from_body[0] = Pose::point(x1, y1);
        world_from_body[1] = Pose::point(x1 + q[1].sin() * self.l2, y1 - q[1].cos() * self.l2);
    }
}

fn main() -> Result<(), lagrange::Error> {
    let (m1, m2, l1, l2, g) = (1.0, 1.0, 1.0, 1.0, 9.81);
    let description = Description::new().angle("θ1").angle("θ2").point("bob 1", m1).point("bob 2", m2).gravity(g);
    let model = Model::new(DoublePendulum { description, l1, l2 })?;

    // q̈ against the textbook closed form of the double pendulum.
    let (q, qdot) = ([1.0_f64, 0.5], [0.3_f64, -0.2]);
    let qddot = accelerations(&model, &mut model.workspace(), 0.0, &q, &qdot)?.to_vec();
    let (d, w1, w2) = (q[0] - q[1], qdot[0], qdot[1]);
    let den = 2.0 * m1 + m2 - m2 * (2.0 * d).cos();
    let a1 = (-g * (2.0 * m1 + m2) * q[0].sin()
        - m2 * g * (q[0] - 2.0 * q[1]).sin()
        - 2.0 * d.sin() * m2 * (w2 * w2 * l2 + w1 * w1 * l1 * d.cos()))
        / (l1 * den);
    let a2 = 2.0 * d.sin() * (w1 * w1 * l1 * (m1 + m2) + g * (m1 + m2) * q[0].cos() + w2 * w2 * l2 * m2 * d.cos())
        / (l2 * den);
    assert!((qddot[0] - a1).abs() < 1e-13 && (qddot[1] - a2).abs() < 1e-13, "{qddot:?} vs [{a1}, {a2}]");

    // Variational integrator: symplectic, energy error bounded over long runs.
    let start = State::new(0.0, [1.0, 0.5], [0.0, 0.0]);
    let run = simulate(&model, &start, 10.0, Method::Variational { dt: 1e-3 }, &Output::Every(2.0))?;
    for k in 0..run.len() {
        println!("t = {:4.1}  θ = {:+.6?}  energy = {:.9}", run.t[k], run.q(k), run.energy[k]);
    }
    let drift = (run.energy[run.len() - 1] - run.energy[0]).abs() / run.energy[0].abs();
    assert!(drift < 1e-5, "energy drift {drift}");
    Ok(())
}
