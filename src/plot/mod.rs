//! Charts (SVG, and PNG with an embedded font): the float-rank stability
//! study, the finite-size scaling of the thresholds, variants of a study
//! against each other, the forced-plane scan, and rod systems themselves.
//!
//! Text is rendered with a font compiled into the binary (Ubuntu Light from
//! `epaint_default_fonts`, through plotters' `ab_glyph` feature), so PNG
//! output needs no system font library: it works on any machine with cargo.

mod bias;
mod chart;
mod compare;
mod horizon;
mod paired;
mod planes;
pub mod rods;
mod stability;
mod stiffening;
mod threshold;
mod transition;
pub use bias::bias_chart;
pub use compare::{compare_chart, speed_accuracy_chart, speed_accuracy_gammas};
pub use horizon::horizon_chart;
pub use paired::paired_chart;
pub use planes::forced_planes_chart;
pub use stability::stability_chart;
pub use stiffening::stiffening_chart;
pub use threshold::{VexSeries, study_charts, threshold_charts, threshold_vs_vex};
pub use transition::transition_chart;
