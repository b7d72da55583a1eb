//! Joints counted the other way ([`Joint::clockwise`]): the crane with its revolute angles
//! clockwise and its rail reversed is the same machine in coordinates `q' = −q`.

use super::{Crane, assert_agree, both_paths, random_state};
use crate::test_support::{Range, rng};
use crate::tree::{Joint, Tree};
use crate::{Description, Mechanism, Model, Pose, Scalar, accelerations};

/// The crane in `q' = −q` for the coordinates in `FLIPPED` (x: the rail reversed; α, β, γ:
/// the angles clockwise; s keeps its direction): poses, potential and forces are the crane's
/// at `q = −q'`, `Q'_i = −Q_i`, and its tree has the same joints turned with
/// [`Joint::clockwise`].
#[derive(Clone, Debug)]
struct Flipped {
    crane: Crane,
    tree: Tree,
}

const FLIPPED: [bool; 5] = [true, true, true, false, true];

fn flip<S: Scalar>(q: &[S]) -> Vec<S> {
    q.iter().zip(FLIPPED).map(|(v, f)| if f { -*v } else { *v }).collect()
}

impl Flipped {
    fn new() -> Self {
        let crane = Crane::new();
        let joints: Vec<Joint> = crane
            .tree
            .joints()
            .iter()
            .zip(FLIPPED)
            .map(|(joint, f)| if f { joint.clone().clockwise() } else { joint.clone() })
            .collect();
        let tree = Tree::new(joints, crane.description.bodies.clone(), 9.81).expect("valid tree");
        Self { crane, tree }
    }
}

impl Mechanism for Flipped {
    fn description(&self) -> &Description {
        self.crane.description()
    }
    fn poses<S: Scalar>(&self, t: S, q: &[S], p: &mut [Pose<S>]) {
        self.crane.poses(t, &flip(q), p);
    }
    fn potential<S: Scalar>(&self, t: S, q: &[S], p: &[Pose<S>]) -> Option<S> {
        self.crane.potential(t, &flip(q), p)
    }
    fn generalized_force<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        let mut crane_force = vec![S::zero(); q.len()];
        self.crane.generalized_force(t, &flip(q), &flip(qdot), &mut crane_force);
        for (f, c) in force.iter_mut().zip(flip(&crane_force)) {
            *f += c;
        }
        true
    }
    fn tree(&self) -> Option<&Tree> {
        Some(&self.tree)
    }
}

/// Model::new checks the clockwise tree's kinematics against the flipped poses at probe
/// states; the articulated-body path then agrees with the generic path (the bound of the
/// module, `c ε κ(M)`), and both give the crane's `q̈` flipped — to the same bound, since the
/// flipped generic path assembles `M' = S M S` (`S = diag(±1)`) with the same arithmetic.
#[test]
fn clockwise_joints_describe_the_same_machine_in_negated_coordinates() {
    let flipped = Flipped::new();
    let crane = Model::new(flipped.crane.clone()).expect("valid");
    let mut ws = crane.workspace();
    let mut rng = rng(0xABA0_0006);
    for _ in 0..20 {
        let (mut q, qdot) = random_state(5, &mut rng);
        q[0] = rng.range(-2.0, 2.0);
        q[3] = rng.range(-0.3, 0.6);
        let t = rng.range(0.0, 10.0);
        let (fast, reference, kappa) = both_paths(&flipped, t, &q, &qdot);
        assert_agree("clockwise crane: tree vs generic", &fast, &reference, kappa);
        let original = accelerations(&crane, &mut ws, t, &flip(&q), &flip(&qdot)).expect("valid");
        assert_agree("clockwise crane vs crane", &fast, &flip(original), kappa);
    }
    // The tree alone, counted clockwise, as a mechanism of its own.
    let (q, qdot) = random_state(5, &mut rng);
    let (fast, reference, kappa) = both_paths(&flipped.tree, 0.0, &q, &qdot);
    assert_agree("clockwise tree", &fast, &reference, kappa);
}

/// Turning a joint clockwise twice gives back the original joint.
#[test]
fn clockwise_twice_is_the_identity() {
    for joint in Crane::new().tree.joints() {
        assert_eq!(joint.clone().clockwise().clockwise(), *joint);
        assert_ne!(joint.clone().clockwise(), *joint);
    }
}
