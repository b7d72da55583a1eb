//! `lagrange report`: the validation report. Every scene (all by default) is simulated to a
//! fixed horizon by every method — the reduced solver's RK4 and variational integrators over
//! steps and its adaptive integrator over tolerances, the Cartesian + multiplier solver over
//! tolerances, and rapier's impulse and multibody joints in f64 and f32 over `dt` and substeps
//! where rapier can build the scene — and measured against the scene's reference: its error
//! over the saved times, its energy error where energy is conserved, its constraint violation
//! where it has one, and its wall time. The summary reads off the work-precision fronts how much
//! smaller our error is than rapier's at equal wall time and how much less time we take at equal
//! error (docs/validation.md#metrics, #targets).
//!
//! After the scenes, a stability section ([`stability`]) runs its cases — stiff springs and
//! strong damping against the methods' stability functions, extreme parameters, a Kepler orbit
//! at `e = 0.99`, chaos, near-singular configurations, long runs, bad input — each measurement
//! checked against theory or a derived bound (the cases involving the `--scene` scenes only).
//!
//! Output (`--out DIR`, default `report/`): `report.json` (schema in
//! `crates/cli/REPORT_SCHEMA.md`), `report.md`, `index.html`, and per scene
//! `<scene>_work_precision.svg`, `<scene>_error.svg` and the animation `<scene>.html`; a summary
//! on standard output and a progress bar on standard error. The scenes run on `--jobs` threads
//! (default: the number of cores), the results the same whatever their number.
//!
//! The pipeline: [`options`] here → the validation library's [`plan`], [`runs`] (with
//! [`reference`] and [`measure`]), [`assemble`] (with [`pareto`]) and [`schema`] → the library's
//! [`render`] (Markdown, SVG plots, the terminal summary; its stability section too); the
//! library's [`stability`] for the stability section; [`driver`] runs it and writes the files.
//!
//! [`plan`]: lagrange_validation::plan
//! [`runs`]: lagrange_validation::runs
//! [`reference`]: lagrange_validation::reference
//! [`measure`]: lagrange_validation::measure
//! [`assemble`]: lagrange_validation::assemble
//! [`pareto`]: lagrange_validation::pareto
//! [`schema`]: lagrange_validation::schema
//! [`stability`]: lagrange_validation::stability
//! [`render`]: lagrange_validation::render

mod driver;
mod options;

pub use driver::run;
pub use options::Args;
