//! A [`RawModel`] as the integrators see it.

use super::Dynamics;
use crate::seed::Tangent;
use crate::{Error, LagrangianFunction, RawModel, RawWorkspace};

impl<F: LagrangianFunction> LagrangianFunction for RawModel<F> {
    type Scratch<S: crate::Scalar> = F::Scratch<S>;

    fn coordinates(&self) -> &[crate::Coordinate] {
        self.function.coordinates()
    }

    fn scratch<S: crate::Scalar>(&self) -> Self::Scratch<S> {
        self.function.scratch()
    }

    fn lagrangian_with<S: crate::Scalar>(&self, scratch: &mut Self::Scratch<S>, t: S, q: &[S], qdot: &[S]) -> S {
        self.function.lagrangian_with(scratch, t, q, qdot)
    }

    fn generalized_force_with<S: crate::Scalar>(
        &self,
        scratch: &mut Self::Scratch<S>,
        t: S,
        q: &[S],
        qdot: &[S],
        force: &mut [S],
    ) -> bool {
        self.has_generalized_force() && self.function.generalized_force_with(scratch, t, q, qdot, force)
    }
}

impl<F: LagrangianFunction> Dynamics for RawModel<F> {
    /// The `f64` raw workspace; the `Dual64` one of the Jacobian's tangent passes (the
    /// Lagrangian then runs in `HyperDual<Dual64>`) hangs off it, allocated up front here or on
    /// the first Jacobian of a workspace from [`RawModel::workspace`].
    type Workspace = RawWorkspace<F>;

    fn new_workspace(&self) -> Self::Workspace {
        let mut ws = self.workspace();
        ws.tangent = Some(Tangent::new(self.workspace_in(), self.dof()));
        ws
    }

    fn accelerations(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        qddot: &mut [f64],
    ) -> Result<(), Error> {
        qddot.copy_from_slice(RawModel::accelerations(self, ws, t, q, qdot)?);
        Ok(())
    }

    fn acceleration_jacobian(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        jacobian: &mut [f64],
    ) -> Result<(), Error> {
        let tangent = ws.tangent.get_or_insert_with(|| Tangent::new(self.workspace_in(), self.dof()));
        let Tangent { workspace, seeds } = &mut **tangent;
        seeds.jacobian(t, q, qdot, jacobian, |t, q, qdot, column| {
            let qddot = RawModel::accelerations(self, workspace, t, q, qdot)?;
            for (c, a) in column.iter_mut().zip(qddot) {
                *c = a.eps;
            }
            Ok(())
        })
    }

    fn energy_function(&self, ws: &mut Self::Workspace, t: f64, q: &[f64], qdot: &[f64]) -> Result<f64, Error> {
        RawModel::energy_function(self, ws, t, q, qdot)
    }

    fn mass_matrix(
        &self,
        ws: &mut Self::Workspace,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        mass: &mut [f64],
    ) -> Result<(), Error> {
        mass.copy_from_slice(RawModel::velocity_hessian(self, ws, t, q, qdot)?);
        Ok(())
    }

    fn momenta(&self, ws: &mut Self::Workspace, t: f64, q: &[f64], qdot: &[f64], p: &mut [f64]) -> Result<(), Error> {
        p.copy_from_slice(RawModel::momenta(self, ws, t, q, qdot)?);
        Ok(())
    }

    fn cyclic_coordinates(&self) -> &[bool] {
        RawModel::cyclic_coordinates(self)
    }

    fn has_generalized_force(&self) -> bool {
        RawModel::has_generalized_force(self)
    }

    fn conserves_energy(&self) -> bool {
        self.is_autonomous() && !RawModel::has_generalized_force(self)
    }
}
