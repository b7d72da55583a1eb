//! The report rendered, for any front end: the Markdown report ([`markdown::render`]) with its
//! stability section ([`stability::markdown`]), the terminal summary ([`terminal::render`]) and the comparison table of `lagrange compare` ([`terminal::comparison`]), the scene catalogue ([`terminal::catalogue`]),
//! the SVG plots of a scene ([`plots::work_precision`], [`plots::errors_over_time`]), an animation as an HTML page ([`animation::page`]) and the report's front page ([`index::page`]). Each
//! returns text; writing files is the caller's.

pub mod animation;
mod cells;
pub mod index;
pub mod markdown;
pub mod plots;
pub mod stability;
pub mod terminal;
