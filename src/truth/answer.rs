//! What truth answers: how it was decided, the degrees of freedom, the
//! rigid clusters and what they span; and the options it is asked with.

use serde::{Deserialize, Serialize};

use crate::graph::ContactGraph;
use crate::math::sparse;
use crate::spanning::Criterion;
use crate::usage;

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

/// A coordinate strain: a symmetric component of the box's velocity
/// gradient `E` (for a shear, `E` has the entry at both `ij` and `ji`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Strain {
    Xx,
    Yy,
    Zz,
    Yz,
    Xz,
    Xy,
}

impl Strain {
    /// The six, in the order of truth's strain columns.
    pub const ALL: [Strain; 6] = [
        Strain::Xx,
        Strain::Yy,
        Strain::Zz,
        Strain::Yz,
        Strain::Xz,
        Strain::Xy,
    ];

    /// Its two axes (equal for a stretch).
    pub fn axes(self) -> [usize; 2] {
        match self {
            Strain::Xx => [0, 0],
            Strain::Yy => [1, 1],
            Strain::Zz => [2, 2],
            Strain::Yz => [1, 2],
            Strain::Xz => [0, 2],
            Strain::Xy => [0, 1],
        }
    }

    /// Its column among the strain columns.
    pub fn index(self) -> usize {
        Strain::ALL
            .iter()
            .position(|&s| s == self)
            .expect("one of the six")
    }

    /// The strains a box periodic along `periodic` has: those with both
    /// axes periodic (6 in a periodic box, 3 in a slab, none in a closed
    /// box). A component with a walled axis has no lattice vector to act
    /// on, or only moves one the way a rigid rotation does.
    pub fn of_box(periodic: [bool; 3]) -> Vec<Strain> {
        Strain::ALL
            .into_iter()
            .filter(|s| s.axes().iter().all(|&a| periodic[a]))
            .collect()
    }
}

impl std::fmt::Display for Strain {
    /// The name in files: `xx` ... `xy`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let [i, j] = self.axes().map(|a| ['x', 'y', 'z'][a]);
        write!(f, "{i}{j}")
    }
}

/// Which strains of its box a system resists (MODEL §10, the strain rank):
/// with the lattice free to deform (the flexible torus), how many
/// independent strains no motion of the rods follows.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Strains {
    /// The strains considered: those of the periodic axes.
    pub considered: Vec<Strain>,
    /// Resisted independent strains, 0 to `considered.len()`: 6 for a
    /// solid, 0 for a fluid. `None` where truth does not know, for `reason`.
    pub rank: Option<u8>,
    /// The coordinate strains resisted alone: no motion follows the box
    /// strained by that one alone.
    pub resisted: Vec<Strain>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

impl Strains {
    /// Unknown, for `reason`.
    pub fn unknown(considered: Vec<Strain>, reason: impl Into<String>) -> Strains {
        Strains {
            considered,
            rank: None,
            resisted: Vec::new(),
            reason: Some(reason.into()),
        }
    }
}

/// Options of a truth evaluation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TruthOptions {
    pub seed: u64,
    /// Redraws of a realization that lands on a degenerate position (the
    /// float fallback draws [`super::fallback::DRAWS_PER_ATTEMPT`] times as many).
    pub attempts: usize,
    /// Independent realizations ranked, 1 to
    /// [`super::decide::MAX_REALIZATIONS`], each in a prime of its own
    /// drawn at random; the generic rank is the largest. One realization
    /// already proves the rank it finds (a realization can only lose rank);
    /// the others guard the flexible answers against an unlucky draw, each
    /// by a check with the clusters found so far contracted. The float
    /// fallback proves nothing from one realization and always ranks twins.
    pub realizations: usize,
    /// The realizations' primes instead of random ones (tests that force a
    /// bad draw in a small prime).
    #[doc(hidden)]
    pub primes: Option<[u32; 3]>,
    /// Stop before a step (the realization and matrix, each dense front)
    /// that would take the process's resident size past this many bytes;
    /// the answer is then undecided ([`Outcome::Undecided`]) with what was
    /// refused. What the machine has available and an address-space limit
    /// are checked without it too.
    pub memory_limit: Option<u64>,
    /// Whether to find the strain rank (six more columns, ranked last).
    pub strain: bool,
}

/// Bytes truth holds per rod and per contact before its realization (the
/// graph, its topology, the 2-core, the planes, the order, per-rod lines):
/// 140 per rod measured on isolated rods.
const NODE_BYTES: u64 = 150;
const CONTACT_BYTES: u64 = 100;

impl TruthOptions {
    /// Refuses, before anything is built, truth on a system of `rods`
    /// rods and `contacts` contacts whose first steps (everything before
    /// the realization, with `more` bytes still to come before them) would
    /// take the process past the memory limit: the sizes a file declares
    /// are checked before they are allocated.
    pub fn check_memory(&self, rods: usize, contacts: usize, more: u64) -> crate::Result<()> {
        let need = NODE_BYTES * rods as u64 + CONTACT_BYTES * contacts as u64 + more;
        usage::reserve(need, 0, self.memory_limit).map_err(|r| {
            let what = format!("truth on {rods} rods and {contacts} contacts");
            crate::Error::Memory(r.describe(&what))
        })?;
        Ok(())
    }

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
            realizations: 2,
            primes: None,
            memory_limit: None,
            strain: true,
        }
    }
}

/// How a truth was decided, with what each way of deciding knows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(into = "Flat", try_from = "Flat")]
pub enum Outcome {
    /// Exact F_p rank at an exact realization, and whether its twin gave
    /// the same rank (`None` without twins; where they differ the larger
    /// rank is the one kept).
    Exact {
        rank: usize,
        dof: usize,
        twins_agree: Option<bool>,
    },
    /// Float rank at twin float realizations that agree, where no exact
    /// construction order exists: the smaller singular-value gap of the
    /// twins (the smallest value counted over the largest one not), and why
    /// it is in floats.
    Float {
        rank: usize,
        dof: usize,
        gap: f64,
        reason: String,
    },
    /// Nothing is claimed, for the reason given; `refused` holds the front
    /// that would have passed the memory limit where that is the reason.
    Undecided {
        reason: String,
        refused: Option<sparse::Refused>,
    },
}

impl Outcome {
    pub fn decision(&self) -> Decision {
        match self {
            Outcome::Exact { .. } => Decision::Exact,
            Outcome::Float { .. } => Decision::Float,
            Outcome::Undecided { .. } => Decision::Undecided,
        }
    }

    /// The rank of the rigidity matrix, if decided.
    pub fn rank(&self) -> Option<usize> {
        match *self {
            Outcome::Exact { rank, .. } | Outcome::Float { rank, .. } => Some(rank),
            Outcome::Undecided { .. } => None,
        }
    }

    /// Internal degrees of freedom of the whole system, if decided.
    pub fn dof(&self) -> Option<usize> {
        match *self {
            Outcome::Exact { dof, .. } | Outcome::Float { dof, .. } => Some(dof),
            Outcome::Undecided { .. } => None,
        }
    }

    /// Why it is undecided, or why in floats.
    pub fn reason(&self) -> Option<&str> {
        match self {
            Outcome::Exact { .. } => None,
            Outcome::Float { reason, .. } | Outcome::Undecided { reason, .. } => Some(reason),
        }
    }

    /// The step that would have passed the memory limit, if that stopped it.
    pub fn refused(&self) -> Option<sparse::Refused> {
        match *self {
            Outcome::Undecided { refused, .. } => refused,
            _ => None,
        }
    }
}

/// An [`Outcome`] as files carry it: flat keys beside the rest of
/// [`Truth`], `rank`, `dof` and `twins_agree` always present.
#[derive(Clone, Serialize, Deserialize)]
struct Flat {
    method: Decision,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    reason: Option<String>,
    rank: Option<usize>,
    dof: Option<usize>,
    twins_agree: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    gap: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    refused: Option<sparse::Refused>,
}

impl From<Outcome> for Flat {
    fn from(o: Outcome) -> Flat {
        let (method, rank, dof) = (o.decision(), o.rank(), o.dof());
        let mut flat = Flat {
            method,
            reason: None,
            rank,
            dof,
            twins_agree: None,
            gap: None,
            refused: None,
        };
        match o {
            Outcome::Exact { twins_agree, .. } => flat.twins_agree = twins_agree,
            Outcome::Float { gap, reason, .. } => {
                (flat.twins_agree, flat.gap, flat.reason) = (Some(true), Some(gap), Some(reason));
            }
            Outcome::Undecided { reason, refused } => {
                (flat.reason, flat.refused) = (Some(reason), refused)
            }
        }
        flat
    }
}

impl TryFrom<Flat> for Outcome {
    type Error = String;

    fn try_from(f: Flat) -> std::result::Result<Outcome, String> {
        let decided = |rank: Option<usize>, dof: Option<usize>| {
            rank.zip(dof)
                .ok_or_else(|| format!("a {} truth needs its rank and dof", f.method))
        };
        let reason = || {
            f.reason
                .clone()
                .ok_or_else(|| format!("a {} truth needs its reason", f.method))
        };
        Ok(match f.method {
            Decision::Exact => {
                let (rank, dof) = decided(f.rank, f.dof)?;
                Outcome::Exact {
                    rank,
                    dof,
                    twins_agree: f.twins_agree,
                }
            }
            Decision::Float => {
                let (rank, dof) = decided(f.rank, f.dof)?;
                let gap = f.gap.ok_or("a float truth needs its gap")?;
                Outcome::Float {
                    rank,
                    dof,
                    gap,
                    reason: reason()?,
                }
            }
            Decision::Undecided => Outcome::Undecided {
                reason: reason()?,
                refused: f.refused,
            },
        })
    }
}

/// The rigidity of a whole system.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Truth {
    #[serde(flatten)]
    pub outcome: Outcome,
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
    /// columns and rows.
    pub parts: usize,
    pub columns: usize,
    pub rows: usize,
    /// Rigid motions not counted as deformations.
    pub trivial_motions: usize,
    /// Rigid clusters of two or more rods, largest first.
    pub clusters: Vec<Cluster>,
    /// The strains of the box it resists; `None` in answers older than it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strains: Option<Strains>,
    /// The largest dense front of the elimination, rows times columns: what
    /// the cost of truth grows with.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub largest_front: Option<(usize, usize)>,
    /// The prime of each exact realization ranked, in order (drawn at
    /// random per evaluation, so that no system meets a fixed bad prime).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub primes: Vec<u32>,
    /// For a generated system: whether a rigid cluster spans under the
    /// criterion asked for (under `Solid`, whether the strain rank reaches
    /// the strains considered; `None` where it is unknown).
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
    /// Whether it spans under `criterion`: under `Solid`, whether it wraps
    /// ([`Criterion::of_clusters`]; a solid is the whole system's).
    pub fn under(self, criterion: Criterion) -> bool {
        match criterion.of_clusters() {
            Criterion::Faces => self.faces,
            _ => self.wrap,
        }
    }
}

impl Truth {
    /// The system `graph`, whose rigid motions that are no deformation
    /// number `trivial_motions`, before anything is decided about it.
    pub(super) fn unranked(graph: &ContactGraph, trivial_motions: usize) -> Truth {
        Truth {
            outcome: Outcome::Undecided {
                reason: "not ranked".to_string(),
                refused: None,
            },
            n_rods: graph.n_nodes(),
            n_contacts: graph.n_edges(),
            core_rods: 0,
            core_contacts: 0,
            plane_classes: 0,
            largest_plane_class: 0,
            parts: 0,
            columns: 0,
            rows: 0,
            trivial_motions,
            clusters: Vec::new(),
            strains: None,
            largest_front: None,
            primes: Vec::new(),
            criterion: None,
            spanning: None,
            seconds: 0.0,
        }
    }

    /// The number of strains resisted, if known.
    pub fn strain_rank(&self) -> Option<u8> {
        self.strains.as_ref().and_then(|s| s.rank)
    }

    /// Rods in the largest rigid cluster (0 when there is none).
    pub fn largest_cluster(&self) -> usize {
        self.clusters.first().map_or(0, |c| c.rods.len())
    }

    pub fn decided(&self) -> bool {
        self.outcome.decision() != Decision::Undecided
    }

    /// Leaves the answer undecided for `reason`.
    pub(super) fn undecide(&mut self, reason: String) {
        self.outcome = Outcome::Undecided {
            reason,
            refused: None,
        };
    }

    /// Records a step stopped before it would pass the memory limit
    /// (`limit`, if one was asked for; the machine's own bounds apply
    /// without one): undecided, with what it needed and held.
    pub(super) fn refuse(&mut self, e: sparse::Refused, limit: Option<u64>) {
        debug_assert!(
            e.refusal.bound != usage::Bound::Limit || limit == Some(e.refusal.limit),
            "refused against a limit not asked for"
        );
        self.outcome = Outcome::Undecided {
            reason: e.refusal.describe(&e.step.describe()),
            refused: Some(e),
        };
    }

    /// Records a decided rank of the matrix and the rigid clusters, with
    /// the outcome `decided` makes of the rank and the degrees of freedom
    /// it leaves (its kernel, plus the `pruned` motions of what the 2-core
    /// removed, less the trivial motions).
    /// Fewer motions than the trivial ones would mean a wrong matrix (the
    /// trivial motions lie in its kernel): the answer is then undecided,
    /// with the reason, never a clamped DOF.
    pub(super) fn decide(
        &mut self,
        rank: usize,
        pruned: usize,
        clusters: Vec<Vec<u32>>,
        decided: impl FnOnce(usize, usize) -> Outcome,
    ) {
        let motions = self.columns - rank + pruned;
        let Some(dof) = motions.checked_sub(self.trivial_motions) else {
            self.undecide(format!(
                "{motions} motions, fewer than the {} trivial ones: the rigidity matrix is wrong",
                self.trivial_motions
            ));
            return;
        };
        self.outcome = decided(rank, dof);
        self.clusters = clusters
            .into_iter()
            .map(|rods| Cluster { rods, spans: None })
            .collect();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn exact(rank: usize, dof: usize) -> Outcome {
        Outcome::Exact {
            rank,
            dof,
            twins_agree: Some(true),
        }
    }

    #[test]
    fn fewer_motions_than_the_trivial_ones_are_undecided_not_clamped() {
        let graph = ContactGraph::new(2, vec![[0, 1]]).unwrap();
        let mut t = Truth::unranked(&graph, 6);
        t.columns = 12;
        t.decide(9, 0, Vec::new(), exact);
        assert_eq!(
            (t.outcome.decision(), t.outcome.dof()),
            (Decision::Undecided, None)
        );
        assert!(
            t.outcome
                .reason()
                .unwrap()
                .contains("3 motions, fewer than the 6 trivial ones")
        );
        let mut t = Truth::unranked(&graph, 6);
        t.columns = 12;
        t.decide(5, 1, vec![vec![0, 1]], exact);
        assert_eq!(t.outcome, exact(5, 2));
        assert_eq!(t.largest_cluster(), 2);
    }

    #[test]
    fn every_outcome_keeps_its_flat_keys_and_reads_back() {
        let graph = ContactGraph::new(2, vec![[0, 1]]).unwrap();
        let refused = sparse::Refused {
            refusal: usage::Refusal {
                need: 1 << 31,
                held: 1 << 30,
                limit: 3 << 29,
                bound: usage::Bound::Limit,
            },
            step: sparse::Step::Front(40, 50),
        };
        let outcomes = [
            exact(5, 2),
            Outcome::Float {
                rank: 4,
                dof: 3,
                gap: 2.5e7,
                reason: "asked for floats; decided in floats".into(),
            },
            Outcome::Undecided {
                reason: "too large".into(),
                refused: Some(refused),
            },
        ];
        for outcome in outcomes {
            let mut t = Truth::unranked(&graph, 6);
            t.outcome = outcome.clone();
            let v = serde_json::to_value(&t).unwrap();
            assert_eq!(v["method"], outcome.decision().to_string());
            assert_eq!(v["rank"].as_u64(), outcome.rank().map(|r| r as u64));
            assert_eq!(v["dof"].as_u64(), outcome.dof().map(|d| d as u64));
            assert_eq!(v["reason"].as_str(), outcome.reason());
            assert_eq!(v["n_rods"], 2);
            assert_eq!(serde_json::from_value::<Truth>(v).unwrap(), t);
        }
    }

    #[test]
    fn a_decided_outcome_without_its_rank_is_refused_by_name() {
        let e = serde_json::from_str::<Outcome>(
            r#"{"method":"float","rank":3,"dof":null,"twins_agree":true,"gap":1e7,"reason":"x"}"#,
        )
        .unwrap_err();
        assert!(
            e.to_string()
                .contains("a float truth needs its rank and dof"),
            "{e}"
        );
    }
}
