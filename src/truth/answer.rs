//! What truth answers: how it was decided, the degrees of freedom, the
//! rigid clusters and what they span; and the options it is asked with.

use serde::{Deserialize, Serialize};

use crate::graph::ContactGraph;
use crate::math::sparse;
use crate::spanning::Criterion;

/// How truth was decided.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Decision {
    /// Exact F_p rank at exact twin realizations.
    Exact,
    /// No construction order exists: float rank with a clear singular-value
    /// gap at twin float realizations that agree ([`super::fallback`]).
    Float,
    /// No realization could be built, or its float rank was unclear;
    /// nothing is claimed.
    Undecided,
}

impl std::fmt::Display for Decision {
    /// The name in files.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Decision::Exact => "exact",
            Decision::Float => "float",
            Decision::Undecided => "undecided",
        })
    }
}

/// Options of a truth evaluation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TruthOptions {
    pub seed: u64,
    /// Redraws of a realization that lands on a degenerate position (the
    /// float fallback draws [`super::fallback::DRAWS_PER_ATTEMPT`] times as many).
    pub attempts: usize,
    /// Rank a second, independent realization too (the generic rank is the
    /// larger). One realization already proves what it finds rigid; the twin
    /// guards the flexible answers against an unlucky draw. The float
    /// fallback proves nothing from one realization and always ranks twins.
    pub twins: bool,
    /// Stop an elimination before a dense front that would take it past
    /// this many bytes; the answer is then undecided ([`Truth::refused`]).
    pub memory_limit: Option<u64>,
}

impl TruthOptions {
    /// The default options with realizations drawn from `seed`.
    pub fn seeded(seed: u64) -> Self {
        TruthOptions {
            seed,
            ..TruthOptions::default()
        }
    }
}

impl Default for TruthOptions {
    fn default() -> Self {
        TruthOptions {
            seed: 1,
            attempts: 8,
            twins: true,
            memory_limit: None,
        }
    }
}

/// The rigidity of a whole system.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Truth {
    pub method: Decision,
    /// Why the answer is undecided, if it is; for a float answer, why it
    /// is in floats.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    pub n_rods: usize,
    pub n_contacts: usize,
    /// Rods and contacts of the 2-core, the part that can be rigid.
    pub core_rods: usize,
    pub core_contacts: usize,
    /// Forced plane classes, and the rods in the largest (MODEL §10: where
    /// it percolates, the line model forces the system flat).
    pub plane_classes: usize,
    pub largest_plane_class: usize,
    /// Rigid parts of the matrix (classes and the other core rods), its
    /// columns, rows and rank.
    pub parts: usize,
    pub columns: usize,
    pub rows: usize,
    pub rank: Option<usize>,
    /// Rigid motions not counted as deformations.
    pub trivial_motions: usize,
    /// Internal degrees of freedom of the whole system.
    pub dof: Option<usize>,
    /// Whether the twin realizations gave the same rank (`None` without twins).
    pub twins_agree: Option<bool>,
    /// Float answers only: the smaller singular-value gap of the twins (the
    /// smallest value counted over the largest one not).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap: Option<f64>,
    /// Rigid clusters of two or more rods, largest first.
    pub clusters: Vec<Cluster>,
    /// The largest dense front of the elimination, rows times columns: what
    /// the cost of truth grows with.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub largest_front: Option<(usize, usize)>,
    /// Set when the elimination stopped for the memory limit, with the
    /// front that would have passed it (the answer is then undecided).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refused: Option<sparse::Refused>,
    /// For a generated system: whether a rigid cluster spans under the
    /// criterion asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub criterion: Option<Criterion>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spanning: Option<bool>,
    pub seconds: f64,
}

/// A rigid cluster: rods with no relative motion.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Cluster {
    /// Member rods, sorted.
    pub rods: Vec<u32>,
    /// Whether it spans the box under each criterion (generated systems only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spans: Option<Spans>,
}

/// Spanning of one cluster under both criteria.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Spans {
    pub wrap: bool,
    pub faces: bool,
}

impl Spans {
    /// Whether it spans under `criterion`.
    pub fn under(self, criterion: Criterion) -> bool {
        match criterion {
            Criterion::Wrap => self.wrap,
            Criterion::Faces => self.faces,
        }
    }
}

impl Truth {
    /// Nothing decided yet about the system `graph`, whose rigid motions
    /// that are no deformation number `trivial_motions`.
    pub(super) fn undecided(graph: &ContactGraph, trivial_motions: usize) -> Truth {
        Truth {
            method: Decision::Undecided,
            reason: None,
            n_rods: graph.n_nodes(),
            n_contacts: graph.n_edges(),
            core_rods: 0,
            core_contacts: 0,
            plane_classes: 0,
            largest_plane_class: 0,
            parts: 0,
            columns: 0,
            rows: 0,
            rank: None,
            trivial_motions,
            dof: None,
            twins_agree: None,
            gap: None,
            clusters: Vec::new(),
            largest_front: None,
            refused: None,
            criterion: None,
            spanning: None,
            seconds: 0.0,
        }
    }

    /// Rods in the largest rigid cluster (0 when there is none).
    pub fn largest_cluster(&self) -> usize {
        self.clusters.first().map_or(0, |c| c.rods.len())
    }

    pub fn decided(&self) -> bool {
        self.method != Decision::Undecided
    }

    /// Records an elimination stopped for the memory limit: undecided,
    /// with the front that would pass it.
    pub(super) fn refuse(&mut self, e: sparse::Refused, limit: Option<u64>) {
        let limit = limit.expect("a refusal needs a limit");
        self.reason = Some(format!(
            "its elimination reached a dense front of {} x {} that would take it to about {}, over the memory limit of {}",
            e.front.0,
            e.front.1,
            gib(e.bytes),
            gib(limit)
        ));
        self.refused = Some(e);
    }

    /// Records a decided rank of the matrix, the degrees of freedom it
    /// leaves (its kernel, plus the `pruned` motions of what the 2-core
    /// removed, less the trivial motions) and the rigid clusters.
    /// Fewer motions than the trivial ones would mean a wrong matrix (the
    /// trivial motions lie in its kernel): the answer is then undecided,
    /// with the reason, never a clamped DOF.
    pub(super) fn decide(
        &mut self,
        method: Decision,
        rank: usize,
        pruned: usize,
        clusters: Vec<Vec<u32>>,
    ) {
        self.rank = Some(rank);
        let motions = self.columns - rank + pruned;
        let Some(dof) = motions.checked_sub(self.trivial_motions) else {
            self.method = Decision::Undecided;
            self.reason = Some(format!(
                "{motions} motions, fewer than the {} trivial ones: the rigidity matrix is wrong",
                self.trivial_motions
            ));
            return;
        };
        self.method = method;
        self.dof = Some(dof);
        self.clusters = clusters
            .into_iter()
            .map(|rods| Cluster { rods, spans: None })
            .collect();
    }
}

/// Bytes in GiB, for messages.
fn gib(bytes: u64) -> String {
    format!("{:.2} GiB", bytes as f64 / (1u64 << 30) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fewer_motions_than_the_trivial_ones_are_undecided_not_clamped() {
        let graph = ContactGraph::new(2, vec![[0, 1]]).unwrap();
        let mut t = Truth::undecided(&graph, 6);
        t.columns = 12;
        t.decide(Decision::Exact, 9, 0, Vec::new());
        assert_eq!((t.method, t.dof), (Decision::Undecided, None));
        assert!(
            t.reason
                .unwrap()
                .contains("3 motions, fewer than the 6 trivial ones")
        );
        let mut t = Truth::undecided(&graph, 6);
        t.columns = 12;
        t.decide(Decision::Exact, 5, 1, vec![vec![0, 1]]);
        assert_eq!(
            (t.method, t.dof, t.rank),
            (Decision::Exact, Some(2), Some(5))
        );
        assert_eq!(t.largest_cluster(), 2);
    }
}
