//! Figures: every plot is drawn with `plotters` (SVG backend), so axes, tick
//! labels and legends have one implementation; images are PNG through the
//! `png` crate ([`image`]). Formatting only: each function takes the numbers
//! an experiment computed and returns the file's bytes.

pub mod image;
pub mod multi;
mod plot;
mod scatter;

pub use plot::{loglog, radial, LogLog, Point, PowerLaw, Radial};
pub use scatter::{scatter, MAX_SCATTER_POINTS};
