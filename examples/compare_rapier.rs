//! A first look at how far rapier is from the exact answer: every lecture scene run for 10 s in
//! the reduced solver and in each maximal-coordinate engine (Cartesian with multipliers, rapier
//! impulse and multibody joints, f64 and f32), at rapier's `dt = 1/240` with 4 substeps.
//!
//! `cargo run --release -p lagrange-examples --example compare_rapier`
use lagrange_maximal::{BuildError, Engine, Settings};
use lagrange_validation::Error;
use lagrange_validation::compare::compare;

const LECTURE: [&str; 8] = [
    "cart_pendulum",
    "harmonic_oscillator",
    "kepler",
    "isotropic_oscillator",
    "atwood",
    "double_atwood",
    "double_double_atwood",
    "wedge",
];

fn main() -> Result<(), Error> {
    let settings = Settings::default();
    println!(
        "max ‖q − q_ref‖∞ over 10 s against the reduced solution (dop853, tol {:e}); energy: max |ΔE|/|E₀|\n",
        lagrange_validation::plan::REFERENCE_TOLERANCE
    );
    println!("{:<22} {:<21} {:>10} {:>10}  notes", "scene", "engine", "max error", "energy");
    for id in LECTURE {
        let scene = lagrange_validation::scene(id)?;
        let params = scene.default_params();
        let initial = scene.default_state(&params)?;
        for engine in Engine::ALL {
            match compare(engine, scene, &params, &initial, &settings, 10.0, 0.1) {
                Ok(c) => {
                    let energy = c.energy_drift.map_or("—".into(), |e| format!("{e:.1e}"));
                    println!(
                        "{id:<22} {:<21} {:>10.1e} {:>10}  {}",
                        engine.name(),
                        c.max_error,
                        energy,
                        c.deviations.join("; ")
                    );
                }
                Err(Error::Build(BuildError::Unbuildable { reason, .. })) => {
                    println!("{id:<22} {:<21} {:>10} {:>10}  not buildable: {reason}", engine.name(), "—", "—")
                }
                Err(e) => return Err(e),
            }
        }
    }
    Ok(())
}
