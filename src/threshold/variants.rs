//! Rule sets, run counts and protocols against each other on the same
//! sequences: `rgc compare` (paper base, sound base, sound + extended
//! motifs) and `rgc tradeoff` (threshold and interval width against CPU time).
//!
//! Each variant is an ordinary study in a directory named after what
//! determines its records, so variants that differ only in how many
//! sequences they analyse share one study, and every study resumes.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

use super::fss::{Estimate, Protocol};
use super::paired;
use super::report;
use super::sequence::{Kind, Record};
use super::study::{self, MotifSet, RunOptions, Shard, StudySpec};
use crate::engine::{CompiledRule, RuleSet};
use crate::output::{self, cell};
use crate::progress::Progress;
use crate::rule_file;
use crate::{Error, Result};

/// One configuration to measure.
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    pub label: String,
    /// Which family of the trade-off it belongs to (`runs`, `motifs`, ...).
    pub family: String,
    /// What spans: an engine's body (rigid) or a true rigid cluster (truth).
    pub kind: Kind,
    pub rules: RuleSet,
    pub motifs: Vec<PathBuf>,
    pub runs: usize,
    pub method: Protocol,
    /// Sequences per box analysed: the first ones of the study.
    pub sequences: u64,
}

impl Variant {
    /// The sound base motifs, one run, nested, on `sequences` per box: what
    /// the experiments' variants change one thing of.
    pub fn sound_base(label: &str, family: &str, sequences: u64) -> Self {
        Variant {
            label: label.into(),
            family: family.into(),
            kind: Kind::Rigid,
            rules: RuleSet::Sound,
            motifs: Vec::new(),
            runs: 1,
            method: Protocol::Nested,
            sequences,
        }
    }
}

/// What a variant measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VariantOutcome {
    pub label: String,
    pub family: String,
    pub rules: RuleSet,
    /// Loaded rules besides the base motifs.
    pub motif_rules: usize,
    pub runs: usize,
    pub method: Protocol,
    // Keeps its stored key, so existing experiments (`results/NAME.json`) read back.
    #[serde(rename = "realizations")]
    pub sequences: u64,
    pub threshold: Estimate,
    /// Width of the threshold's interval.
    pub interval_width: Option<f64>,
    pub nu: Estimate,
    /// Relative difference of the threshold to the first variant's.
    pub relative_difference: f64,
    /// Nested protocol: the mean over sequences (all boxes) of the
    /// difference of each sequence's critical density to the reference
    /// variant's on the same sequence, with a 95% normal interval. Paired,
    /// so far tighter than the difference of two thresholds.
    pub paired_difference: Option<Estimate>,
    /// The variant both differences are taken against.
    pub paired_with: Option<String>,
    /// The threshold minus that of the variant it is measured against, with
    /// the two intervals' half-widths added in quadrature.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub threshold_difference: Option<Estimate>,
    /// CPU seconds of the analysed sequences.
    pub cpu_seconds: f64,
    /// How often one run misses a spanning body that all runs find together.
    pub single_run_miss_rate: Option<f64>,
    /// Nested: fresh compressions at the critical number that missed the spanning body.
    pub fresh_misses: usize,
    pub fresh_checks: usize,
    /// The study directory.
    pub study: String,
}

impl VariantOutcome {
    /// How far the variant sits from the one it is measured against: the
    /// paired difference where there is one, else the difference of
    /// thresholds (the accuracy axis of `rgc tradeoff`).
    pub fn difference(&self) -> Option<Estimate> {
        self.paired_difference.or(self.threshold_difference)
    }
}

/// Which variant each variant's paired difference is taken against.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pairing {
    First,
    /// The one listed before it (a chain: paper, sound, sound + extended).
    Previous,
}

/// Variants to measure against each other, and which one each is paired with.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    pub variants: Vec<Variant>,
    pub pairing: Pairing,
}

/// `rgc compare`: the paper's base motifs, the sound base motifs, and the
/// sound ones with the `extended` rule files, each with `runs` runs per
/// system on `sequences` per box; each is paired with the one before, so
/// the chain shows what each step changes.
pub fn compare_design(runs: usize, sequences: u64, extended: &[PathBuf]) -> Design {
    let variant = |label: &str, rules: RuleSet, motifs: &[PathBuf]| Variant {
        label: label.into(),
        family: "rules".into(),
        kind: Kind::Rigid,
        rules,
        motifs: motifs.to_vec(),
        runs,
        method: Protocol::Nested,
        sequences,
    };
    Design {
        variants: vec![
            variant("paper base", RuleSet::Paper, &[]),
            variant("sound base", RuleSet::Sound, &[]),
            variant("sound + extended", RuleSet::Sound, extended),
        ],
        pairing: Pairing::Previous,
    }
}

/// `rgc tradeoff`: bias against the exact truth and interval width against
/// CPU time. Truth comes first and every variant is measured against it:
/// the paired difference of critical densities on the same sequences
/// (nested), or the difference of thresholds (fixed protocol). Each variant
/// changes one thing of the sound base motifs, one run, nested, `sequences`
/// per box:
/// * `runs`: each count of `runs_list`; more than 10 runs analyse half the
///   sequences, which is where their cost puts them;
/// * `motifs`: the audit's rule files in `rule_dir`, added size by size
///   (`rods-6.json`, then `rods-8.json`, then `mixed-4.json`);
/// * `realizations` (the family's stored name): a quarter and a half of the
///   sequences;
/// * `method`: the fixed protocol with 1 and 10 runs.
pub fn tradeoff_design(runs_list: &[usize], sequences: u64, rule_dir: &Path) -> Design {
    let r = sequences;
    let base = Variant::sound_base("", "", r);
    let mut variants = vec![Variant {
        kind: Kind::Truth,
        ..Variant::sound_base("truth", "truth", r)
    }];
    for &k in runs_list {
        variants.push(Variant {
            label: format!("K={k}"),
            family: "runs".into(),
            runs: k,
            sequences: if k > 10 { r / 2 } else { r },
            ..base.clone()
        });
    }
    let m = |f: &str| rule_dir.join(f);
    for (label, files) in [
        ("+rods<=6 (=<=7)", vec![m("rods-6.json")]),
        ("+rods<=8", vec![m("rods-6.json"), m("rods-8.json")]),
        (
            "+rods<=8 +mixed<=4",
            vec![m("rods-6.json"), m("rods-8.json"), m("mixed-4.json")],
        ),
    ] {
        variants.push(Variant {
            label: label.into(),
            family: "motifs".into(),
            motifs: files,
            ..base.clone()
        });
    }
    for n in [r / 4, r / 2] {
        variants.push(Variant {
            label: format!("R={n}"),
            // Keeps its stored name, so the committed tables stay as they are.
            family: "realizations".into(),
            sequences: n,
            ..base.clone()
        });
    }
    for k in [1, 10] {
        variants.push(Variant {
            label: format!("fixed K={k}"),
            family: "method".into(),
            runs: k,
            method: Protocol::Fixed,
            ..base.clone()
        });
    }
    Design {
        variants,
        pairing: Pairing::First,
    }
}

/// Checks, before any sequence runs, every variant's study as it will
/// be analysed (its own sequences, runs and protocol on `template`), so
/// a variant too small for the scaling fit fails at once.
pub fn check_variants(template: &StudySpec, variants: &[Variant]) -> Result<()> {
    for v in variants {
        let spec = StudySpec {
            kind: v.kind,
            rules: v.rules,
            runs: v.runs,
            method: v.method,
            sequences: v.sequences,
            ..template.clone()
        };
        spec.validate_for_analysis().map_err(|e| match e {
            Error::Parameter(m) => Error::Parameter(format!("variant {:?}: {m}", v.label)),
            e => e,
        })?;
    }
    Ok(())
}

/// The design `make` gives for `template`'s sequences, checked with
/// [`check_variants`]. When it fails and more sequences would do, the
/// message names the fewest (`tradeoff` analyses a quarter of them in one
/// variant, so it needs four times what a single study does).
pub fn checked_design(make: impl Fn(u64) -> Design, template: &StudySpec) -> Result<Design> {
    let design = make(template.sequences);
    let Err(e) = check_variants(template, &design.variants) else {
        return Ok(design);
    };
    let works = |r: u64| {
        let spec = StudySpec {
            sequences: r,
            ..template.clone()
        };
        check_variants(&spec, &make(r).variants).is_ok()
    };
    let fewest = (template.sequences + 1..=template.sequences.max(1) * 1000).find(|&r| works(r));
    Err(match (e, fewest) {
        (Error::Parameter(m), Some(r)) => {
            Error::Parameter(format!("{m}; this design needs --sequences {r} or more"))
        }
        (e, _) => e,
    })
}

/// A study directory name from everything that determines its records, so
/// studies that differ in any parameter never meet in one directory:
/// `rigid-sound-base-k1-nested-r100-g23-L4_5_6-wrap-s1` (kind, rules,
/// motifs, runs, protocol, sequences, gamma, boxes, criterion, seed, and
/// the grid points of the fixed protocol).
pub fn study_name(spec: &StudySpec) -> String {
    let boxes: Vec<String> = spec.boxes.iter().map(f64::to_string).collect();
    let mut name = format!(
        "{}-g{}-L{}-{}-s{}",
        legacy_name(spec),
        spec.gamma,
        boxes.join("_"),
        format!("{:?}", spec.criterion).to_lowercase(),
        spec.seed
    );
    if spec.method == Protocol::Fixed {
        name += &format!("-grid{}", spec.grid_points);
    }
    name
}

/// The shorter name studies had before gamma, boxes, criterion and seed
/// joined it (the committed `results/studies/` use it).
fn legacy_name(spec: &StudySpec) -> String {
    let motifs = if spec.motifs.rules == 0 {
        "base".to_string()
    } else {
        format!("m{}-{}", spec.motifs.rules, &spec.motifs.digest[..8])
    };
    format!(
        "{:?}-{:?}-{}-k{}-{:?}-r{}",
        spec.kind, spec.rules, motifs, spec.runs, spec.method, spec.sequences
    )
    .to_lowercase()
}

/// Where `spec`'s study lives under `root`: the directory [`study_name`]
/// names, unless it does not exist and one under the shorter name of
/// earlier versions holds this very study, which then resumes there (so the
/// committed studies need not move).
pub fn study_dir(root: &Path, spec: &StudySpec) -> PathBuf {
    let dir = root.join(study_name(spec));
    if dir.exists() {
        return dir;
    }
    let legacy = root.join(legacy_name(spec));
    match study::read_spec(&legacy) {
        Ok(there) if there.same(spec) => legacy,
        _ => dir,
    }
}

/// Runs (or resumes) every variant's study on the sequences of `template`
/// (its `sequences` is ignored: each variant says how many it analyses).
/// Variants whose records would be the same share one study, run with as
/// many sequences as the most demanding of them analyses, each step under
/// `memory_limit` ([`RunOptions`]). Returns, per variant, the index of its
/// study among the returned specs and directories.
pub fn run_studies(
    template: &StudySpec,
    variants: &[Variant],
    root: &Path,
    memory_limit: Option<u64>,
    progress: &dyn Progress,
) -> Result<(Vec<StudySpec>, Vec<PathBuf>, Vec<usize>)> {
    let mut specs: Vec<(StudySpec, Vec<CompiledRule>)> = Vec::new();
    let mut of_variant = Vec::new();
    check_variants(template, variants)?;
    for v in variants {
        let loaded = rule_file::load(&v.motifs)?;
        for d in &loaded.dropped {
            progress.note(&format!("warning: {d}"));
        }
        let rules = loaded.rules;
        let spec = StudySpec {
            kind: v.kind,
            rules: v.rules,
            motifs: MotifSet::of(&rules, &v.motifs),
            runs: v.runs,
            method: v.method,
            sequences: v.sequences,
            ..template.clone()
        };
        let same = |s: &StudySpec| {
            StudySpec {
                sequences: spec.sequences,
                ..s.clone()
            } == spec
        };
        let k = match specs.iter().position(|(s, _)| same(s)) {
            Some(k) => {
                let r = &mut specs[k].0.sequences;
                *r = (*r).max(v.sequences);
                k
            }
            None => {
                specs.push((spec, rules.iter().map(CompiledRule::new).collect()));
                specs.len() - 1
            }
        };
        of_variant.push(k);
    }
    let dirs: Vec<PathBuf> = specs.iter().map(|(s, _)| study_dir(root, s)).collect();
    for ((spec, rules), dir) in specs.iter().zip(&dirs) {
        let opts = RunOptions {
            out: dir.clone(),
            shard: Shard::WHOLE,
            extend: false,
            memory_limit,
        };
        progress.note(&format!("study {}", opts.out.display()));
        study::run(spec, rules, &opts, progress)?;
    }
    Ok((
        specs.into_iter().map(|(s, _)| s).collect(),
        dirs,
        of_variant,
    ))
}

/// The first `sequences` records of a finished study, in study order.
pub fn variant_records(spec: &StudySpec, dir: &Path, sequences: u64) -> Result<Vec<Record>> {
    Ok(study::in_study_order(spec, study::read_records(dir, spec)?)
        .into_iter()
        .filter(|r| r.index < sequences)
        .collect())
}

/// Runs (or resumes) every variant's study ([`run_studies`]) and analyses
/// each. A variant analysing fewer sequences than another of the same
/// study shares its records.
pub fn run_variants(
    template: &StudySpec,
    variants: &[Variant],
    root: &Path,
    memory_limit: Option<u64>,
    bootstrap: usize,
    pairing: Pairing,
    progress: &dyn Progress,
) -> Result<Vec<VariantOutcome>> {
    let (specs, dirs, of_variant) = run_studies(template, variants, root, memory_limit, progress)?;
    let mut outcomes: Vec<VariantOutcome> = Vec::new();
    let mut analysed: Vec<Vec<Record>> = Vec::new();
    for (v, &k) in variants.iter().zip(&of_variant) {
        let spec = &specs[k];
        let dir = &dirs[k];
        let records = variant_records(spec, dir, v.sequences)?;
        let subset = StudySpec {
            sequences: v.sequences,
            ..spec.clone()
        };
        // The records stay in the study directory for a later analysis.
        let summary = report::summarize(&subset, &records, bootstrap).map_err(|e| match e {
            Error::Analysis(m) => Error::Analysis(format!(
                "variant {:?}: {m} (its sequences are kept in {})",
                v.label,
                dir.display()
            )),
            e => e,
        })?;
        let t = summary.fss.threshold;
        let partner = match pairing {
            Pairing::First => (!analysed.is_empty()).then_some(0),
            Pairing::Previous => analysed.len().checked_sub(1),
        };
        let threshold_difference = partner.map(|p| difference(t, outcomes[p].threshold));
        let paired_with = partner.map(|p| variants[p].label.clone());
        // Variants reading one study (sequence subsets) have nothing to pair.
        let paired = partner
            .filter(|&p| of_variant[p] != k)
            .and_then(|p| paired_difference(spec, &analysed[p], &records));
        analysed.push(records.clone());
        let reference = outcomes.first().map_or(t.value, |o| o.threshold.value);
        outcomes.push(VariantOutcome {
            label: v.label.clone(),
            family: v.family.clone(),
            rules: v.rules,
            motif_rules: spec.motifs.rules,
            runs: v.runs,
            method: v.method,
            sequences: v.sequences,
            threshold: t,
            interval_width: t.lo.zip(t.hi).map(|(lo, hi)| hi - lo),
            nu: summary.fss.nu,
            relative_difference: (t.value - reference) / reference,
            paired_difference: paired,
            paired_with,
            threshold_difference,
            cpu_seconds: report::timing(&subset, &records).cpu_seconds,
            single_run_miss_rate: summary.order.single_run_miss_rate,
            fresh_misses: summary.order.fresh_misses,
            fresh_checks: summary.order.fresh_checks,
            study: dir.display().to_string(),
        });
    }
    Ok(outcomes)
}

/// `a - b`, with the half-widths of their intervals added in quadrature on
/// each side (the two may be correlated: this errs on the wide side).
fn difference(a: Estimate, b: Estimate) -> Estimate {
    let value = a.value - b.value;
    let half = |x: Option<f64>, y: Option<f64>| Some(x?.hypot(y?));
    Estimate {
        value,
        lo: half(a.lo.map(|lo| a.value - lo), b.hi.map(|hi| hi - b.value)).map(|h| value - h),
        hi: half(a.hi.map(|hi| hi - a.value), b.lo.map(|lo| b.value - lo)).map(|h| value + h),
    }
}

/// Mean difference of critical densities on the sequences both sets of
/// records have (nested protocol), with a 95% normal interval.
fn paired_difference(spec: &StudySpec, first: &[Record], records: &[Record]) -> Option<Estimate> {
    if spec.method != Protocol::Nested {
        return None;
    }
    let pairs = paired::pairs((spec.kind, first), (spec.kind, records));
    paired::mean_interval(&pairs.iter().map(|(f, r)| r - f).collect::<Vec<_>>())
}

/// One variant as both tables show it: every field is a column of the CSV
/// (serde), and each column of the Markdown table ([`MARKDOWN`]) is drawn
/// from these fields, so the two tables cannot drift apart.
#[derive(Serialize)]
struct Row<'a> {
    /// Lowercase in the CSV, as the committed tables have it.
    #[serde(serialize_with = "lowercase")]
    label: &'a str,
    #[serde(serialize_with = "lowercase")]
    family: &'a str,
    rules: RuleSet,
    motif_rules: usize,
    runs: usize,
    method: Protocol,
    // Keeps its stored column name, so the committed CSV tables stay as they are.
    #[serde(rename = "realizations")]
    sequences: u64,
    #[serde(serialize_with = "cell::fixed::<6, _>")]
    threshold: f64,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    threshold_lo: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    threshold_hi: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    interval_width: Option<f64>,
    #[serde(serialize_with = "cell::fixed::<6, _>")]
    nu: f64,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    nu_lo: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    nu_hi: Option<f64>,
    #[serde(serialize_with = "cell::fixed::<6, _>")]
    relative_difference: f64,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    paired_difference: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    paired_lo: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    paired_hi: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    threshold_difference: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    threshold_difference_lo: Option<f64>,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    threshold_difference_hi: Option<f64>,
    /// The Markdown table's only field that is no CSV column.
    #[serde(skip)]
    paired_with: Option<&'a str>,
    #[serde(serialize_with = "cell::fixed::<3, _>")]
    cpu_seconds: f64,
    #[serde(serialize_with = "cell::fixed_opt::<6, _>")]
    single_run_miss_rate: Option<f64>,
    fresh_misses: usize,
    fresh_checks: usize,
}

fn lowercase<S: serde::Serializer>(v: &&str, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_str(&v.to_lowercase())
}

impl<'a> Row<'a> {
    fn of(o: &'a VariantOutcome) -> Self {
        let paired = o.paired_difference;
        Row {
            label: &o.label,
            family: &o.family,
            rules: o.rules,
            motif_rules: o.motif_rules,
            runs: o.runs,
            method: o.method,
            sequences: o.sequences,
            threshold: o.threshold.value,
            threshold_lo: o.threshold.lo,
            threshold_hi: o.threshold.hi,
            interval_width: o.interval_width,
            nu: o.nu.value,
            nu_lo: o.nu.lo,
            nu_hi: o.nu.hi,
            relative_difference: o.relative_difference,
            paired_difference: paired.map(|p| p.value),
            paired_lo: paired.and_then(|p| p.lo),
            paired_hi: paired.and_then(|p| p.hi),
            threshold_difference: o.threshold_difference.map(|d| d.value),
            threshold_difference_lo: o.threshold_difference.and_then(|d| d.lo),
            threshold_difference_hi: o.threshold_difference.and_then(|d| d.hi),
            paired_with: o.paired_with.as_deref(),
            cpu_seconds: o.cpu_seconds,
            single_run_miss_rate: o.single_run_miss_rate,
            fresh_misses: o.fresh_misses,
            fresh_checks: o.fresh_checks,
        }
    }
}

/// `[lo, hi]` to 3 places, or a dash.
fn interval(lo: Option<f64>, hi: Option<f64>) -> String {
    match (lo, hi) {
        (Some(lo), Some(hi)) => format!("[{lo:.3}, {hi:.3}]"),
        _ => "—".into(),
    }
}

/// A difference with its interval and the variant it is taken against, or a dash.
fn against(r: &Row, d: Option<f64>, lo: Option<f64>, hi: Option<f64>) -> String {
    d.map_or("—".into(), |d| {
        format!(
            "{d:+.3} {} (vs {})",
            interval(lo, hi),
            r.paired_with.unwrap_or("?")
        )
    })
}

/// A Markdown column: its heading and how a [`Row`] fills its cell.
type Column = (&'static str, fn(&Row) -> String);

/// The Markdown table's columns.
const MARKDOWN: [Column; 15] = [
    ("variant", |r| r.label.to_string()),
    ("rules", |r| format!("{:?}", r.rules)),
    ("motifs", |r| r.motif_rules.to_string()),
    ("runs", |r| r.runs.to_string()),
    ("method", |r| format!("{:?}", r.method)),
    ("sequences/box", |r| r.sequences.to_string()),
    ("threshold", |r| format!("{:.3}", r.threshold)),
    ("95% interval", |r| interval(r.threshold_lo, r.threshold_hi)),
    ("rel. diff.", |r| {
        format!("{:+.2}%", 100.0 * r.relative_difference)
    }),
    ("paired diff. of critical densities (against)", |r| {
        against(r, r.paired_difference, r.paired_lo, r.paired_hi)
    }),
    ("diff. of thresholds (against)", |r| {
        against(
            r,
            r.threshold_difference,
            r.threshold_difference_lo,
            r.threshold_difference_hi,
        )
    }),
    ("nu", |r| {
        format!("{:.3} {}", r.nu, interval(r.nu_lo, r.nu_hi))
    }),
    ("CPU s", |r| format!("{:.0}", r.cpu_seconds)),
    ("single-run miss", |r| {
        r.single_run_miss_rate
            .map_or("—".into(), |m| format!("{:.1}%", 100.0 * m))
    }),
    ("fresh misses", |r| {
        if r.fresh_checks > 0 {
            format!("{}/{}", r.fresh_misses, r.fresh_checks)
        } else {
            "—".into()
        }
    }),
];

/// The outcomes as a Markdown table.
pub fn markdown(title: &str, command: &str, outcomes: &[VariantOutcome]) -> String {
    let line = |cells: Vec<String>| format!("| {} |\n", cells.join(" | "));
    let mut md = format!("# {title}\n\nMade by `{command}`.\n\n");
    md += &line(MARKDOWN.iter().map(|c| c.0.to_string()).collect());
    md += &format!("|{}\n", "---|".repeat(MARKDOWN.len()));
    for o in outcomes {
        let row = Row::of(o);
        md += &line(MARKDOWN.iter().map(|c| (c.1)(&row)).collect());
    }
    md
}

/// The outcomes as CSV.
pub fn csv(outcomes: &[VariantOutcome]) -> String {
    String::from_utf8(output::csv(outcomes.iter().map(Row::of))).expect("CSV of UTF-8 is UTF-8")
}
