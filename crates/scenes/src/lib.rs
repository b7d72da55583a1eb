//! # lagrange-scenes — the lecture's mechanical systems, and more, with their closed forms
//!
//! Every scene is a planar system described to the [`lagrange`] engine (bodies and their poses as
//! functions of the generalized coordinates, or a raw Lagrangian), which derives
//! `M(q, t) q̈ = f(q, q̇, t)` by automatic differentiation. Next to that description each scene
//! carries what the engine is checked against: hand-coded closed-form accelerations (no AD, no
//! engine) from `docs/scenes.md` (the lecture's systems derived independently) or from a derivation
//! in the scene's file, exact solutions where the motion has one, and conserved quantities.
//!
//! Each scene is one type (e.g. [`CartPendulum`]) with public fields named after the physics, a
//! validating constructor `new`, its parameter table `PARAMS` and extra closed forms, implementing
//! [`lagrange::Mechanism`] (or [`lagrange::Lagrangian`]) and [`SceneType`]: id, title,
//! parameters, `from_params`, default state, closed-form accelerations ([`ClosedForm`]), exact
//! solution and constants of the motion ([`Conserved`]). The scene types are listed once, in
//! [`for_each_scene!`]; from that list come the object-safe [`Scene`]s for code that picks
//! scenes by id at run time ([`all`], [`find`], [`ids`], [`scene_of`]) with [`Params`] set by
//! parameter name or lecture symbol, and [`visit_mechanism`], which runs a
//! [`MechanismVisitor`] on a scene's concrete mechanism type.
//! A new scene is its file here and one line in that list.
//!
//! # Scenes
//!
//! | id | system | coordinates | reference |
//! |---|---|---|---|
//! | `cart_pendulum` | pendulum on a movable support | `X`, `θ` | docs/scenes.md#cart_pendulum |
//! | `harmonic_oscillator` | mass on a spring, optional damping | `x` | §2 |
//! | `kepler` | central force `V = −k/r` | `r`, `θ` | §3a |
//! | `isotropic_oscillator` | central force `V = ½ k r²` | `r`, `θ` | §3b |
//! | `atwood` | Atwood machine, massive pulley | `x` | §4 |
//! | `double_atwood` | double Atwood machine | `x`, `x'` | §5 |
//! | `double_double_atwood` | two movable pulleys, four masses | `x`, `x'`, `x''` | §6 |
//! | `wedge` | block on a movable wedge | `x`, `x'` | §7 |
//! | `double_pendulum` | two point masses on rods | `θ1`, `θ2` | beyond the lecture |
//! | `chain` | `N` rigid links | `θ1` … `θN` | beyond the lecture |
//! | `spring_pendulum` | elastic pendulum | `r`, `θ` | beyond the lecture |
//! | `driven_pendulum` | horizontally driven support (rheonomic) | `θ` | beyond the lecture |
//! | `charged_particle` | uniform magnetic field (raw Lagrangian) | `x`, `y` | beyond the lecture |
//! | `nonminimal_pendulum` | pendulum in Cartesian coordinates, 1 holonomic constraint | `x`, `y` | docs/scenes.md#nonminimal_pendulum |
//! | `chaplygin_sleigh` | knife edge, 1 velocity constraint | `x`, `y`, `φ` | docs/scenes.md#chaplygin_sleigh |
//! | `rolling_disc` | disc rolling down an incline, 1 velocity constraint | `s`, `φ` | docs/scenes.md#rolling_disc |
//! | `four_bar` | crank-rocker four-bar, 2 loop constraints | `θ2`, `θ3`, `θ4` | docs/scenes.md#four_bar |
//! | `slider_crank` | slider-crank with flywheel, 2 loop constraints | `φ`, `ψ`, `x` | docs/scenes.md#slider_crank |
//! | `andrews_squeezer` | Andrews' squeezing mechanism, 6 loop constraints | `β`, `Θ`, `γ`, `Φ`, `δ`, `Ω`, `ε` | docs/scenes.md#andrews_squeezer |
//! | `parallelogram_chain` | `N` parallelogram windows, `2N` loop constraints (rank `N` lying flat) | `θ0`, `φ0`, … `θN` | docs/scenes.md#parallelogram_chain |
//! | `change_point_four_bar` | four-bar with `a + b = c + d`, flat once per turn | `θ2`, `θ3`, `θ4` | docs/scenes.md#change_point_four_bar |
//! | `redundant_parallelogram` | parallelogram with a third crank, a redundant loop row | `θ1`, `φ`, `θ2`, `θ3` | docs/scenes.md#redundant_parallelogram |
//!
//! Conventions follow docs/scenes.md: gravity `g` along −y, angles counter-clockwise, pendulum
//! angles from the downward vertical, pulley depths measured downward.
//!
//! # Example: the engine against the lecture's closed form
//!
//! ```
//! use lagrange::{Model, Buffered, System};
//! use lagrange_scenes::{CartPendulum, Scene};
//!
//! // Cart mass M = 2, bob mass m = 1, rod length r = 1.5, g = 9.81.
//! let cart_pendulum = CartPendulum::new(2.0, 1.0, 1.5, 9.81)?;
//! let (q, qdot) = ([0.0, 0.3], [0.1, 0.5]);
//! // Ẍ = m sinθ (r θ̇² + g cosθ) / (M + m sin²θ), and θ̈ (docs/scenes.md#cart_pendulum).
//! let closed_form = cart_pendulum.closed_form_accelerations(&q, &qdot);
//!
//! let mut system = Buffered::new(Model::new(cart_pendulum)?);
//! let engine = system.accelerations(0.0, &q, &qdot)?;
//! for (a, b) in engine.iter().zip(closed_form) {
//!     approx::assert_relative_eq!(*a, b, max_relative = 1e-12);
//! }
//!
//! // The same through the registry, with parameters set by symbol.
//! let scene = lagrange_scenes::find("cart_pendulum").expect("registered");
//! let mut params = scene.default_params();
//! params.set("r", 1.5)?;
//! let mut system = scene.build(&params)?;
//! let from_registry = system.accelerations(0.0, &q, &qdot)?.to_vec();
//! let closed_form = scene.closed_form_accelerations(&params, 0.0, &q, &qdot)?;
//! assert_eq!(closed_form.map(|a| a.len()), Some(from_registry.len()));
//! # Ok::<(), lagrange::Error>(())
//! ```

/// Call the macro `$callback` with every scene type, in registry order (the lecture's systems
/// followed by those beyond it): the one list of scenes, from which [`all`], [`find`], [`ids`]
/// and [`visit_mechanism`](crate::visit_mechanism) are generated, and which other crates use to
/// dispatch to their own per-scene descriptions (`$callback!(Type, Type, …)`, each a path).
#[macro_export]
macro_rules! for_each_scene {
    ($callback:ident) => {
        $callback! {
            $crate::CartPendulum,
            $crate::HarmonicOscillator,
            $crate::Kepler,
            $crate::IsotropicOscillator,
            $crate::Atwood,
            $crate::DoubleAtwood,
            $crate::DoubleDoubleAtwood,
            $crate::Wedge,
            $crate::DoublePendulum,
            $crate::Chain,
            $crate::SpringPendulum,
            $crate::DrivenPendulum,
            $crate::ChargedParticle,
            $crate::NonminimalPendulum,
            $crate::ChaplyginSleigh,
            $crate::RollingDisc,
            $crate::FourBar,
            $crate::SliderCrank,
            $crate::AndrewsSqueezer,
            $crate::ParallelogramChain,
            $crate::ChangePointFourBar,
            $crate::RedundantParallelogram
        }
    };
}

mod checks;
mod conserved;
mod elliptic;
mod graph_scene;
#[cfg(test)]
mod graph_tests;
mod linkage;
mod params;
mod pendulum;
mod scene;
#[cfg(test)]
mod testing;
mod uniform_acceleration;
mod visit;

pub mod andrews_squeezer;
pub mod atwood;
pub mod cart_pendulum;
pub mod chain;
pub mod change_point_four_bar;
pub mod chaplygin_sleigh;
pub mod charged_particle;
pub mod double_atwood;
pub mod double_double_atwood;
pub mod double_pendulum;
pub mod driven_pendulum;
pub mod four_bar;
pub mod harmonic_oscillator;
pub mod isotropic_oscillator;
pub mod kepler;
pub mod nonminimal_pendulum;
pub mod parallelogram_chain;
pub mod redundant_parallelogram;
pub mod rolling_disc;
pub mod slider_crank;
pub mod spring_pendulum;
pub mod wedge;

pub use andrews_squeezer::AndrewsSqueezer;
pub use atwood::Atwood;
pub use cart_pendulum::CartPendulum;
pub use chain::Chain;
pub use change_point_four_bar::{ChangePointCrank, ChangePointFourBar};
pub use chaplygin_sleigh::{ChaplyginSleigh, SleighMotion};
pub use charged_particle::ChargedParticle;
pub use conserved::{Conserved, Invariant};
pub use double_atwood::DoubleAtwood;
pub use double_double_atwood::DoubleDoubleAtwood;
pub use double_pendulum::DoublePendulum;
pub use driven_pendulum::DrivenPendulum;
pub use four_bar::{FourBar, FourBarCrank};
pub use graph_scene::{GraphScene, register};
pub use harmonic_oscillator::HarmonicOscillator;
pub use isotropic_oscillator::IsotropicOscillator;
pub use kepler::{Kepler, Orbit};
pub use nonminimal_pendulum::NonminimalPendulum;
pub use parallelogram_chain::ParallelogramChain;
pub use params::{Domain, ParamSpec, Params};
pub use redundant_parallelogram::RedundantParallelogram;
pub use rolling_disc::RollingDisc;
pub use scene::{RapierDeviation, SINGULAR_DEFAULT_MOTION, Scene, SceneType, all, find, ids, scene_of};
pub use slider_crank::{SliderCrank, SliderCrankCrank};
pub use spring_pendulum::SpringPendulum;
pub use visit::{ClosedForm, MechanismVisitor, unknown_scene, visit_mechanism};
pub use wedge::Wedge;
