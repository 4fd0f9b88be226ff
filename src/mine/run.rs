//! A whole mining run: every system mined in parallel, then every distinct
//! pattern checked exactly and against the engine.

use rayon::prelude::*;
use std::time::Instant;

use super::parameters::Parameters;
use super::report::{Report, stamp};
use super::system::mine_system;
use super::tally::{summaries, tally};
use crate::Result;
use crate::engine::{CompiledRule, Engine, RuleSet};
use crate::progress::Progress;
use crate::rule_file;

/// Mines every system of `params` (in parallel; the result does not depend
/// on the thread count), then checks every distinct pattern exactly and
/// against the engine. `extended` are the rules of `params.extended`.
pub fn run(
    params: &Parameters,
    extended: &[CompiledRule],
    command: &str,
    progress: &dyn Progress,
) -> Result<Report> {
    params.validate()?;
    let start = Instant::now();
    let jobs: Vec<(f64, u64)> = params
        .densities
        .iter()
        .flat_map(|&rho| params.seeds().map(move |s| (rho, s)))
        .collect();
    progress.start("systems mined", jobs.len() as u64);
    let mined = jobs
        .par_iter()
        .map(|&(rho, seed)| {
            let m = mine_system(params.gamma, params.box_len, rho, seed, &params.search);
            progress.advance(1);
            m
        })
        .collect::<Result<Vec<_>>>()?;
    progress.finish();
    let mut motifs = tally(params, &mined);
    progress.start("patterns checked", motifs.len() as u64);
    let sound = Engine::base(RuleSet::Sound);
    let with = Engine::with_rules(RuleSet::Sound, extended);
    let checks = motifs
        .par_iter()
        .map(|m| {
            let v = crate::rigidity::check_exact(&m.pattern, rule_file::RULE_SEED)?;
            let compresses = sound.compresses(&m.pattern, params.runs)?;
            let extended = (!params.extended.is_empty())
                .then(|| with.compresses(&m.pattern, params.runs))
                .transpose()?;
            progress.advance(1);
            Ok((v.class, v.dof, compresses, extended))
        })
        .collect::<Result<Vec<_>>>()?;
    progress.finish();
    let mut k = 0;
    for (m, (class, dof, compresses, extended)) in motifs.iter_mut().zip(checks) {
        m.candidate = class == "rigid" && !compresses;
        m.class = class;
        m.dof = dof;
        m.sound_compresses = compresses;
        m.extended_compresses = extended;
        if m.candidate && k < params.top {
            m.rule = Some(format!("mined-{k}"));
            k += 1;
        }
    }
    let densities = summaries(params, &mined, &motifs);
    Ok(Report {
        stamp: stamp(command, params),
        densities,
        systems: mined.into_iter().map(|(s, _)| s).collect(),
        motifs,
        seconds: start.elapsed().as_secs_f64(),
    })
}
