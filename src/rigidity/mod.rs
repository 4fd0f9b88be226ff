//! Exact generic rigidity of a typed pattern (MODEL §2–§4), in the order
//! the verdict is built:
//!
//! * [`incidence`] — lines, contact points and plane groupings of a pattern;
//! * [`construction`] — exact realizations over F_p (and floats), plane by
//!   plane and line by line;
//! * [`projection`] — a float realization by Levenberg–Marquardt where no
//!   rational construction order exists;
//! * [`family`] — realization families, their dimensions and which are
//!   components;
//! * [`framework`] — the point-based rigidity matrix at a realization;
//! * [`verdict`] — rigid, flexible or component-dependent over every
//!   component, exactly or by floats.

pub mod construction;
pub mod family;
pub mod framework;
pub mod incidence;
pub mod projection;
pub mod rank;
pub mod verdict;

pub use verdict::{ComponentReport, Ranker, Verdict, check_exact, check_float, exact_class};
