//! The animation's frames (`lagrange_validation::animation`) and its page: every scene animates
//! in every engine that builds it, the frames are the motion (against a closed form), a page is
//! self-contained and small, and a normal mode plays beside the nonlinear motion it predicts.

use lagrange_maximal::maps::ReadBack;
use lagrange_maximal::sketch::{Anchor, Figure};
use lagrange_maximal::{BuildError, Engine, Settings, build};
use lagrange_scenes::all;
use lagrange_validation::Error;
use lagrange_validation::animation::{Animation, animate, animate_mode, frame_interval};
use lagrange_validation::render::animation::page;

use lagrange_tests::scene;

/// The JSON data a page carries, parsed back.
fn page_data(html: &str) -> serde_json::Value {
    let start = html.find(r#"<script id="data" type="application/json">"#).expect("the data element") + 42;
    let end = start + html[start..].find("</script>").expect("its end");
    serde_json::from_str(&html[start..end].replace("<\\/", "</")).expect("the data is JSON")
}

/// Every anchor of the sketch names a body that exists, and there is one figure per body.
fn check_sketch(animation: &Animation) {
    let bodies = animation.bodies.len();
    assert_eq!(animation.sketch.bodies.len(), bodies, "{}: one figure per body", animation.scene);
    let anchors = animation.sketch.links.iter().flat_map(|l| [&l.a, &l.b]).chain(&animation.sketch.pins);
    for anchor in anchors.chain(animation.sketch.slides.iter().map(|s| &s.at)) {
        if let Anchor::Body { body, .. } = anchor {
            assert!(*body < bodies, "{}: an anchor on body {body} of {bodies}", animation.scene);
        }
    }
    for figure in &animation.sketch.bodies {
        let size = match figure {
            Figure::Dot => 1.0,
            Figure::Disc { radius } => *radius,
            Figure::Rectangle { half_extents } => half_extents[0].min(half_extents[1]),
            Figure::Link { points } => points.len() as f64 - 1.0,
        };
        assert!(size > 0.0 && size.is_finite(), "{}: a figure with nothing to draw: {figure:?}", animation.scene);
    }
}

#[test]
fn every_scene_animates_in_every_engine_that_builds_it() {
    let settings = Settings::default();
    for &scene in all() {
        let params = scene.default_params();
        let initial = scene.default_state(&params).unwrap();
        // A second of motion, or the scene's own span (the squeezer's 30 ms).
        let t_end = initial.t + scene.horizon().unwrap_or(1.0).min(1.0);
        let animation = animate(scene, &params, &initial, &Engine::ALL, &settings, t_end)
            .unwrap_or_else(|e| panic!("{}: {e}", scene.id()));
        check_sketch(&animation);
        assert_eq!(animation.tracks.len(), 1 + Engine::ALL.len());
        let reduced = &animation.tracks[0];
        assert_eq!(reduced.label, "reduced");
        // The first frame is the initial state's bodies.
        let read_back = ReadBack::new(scene, &params).unwrap();
        let start: Vec<[f64; 3]> = read_back.body_states(&initial).unwrap().iter().map(|b| b.pose).collect();
        // A point mass's angle is no part of the motion (a polar build turns the particle with
        // its arm): positions only.
        let compared: Vec<usize> = read_back.bodies().iter().map(|b| if b.inertia == 0.0 { 2 } else { 3 }).collect();
        assert_eq!(reduced.poses[0], start, "{}", scene.id());
        for (engine, track) in Engine::ALL.iter().zip(&animation.tracks[1..]) {
            assert_eq!(track.label, engine.name());
            match build(*engine, scene, &params, &initial, &settings) {
                Err(BuildError::Unbuildable { reason, .. }) => {
                    assert!(
                        track.times.is_empty(),
                        "{} {engine}: frames from an engine that cannot build it",
                        scene.id()
                    );
                    assert_eq!(track.note.as_deref(), Some(reason.as_str()));
                }
                Err(e) => panic!("{} {engine}: {e}", scene.id()),
                Ok(_) => {
                    // At least one frame per rapier step or 1/60 s, over the whole run.
                    assert!(track.times.len() >= 8, "{} {engine}: {} frames", scene.id(), track.times.len());
                    assert!((track.times.last().unwrap() - t_end).abs() <= settings.dt, "{} {engine}", scene.id());
                    assert_eq!(track.poses.len(), track.times.len());
                    assert_eq!(track.errors.as_ref().map(Vec::len), Some(track.times.len()));
                    for frame in &track.poses {
                        assert_eq!(frame.len(), animation.bodies.len());
                        assert!(frame.iter().flatten().all(|v| v.is_finite()), "{} {engine}", scene.id());
                    }
                    // Every engine starts from the same bodies (to round-off of the build's
                    // own placement, e.g. rapier's f32 poses).
                    let gap = track.poses[0]
                        .iter()
                        .zip(&start)
                        .zip(&compared)
                        .flat_map(|((a, b), &n)| (0..n).map(move |c| (a[c] - b[c]).abs()));
                    let gap = gap.fold(0.0, f64::max);
                    let roundoff = if engine.name().ends_with("f32") { 1e-6 } else { 1e-12 };
                    assert!(gap <= roundoff, "{} {engine}: first frame {gap:e} from the initial bodies", scene.id());
                }
            }
        }
        // The page carries every track's frames and fetches nothing.
        let html = page(&animation);
        for external in ["http://", "https://", " src=", "@import", "url("] {
            assert!(!html.contains(external), "{}: the page refers to something outside it ({external})", scene.id());
        }
        let data = page_data(&html);
        for (track, parsed) in animation.tracks.iter().zip(data["tracks"].as_array().unwrap()) {
            assert_eq!(parsed["poses"].as_array().unwrap().len(), track.poses.len());
        }
    }
}

#[test]
fn the_frames_are_the_motion() {
    // The harmonic oscillator's closed form x₀ cos ωt, against the reduced and Cartesian tracks'
    // mass position frame by frame: the frames are at their times, of the right body.
    let s = scene("harmonic_oscillator");
    let params = s.default_params();
    let initial = s.default_state(&params).unwrap();
    let (k, m) = (params.get("stiffness"), params.get("mass"));
    let omega = (k / m).sqrt();
    let animation = animate(s, &params, &initial, &[Engine::Cartesian], &Settings::default(), 5.0).unwrap();
    for track in &animation.tracks {
        let mut worst = 0.0_f64;
        for (t, frame) in track.times.iter().zip(&track.poses) {
            let x = initial.q[0] * (omega * t).cos();
            worst = worst.max((frame[0][0] - x).abs());
        }
        // dop853 at 3e-15 and the Cartesian engine at 1e-12 over 3.6 periods: global errors
        // of 1e-13 and 1e-10 measured; 1e-8 leaves two orders for the Cartesian one.
        assert!(worst < 1e-8, "{}: {worst:e} from x₀ cos ωt", track.label);
        assert_eq!(track.times.len(), 301, "{}: 60 frames a second over 5 s", track.label);
    }
}

#[test]
fn a_ten_second_chain_page_stays_under_two_megabytes() {
    let s = scene("chain");
    let params = s.default_params();
    let initial = s.default_state(&params).unwrap();
    let animation = animate(s, &params, &initial, &Engine::ALL, &Settings::default(), 10.0).unwrap();
    let html = page(&animation);
    assert!(animation.tracks.iter().all(|t| t.times.len() == 601), "60 frames a second over 10 s");
    assert!(html.len() < 2_000_000, "{} bytes", html.len());
}

#[test]
fn a_mode_plays_beside_the_nonlinear_motion_it_predicts() {
    // The double pendulum's faster mode: the nonlinear run from q* + a v at rest stays within
    // O(a²)·a of the linear motion (measured gap 7e-6 at a = 0.01 over four periods); halving a
    // divides the gap by 4 or more (second-order terms, or third for a symmetric potential).
    let s = scene("double_pendulum");
    let params = s.default_params();
    let gap = |amplitude: f64| {
        let animation = animate_mode(s, &params, (0.0, &[0.0, 0.0]), 1, amplitude, Some(4.0)).unwrap();
        check_sketch(&animation);
        assert_eq!(animation.tracks.len(), 2);
        let nonlinear = &animation.tracks[1];
        nonlinear.errors.as_ref().unwrap().iter().copied().fold(0.0, f64::max)
    };
    let (big, small) = (gap(0.02), gap(0.01));
    assert!(small < 0.02 * 0.01, "gap {small:e} at a = 0.01");
    assert!(big / small > 3.5, "halving the amplitude: {big:e} → {small:e}");
}

#[test]
fn a_mode_that_does_not_oscillate_is_refused() {
    let cart = scene("cart_pendulum");
    let params = cart.default_params();
    let q = cart.default_state(&params).unwrap().q;
    // Mode 0 is the free cart's translation; there are two modes.
    let zero = animate_mode(cart, &params, (0.0, &q), 0, 0.1, Some(1.0)).unwrap_err();
    assert!(matches!(zero, Error::Mode { index: 0, .. }) && zero.to_string().contains("zero mode"), "{zero}");
    let missing = animate_mode(cart, &params, (0.0, &q), 2, 0.1, Some(1.0)).unwrap_err();
    assert!(missing.to_string().contains("has 2 modes"), "{missing}");
    // Without an end, four periods of ω² = g (M + m)/(M r).
    let played = animate_mode(cart, &params, (0.0, &q), 1, 0.1, None).unwrap();
    let (g, big, small, r) =
        (params.get("gravity"), params.get("cart_mass"), params.get("bob_mass"), params.get("rod_length"));
    let four_periods = 4.0 * std::f64::consts::TAU / (g * (big + small) / (big * r)).sqrt();
    let end = *played.tracks[0].times.last().unwrap();
    // Frames lie on their own grid (1/60 s here): the last is the one nearest the span's end.
    let half_frame = 0.5 * frame_interval(0.0, four_periods);
    assert!((end - four_periods).abs() <= half_frame * (1.0 + 1e-9), "{end} vs {four_periods}");
    // No equilibrium at all.
    let kepler = scene("kepler");
    let params = kepler.default_params();
    let error = animate_mode(kepler, &params, (0.0, &[1.0, 0.0]), 0, 0.1, Some(1.0)).unwrap_err();
    assert!(matches!(error, Error::Engine(lagrange::Error::NoEquilibrium { .. })), "{error}");
    // Upright four-bar: its one mode is unstable.
    let four_bar = scene("four_bar");
    let params = four_bar.default_params();
    let q = four_bar.default_state(&params).unwrap().q;
    let unstable = animate_mode(four_bar, &params, (0.0, &q), 0, 0.1, Some(1.0)).unwrap_err();
    assert!(unstable.to_string().contains("unstable"), "{unstable}");
}
