//! One module per subcommand, and two they share: [`files`] (output written whole or not at
//! all) and [`long_work`] (cost estimates, refusals of absurd requests, progress bars).

pub mod accel;
pub mod animate;
pub mod compare;
pub mod eom;
pub mod files;
pub mod long_work;
pub mod modes;
pub mod report;
pub mod scenes;
pub mod simulate;
