//! The integration tests: one binary, one module per concern.

mod charts;
mod cli;
mod contacts;
mod defects;
mod engine;
mod enumerate;
mod float;
mod fss;
mod graphio;
mod layers;
mod projection;
mod rank;
mod rigidity;
mod rulefiles;
mod rules;
mod sample;
mod spanning;
mod stability;
mod threshold;
