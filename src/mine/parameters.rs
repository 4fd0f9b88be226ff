//! What a mining run is made of, checked before any work, and how the
//! provenance of its rules names it.

use serde::{Deserialize, Serialize};

use super::search::Search;
use crate::rods::RodParams;
use crate::{Error, Result};

/// What a mining run is made of: what the refusal to replace its results compares.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Parameters {
    pub gamma: f64,
    #[serde(rename = "box")]
    pub box_len: f64,
    /// Rods per unit volume, in the order given.
    pub densities: Vec<f64>,
    /// Systems per density; system `i` has seed `seed + i` at every density
    /// (so one seed's systems are nested, and `rgc sample`/`rgc truth` with
    /// that seed make the same rods).
    pub systems: u64,
    pub seed: u64,
    #[serde(flatten)]
    pub search: Search,
    /// Motif orders in which the engine may compress a pattern.
    pub runs: u64,
    /// Rules written at most (the most frequent first).
    pub top: usize,
    /// Extended rule files also tried on every pattern (informative only).
    #[serde(default)]
    pub extended: Vec<String>,
}

impl Parameters {
    /// Checks everything before any work: every system valid, densities
    /// distinct, at least one system, a search and an engine check that do something.
    pub fn validate(&self) -> Result<()> {
        if self.densities.is_empty() {
            return Err(Error::Parameter("no density to mine".into()));
        }
        for (i, &rho) in self.densities.iter().enumerate() {
            RodParams::new(self.gamma, self.box_len, rho)?;
            if self.densities[..i].contains(&rho) {
                return Err(Error::Parameter(format!("density {rho} is given twice")));
            }
        }
        if self.systems == 0 {
            return Err(Error::Parameter(
                "at least one system per density is needed".into(),
            ));
        }
        if self.runs == 0 {
            return Err(Error::Parameter(
                "at least one motif order is needed to tell whether the engine compresses a pattern"
                    .into(),
            ));
        }
        self.search.validate()
    }

    /// The seeds of the systems of each density.
    pub fn seeds(&self) -> impl Iterator<Item = u64> + '_ {
        (0..self.systems).map(|i| self.seed.wrapping_add(i))
    }

    /// What the rules' provenance says was mined.
    pub fn enumeration(&self) -> String {
        let densities: Vec<String> = self.densities.iter().map(f64::to_string).collect();
        format!(
            "minimal missed rigid sets in generated systems: gamma {}, box {}, densities {}, \
             {} systems each (seeds {} to {}), sound run 0 as the quotient, truth in the box; \
             {} seed pairs per missed cluster, radius <= {}, <= {} rods per ball",
            self.gamma,
            self.box_len,
            densities.join(","),
            self.systems,
            self.seed,
            self.seed.wrapping_add(self.systems - 1),
            self.search.pairs,
            self.search.max_radius,
            self.search.max_ball_rods
        )
    }

    /// What the rules were checked against.
    pub fn audited_against(&self) -> String {
        format!(
            "sound base motifs, {} motif orders (compressed to one node in none)",
            self.runs
        )
    }
}
