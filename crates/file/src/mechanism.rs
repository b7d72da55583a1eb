//! A coordinates-form scene file as the engine sees it: a [`Mechanism`] (bodies placed by
//! expressions) or a raw [`Lagrangian`], each function one compiled [`Tape`].

use crate::tape::Tape;
use lagrange::{Bounds, Coordinate, Description, Lagrangian, Mechanism, Pose, Scalar};
use std::any::Any;
use std::cell::RefCell;

thread_local! {
    /// Working memory of the tapes, one buffer per scalar type, kept for the thread's life:
    /// the engine's calls (`poses`, `constraints`, …) carry no scratch of their own, and a
    /// tape evaluation must not allocate.
    static BUFFERS: RefCell<Vec<Box<dyn Any>>> = const { RefCell::new(Vec::new()) };
}

/// Run `f` with this thread's buffer of `S`, at least `len` long.
fn with_buffer<S: Scalar, R>(len: usize, f: impl FnOnce(&mut [S]) -> R) -> R {
    BUFFERS.with(|buffers| {
        let mut buffers = buffers.borrow_mut();
        let index = match buffers.iter().position(|b| b.is::<Vec<S>>()) {
            Some(i) => i,
            None => {
                buffers.push(Box::new(Vec::<S>::new()));
                buffers.len() - 1
            }
        };
        let buffer = buffers[index].downcast_mut::<Vec<S>>().expect("the buffer's type was just checked");
        if buffer.len() < len {
            buffer.resize(len, S::zero());
        }
        f(&mut buffer[..len])
    })
}

/// A tape's inputs `(t, q)` or `(t, q, q̇)`, its slots and its outputs in one buffer.
fn evaluate<S: Scalar, R>(tape: &Tape, t: S, q: &[S], qdot: Option<&[S]>, read: impl FnOnce(&[S]) -> R) -> R {
    let inputs = 1 + q.len() + qdot.map_or(0, <[S]>::len);
    with_buffer::<S, R>(inputs + tape.len() + tape.outputs(), |buffer| {
        let (input, rest) = buffer.split_at_mut(inputs);
        input[0] = t;
        input[1..=q.len()].copy_from_slice(q);
        if let Some(qdot) = qdot {
            input[1 + q.len()..].copy_from_slice(qdot);
        }
        let (slots, out) = rest.split_at_mut(tape.len());
        tape.eval(input, slots, out);
        read(out)
    })
}

/// A strict bound of the admissible region.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Bound {
    /// The quantity as written (`r > 0`).
    pub quantity: String,
    /// Above (`true`) or below the limit.
    pub above: bool,
    /// The limit.
    pub limit: f64,
}

/// The functions of a coordinates-form file, compiled for one set of parameters.
#[derive(Clone, Debug)]
pub(crate) struct Functions {
    /// `(x, y, φ)` of every body from `(t, q)`.
    pub poses: Tape,
    /// `V(t, q)`, if the file has one.
    pub potential: Option<Tape>,
    /// `Q(t, q, q̇)` of the coordinates in `forced`.
    pub forces: Option<Tape>,
    /// The coordinate each output of `forces` acts along.
    pub forced: Vec<usize>,
    /// `Φ(t, q)`.
    pub constraints: Tape,
    /// The velocity constraints' residuals at `(t, q, q̇)`.
    pub velocity: Tape,
    /// `L(t, q, q̇)` of a raw-Lagrangian file.
    pub lagrangian: Option<Tape>,
    /// The region's quantities at `(t, q, q̇)`, and their bounds.
    pub region: Tape,
    /// The bounds, one per output of `region`.
    pub bounds: Vec<Bound>,
}

impl Functions {
    fn admissible(&self, t: f64, q: &[f64], qdot: &[f64], bounds: &mut Bounds) -> bool {
        if self.bounds.is_empty() {
            return false;
        }
        evaluate(&self.region, t, q, Some(qdot), |values| {
            for (bound, &value) in self.bounds.iter().zip(values) {
                if bound.above {
                    bounds.above(&bound.quantity, value, bound.limit);
                } else {
                    bounds.below(&bound.quantity, value, bound.limit);
                }
            }
        });
        true
    }

    fn generalized_force<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        let Some(tape) = &self.forces else { return false };
        evaluate(tape, t, q, Some(qdot), |values| {
            for (&i, &value) in self.forced.iter().zip(values) {
                force[i] += value;
            }
        });
        true
    }
}

/// A mechanism read from a coordinates-form file: bodies placed by the file's expressions.
#[derive(Clone, Debug)]
pub struct FileMechanism {
    description: Description,
    functions: Functions,
}

impl FileMechanism {
    pub(crate) fn new(description: Description, functions: Functions) -> Self {
        Self { description, functions }
    }
}

impl Mechanism for FileMechanism {
    fn description(&self) -> &Description {
        &self.description
    }

    fn poses<S: Scalar>(&self, t: S, q: &[S], world_from_body: &mut [Pose<S>]) {
        evaluate(&self.functions.poses, t, q, None, |values| {
            for (pose, v) in world_from_body.iter_mut().zip(values.chunks_exact(3)) {
                *pose = Pose::new(v[0], v[1], v[2]);
            }
        });
    }

    fn potential<S: Scalar>(&self, t: S, q: &[S], _world_from_body: &[Pose<S>]) -> Option<S> {
        let tape = self.functions.potential.as_ref()?;
        Some(evaluate(tape, t, q, None, |values| values[0]))
    }

    fn generalized_force<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        self.functions.generalized_force(t, q, qdot, force)
    }

    fn admissible(&self, t: f64, q: &[f64], qdot: &[f64], bounds: &mut Bounds) -> bool {
        self.functions.admissible(t, q, qdot, bounds)
    }

    fn constraints<S: Scalar>(&self, t: S, q: &[S], phi: &mut [S]) {
        evaluate(&self.functions.constraints, t, q, None, |values| phi.copy_from_slice(values));
    }

    fn velocity_constraint<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], residual: &mut [S]) {
        evaluate(&self.functions.velocity, t, q, Some(qdot), |values| residual.copy_from_slice(values));
    }
}

/// A system read from a coordinates-form file that gives its Lagrangian `L(t, q, q̇)` directly.
#[derive(Clone, Debug)]
pub struct FileLagrangian {
    coordinates: Vec<Coordinate>,
    functions: Functions,
}

impl FileLagrangian {
    pub(crate) fn new(coordinates: Vec<Coordinate>, functions: Functions) -> Self {
        Self { coordinates, functions }
    }
}

impl Lagrangian for FileLagrangian {
    fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }

    fn lagrangian<S: Scalar>(&self, t: S, q: &[S], qdot: &[S]) -> S {
        let tape = self.functions.lagrangian.as_ref().expect("a raw-Lagrangian file has a Lagrangian");
        evaluate(tape, t, q, Some(qdot), |values| values[0])
    }

    fn generalized_force<S: Scalar>(&self, t: S, q: &[S], qdot: &[S], force: &mut [S]) -> bool {
        self.functions.generalized_force(t, q, qdot, force)
    }

    fn admissible(&self, t: f64, q: &[f64], qdot: &[f64], bounds: &mut Bounds) -> bool {
        self.functions.admissible(t, q, qdot, bounds)
    }
}
