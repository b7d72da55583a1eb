//! A double pendulum in a few lines: choose coordinates, write where the bodies are, simulate.
use lagrange::{Body, Coordinate, Mechanism, Method, Model, Output, Pose, Scalar, State};

/// Two point masses on massless rods; θ1, θ2 from the downward vertical.
struct DoublePendulum {
    bodies: [Body; 2],
    coordinates: [Coordinate; 2],
    lengths: [f64; 2],
}

impl Mechanism for DoublePendulum {
    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }
    fn bodies(&self) -> &[Body] {
        &self.bodies
    }
    fn gravity(&self) -> f64 {
        9.81
    }
    // Where each body is, as a function of q: written once, differentiated exactly.
    fn poses<S: Scalar>(&self, q: &[S], _t: S, world_from_body: &mut [Pose<S>]) {
        let (s1, c1) = q[0].sin_cos();
        let (s2, c2) = q[1].sin_cos();
        let (x1, y1) = (s1 * self.lengths[0], -c1 * self.lengths[0]);
        world_from_body[0] = Pose::point(x1, y1);
        world_from_body[1] = Pose::point(x1 + s2 * self.lengths[1], y1 - c2 * self.lengths[1]);
    }
}

fn main() -> Result<(), lagrange::Error> {
    let model = Model::new(DoublePendulum {
        bodies: [Body::point("bob 1", 1.0), Body::point("bob 2", 1.0)],
        coordinates: [Coordinate::angle("θ1"), Coordinate::angle("θ2")],
        lengths: [1.0, 1.0],
    })?;
    let start = State::new(0.0, [1.0, 0.5], [0.0, 0.0]);
    // Variational integrator: symplectic, energy error bounded over long runs.
    let run = lagrange::simulate(&model, &start, 10.0, Method::Variational { dt: 1e-3 }, &Output::Every(2.0))?;
    for k in 0..run.len() {
        println!("t = {:4.1}  θ = {:+.6?}  energy = {:.9}", run.t[k], run.q(k), run.energy[k]);
    }
    let drift = (run.energy[run.len() - 1] - run.energy[0]).abs() / run.energy[0].abs();
    assert!(drift < 1e-5, "energy drift {drift}");
    Ok(())
}
