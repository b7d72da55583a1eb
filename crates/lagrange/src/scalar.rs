//! The one scalar bound of the engine.

use num_dual::DualNum;

/// A real number or a (nested) dual number over `f64`.
///
/// Everything the user writes (poses, potentials, forces, Lagrangians) and everything the
/// engine assembles is generic over this bound and nothing stronger, so that engine-internal
/// derivatives can be differentiated again (Newton Jacobians of implicit integrators): nested
/// duals such as `Dual<HyperDual64>` satisfy it. Constants enter as `S::from(c)`; the real
/// part is read with [`num_dual::DualStruct::re`].
pub trait Scalar: DualNum<Primitive = f64> + Copy {}

impl<T: DualNum<Primitive = f64> + Copy> Scalar for T {}
