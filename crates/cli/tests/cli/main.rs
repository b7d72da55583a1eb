//! The `lagrange` command line as a user runs it, one module per surface; with the browser check
//! of the animation pages and the Python package's pytest suite, which run against this build of
//! the command. One test binary (`cargo test -p lagrange-cli --test cli -- MODULE::` runs one
//! module).

mod browser;
mod commands;
mod files;
mod outputs;
mod python;
mod report;
mod robustness;
