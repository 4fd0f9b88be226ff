//! Motifs mined from real systems: where truth (MODEL §10) finds rigidity
//! that 3D-RGC misses, the smallest sets of the engine's nodes that carry
//! it, as typed patterns (MODEL §6), counted over many generated systems
//! and written as a rule file.
//!
//! Per system:
//! * one `sound` compression, run 0 of the system's seed (the order `rgc
//!   sample --seed S --runs 1` uses); its bodies and free rods are the
//!   nodes of the *quotient*;
//! * truth of the whole system; a rigid cluster holding two or more whole
//!   quotient nodes is rigidity the engine missed;
//! * per such cluster, up to [`Search::pairs`] seed pairs `(x, y)` of
//!   adjacent whole nodes per started ten whole nodes of it (so that the
//!   spanning cluster is sampled in proportion), drawn by a shuffle seeded
//!   by the system seed and the cluster's index;
//! * for each pair, the quotient ball around `{x, y}`, over the nodes in or
//!   touching the cluster (a lock can stay outside it), grows one layer at
//!   a time from radius 0, at most [`Search::max_radius`] layers and
//!   [`Search::max_ball_rods`] rods (beyond, or when those nodes run out,
//!   the pair is *not local*). At each radius where truth puts `x` and `y`
//!   in one cluster, the nodes that cluster holds whole are restricted to
//!   themselves until truth holds all of them in one cluster; if the pair
//!   survives, they shrink to a *whole* minimal set. If no radius gives one,
//!   the first ball that held the pair shrinks to a minimal set that only
//!   keeps the pair together (*not whole*, see below);
//! * shrinking drops the nodes other than the pair, farthest from it first:
//!   halves, quarters ... while the set keeps what it must, then single
//!   nodes, pass after pass until no node can go (rigidity is not monotone
//!   under forced planes, so one pass is not enough). No node of the result
//!   can be removed: it is a *minimal missed rigid set*.
//!
//! Truth on a set is that of the rods of its nodes with every contact among
//! them, in the system's own periodic box (a finite framework for a graph
//! given without one: the two agree on a set that does not wrap the box).
//! Each call ranks one realization: a rigid answer is proved by it, a
//! flexible one is wrong with probability about `1/p`, which could only keep
//! a node that might go.
//!
//! A set becomes a pattern ([`Pattern::from_host`]): a body a planar or
//! spatial node labelled by its rods that touch the rest of the set, a free
//! rod a rod node. The planes kept inside a spatial body cannot be
//! expressed, so such a pattern is more generic than its host. Equal
//! patterns (canonical form) are counted together; each distinct one gets
//! its exact verdict on every realization component and whether the
//! `sound` engine compresses it to one node in [`Parameters::runs`] orders.
//! The ones rigid on every component and missed become rules.
//!
//! [`Pattern::from_host`]: crate::pattern::Pattern::from_host
//!
//! A minimal set need not be one rigid cluster: a body touching the rest at
//! two points (a locking bar) holds `x` and `y` together while itself
//! turning about the line through its two contacts; two touching rods held
//! at one further point each by one body are a rigid pair that turns about
//! the line through those points. Such a set is recorded (not *whole*);
//! its pattern is flexible, and no rule can merge it, since a rule merges
//! all of its nodes.
//!
//! A pattern also forgets the contacts inside a body, and a planar body's
//! inner contacts can force another rod into its plane (a rod touching two
//! rods of a plane lies in it): a whole set can then be rigid under truth
//! while its pattern is only component-dependent, and is no rule either.
//!
//! The files, each using only those listed before it:
//! * `spaced` — rod lists as one space-separated string in the JSON;
//! * `quotient` — the engine's nodes as a graph, truth on sets of them and
//!   the pattern of a set;
//! * `search` — the caps ([`Search`]) and the search of one system for its
//!   minimal sets ([`mine`]);
//! * `parameters` — what a run is made of ([`Parameters`]);
//! * `system` — one generated system, or one contact graph, mined whole
//!   ([`mine_system`], [`mine_graph`]);
//! * `tally` — the sets counted by pattern and the systems per density
//!   ([`MinedMotif`], [`DensitySummary`]);
//! * `report` — `mined-motifs.{json,csv,md}` under their [`stamp`], the
//!   rules, and the refusal to replace another run's ([`Report`],
//!   [`check_replace`]);
//! * `run` — a whole run ([`run`]).

mod parameters;
mod quotient;
mod report;
mod run;
mod search;
mod spaced;
mod system;
mod tally;

pub use parameters::Parameters;
pub use report::{FORMAT, Made, Report, check_replace, csv, markdown, rules, stamp, write};
pub use run::run;
pub use search::{Counts, Mined, MinimalSet, Search, mine};
pub use system::{SystemReport, mine_graph, mine_system};
pub use tally::{DensitySummary, Example, MinedMotif};
