//! The frames of an animation: a scene's motion as body poses over time, from the reduced
//! solution and from each maximal engine's run — the same runs [`compare`] makes, sampled
//! finely — with each engine's error against time; or a normal mode's linear motion beside the
//! nonlinear motion it predicts. [`render::animation`](crate::render::animation) writes it as
//! one self-contained HTML page (docs/animation.md).
//!
//! ```
//! use lagrange_maximal::{Engine, Settings};
//! use lagrange_validation::animation::animate;
//!
//! let scene = lagrange_validation::scene("double_pendulum")?;
//! let params = scene.default_params();
//! let initial = scene.default_state(&params)?;
//! let settings = Settings::default();
//! let animation = animate(scene, &params, &initial, &[Engine::Cartesian], &settings, 0.5)?;
//! assert_eq!(animation.tracks.len(), 2); // the reduced solution and the Cartesian engine
//! assert!(animation.tracks.iter().all(|t| t.poses.len() == t.times.len() && t.times.len() > 25));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::Error;
use crate::compare::compare;
use crate::plan::{REFERENCE_TOLERANCE, reference_method};
use crate::reference::closed_form;
use lagrange::modes::{ModeKind, normal_modes};
use lagrange::{Output, State};
use lagrange_maximal::maps::ReadBack;
use lagrange_maximal::{BuildError, Engine, Settings, Sketch, sketch};
use lagrange_scenes::{Params, Scene};
use lagrange_testing::max_abs_diff;
use serde::Serialize;

/// Frames per second of simulated time when the run is short enough.
pub const FRAME_RATE: f64 = 60.0;

/// The most frames an animation carries (a longer run is sampled more sparsely).
pub const MAX_FRAMES: usize = 1200;

/// A motion to draw: the scene's sketch and one track of poses per solution.
#[derive(Clone, Debug, Serialize)]
pub struct Animation {
    /// The scene's id.
    pub scene: String,
    /// Its title.
    pub title: String,
    /// The bodies' names, in the order of every frame's poses.
    pub bodies: Vec<String>,
    /// How the mechanism is drawn.
    pub sketch: Sketch,
    /// What the tracks' errors are measured against, in words.
    pub reference: String,
    /// The tracks: first the reduced solution (or, for a mode, its linear motion), then each
    /// engine asked for.
    pub tracks: Vec<Track>,
}

/// One solution's motion.
#[derive(Clone, Debug, Serialize)]
pub struct Track {
    /// `reduced`, an engine's name, or the motion of a mode.
    pub label: String,
    /// The times of the frames (s).
    pub times: Vec<f64>,
    /// The body poses `(x, y, φ)` at each time.
    pub poses: Vec<Vec<[f64; 3]>>,
    /// `‖q − q_ref‖∞` at each time (m or rad) against [`Animation::reference`], where measured.
    pub errors: Option<Vec<f64>>,
    /// Why an engine has no frames (it cannot build the scene), or where its build departs
    /// from the scene.
    pub note: Option<String>,
}

/// The most frames a short run gets: a run shorter than `MIN_FRAMES / FRAME_RATE` seconds (a
/// squeezer's 30 ms) is sampled this often, to be played slowed down.
pub const MIN_FRAMES: usize = 300;

/// The interval between frames over a run from `t0` to `t_end`: 1/[`FRAME_RATE`] s, longer
/// when that would make more than [`MAX_FRAMES`] frames, shorter when it would make fewer than
/// [`MIN_FRAMES`]. (A rapier run is sampled on its own step grid, [`compare`]'s, at most this
/// often.)
pub fn frame_interval(t0: f64, t_end: f64) -> f64 {
    let span = t_end - t0;
    (span / MAX_FRAMES as f64).max((1.0 / FRAME_RATE).min(span / MIN_FRAMES as f64))
}

/// The animation of `scene` from `initial` to `t_end`: the reduced solution at the report's
/// reference tolerance, and each of `engines` run as [`compare`] runs it (an engine that cannot
/// build the scene gets a track without frames, with the reason), every [`frame_interval`].
/// Errors are `compare`'s: against the scene's closed form where it has one, otherwise the
/// reduced solution; the reduced track's own error is shown against the closed form.
///
/// # Errors
/// A scene that places no bodies ([`Error::Undrawable`]), the reduced run's failure
/// ([`Error::Reference`]), or an engine's failure other than being unable to build the scene.
pub fn animate(
    scene: &dyn Scene,
    params: &Params,
    initial: &State,
    engines: &[Engine],
    settings: &Settings,
    t_end: f64,
) -> Result<Animation, Error> {
    let every = frame_interval(initial.t, t_end);
    let count = ((t_end - initial.t) / every).round() as usize;
    let times: Vec<f64> = (0..=count).map(|k| initial.t + k as f64 * every).collect();
    let system = scene.build(params)?;
    // The scene's read-back places the bodies (resolved once), where it has one.
    let read_back = ReadBack::new(scene, params).ok();
    let run = system
        .simulate(initial, *times.last().unwrap_or(&initial.t), reference_method(), &Output::Times(times.clone()))
        .map_err(|source| Error::Reference { scene: scene.id().to_string(), source })?;
    let coordinates: Vec<&[f64]> = (0..times.len()).map(|k| run.q(k)).collect();
    let exact = closed_form(scene, params, initial, &times)?;
    let errors = exact.as_ref().map(|exact| coordinates.iter().zip(exact).map(|(q, e)| max_abs_diff(q, e)).collect());
    let reference = if exact.is_some() {
        "the scene's closed form".to_string()
    } else {
        format!("the reduced solution (dop853, tol {REFERENCE_TOLERANCE:e})")
    };
    let poses = place((scene, params, read_back.as_ref()), &times, &coordinates)?;
    let mut tracks = vec![Track { label: "reduced".into(), times: times.clone(), poses, errors, note: None }];
    for &engine in engines {
        let track = match compare(engine, scene, params, initial, settings, t_end, every) {
            Ok(c) => Track {
                label: engine.name().into(),
                times: c.times,
                poses: c.poses,
                errors: Some(c.errors),
                note: (!c.deviations.is_empty()).then(|| c.deviations.join("; ")),
            },
            Err(Error::Build(BuildError::Unbuildable { reason, .. })) => Track {
                label: engine.name().into(),
                times: Vec::new(),
                poses: Vec::new(),
                errors: None,
                note: Some(reason),
            },
            Err(error) => return Err(error),
        };
        tracks.push(track);
    }
    Ok(Animation {
        scene: scene.id().into(),
        title: scene.title().into(),
        bodies: body_names(read_back.as_ref(), system.bodies()),
        sketch: sketch(scene, params)?,
        reference,
        tracks,
    })
}

/// The animation of normal mode `index` (0: lowest `ω²`) about the equilibrium nearest `q`
/// ([`lagrange::modes::normal_modes`]): the linear motion `q* + a v cos ωt` (mode shape `v`
/// scaled to a largest entry of 1) and the nonlinear motion from `q* + a v` at rest (put back
/// on the constraints of a loop), from `t0` to `t_end` (default: four periods of the mode), the
/// nonlinear track's error measured against the linear motion — which it approaches as `a²`
/// (docs/method.md#normal-modes).
///
/// # Errors
/// No equilibrium near `q` ([`lagrange::Error::NoEquilibrium`]); no mode `index`, or a zero or
/// unstable mode ([`Error::Mode`]); a failing run.
pub fn animate_mode(
    scene: &dyn Scene,
    params: &Params,
    (t0, q): (f64, &[f64]),
    index: usize,
    amplitude: f64,
    t_end: Option<f64>,
) -> Result<Animation, Error> {
    let mut system = scene.build(params)?;
    // The scene's read-back places the bodies (resolved once), where it has one.
    let read_back = ReadBack::new(scene, params).ok();
    let modes = normal_modes(system.as_mut(), t0, q)?;
    let count = modes.modes.len();
    let mode = modes.modes.get(index).ok_or_else(|| Error::Mode {
        index,
        why: format!("the mechanism has {count} mode{} (0 to {})", if count == 1 { "" } else { "s" }, count.max(1) - 1),
    })?;
    match mode.kind {
        ModeKind::Oscillating => {}
        ModeKind::Zero => {
            return Err(Error::Mode {
                index,
                why: "is a zero mode (ω² = 0): a free motion, not an oscillation".into(),
            });
        }
        ModeKind::Unstable => {
            let why = format!("is unstable (ω² = {:.6e}): the equilibrium is not a resting state", mode.omega_squared);
            return Err(Error::Mode { index, why });
        }
    }
    let omega = mode.omega();
    let t_end = t_end.unwrap_or(t0 + 4.0 * std::f64::consts::TAU / omega);
    let n = modes.equilibrium.len();
    let every = frame_interval(t0, t_end);
    let frames = ((t_end - t0) / every).round() as usize;
    let times: Vec<f64> = (0..=frames).map(|k| t0 + k as f64 * every).collect();
    let linear: Vec<Vec<f64>> = times
        .iter()
        .map(|t| {
            let c = amplitude * (omega * (t - t0)).cos();
            modes.equilibrium.iter().zip(&mode.shape).map(|(q, v)| q + c * v).collect()
        })
        .collect();
    let mut start = State::new(t0, linear[0].clone(), vec![0.0; n]);
    if system.constraint_counts() != (0, 0) {
        // The displaced state back on the loop's constraints (an O(a²) correction), holding the
        // coordinate the mode moves most.
        let most = (0..n).fold(0, |m, i| if mode.shape[i].abs() > mode.shape[m].abs() { i } else { m });
        let held: Vec<bool> = (0..n).map(|i| i == most).collect();
        start = system.assemble(&start, &held)?;
    }
    let run = system
        .simulate(&start, *times.last().unwrap_or(&t0), reference_method(), &Output::Times(times.clone()))
        .map_err(|source| Error::Reference { scene: scene.id().to_string(), source })?;
    let nonlinear: Vec<&[f64]> = (0..times.len()).map(|k| run.q(k)).collect();
    let errors = nonlinear.iter().zip(&linear).map(|(q, l)| max_abs_diff(q, l)).collect();
    let linear_refs: Vec<&[f64]> = linear.iter().map(Vec::as_slice).collect();
    let label = format!("mode {index} (linear, ω = {omega:.6} rad/s)");
    let tracks = vec![
        Track {
            label,
            times: times.clone(),
            poses: place((scene, params, read_back.as_ref()), &times, &linear_refs)?,
            errors: None,
            note: None,
        },
        Track {
            label: "nonlinear (reduced)".into(),
            times: times.clone(),
            poses: place((scene, params, read_back.as_ref()), &times, &nonlinear)?,
            errors: Some(errors),
            note: Some(format!("released at rest from the equilibrium displaced by {amplitude} × the mode shape")),
        },
    ];
    Ok(Animation {
        scene: scene.id().into(),
        title: format!("{} — normal mode {index}", scene.title()),
        bodies: body_names(read_back.as_ref(), system.bodies()),
        sketch: sketch(scene, params)?,
        reference: format!("the linear motion of mode {index}"),
        tracks,
    })
}

/// The bodies' names: the maximal description's (a raw Lagrangian's particle has one there),
/// else the system's.
fn body_names(read_back: Option<&ReadBack>, bodies: &[lagrange::Body]) -> Vec<String> {
    read_back.map_or(bodies, ReadBack::bodies).iter().map(|b| b.name.clone()).collect()
}

/// The body poses at each `(times[k], coordinates[k])`: read back through the scene's maximal
/// description, or placed by the scene's own poses (a scene file).
fn place(
    (scene, params, read_back): (&dyn Scene, &Params, Option<&ReadBack>),
    times: &[f64],
    coordinates: &[&[f64]],
) -> Result<Vec<Vec<[f64; 3]>>, Error> {
    if let Some(read_back) = read_back {
        return times
            .iter()
            .zip(coordinates)
            .map(|(&t, q)| {
                let state = State::new(t, q.to_vec(), vec![0.0; q.len()]);
                Ok(read_back.body_states(&state)?.iter().map(|b| b.pose).collect())
            })
            .collect();
    }
    let states: Vec<(f64, &[f64])> = times.iter().copied().zip(coordinates.iter().copied()).collect();
    scene.body_poses(params, &states)?.ok_or_else(|| Error::Undrawable { scene: scene.id().into() })
}
