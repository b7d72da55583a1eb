//! One module per subcommand.

pub mod accel;
pub mod compare;
pub mod report;
pub mod scenes;
pub mod simulate;
