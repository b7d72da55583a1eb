//! The reference trajectory every run of a scene is measured against: the scene's closed form
//! where it has one, otherwise a tight-tolerance reduced solution.

use crate::Error;
use crate::fixtures::max_abs_diff;
use crate::plan::REFERENCE_TOLERANCE;
use lagrange::{Method, Output, State, Tolerances};
use lagrange_scenes::{Params, Scene};

/// Where a reference comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReferenceKind {
    /// The scene's exact solution (`Scene::exact_solution`) at every saved time.
    ClosedForm,
    /// The reduced solver's adaptive integrator at [`REFERENCE_TOLERANCE`].
    ReducedAdaptive,
}

impl ReferenceKind {
    /// `closed_form` or `reduced_adaptive`.
    pub fn name(self) -> &'static str {
        match self {
            ReferenceKind::ClosedForm => "closed_form",
            ReferenceKind::ReducedAdaptive => "reduced_adaptive",
        }
    }

    /// The tolerance of a computed reference.
    pub fn tolerance(self) -> Option<f64> {
        match self {
            ReferenceKind::ClosedForm => None,
            ReferenceKind::ReducedAdaptive => Some(REFERENCE_TOLERANCE),
        }
    }
}

/// `q_ref` at the saved times of one scene with one parameter set.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    /// The parameters it solves (the scene's, or an engine's deviation of them).
    pub params: Params,
    /// Where it comes from.
    pub kind: ReferenceKind,
    /// `q_ref` at each saved time (samples × n).
    pub q: Vec<Vec<f64>>,
}

impl Reference {
    /// The reference of `scene` with `params` from `initial` at `times`: the closed form when it
    /// covers every saved time, otherwise the reduced solution at [`REFERENCE_TOLERANCE`].
    ///
    /// # Errors
    /// Invalid parameters, or a failing reference run.
    pub fn new(scene: &dyn Scene, params: &Params, initial: &State, times: &[f64]) -> Result<Reference, Error> {
        let context = |source| Error::Reference { scene: scene.id().to_string(), source };
        let mut exact = Vec::with_capacity(times.len());
        for &t in times {
            match scene.exact_solution(params, initial, t).map_err(context)? {
                Some(state) => exact.push(state.q),
                None => break,
            }
        }
        if exact.len() == times.len() {
            return Ok(Reference { params: params.clone(), kind: ReferenceKind::ClosedForm, q: exact });
        }
        let system = scene.build(params).map_err(context)?;
        let t_end = times.last().copied().unwrap_or(initial.t);
        let method = Method::Adaptive { tol: Tolerances::uniform(REFERENCE_TOLERANCE) };
        let trajectory = system.simulate(initial, t_end, method, &Output::Times(times.to_vec())).map_err(context)?;
        let q = (0..trajectory.len()).map(|k| trajectory.q(k).to_vec()).collect();
        Ok(Reference { params: params.clone(), kind: ReferenceKind::ReducedAdaptive, q })
    }

    /// `‖q − q_ref‖∞` at saved time `k`.
    pub fn error(&self, k: usize, q: &[f64]) -> f64 {
        max_abs_diff(q, &self.q[k])
    }
}

/// References by parameter set: the scene's own, and one per deviation an engine needs.
#[derive(Debug, Default)]
pub struct References {
    /// Computed so far.
    known: Vec<Reference>,
}

impl References {
    /// The reference for `params`, computed on first use.
    ///
    /// # Errors
    /// As [`Reference::new`].
    pub fn get(
        &mut self,
        scene: &dyn Scene,
        params: &Params,
        initial: &State,
        times: &[f64],
    ) -> Result<&Reference, Error> {
        let index = match self.known.iter().position(|r| &r.params == params) {
            Some(index) => index,
            None => {
                self.known.push(Reference::new(scene, params, initial, times)?);
                self.known.len() - 1
            }
        };
        Ok(&self.known[index])
    }
}
