//! What a mining run leaves: `mined-motifs.{json,csv,md}`, the rules of its
//! top candidates, and the refusal to replace another run's results.

use serde::{Deserialize, Serialize};
use std::path::Path;

use super::parameters::Parameters;
use super::system::SystemReport;
use super::tally::{DensitySummary, MinedMotif};
use crate::output::{self, cell};
use crate::pattern::MAX_PATTERN_NODES;
use crate::rule_file::{self, Provenance, Rule};
use crate::stamp::{self as envelope, Stamp};
use crate::{Error, Result};

/// The format tag of `mined-motifs.json`.
pub const FORMAT: &str = "rgc-mined-motifs/1";

/// What made `mined-motifs.json`: the mining run's parameters.
pub type Made = envelope::Parameters<Parameters>;

/// The stamp of `mined-motifs.json` that `command` writes with `params`.
pub fn stamp(command: &str, params: &Parameters) -> Stamp<Made> {
    Stamp::with_parameters(FORMAT, command, params.clone())
}

/// What `mined-motifs.json` holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Report {
    #[serde(flatten)]
    pub stamp: Stamp<Made>,
    pub densities: Vec<DensitySummary>,
    pub systems: Vec<SystemReport>,
    /// Every distinct pattern, most frequent first.
    pub motifs: Vec<MinedMotif>,
    pub seconds: f64,
}

/// The rules of the report: its top candidates, most frequent first, each
/// verified now, with the frequency per density in its provenance.
pub fn rules(report: &Report) -> Result<Vec<Rule>> {
    let p = &report.stamp.made.parameters;
    report
        .motifs
        .iter()
        .filter_map(|m| m.rule.as_ref().map(|id| (id, m)))
        .map(|(id, m)| {
            let provenance = Provenance {
                source: "mined".into(),
                enumeration: Some(p.enumeration()),
                audited_against: Some(p.audited_against()),
                command: Some(report.stamp.command.clone()),
                version: Some(env!("CARGO_PKG_VERSION").into()),
                frequency: m.per_density.clone(),
            };
            Rule::new(id.clone(), m.pattern.clone(), provenance)
        })
        .collect()
}

/// Refuses, unless `force`, to replace results or a rule file that
/// another mining run made: `results` (`mined-motifs.json`) stamped other
/// than `stamp` (see [`Stamp::check_replace`]), or a rule file whose rules
/// were not mined with the same enumeration (a rule file without rules
/// holds nothing to lose). A missing file is fine.
pub fn check_replace(
    results: &Path,
    rule_file_path: &Path,
    stamp: &Stamp<Made>,
    force: bool,
) -> Result<()> {
    stamp.check_replace(results, "mining run", force)?;
    if force {
        return Ok(());
    }
    let Some(text) = envelope::existing(rule_file_path)? else {
        return Ok(());
    };
    let params = &stamp.made.parameters;
    let same = serde_json::from_str::<rule_file::RuleFile>(&text).is_ok_and(|f| {
        f.rules.iter().all(|r| {
            r.provenance.source == "mined"
                && r.provenance.enumeration.as_deref() == Some(&params.enumeration())
                && r.provenance.audited_against.as_deref() == Some(&params.audited_against())
        })
    });
    if same {
        return Ok(());
    }
    Err(Error::Parameter(format!(
        "{} holds rules not mined with these parameters; choose another --out, or --force to replace them",
        rule_file_path.display()
    )))
}

/// One row of `mined-motifs.csv`, before the per-density cells.
#[derive(Serialize)]
struct Row<'a> {
    rank: usize,
    canonical: &'a str,
    nodes: usize,
    rod_nodes: usize,
    planar: usize,
    spatial: usize,
    contacts: usize,
    class: &'a str,
    #[serde(serialize_with = "cell::display_opt")]
    dof: Option<usize>,
    sound_compresses: bool,
    #[serde(serialize_with = "cell::display_opt")]
    extended_compresses: Option<bool>,
    candidate: bool,
    rule: &'a str,
    occurrences: u64,
    systems: u64,
    whole: u64,
    wrapping: u64,
    example_density: f64,
    example_seed: u64,
}

/// Every pattern, with its occurrences and systems per density.
pub fn csv(report: &Report) -> Vec<u8> {
    let more: Vec<String> = report
        .stamp
        .made
        .parameters
        .densities
        .iter()
        .flat_map(|rho| [format!("occurrences_{rho}"), format!("systems_{rho}")])
        .collect();
    output::csv_with_more(
        &more,
        report.motifs.iter().map(|m| {
            let cells: Vec<u64> = m
                .per_density
                .iter()
                .flat_map(|f| [f.occurrences, f.systems])
                .collect();
            (
                Row {
                    rank: m.rank,
                    canonical: &m.canonical,
                    nodes: m.nodes,
                    rod_nodes: m.rod_nodes,
                    planar: m.planar,
                    spatial: m.spatial,
                    contacts: m.contacts,
                    class: &m.class,
                    dof: m.dof,
                    sound_compresses: m.sound_compresses,
                    extended_compresses: m.extended_compresses,
                    candidate: m.candidate,
                    rule: m.rule.as_deref().unwrap_or(""),
                    occurrences: m.occurrences,
                    systems: m.systems,
                    whole: m.whole,
                    wrapping: m.wrapping,
                    example_density: m.example.density,
                    example_seed: m.example.seed,
                },
                cells,
            )
        }),
    )
}

/// Patterns listed in each Markdown table.
const MARKDOWN_MOTIFS: usize = 30;

/// The per-density summary, the most frequent patterns and the most
/// frequent rule candidates as Markdown.
pub fn markdown(report: &Report) -> String {
    let p = &report.stamp.made.parameters;
    let mut md = format!(
        "# Motifs 3D-RGC misses, mined from generated systems\n\n\
         Command: `{}`\n\n{}.\n\n",
        report.stamp.command,
        p.enumeration()
    );
    md += "| density | systems | truth spans | sound spans | quotient nodes | missed clusters | rods in them | seed pairs | minimal sets (found) | not local | too large | not whole | nodes per set (mean, max) | patterns | rule candidates |\n";
    md += "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for d in &report.densities {
        md += &format!(
            "| {} | {} | {} | {} | {:.1} | {} | {:.1} | {} | {} ({}) | {} | {} | {} | {:.1}, {} | {} | {} |\n",
            d.density,
            d.systems,
            d.truth_spans,
            d.sound_spans,
            d.mean_nodes,
            d.missed_clusters,
            d.mean_missed_rods,
            d.pairs,
            d.sets,
            d.found,
            d.not_local,
            d.too_large,
            d.not_whole,
            d.mean_set_nodes,
            d.max_set_nodes,
            d.patterns,
            d.candidates
        );
    }
    md += &format!(
        "\nQuotient nodes (the `sound` run's bodies and free rods) and rods in missed clusters \
         (true clusters holding two or more whole nodes) are means per system; the other counts \
         are sums over the systems of a density. *Minimal sets*: distinct sets the seed pairs \
         gave (*found*: pairs that gave one). *Not local*: pairs not rigid together within \
         radius {} and {} rods of the quotient ball, or before the nodes in or touching their \
         cluster ran out. *Too large*: sets beyond a pattern's {MAX_PATTERN_NODES} nodes or 96 \
         contacts. *Not whole*: sets in which some node only holds the others together while \
         turning itself (a lock); their patterns cannot be rigid, and no rule can express them.\n\n",
        p.search.max_radius, p.search.max_ball_rods
    );
    md += &format!(
        "## The {} most frequent of {} patterns\n\n",
        MARKDOWN_MOTIFS.min(report.motifs.len()),
        report.motifs.len()
    );
    md += &motif_table(p, report.motifs.iter().take(MARKDOWN_MOTIFS));
    let candidates: Vec<&MinedMotif> = report.motifs.iter().filter(|m| m.candidate).collect();
    md += &format!(
        "\n## The {} most frequent of {} rule candidates (rigid on every component, missed by sound)\n\n",
        MARKDOWN_MOTIFS.min(candidates.len()),
        candidates.len()
    );
    md += &motif_table(p, candidates.into_iter().take(MARKDOWN_MOTIFS));
    md += "\nPer density: occurrences (distinct minimal sets) and, in parentheses, the systems \
           holding one. *Whole*: occurrences that truth holds in one cluster, of all. \
           *Extended*: whether sound with the extended rule files compresses it.\n";
    md
}

/// A Markdown table of patterns.
fn motif_table<'a>(p: &Parameters, motifs: impl Iterator<Item = &'a MinedMotif>) -> String {
    let heads: Vec<String> = p.densities.iter().map(|rho| format!("rho {rho}")).collect();
    let mut md = format!(
        "| rank | rule | nodes (rod/planar/spatial) | contacts | exact verdict | sound compresses | extended | whole | {} | example (density, seed) | canonical form |\n",
        heads.join(" | ")
    );
    md += &format!(
        "|---:|---|---|---:|---|---|---|---:|{}---|---|\n",
        "---:|".repeat(heads.len())
    );
    let yes = |b: bool| if b { "yes" } else { "no" };
    for m in motifs {
        let cells: Vec<String> = m
            .per_density
            .iter()
            .map(|f| format!("{} ({})", f.occurrences, f.systems))
            .collect();
        md += &format!(
            "| {} | {} | {} ({}/{}/{}) | {} | {}{} | {} | {} | {}/{} | {} | {}, {} | `{}` |\n",
            m.rank,
            m.rule.as_deref().unwrap_or(""),
            m.nodes,
            m.rod_nodes,
            m.planar,
            m.spatial,
            m.contacts,
            m.class,
            m.dof.map_or(String::new(), |d| format!(", {d} DOF")),
            yes(m.sound_compresses),
            m.extended_compresses.map_or("", yes),
            m.whole,
            m.occurrences,
            cells.join(" | "),
            m.example.density,
            m.example.seed,
            m.canonical
        );
    }
    md
}

/// Writes `mined-motifs.{json,csv,md}` into `dir`, atomically.
pub fn write(report: &Report, dir: &Path) -> Result<()> {
    output::write_atomic(&dir.join("mined-motifs.json"), envelope::json(report))?;
    output::write_atomic(&dir.join("mined-motifs.csv"), csv(report))?;
    output::write_atomic(&dir.join("mined-motifs.md"), markdown(report))
}
