//! Support for the integration tests: sampling of scene parameters and states, and the
//! mechanisms more than one check uses ([`parallelogram`]). The shared numeric helpers (seeded
//! generator, maxima, closeness, condition number) are `lagrange-testing`'s and the tolerances
//! with their reasons the validation library's, both re-exported here.

pub mod sampling;

pub use lagrange_testing::{condition_number, max_abs, max_abs_diff, rng};
pub use lagrange_validation::tolerance;

use lagrange::{Description, Mechanism, Model, Pose, Scalar};
use lagrange_scenes::Scene;

/// The registered scene `id` (through the validation library's one lookup); panics on an
/// unknown id, which in a test is a bug of the test.
pub fn scene(id: &str) -> &'static dyn Scene {
    lagrange_validation::scene(id).unwrap_or_else(|e| panic!("{e}"))
}

/// Three unit cranks from (0, 0), (1, 0), (2, 0) at angles q0, q1, q2, point masses at their
/// tips, four loop equations of which two are redundant on the parallelogram; a torque of
/// 2 N m on the first crank. The contradicting variant adds `t²` to the fourth row.
pub struct Parallelogram {
    description: Description,
    contradict: bool,
}

impl Mechanism for Parallelogram {
    fn description(&self) -> &Description {
        &self.description
    }
    fn poses<S: Scalar>(&self, _t: S, q: &[S], p: &mut [Pose<S>]) {
        p[0] = Pose::point(q[0].cos(), q[0].sin());
        p[1] = Pose::point(q[1].cos() + 1.0, q[1].sin());
        p[2] = Pose::point(q[2].cos() + 2.0, q[2].sin());
    }
    fn generalized_force<S: Scalar>(&self, _t: S, _q: &[S], _qdot: &[S], force: &mut [S]) -> bool {
        force[0] += S::from(2.0);
        true
    }
    fn constraints<S: Scalar>(&self, t: S, q: &[S], phi: &mut [S]) {
        phi[0] = q[1].cos() - q[0].cos();
        phi[1] = q[1].sin() - q[0].sin();
        phi[2] = q[2].cos() - q[0].cos();
        phi[3] = q[2].sin() - q[1].sin() + if self.contradict { t * t } else { S::zero() };
    }
}

/// The [`Parallelogram`] model, contradicting (`t²` in the fourth row) or not.
pub fn parallelogram(contradict: bool) -> Model<Parallelogram> {
    Model::new(Parallelogram {
        description: Description::new()
            .angle("q0")
            .angle("q1")
            .angle("q2")
            .point("a", 1.0)
            .point("b", 2.0)
            .point("c", 0.5)
            .gravity(9.81)
            .constraint("Φ1")
            .constraint("Φ2")
            .constraint("Φ3")
            .constraint("Φ4"),
        contradict,
    })
    .expect("valid")
}
