//! Measuring the sequences of truth studies: each sequence's moduli one
//! rod below and at its critical number and at the spec's densities, one
//! journal line per sequence, so that a killed run resumes; a sequence in
//! progress is saved after each side in `partial/`, so that it resumes
//! from its last side.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::record::{Partial, SequenceStiffening, Side, StiffeningSpec};
use super::summary::{Stiffening, one_grid_per_box, shear_decay, summarize_grids};
use crate::engine::run_seed;
use crate::moduli::{self, Floats, ModuliOptions, Solver};
use crate::progress::Progress;
use crate::threshold::journal::{self, Line};
use crate::threshold::report;
use crate::threshold::sequence::{Record, Sequence};
use crate::truth::TruthOptions;
use crate::{Error, Result, output};

/// The moduli of the first `n` rods of `r`'s sequence `seq`, truth's
/// realizations seeded as the study's step at `n`, on the realization
/// nearest the rods; with `next` (the floats of more rods of the sequence),
/// on that one kept for these rods where it is not special for them, so
/// that the two sides are one geometry. Returns the floats it used, if any.
/// Truth, the projection and the factor are refused past `limit` (bytes
/// resident).
fn side(
    seq: &Sequence,
    r: &Record,
    n: usize,
    spec: &StiffeningSpec,
    next: Option<&Floats>,
    limit: Option<u64>,
) -> Result<(Side, Option<Floats>)> {
    let graph = seq.graph(n);
    let opts = ModuliOptions {
        stiffness: spec.stiffness,
        truth: TruthOptions {
            memory_limit: limit,
            ..TruthOptions::seeded(run_seed(r.seed, n as u64))
        },
        solver: spec.solver,
        lsmr_iterations: spec.lsmr_iterations,
    };
    let view = seq.view(n, &graph);
    let blank = Side {
        rods: n,
        strain_rank: None,
        shear: None,
        bulk: None,
        born_shear: None,
        realization: None,
        moved: None,
        largest: None,
        failed: None,
        settled: None,
        solver: None,
        lsmr_iterations: None,
    };
    let failed = |e: Error, side: Side| match e {
        // Over the memory limit is no answer about the sequence: stop.
        Error::Memory(_) => Err(e),
        e => Ok((
            Side {
                failed: Some(e.to_string()),
                ..side
            },
            None,
        )),
    };
    let exact = match moduli::exact(view, opts) {
        Ok(exact) => exact,
        Err(e) => return failed(e, blank),
    };
    let known = Side {
        strain_rank: Some(exact.strain_rank),
        largest: Some(exact.largest_cluster),
        ..blank
    };
    // Where the rods resist no strain the tensor is zero: no floats (and
    // no Born tensor, which needs a realization).
    if exact.strain_rank == 0 {
        let zero = Side {
            shear: Some(0.0),
            bulk: Some(0.0),
            ..known
        };
        return Ok((zero, None));
    }
    let of = |e: moduli::Elastic| Side {
        shear: Some(e.shear),
        bulk: Some(e.bulk),
        born_shear: Some(e.born_shear),
        realization: Some(e.realization),
        moved: e.moved.map(|m| m.contacts),
        settled: Some(e.conditioning.settled),
        solver: Some(e.conditioning.solver),
        lsmr_iterations: (e.conditioning.solver == Solver::Lsmr).then_some(spec.lsmr_iterations),
        ..known.clone()
    };
    // The larger system's geometry, unless it is special for these rods
    // (no gap at their strain rank): then their own.
    if let Some(next) = next
        && let Ok(e) = moduli::of_floats(view, exact, &next.prefix(view), opts)
    {
        return Ok((of(e), None));
    }
    // Only the realization nearest the rods compares across sequences:
    // where it fails the side fails (keeping the exact strain rank),
    // without the costly random start.
    let floats = match moduli::floats(view, opts.truth.seed, false, opts.truth.memory_limit) {
        Ok(f) => f,
        Err(e) => return failed(e, known),
    };
    match moduli::of_floats(view, exact, &floats, opts) {
        Ok(e) => Ok((of(e), Some(floats))),
        Err(e) => failed(e, known),
    }
}

/// Rods at `density` in a cubic box of side `box_len`.
fn rods_at(density: f64, box_len: f64) -> usize {
    (density * box_len.powi(3)).round() as usize
}

/// One sequence: its moduli one rod below and at the critical number, and
/// at each density of `spec`, within `limit` (bytes resident); resumed
/// from the sides saved in `part`, and saved there after each side.
fn probe(
    gamma: f64,
    r: &Record,
    spec: &StiffeningSpec,
    limit: Option<u64>,
    part: &Path,
) -> Result<SequenceStiffening> {
    let start = Instant::now();
    let n = r.rigid_critical.expect("chosen records are decided");
    let grid: Vec<usize> = spec
        .densities
        .iter()
        .map(|&d| rods_at(d, r.box_len))
        .collect();
    let mut done = resumed(part, n, &grid)?;
    let spent = done.seconds;
    let seconds = || spent + start.elapsed().as_secs_f64();
    // A side LSMR left unsettled under a smaller cap than the spec's is
    // measured again (`--extend` with a larger cap).
    let stale = |s: &Side| s.settles_under(spec.lsmr_iterations);
    let pair_due = done.pair.as_ref().is_none_or(|(b, a)| stale(b) || stale(a));
    let grid_due: Vec<usize> = (0..grid.len())
        .filter(|&i| done.grid.get(i).is_none_or(stale))
        .collect();
    // A line whose sides all stand (extended to a cap they settled under)
    // costs no rods and no time.
    if pair_due || !grid_due.is_empty() {
        // One sequence to the most rods any side needs; each side a prefix.
        let most = grid.iter().copied().fold(n, usize::max);
        let seq = Sequence::new(gamma, r.box_len, most, r.seed)?;
        if pair_due {
            // The critical rod's side first: the side below it is measured
            // on the same realization, so that the jump is the rod's, not
            // another member's of the family.
            let (at, floats) = side(&seq, r, n, spec, None, limit)?;
            let (before, _) = side(&seq, r, n - 1, spec, floats.as_ref(), limit)?;
            done.pair = Some((before, at));
            done.seconds = seconds();
            save(part, &done)?;
        }
        for i in grid_due {
            let s = side(&seq, r, grid[i], spec, None, limit)?.0;
            match done.grid.get_mut(i) {
                Some(old) => *old = s,
                None => done.grid.push(s),
            }
            done.seconds = seconds();
            save(part, &done)?;
        }
    }
    let (before, at) = done.pair.expect("measured above");
    Ok(SequenceStiffening {
        gamma,
        box_len: r.box_len,
        index: r.index,
        at,
        before,
        grid: done.grid,
        seconds: done.seconds,
    })
}

/// The sides saved in `part` for a sequence critical at `n` rods on the
/// grid of `grid` rods (none if there is no file); a file whose sides are
/// of other numbers of rods is refused.
fn resumed(part: &Path, n: usize, grid: &[usize]) -> Result<Partial> {
    if !part.exists() {
        return Ok(Partial::default());
    }
    let done: Partial = journal::read_spec(part, "stiffening sequence in progress")?;
    let pair_fits = done
        .pair
        .as_ref()
        .is_none_or(|(before, at)| (before.rods, at.rods) == (n - 1, n));
    let grid_fits = done.grid.len() <= grid.len()
        && (done.pair.is_some() || done.grid.is_empty())
        && done.grid.iter().zip(grid).all(|(s, &m)| s.rods == m);
    if !(pair_fits && grid_fits) {
        return Err(Error::Parameter(format!(
            "{} holds the sides of another sequence than this measurement's (critical at {n} rods, grid {grid:?}): remove it",
            part.display()
        )));
    }
    Ok(done)
}

/// Saves the sides of a sequence in progress to `part` (atomically).
fn save(part: &Path, done: &Partial) -> Result<()> {
    if let Some(dir) = part.parent() {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    output::write_atomic(part, serde_json::to_vec(done).expect("sides serialize"))
}

/// Where the sides of sequence `index` of box `box_len` at aspect ratio
/// `gamma` are saved while it is measured, in the directory `partial`.
fn part_file(partial: &Path, gamma: f64, box_len: f64, index: u64) -> PathBuf {
    partial.join(format!("gamma{gamma}-box{box_len}-{index}.json"))
}

/// The directory's spec file and lines.
fn files(out: &Path) -> (PathBuf, PathBuf) {
    (out.join("stiffening.json"), out.join("stiffening.jsonl"))
}

/// Gives the finished sequences of the measurement in `out` the densities
/// `spec` adds after its grid's last, or its larger cap on LSMR's
/// iterations: each line goes back to `partial/` as a sequence in
/// progress with the old grid measured, and leaves the journal, and then
/// the spec takes the new grid, solver and cap, so that the run measures
/// only the new sides (each a prefix of its own, as if measured with the
/// rest) and those LSMR left unsettled under a smaller cap (a critical
/// side with its pair, one geometry). Killed at any point, the same
/// command finishes it. A directory already on `spec` is left as it is.
fn extend(out: &Path, spec: &StiffeningSpec) -> Result<()> {
    let (spec_file, lines) = files(out);
    if !spec_file.exists() {
        return Err(Error::Parameter(format!(
            "--extend: {} holds no stiffening measurement to extend",
            out.display()
        )));
    }
    let there: StiffeningSpec = journal::read_spec(&spec_file, "stiffening spec")?;
    if &there == spec {
        return Ok(());
    }
    let old = &there.densities;
    let same_else = StiffeningSpec {
        densities: old.clone(),
        solver: there.solver,
        lsmr_iterations: there.lsmr_iterations,
        ..spec.clone()
    } == there;
    let more = spec.densities.len() > old.len();
    let cap = (there.lsmr_iterations, spec.lsmr_iterations);
    let continues = spec.densities.starts_with(old) && cap.1 >= cap.0 && (more || cap.1 > cap.0);
    if !(same_else && continues) {
        return Err(Error::Parameter(format!(
            "--extend adds densities after the last of {} ({old:?}), or raises LSMR's iterations per strain ({}), with the same studies, boxes, sequences and k; this run's are {:?} and {}",
            spec_file.display(),
            cap.0,
            spec.densities,
            cap.1
        )));
    }
    let partial = out.join("partial");
    for s in read(&lines)? {
        let part = Partial {
            pair: Some((s.before, s.at)),
            grid: s.grid,
            seconds: s.seconds,
        };
        save(&part_file(&partial, s.gamma, s.box_len, s.index), &part)?;
    }
    // The lines go only once their sides are saved, and the spec changes
    // last: a run killed before it extends again from the same state.
    output::write_atomic(&lines, Vec::new())?;
    output::write_atomic(
        &spec_file,
        serde_json::to_string_pretty(spec).expect("spec serializes"),
    )
}

/// Measures the chosen sequences of the truth studies `dirs` into `out`
/// (resuming what is there; with `grow`, first giving its finished
/// sequences the new densities of `spec`) and summarizes them with the
/// sequences of the measurements `with` (other boxes, with the same
/// springs; each box on its own grid) per aspect ratio and box, and across
/// boxes.
pub fn run(
    dirs: &[PathBuf],
    spec: &StiffeningSpec,
    out: &Path,
    grow: bool,
    with: &[PathBuf],
    memory_limit: Option<u64>,
    progress: &dyn Progress,
) -> Result<Stiffening> {
    if spec.solver == Solver::Auto {
        return Err(Error::Parameter(
            "a stiffening measurement solves by the QR or by LSMR (--solver qr or lsmr), not by what the memory free at the time allows".into(),
        ));
    }
    let others = with
        .iter()
        .map(|dir| joined(dir, spec))
        .collect::<Result<Vec<_>>>()?;
    if !(spec.stiffness.is_finite() && spec.stiffness > 0.0) {
        return Err(Error::Parameter(format!(
            "the spring stiffness k must be positive and finite, not {}",
            spec.stiffness
        )));
    }
    if spec.densities.iter().any(|d| !(d.is_finite() && *d > 0.0))
        || spec.densities.windows(2).any(|w| w[0] >= w[1])
    {
        return Err(Error::Parameter(format!(
            "--densities must increase and be positive, not {:?}",
            spec.densities
        )));
    }
    let decided = journal::decided_truth_records(
        dirs,
        &spec.boxes,
        spec.sequences,
        "the stiffness across the critical rod",
    )?;
    // Before any work: no box on two grids, no sequence joined twice.
    let measured: Vec<(&[f64], (f64, f64))> = decided
        .iter()
        .map(|(gamma, r)| (spec.densities.as_slice(), (*gamma, r.box_len)))
        .chain(others.iter().flat_map(|(d, seqs)| {
            seqs.iter()
                .map(move |s| (d.as_slice(), (s.gamma, s.box_len)))
        }))
        .collect();
    one_grid_per_box(&measured)?;
    let mut keys: Vec<(f64, f64, u64)> = decided
        .iter()
        .map(|(gamma, r)| (*gamma, r.box_len, r.index))
        .collect();
    for (dir, (_, more)) in with.iter().zip(&others) {
        for s in more {
            if keys.contains(&s.key()) {
                return Err(Error::Parameter(format!(
                    "{} measured sequence {} of box {} at gamma {} again: join measurements of other boxes",
                    dir.display(),
                    s.index,
                    s.box_len,
                    s.gamma
                )));
            }
            keys.push(s.key());
        }
    }
    output::check_dir(out)?;
    if grow {
        extend(out, spec)?;
    }
    let (spec_file, lines) = files(out);
    let partial = out.join("partial");
    let mine = journal::measure(
        (&spec_file, spec, "stiffening spec"),
        &lines,
        &decided,
        progress,
        |gamma, r| {
            let part = part_file(&partial, gamma, r.box_len, r.index);
            probe(gamma, r, spec, memory_limit, &part)
        },
    )?;
    // Every sequence is a line now: what was saved in progress is in them.
    if let Err(e) = std::fs::remove_dir_all(&partial)
        && e.kind() != std::io::ErrorKind::NotFound
    {
        return Err(Error::io(&partial, e));
    }
    // Each aspect ratio's threshold from its finished study (the first
    // given, where several have one aspect ratio); a study in progress has
    // no summary yet.
    let mut thresholds: Vec<(f64, f64)> = Vec::new();
    for dir in dirs.iter().filter(|d| d.join("summary.json").exists()) {
        let s = report::read_summary(dir)?;
        if !thresholds.iter().any(|t| t.0 == s.study.gamma) {
            thresholds.push((s.study.gamma, s.fss.threshold.value));
        }
    }
    let every: Vec<SequenceStiffening> = mine
        .iter()
        .chain(others.iter().flat_map(|(_, more)| more))
        .cloned()
        .collect();
    let decay = shear_decay(&every);
    let parts = std::iter::once((spec.densities.clone(), mine))
        .chain(others)
        .collect();
    Ok(Stiffening {
        boxes: summarize_grids(parts, &thresholds),
        decay,
    })
}

/// The sequences measured so far.
pub fn read(lines: &Path) -> Result<Vec<SequenceStiffening>> {
    journal::read(lines, "stiffening")
}

/// The grid and sequences of the measurement in `dir`, which must share
/// `spec`'s springs (moduli scale with `k`, but a study compares one).
fn joined(dir: &Path, spec: &StiffeningSpec) -> Result<(Vec<f64>, Vec<SequenceStiffening>)> {
    let (spec_file, lines) = files(dir);
    let there: StiffeningSpec = journal::read_spec(&spec_file, "stiffening spec")?;
    if there.stiffness != spec.stiffness {
        return Err(Error::Parameter(format!(
            "{} measured with k = {}, this measurement with k = {}: join only measurements of one spring stiffness",
            dir.display(),
            there.stiffness,
            spec.stiffness
        )));
    }
    Ok((there.densities, read(&lines)?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::threshold::stiffening::summary::summarize;

    /// A spec of one sequence, no densities, `k = 1`.
    fn one_sequence() -> StiffeningSpec {
        StiffeningSpec {
            studies: vec![],
            boxes: vec![],
            sequences: 1,
            stiffness: 1.0,
            densities: vec![],
            solver: Solver::Qr,
            lsmr_iterations: moduli::LSMR_ITERATIONS,
        }
    }

    /// The record of the gamma 23, L = 3 sequence of `seed`, critical at
    /// `n` rods.
    fn record(seed: u64, n: usize) -> Record {
        serde_json::from_value(serde_json::json!({
            "box": 3.0, "index": 0, "seed": seed, "contact_critical": 10,
            "rigid_critical": n, "steps": [], "fresh": null, "fixed": [],
            "contacts": [], "seconds": 0.0
        }))
        .unwrap()
    }

    #[test]
    fn near_the_threshold_the_rod_raises_g_on_one_geometry() {
        // The solid study's sequence 31 at L = 5: strain rank 5 -> 6 at
        // 4,295 rods. The normal equations left soft modes unrelaxed and
        // gave G 2.86e-6 below the rod and 2.82e-6 at it; by QR 3.18e-7
        // and 3.56e-7 (1.73e-7 and 2.08e-7 on the member reached before
        // moved lines kept their contacts).
        let spec = one_sequence();
        let mut r = record(2_787_861_376_596_761_304, 4295);
        r.box_len = 5.0;
        let s = probe(23.0, &r, &spec, None, &scratch("raises")).unwrap();
        let (b, a) = (&s.before, &s.at);
        assert_eq!((b.strain_rank, a.strain_rank), (Some(5), Some(6)));
        assert!(b.one_geometry_with(a));
        let (gb, ga) = (b.shear.unwrap(), a.shear.unwrap());
        assert!((gb - 3.1784e-7).abs() < 1e-11, "{gb}");
        assert!((ga - 3.5565e-7).abs() < 1e-11, "{ga}");
    }

    /// A file for the sides in progress of the test `name`, not there yet.
    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("rgc-stiffening-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir.join("partial.json")
    }

    #[test]
    fn a_killed_sequence_resumes_from_its_saved_sides() {
        // Sequence of seed 1 at L = 3, critical at 1,101 rods, on a grid of
        // two densities: the pair and the first grid side saved, then a
        // kill.
        let spec = StiffeningSpec {
            densities: vec![38.0, 42.0],
            ..one_sequence()
        };
        let r = record(1, 1101);
        let part = scratch("resume");
        let whole = probe(23.0, &r, &spec, None, &part).unwrap();
        let saved: Partial = journal::read_spec(&part, "partial").unwrap();
        assert_eq!(saved.grid.len(), 2);
        // Every side standing, nothing is measured and no time is added.
        let timed = Partial {
            seconds: 5.0,
            ..saved.clone()
        };
        output::write_atomic(&part, serde_json::to_vec(&timed).unwrap()).unwrap();
        let standing = probe(23.0, &r, &spec, None, &part).unwrap();
        assert_eq!((standing.seconds, &standing.grid), (5.0, &whole.grid));
        // What the file holds is taken, not measured again: a side marked
        // in it comes back marked, and the time spent before is kept.
        let mut cut = saved.clone();
        cut.grid.truncate(1);
        cut.grid[0].moved = Some(-1.0);
        cut.seconds = 1e6;
        output::write_atomic(&part, serde_json::to_vec(&cut).unwrap()).unwrap();
        let resumed = probe(23.0, &r, &spec, None, &part).unwrap();
        assert_eq!(resumed.grid[0].moved, Some(-1.0));
        assert_eq!(resumed.grid[1], whole.grid[1]);
        assert_eq!((&resumed.before, &resumed.at), (&whole.before, &whole.at));
        assert!(resumed.seconds > 1e6);
        // Sides of other numbers of rods (another sequence's) are refused.
        let other = record(1, 1200);
        let err = probe(23.0, &other, &spec, None, &part)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("holds the sides of another sequence") && err.contains("1200"),
            "{err}"
        );
    }

    /// The side of `n` rods of the gamma 23, L = 3 sequence of `seed`.
    fn side_of(seed: u64, n: usize) -> Side {
        let seq = Sequence::new(23.0, 3.0, n, seed).unwrap();
        super::side(&seq, &record(seed, n), n, &one_sequence(), None, None)
            .unwrap()
            .0
    }

    #[test]
    fn the_side_below_the_critical_rod_is_measured_on_its_geometry() {
        // Solids on both sides (density 40.8): the rod's springs add to one
        // geometry, so no modulus falls, and the realization below is the
        // critical one kept for its rods.
        let spec = one_sequence();
        for seed in [1, 2, 3] {
            let part = scratch(&format!("below-{seed}"));
            let s = probe(23.0, &record(seed, 1101), &spec, None, &part).unwrap();
            let (b, a) = (&s.before, &s.at);
            assert_eq!((b.strain_rank, a.strain_rank), (Some(6), Some(6)));
            assert_eq!(a.realization.as_deref(), Some("nearest"));
            assert_eq!(b.realization.as_deref(), Some("nearest-next"));
            assert!(b.one_geometry_with(a) && b.comparable());
            let (gb, ga) = (b.shear.unwrap(), a.shear.unwrap());
            assert!(0.0 < gb && gb <= ga * (1.0 + 1e-9), "{b:?} {a:?}");
            assert!(b.bulk.unwrap() <= a.bulk.unwrap() * (1.0 + 1e-9));
            assert!(b.born_shear.unwrap() <= a.born_shear.unwrap() * (1.0 + 1e-12));
            // How far that realization lies from these rods is their own.
            assert!(b.moved.is_some_and(|m| m > 0.0));
            let summary = &summarize(std::slice::from_ref(&s), &spec.densities, &[])[0];
            assert_eq!((summary.one_geometry, summary.shear_fell), (1, 0));
            let jump = summary.shear_jump.unwrap().mean;
            assert!((jump - (ga - gb)).abs() < 1e-18, "{jump}");
        }
    }

    #[test]
    fn a_side_whose_floats_fail_keeps_its_exact_strain_rank() {
        // Seed 5, 1,100 rods: the projection from the rods stays on a
        // special position after every kick, and no random start stands in.
        let n = 1100;
        let s = side_of(5, n);
        let why = s.failed.as_deref().expect("the floats fail");
        assert!(why.contains("special after 3 rounds of 8 repairs"), "{why}");
        assert_eq!(s.strain_rank, Some(6));
        assert!(s.largest.is_some_and(|l| l > 0 && l <= n));
        assert_eq!((s.shear, s.realization.as_deref()), (None, None));
        assert!(!s.comparable());
    }

    #[test]
    fn a_special_position_is_cured_by_growing_kicks_or_a_later_round() {
        // Seed 20, 1,100 rods: the projection from the rods lands on a
        // special member, and the fifth kick of its first round (0.16 rod
        // lengths) leaves it.
        let s = side_of(20, 1100);
        assert_eq!(s.failed, None);
        assert_eq!(s.realization.as_deref(), Some("nearest"));
        assert!(s.comparable() && s.shear.is_some_and(|g| g > 0.0));
        // Seed 6, 1,100 rods: a whole round of kicks leaves it special,
        // the second round's draws cure it.
        let s = side_of(6, 1100);
        assert_eq!(s.failed, None);
        assert_eq!(s.realization.as_deref(), Some("nearest"));
        assert!(s.comparable() && s.shear.is_some_and(|g| g > 0.0));
    }
}
