//! The motifs the engine compresses, by the paper's names, and how many
//! instances of each one run compressed.

use serde::{Deserialize, Serialize};

/// The base motifs, by the paper's names (serialized as [`MotifCounts`]
/// names them).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Motif {
    /// 3D3C grown to a 3-clique community of rods (3D3C with 3D2B).
    #[serde(rename = "community")]
    Community,
    /// A rod touching a body at two or more contacts.
    #[serde(rename = "3D2B")]
    D2B,
    /// Two bodies with three or more contacts, not all on one rod.
    #[serde(rename = "3D2A")]
    D2A,
    /// Three bodies pairwise in contact (1, 2, 2 contacts).
    #[serde(rename = "3D3A")]
    D3A,
    /// Two bodies with two contacts and a rod touching both.
    #[serde(rename = "3D3B")]
    D3B,
    /// A body touching a path of three rods.
    #[serde(rename = "3D4")]
    D4,
    /// Two rods touching the same four rods (K_{2,4}).
    #[serde(rename = "3D6")]
    D6,
    /// A rule loaded from a file.
    #[serde(rename = "rule")]
    Rule,
}

/// How many instances of each motif one run compressed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct MotifCounts {
    pub community: u32,
    #[serde(rename = "3D2B")]
    pub d2b: u32,
    #[serde(rename = "3D2A")]
    pub d2a: u32,
    #[serde(rename = "3D3A")]
    pub d3a: u32,
    #[serde(rename = "3D3B")]
    pub d3b: u32,
    #[serde(rename = "3D4")]
    pub d4: u32,
    #[serde(rename = "3D6")]
    pub d6: u32,
    /// Instances of loaded rules.
    pub rules: u32,
}

impl MotifCounts {
    /// Counts one instance of `motif`.
    pub(super) fn add(&mut self, motif: Motif) {
        let slot = match motif {
            Motif::Community => &mut self.community,
            Motif::D2B => &mut self.d2b,
            Motif::D2A => &mut self.d2a,
            Motif::D3A => &mut self.d3a,
            Motif::D3B => &mut self.d3b,
            Motif::D4 => &mut self.d4,
            Motif::D6 => &mut self.d6,
            Motif::Rule => &mut self.rules,
        };
        *slot += 1;
    }
}
