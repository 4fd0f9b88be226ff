//! The benchmarks behind `rgc bench`: the foundation benchmark (contact
//! detection and one compression, single threaded, on the reference systems
//! of the paper's aspect ratios, with rule sets and networkx as
//! references), the rule sets' cost against the base engine, and the
//! truth benchmarks: how the cost of exact whole-system rigidity grows
//! with the system, and so how large a box truth can decide; and what
//! loading the extended rule sets costs. Every
//! figure, median and ratio is made here; the command line only prints them.

pub mod aspects;
pub mod foundation;
pub mod growth;
pub mod measure;
pub mod moduli;
pub mod networkx;
pub mod rule_load;
pub mod rules;
pub mod truth;

pub use crate::usage::{peak_rss_mib, reset_peak_rss};
pub use aspects::{
    ASPECT_LARGE, ASPECT_PAIR, ASPECT_SYSTEMS, AspectReport, AspectScaling, SMALL_LIMIT, limits_of,
    run_memory_limits, run_truth_aspects,
};
pub use foundation::{
    BenchReport, BenchRow, RULE_SETS, RULES_SYSTEM, RuleSetBench, RulesRow, SYSTEMS,
    check_max_rods, load_rule_sets, run,
};
pub use growth::Growth;
pub use measure::one_thread;
pub use networkx::{Foundation, NETWORKX_STEP, Networkx, against_networkx, networkx_version};
pub use rule_load::{LOAD_SETS, RuleLoadReport, RuleLoadRow, run_rule_load};
pub use rules::{
    LoadRow, LoadedSet, RULE_SYSTEMS, RuleSetFiles, RulesReport, SetRow, default_rule_sets,
    load_set,
};
pub use truth::{
    LimitRow, PREDICT_MAX_BOX, REACH_DENSITY, Reach, Scaling, StrainCost, TAIL_BOXES,
    TRUTH_DENSITIES, TRUTH_GAMMA, TruthPlan, TruthReport, TruthRow, TruthSystem, measure_truth,
    measure_truth_at, predict_largest_box, run_truth, truth_in_child, within_limit,
};
