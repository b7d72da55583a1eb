//! A coordinates-form file as a [`Scene`]: parameters from the file's table, the model
//! compiled for each set of parameters, the initial state the file gives.

use crate::coordinates::{Compiled, CoordinateForm};
use lagrange::graph::JointGraph;
use lagrange::{Coordinate, Error, State, System};
use lagrange_scenes::{Conserved, ParamSpec, Params, RapierDeviation, Scene};

/// A scene read from a coordinates-form file ([`load`](crate::load)).
///
/// It has no closed form, no exact solution and no maximal build (it has no joints): its
/// independent check is the engine's own, the constraints, energy and the region along a run.
#[derive(Clone, Debug)]
pub struct FileScene {
    id: &'static str,
    title: &'static str,
    reference: &'static str,
    horizon: Option<f64>,
    params: &'static [ParamSpec],
    form: CoordinateForm,
    coordinates: Vec<Coordinate>,
}

/// The engine's model of a coordinates-form file ([`FileScene::model`]).
#[derive(Clone, Debug)]
pub enum FileModel {
    /// Bodies placed by expressions.
    Bodies(Box<lagrange::Model<crate::FileMechanism>>),
    /// A raw Lagrangian.
    Raw(Box<lagrange::RawModel<crate::FileLagrangian>>),
}

/// A string that lives as long as the program (a loaded scene's names, as a registered
/// [`GraphScene`](lagrange_scenes::GraphScene)'s).
pub(crate) fn leak(s: String) -> &'static str {
    Box::leak(s.into_boxed_str())
}

impl FileScene {
    pub(crate) fn new(
        id: String,
        title: String,
        reference: String,
        horizon: Option<f64>,
        params: Vec<ParamSpec>,
        form: CoordinateForm,
    ) -> Self {
        Self {
            id: leak(id),
            title: leak(title),
            reference: leak(reference),
            horizon,
            params: Box::leak(params.into_boxed_slice()),
            coordinates: form.coordinates.clone(),
            form,
        }
    }

    /// The parameter values in the file's order, checked to be this scene's.
    fn values(&self, params: &Params) -> Result<Vec<f64>, Error> {
        if params.specs() != self.params {
            return Err(Error::InvalidParameter {
                name: "parameters".into(),
                value: f64::NAN,
                why: format!("were made for another scene than `{}`", self.id),
            });
        }
        Ok(self.form.parameters.iter().map(|p| params.get(p)).collect())
    }

    /// The file compiled with `params`.
    pub(crate) fn compiled(&self, params: &Params) -> Result<Compiled, Error> {
        let values = self.values(params)?;
        self.form.compile(&values).map_err(|(_, why, _)| Error::InvalidParameter {
            name: "parameters".into(),
            value: f64::NAN,
            why: format!("make the file's expressions invalid: {why}"),
        })
    }

    /// The compiled file's system and its initial state brought onto its constraints (the
    /// first coordinate held), if it has any.
    pub(crate) fn system_and_state(&self, params: &Params) -> Result<(Box<dyn System>, State), Error> {
        let (system, initial) = self.compiled(params)?.system()?;
        let (m, _) = system.constraint_counts();
        if m == 0 {
            return Ok((system, initial));
        }
        let mut held = vec![false; initial.q.len()];
        held[0] = true;
        let state = system.assemble(&initial, &held)?;
        Ok((system, state))
    }

    /// The engine's typed model of the file with `params` (for code that needs the
    /// [`Dynamics`](lagrange::Dynamics) interface rather than [`System`]).
    ///
    /// # Errors
    /// As [`Scene::build`].
    pub fn model(&self, params: &Params) -> Result<FileModel, Error> {
        Ok(match self.compiled(params)? {
            Compiled::Bodies(m, _) => FileModel::Bodies(Box::new(lagrange::Model::new(m)?)),
            Compiled::Raw(l, _) => FileModel::Raw(Box::new(lagrange::RawModel::new(l)?)),
        })
    }

    /// The coordinates-form file's parts.
    pub(crate) fn form(&self) -> &CoordinateForm {
        &self.form
    }

    /// The scene's equations, derived symbolically from the file's expressions
    /// ([`crate::symbolic`]).
    ///
    /// # Errors
    /// An expression the derivation does not take (`abs`, a variable exponent, a number
    /// beyond exact 128-bit rationals).
    pub fn equations(&self) -> Result<crate::symbolic::Equations, crate::symbolic::algebra::Unsupported> {
        let symbols: Vec<String> = self.params.iter().map(|p| p.symbol.to_string()).collect();
        crate::symbolic::derive(&self.form, &symbols)
    }

    /// The bounds of the admissible region as written (`r above 0`), empty without one.
    pub fn region(&self) -> Vec<String> {
        self.form
            .region
            .iter()
            .map(|(quantity, above, limit)| {
                format!("{} {} {limit}", quantity.text, if *above { "above" } else { "below" })
            })
            .collect()
    }

    /// Every body's pose as the derivation simplifies it.
    pub(crate) fn poses(&self) -> Result<Vec<crate::symbolic::BodyPose>, crate::symbolic::algebra::Unsupported> {
        let symbols: Vec<String> = self.params.iter().map(|p| p.symbol.to_string()).collect();
        crate::symbolic::poses(&self.form, &symbols)
    }
}

impl Scene for FileScene {
    fn id(&self) -> &'static str {
        self.id
    }

    fn title(&self) -> &'static str {
        self.title
    }

    fn reference(&self) -> &'static str {
        self.reference
    }

    fn horizon(&self) -> Option<f64> {
        self.horizon
    }

    fn params(&self) -> &'static [ParamSpec] {
        self.params
    }

    fn coordinates(&self, params: &Params) -> Result<Vec<Coordinate>, Error> {
        self.values(params)?;
        Ok(self.coordinates.clone())
    }

    fn default_state(&self, params: &Params) -> Result<State, Error> {
        self.system_and_state(params).map(|(_, state)| state)
    }

    fn build(&self, params: &Params) -> Result<Box<dyn System>, Error> {
        self.compiled(params)?.system().map(|(system, _)| system)
    }

    fn closed_form_accelerations(
        &self,
        params: &Params,
        _t: f64,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<Option<Vec<f64>>, Error> {
        check(self.coordinates.len(), q.len(), qdot.len())?;
        self.values(params)?;
        Ok(None)
    }

    fn exact_solution(&self, params: &Params, initial: &State, _t: f64) -> Result<Option<State>, Error> {
        check(self.coordinates.len(), initial.q.len(), initial.qdot.len())?;
        self.values(params)?;
        Ok(None)
    }

    fn conserved_quantities(&self, params: &Params) -> Result<Vec<Conserved>, Error> {
        self.values(params)?;
        Ok(Vec::new())
    }

    fn joint_graph(&self, params: &Params) -> Result<Option<JointGraph>, Error> {
        self.values(params)?;
        Ok(None)
    }

    fn rapier_deviations(&self, _multibody: bool) -> &'static [RapierDeviation] {
        &[]
    }

    fn body_poses(&self, params: &Params, states: &[(f64, &[f64])]) -> Result<Option<Vec<Vec<[f64; 3]>>>, Error> {
        let Compiled::Bodies(mechanism, _) = self.compiled(params)? else { return Ok(None) };
        let bodies = lagrange::Mechanism::description(&mechanism).bodies.len();
        let mut poses = vec![lagrange::Pose::<f64>::default(); bodies];
        states
            .iter()
            .map(|&(t, q)| {
                if q.len() != self.coordinates.len() {
                    return Err(Error::DimensionMismatch { what: "q", expected: self.coordinates.len(), got: q.len() });
                }
                lagrange::Mechanism::poses(&mechanism, t, q, &mut poses);
                Ok(poses.iter().map(|p| [p.x, p.y, p.angle]).collect())
            })
            .collect::<Result<Vec<_>, Error>>()
            .map(Some)
    }
}

fn check(n: usize, q: usize, qdot: usize) -> Result<(), Error> {
    for (what, got) in [("q", q), ("q̇", qdot)] {
        if got != n {
            return Err(Error::DimensionMismatch { what, expected: n, got });
        }
    }
    Ok(())
}
