//! The reference trajectory every run of a scene is measured against: the scene's closed form
//! where it has one, otherwise a tight-tolerance reduced solution.

use crate::Error;
use crate::plan::{REFERENCE_TOLERANCE, reference_method};
use lagrange::{Output, State};
use lagrange_scenes::{Params, Scene};
use lagrange_testing::max_abs_diff;

/// Where a reference comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReferenceKind {
    /// The scene's exact solution (`Scene::exact_solution`) at every saved time.
    ClosedForm,
    /// The reduced solver at [`REFERENCE_TOLERANCE`] with [`reference_method`] (Dormand–Prince
    /// 8(5,3)).
    Reduced,
}

impl ReferenceKind {
    /// `closed_form` or `reduced_dop853`.
    pub fn name(self) -> &'static str {
        match self {
            ReferenceKind::ClosedForm => "closed_form",
            ReferenceKind::Reduced => "reduced_dop853",
        }
    }

    /// The tolerance of a computed reference.
    pub fn tolerance(self) -> Option<f64> {
        match self {
            ReferenceKind::ClosedForm => None,
            ReferenceKind::Reduced => Some(REFERENCE_TOLERANCE),
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
        if let Some(exact) = closed_form(scene, params, initial, times)? {
            return Ok(Reference { params: params.clone(), kind: ReferenceKind::ClosedForm, q: exact });
        }
        let system = scene.build(params).map_err(context)?;
        let t_end = times.last().copied().unwrap_or(initial.t);
        let trajectory =
            system.simulate(initial, t_end, reference_method(), &Output::Times(times.to_vec())).map_err(context)?;
        let q = (0..trajectory.len()).map(|k| trajectory.q(k).to_vec()).collect();
        Ok(Reference { params: params.clone(), kind: ReferenceKind::Reduced, q })
    }

    /// `‖q − q_ref‖∞` at saved time `k`.
    pub fn error(&self, k: usize, q: &[f64]) -> f64 {
        max_abs_diff(q, &self.q[k])
    }
}

/// `q` of the scene's exact solution (`Scene::exact_solution`) from `initial` at every time of
/// `times`, or `None` when the scene has none for this state at one of them.
///
/// # Errors
/// [`Error::Reference`] for invalid parameters.
pub fn closed_form(
    scene: &dyn Scene,
    params: &Params,
    initial: &State,
    times: &[f64],
) -> Result<Option<Vec<Vec<f64>>>, Error> {
    let mut exact = Vec::with_capacity(times.len());
    for &t in times {
        match scene
            .exact_solution(params, initial, t)
            .map_err(|source| Error::Reference { scene: scene.id().to_string(), source })?
        {
            Some(state) => exact.push(state.q),
            None => return Ok(None),
        }
    }
    Ok(Some(exact))
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

/// A solution published by others for a scene's default state, at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Published {
    /// Where it is published.
    pub source: &'static str,
    /// The time of the published solution (s).
    pub t: f64,
    /// The published coordinates.
    pub q: &'static [f64],
}

/// The published solution of a scene's default state, where one exists: Andrews' squeezer at
/// `t = 0.03` (the CWI/Bari IVP test set).
pub fn published(scene: &str) -> Option<Published> {
    (scene == "andrews_squeezer").then_some(Published {
        source: "CWI/Bari IVP test set, problem andrews (PSIDE, tol 1e-14; about 3e-10 relative)",
        t: crate::andrews::T_END,
        q: &crate::andrews::PUBLISHED_AT_0_03[0],
    })
}

impl Reference {
    /// `max_i |q_i − q_i^pub| / |q_i^pub|` between this reference and the published solution,
    /// when the published time is one of `times` (to 1e-12 relative).
    pub fn published_agreement(&self, published: &Published, times: &[f64]) -> Option<f64> {
        let k = times.iter().position(|&t| (t - published.t).abs() <= 1e-12 * published.t.abs().max(1.0))?;
        Some(self.q[k].iter().zip(published.q).map(|(a, b)| ((a - b) / b).abs()).fold(0.0, f64::max))
    }
}
