//! A body [`Model`] as the integrators see it.

use super::Dynamics;
use crate::eom::{self, energy};
use crate::seed::Tangent;
use crate::{Error, Mechanism, Model, Workspace};

/// The body model's workspace is its `f64` [`Workspace`]; the `Dual64` workspace of the
/// Jacobian's tangent passes hangs off it ([`new_workspace`](Dynamics::new_workspace) allocates
/// it up front, a workspace from [`Model::workspace`] on its first Jacobian).
impl<M: Mechanism> Dynamics for Model<M> {
    type Workspace = Workspace<f64>;

    fn new_workspace(&self) -> Workspace<f64> {
        let mut ws = self.workspace();
        ws.tangent = Some(Tangent::new(self.workspace(), self.n));
        ws
    }

    fn accelerations(
        &self,
        ws: &mut Workspace<f64>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        qddot: &mut [f64],
    ) -> Result<(), Error> {
        qddot.copy_from_slice(eom::accelerations(self, ws, t, q, qdot)?);
        Ok(())
    }

    fn acceleration_jacobian(
        &self,
        ws: &mut Workspace<f64>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        jacobian: &mut [f64],
    ) -> Result<(), Error> {
        let tangent = ws.tangent.get_or_insert_with(|| Tangent::new(self.workspace(), self.n));
        let Tangent { workspace, seeds } = &mut **tangent;
        seeds.jacobian(t, q, qdot, jacobian, |t, q, qdot, column| {
            let qddot = eom::accelerations(self, workspace, t, q, qdot)?;
            for (c, a) in column.iter_mut().zip(qddot) {
                *c = a.eps;
            }
            Ok(())
        })
    }

    fn energy_function(&self, ws: &mut Workspace<f64>, t: f64, q: &[f64], qdot: &[f64]) -> Result<f64, Error> {
        energy::energy_function(self, ws, t, q, qdot)
    }

    fn mass_matrix(
        &self,
        ws: &mut Workspace<f64>,
        t: f64,
        q: &[f64],
        _qdot: &[f64],
        mass: &mut [f64],
    ) -> Result<(), Error> {
        mass.copy_from_slice(eom::mass_matrix(self, ws, t, q)?);
        Ok(())
    }

    fn momenta(&self, ws: &mut Workspace<f64>, t: f64, q: &[f64], qdot: &[f64], p: &mut [f64]) -> Result<(), Error> {
        p.copy_from_slice(energy::momenta(self, ws, t, q, qdot)?);
        Ok(())
    }

    fn cyclic_coordinates(&self) -> &[bool] {
        Model::cyclic_coordinates(self)
    }

    fn has_generalized_force(&self) -> bool {
        self.has_force || self.has_applied
    }

    fn conserves_energy(&self) -> bool {
        Model::conserves_energy(self)
    }

    fn bodies(&self) -> &[crate::Body] {
        self.mechanism.bodies()
    }

    fn reaction_forces(
        &self,
        ws: &mut Workspace<f64>,
        t: f64,
        q: &[f64],
        qdot: &[f64],
        reaction: &mut [f64],
    ) -> Result<bool, Error> {
        reaction.copy_from_slice(crate::reaction_forces(self, ws, t, q, qdot)?);
        Ok(true)
    }
}
