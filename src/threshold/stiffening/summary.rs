//! What the measured sequences say: per aspect ratio and box, the moduli
//! on both sides of the critical rod and along the density grid with the
//! exponent `f`, and across boxes the shear modulus at the critical rod.

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::record::{SequenceStiffening, Side};
use crate::math::stats;
use crate::threshold::transition;
use crate::{Error, Result, output};

/// A measurement's summary: per aspect ratio and box, and across boxes
/// the shear modulus at the critical rod.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Stiffening {
    pub boxes: Vec<StiffeningSummary>,
    pub decay: Vec<ShearDecay>,
}
/// The shear modulus at the critical rod against the box, per aspect
/// ratio: one that appears continuously vanishes there as the box grows
/// (`G ~ (rho - rho_c)^f` and `rho - rho_c ~ L^(-1/nu)` give `L^(-f/nu)`),
/// one that jumps keeps a finite value.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ShearDecay {
    pub gamma: f64,
    /// Per box: its side, the sequences whose critical side compares, and
    /// their mean and geometric mean `G` (`k / L_rod`; the geometric none
    /// where a `G` is zero).
    pub boxes: Vec<(f64, usize, f64, Option<f64>)>,
    /// The mean `G` as `~ L^(-x)`, over every box and over the largest
    /// ([`transition::power_decay`]; none below three boxes).
    pub decay: Vec<transition::Decay>,
    /// The same for the geometric mean ([`transition::geometric_decay`]):
    /// `G` at the rod spans orders of magnitude between sequences, and
    /// between members of the family on one sequence.
    pub geometric: Vec<transition::Decay>,
}

/// The (aspect ratio, box) pairs of `all`, in that order.
fn boxes(all: &[SequenceStiffening]) -> Vec<(f64, f64)> {
    let mut keys: Vec<(f64, f64)> = all.iter().map(|s| (s.gamma, s.box_len)).collect();
    keys.sort_by(|a, b| a.partial_cmp(b).expect("finite"));
    keys.dedup();
    keys
}

/// [`ShearDecay`] of each aspect ratio of `all` with two boxes or more.
pub fn shear_decay(all: &[SequenceStiffening]) -> Vec<ShearDecay> {
    let keys = boxes(all);
    let mut gammas: Vec<f64> = keys.iter().map(|k| k.0).collect();
    gammas.dedup();
    gammas
        .into_iter()
        .filter_map(|gamma| {
            let values: Vec<(f64, Vec<f64>)> = keys
                .iter()
                .filter(|k| k.0 == gamma)
                .map(|&(_, l)| {
                    let g = all
                        .iter()
                        .filter(|s| (s.gamma, s.box_len) == (gamma, l))
                        .filter(|s| s.at.failed.is_none() && s.at.comparable())
                        .filter_map(|s| s.at.shear)
                        .collect();
                    (l, g)
                })
                .filter(|(_, g): &(f64, Vec<f64>)| !g.is_empty())
                .collect();
            (values.len() >= 2).then(|| ShearDecay {
                gamma,
                boxes: values
                    .iter()
                    .map(|(l, g)| {
                        let mean = g.iter().sum::<f64>() / g.len() as f64;
                        (*l, g.len(), mean, stats::geometric_mean(g))
                    })
                    .collect(),
                decay: transition::power_decay(&values),
                geometric: transition::geometric_decay(&values),
            })
        })
        .collect()
}

/// A mean with the half-width of its 95% normal interval (`1.96 sd /
/// sqrt n`; none from a single value).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Mean {
    pub mean: f64,
    pub half_width: Option<f64>,
}

impl Mean {
    fn of(x: &[f64]) -> Option<Mean> {
        (!x.is_empty()).then(|| {
            let (mean, sd) = stats::mean_sd(x);
            Mean {
                mean,
                half_width: (x.len() > 1).then(|| 1.96 * sd / (x.len() as f64).sqrt()),
            }
        })
    }
}

/// One box of one aspect ratio, over the sequences with moduli on both
/// sides of the critical rod.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StiffeningSummary {
    pub gamma: f64,
    #[serde(rename = "box")]
    pub box_len: f64,
    pub sequences: usize,
    /// Sequences with moduli on both sides, and those where a side failed.
    pub measured: usize,
    pub failed: usize,
    /// Of the measured: the strain rank below and at the critical rod.
    pub strain_rank_before: Option<Mean>,
    pub strain_rank_at: Option<Mean>,
    /// How many resist no strain below it and some at it, and how many
    /// resist every strain at it.
    pub rank_rises_from_zero: usize,
    pub solid_at: usize,
    /// The shear modulus below and at the rod (`k / L_rod`) over the pairs
    /// of [`Side::comparable`] sides, and their difference per sequence
    /// over the pairs on one geometry (the critical side's realization on
    /// both).
    pub shear_before: Option<Mean>,
    pub shear_at: Option<Mean>,
    pub shear_jump: Option<Mean>,
    /// Where both sides are [`Side::comparable`], and where they are one
    /// geometry.
    pub both_comparable: usize,
    pub one_geometry: usize,
    /// Pairs on one geometry whose `G` fell at the critical rod beyond
    /// rounding (`1e-9` of the Born modulus): adding springs to one
    /// geometry cannot lower it, so any is a defect.
    pub shear_fell: usize,
    /// Critical sides (below or at the rod) whose relaxation did not
    /// settle: their `G` is an upper bound.
    pub unsettled: usize,
    /// At each density of the spec.
    pub grid: Vec<GridPoint>,
    /// The exponent `f` of `G ~ (rho - rho_t)^f` from the mean shear
    /// modulus at the densities above the studies' threshold `rho_t`, and
    /// from every sequence's moduli above its own critical density.
    pub exponent: Option<Exponent>,
    pub exponent_own: Option<Exponent>,
}

/// The exponent `f` of `G ~ (rho - rho_c)^f`: the slope of `ln G` against
/// `ln (rho - rho_c)` by least squares, with its 95% bootstrap interval
/// over the sequences. Only [`Side::comparable`] sides count.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Exponent {
    pub f: f64,
    pub interval: Option<(f64, f64)>,
    /// `rho_c`: the studies' threshold, or none where each sequence's own
    /// critical density (its critical number over the volume) is used.
    pub threshold: Option<f64>,
    /// Points fitted (densities, or sequences times densities), and the
    /// range of `rho - rho_c` they span.
    pub points: usize,
    pub from: f64,
    pub to: f64,
}

/// Bootstrap resamples of an exponent's sequences, and their seed.
const RESAMPLES: usize = 1000;
const BOOTSTRAP_SEED: u64 = 1;

impl Exponent {
    /// The slope through `(rho - rho_c, G)` points on log-log axes (none
    /// without two distinct `rho - rho_c`), their number and range.
    fn slope(points: &[(f64, f64)]) -> Option<(f64, usize, f64, f64)> {
        let logs: Vec<(f64, f64)> = points.iter().map(|&(x, g)| (x.ln(), g.ln())).collect();
        let fit = stats::line(&logs)?;
        let from = points.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
        let to = points.iter().map(|p| p.0).fold(0.0, f64::max);
        Some((fit.beta[1], points.len(), from, to))
    }

    /// `points` of the sequences, fitted, with the bootstrap over them.
    fn fit(
        of: &[&SequenceStiffening],
        threshold: Option<f64>,
        points: impl Fn(&[&SequenceStiffening]) -> Vec<(f64, f64)>,
    ) -> Option<Exponent> {
        let (f, n, from, to) = Exponent::slope(&points(of))?;
        let mut boot = stats::bootstrap(&[of.to_vec()], RESAMPLES, BOOTSTRAP_SEED, |r| {
            Exponent::slope(&points(&r[0])).map(|s| s.0)
        });
        Some(Exponent {
            f,
            interval: stats::percentile_interval(&mut boot, 0.95),
            threshold,
            points: n,
            from,
            to,
        })
    }

    /// From the mean `G` over the sequences at each density above `rho_t`
    /// (a sequence that resists no strain there counts with `G = 0`, which
    /// no realization decides).
    fn of_threshold(of: &[&SequenceStiffening], densities: &[f64], rho_t: f64) -> Option<Self> {
        Exponent::fit(of, Some(rho_t), |seqs| {
            densities
                .iter()
                .enumerate()
                .filter(|&(_, &d)| d > rho_t)
                .filter_map(|(i, &d)| {
                    let g: Vec<f64> = seqs
                        .iter()
                        .filter_map(|s| s.grid.get(i))
                        .filter(|s| s.comparable())
                        .filter_map(|s| s.shear)
                        .collect();
                    let mean = g.iter().sum::<f64>() / g.len() as f64;
                    (mean > 0.0).then_some((d - rho_t, mean))
                })
                .collect()
        })
    }

    /// From every sequence's `G` at each density above its own critical
    /// density.
    fn of_own(of: &[&SequenceStiffening], densities: &[f64]) -> Option<Self> {
        Exponent::fit(of, None, |seqs| {
            seqs.iter()
                .flat_map(|s| {
                    let critical = s.at.rods as f64 / s.box_len.powi(3);
                    densities
                        .iter()
                        .zip(&s.grid)
                        .filter(move |&(&d, side)| d > critical && side.comparable())
                        .filter_map(move |(&d, side)| {
                            side.shear.filter(|&g| g > 0.0).map(|g| (d - critical, g))
                        })
                })
                .collect()
        })
    }
}

/// One density of one box: the moduli over the sequences measured there.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GridPoint {
    pub density: f64,
    pub rods: usize,
    pub measured: usize,
    pub failed: usize,
    /// How many resist every strain; the mean strain rank.
    pub solid: usize,
    pub strain_rank: Option<Mean>,
    /// `k / L_rod`, over the [`Side::comparable`] sides.
    pub shear: Option<Mean>,
    pub bulk: Option<Mean>,
    /// The largest true cluster's share of the rods.
    pub largest_share: Option<Mean>,
    /// Sides that are [`Side::comparable`] (the rest projected from a random
    /// start: not comparable).
    pub comparable: usize,
    /// Measured sides whose relaxation did not settle.
    pub unsettled: usize,
}

impl GridPoint {
    fn of(density: f64, sides: &[&Side]) -> GridPoint {
        let ok: Vec<&&Side> = sides.iter().filter(|s| s.failed.is_none()).collect();
        // The moduli only where they compare across sequences.
        let comparable: Vec<&&Side> = ok.iter().copied().filter(|s| s.comparable()).collect();
        let mean = |over: &[&&Side], f: &dyn Fn(&Side) -> Option<f64>| {
            Mean::of(&over.iter().filter_map(|s| f(s)).collect::<Vec<_>>())
        };
        GridPoint {
            density,
            rods: sides.first().map_or(0, |s| s.rods),
            measured: ok.len(),
            failed: sides.len() - ok.len(),
            solid: ok.iter().filter(|s| s.strain_rank == Some(6)).count(),
            strain_rank: mean(&ok, &|s| s.strain_rank.map(f64::from)),
            shear: mean(&comparable, &|s| s.shear),
            bulk: mean(&comparable, &|s| s.bulk),
            largest_share: mean(&ok, &|s| s.largest.map(|l| l as f64 / s.rods as f64)),
            comparable: comparable.len(),
            unsettled: ok.iter().filter(|s| s.unsettled()).count(),
        }
    }
}

/// Per aspect ratio and box, in that order, at `densities` (the grid all
/// of `all` was measured on, by position); the exponent `f` against each
/// aspect ratio's threshold `rho_t` in `thresholds` (aspect ratio,
/// threshold) where it has one.
pub fn summarize(
    all: &[SequenceStiffening],
    densities: &[f64],
    thresholds: &[(f64, f64)],
) -> Vec<StiffeningSummary> {
    let keys = boxes(all);
    keys.into_iter()
        .map(|(gamma, box_len)| {
            let of: Vec<&SequenceStiffening> = all
                .iter()
                .filter(|s| (s.gamma, s.box_len) == (gamma, box_len))
                .collect();
            let measured: Vec<(&Side, &Side)> = of
                .iter()
                .filter(|s| s.before.failed.is_none() && s.at.failed.is_none())
                .map(|s| (&s.before, &s.at))
                .collect();
            // The moduli over the pairs whose sides both compare.
            let comparable: Vec<(&Side, &Side)> = measured
                .iter()
                .copied()
                .filter(|(b, a)| b.comparable() && a.comparable())
                .collect();
            let one: Vec<(&Side, &Side)> = measured
                .iter()
                .copied()
                .filter(|(b, a)| b.one_geometry_with(a))
                .collect();
            let mean = |over: &[(&Side, &Side)], f: &dyn Fn(&Side, &Side) -> Option<f64>| {
                Mean::of(&over.iter().filter_map(|(b, a)| f(b, a)).collect::<Vec<_>>())
            };
            let rank = |s: &Side| s.strain_rank.map(f64::from);
            StiffeningSummary {
                gamma,
                box_len,
                sequences: of.len(),
                measured: measured.len(),
                failed: of.len() - measured.len(),
                strain_rank_before: mean(&measured, &|b, _| rank(b)),
                strain_rank_at: mean(&measured, &|_, a| rank(a)),
                rank_rises_from_zero: measured
                    .iter()
                    .filter(|(b, a)| b.strain_rank == Some(0) && a.strain_rank > Some(0))
                    .count(),
                solid_at: measured
                    .iter()
                    .filter(|(_, a)| a.strain_rank == Some(6))
                    .count(),
                shear_before: mean(&comparable, &|b, _| b.shear),
                shear_at: mean(&comparable, &|_, a| a.shear),
                shear_jump: mean(&one, &|b, a| Some(a.shear? - b.shear?)),
                both_comparable: comparable.len(),
                one_geometry: one.len(),
                shear_fell: one
                    .iter()
                    .filter(|(b, a)| {
                        let (Some(gb), Some(ga)) = (b.shear, a.shear) else {
                            return false;
                        };
                        ga < gb - 1e-9 * a.born_shear.unwrap_or(0.0)
                    })
                    .count(),
                unsettled: measured
                    .iter()
                    .map(|(b, a)| usize::from(b.unsettled()) + usize::from(a.unsettled()))
                    .sum(),
                grid: densities
                    .iter()
                    .enumerate()
                    .map(|(i, &d)| {
                        let sides: Vec<&Side> = of.iter().filter_map(|s| s.grid.get(i)).collect();
                        GridPoint::of(d, &sides)
                    })
                    .collect(),
                exponent: thresholds
                    .iter()
                    .find(|t| t.0 == gamma)
                    .and_then(|t| Exponent::of_threshold(&of, densities, t.1)),
                exponent_own: Exponent::of_own(&of, densities),
            }
        })
        .collect()
}

/// Refuses a box measured on two grids (each entry a grid and an
/// aspect ratio and box measured on it): its points would not make one
/// curve. Checked before the work, so that [`summarize_grids`] need not.
pub(super) fn one_grid_per_box(measured: &[(&[f64], (f64, f64))]) -> Result<()> {
    for (i, &(a, (gamma, box_len))) in measured.iter().enumerate() {
        if let Some((b, _)) = measured[i + 1..]
            .iter()
            .find(|&&(b, key)| key == (gamma, box_len) && b != a)
        {
            return Err(Error::Parameter(format!(
                "box {box_len} at gamma {gamma} was measured at densities {a:?} and at {b:?}: join a box's measurements only on one grid"
            )));
        }
    }
    Ok(())
}

/// [`summarize`] over measurements on several grids (each its densities
/// and sequences), every box on one grid ([`one_grid_per_box`]): the
/// sequences of one grid pooled, each box on the grid it was measured on,
/// in (aspect ratio, box) order. A larger box costs more per side, so its
/// grid may stop lower.
pub(super) fn summarize_grids(
    parts: Vec<(Vec<f64>, Vec<SequenceStiffening>)>,
    thresholds: &[(f64, f64)],
) -> Vec<StiffeningSummary> {
    let mut grids: Vec<(Vec<f64>, Vec<SequenceStiffening>)> = Vec::new();
    for (densities, sequences) in parts {
        match grids.iter_mut().find(|g| g.0 == densities) {
            Some(g) => g.1.extend(sequences),
            None => grids.push((densities, sequences)),
        }
    }
    let mut boxes: Vec<StiffeningSummary> = grids
        .iter()
        .flat_map(|(densities, sequences)| summarize(sequences, densities, thresholds))
        .collect();
    let key = |s: &StiffeningSummary| (s.gamma, s.box_len);
    boxes.sort_by(|a, b| key(a).partial_cmp(&key(b)).expect("finite"));
    boxes
}

/// Writes `PREFIX.json` (with the command that made it): one entry per
/// aspect ratio and box, and the shear modulus at the critical rod across
/// boxes.
pub fn write(prefix: &Path, summary: &Stiffening, command: &str) -> Result<PathBuf> {
    let json = output::with_extension(prefix, "json");
    let doc = serde_json::json!({
        "command": command,
        "boxes": summary.boxes,
        "decay": summary.decay,
    });
    output::write_atomic(
        &json,
        serde_json::to_string_pretty(&doc).expect("summaries serialize"),
    )?;
    Ok(json)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A side as measured: with no strain resisted, zero moduli and no
    /// realization.
    fn side(rods: usize, shear: f64, realization: &str) -> Side {
        let solid = shear > 0.0;
        Side {
            rods,
            strain_rank: Some(if solid { 6 } else { 0 }),
            shear: Some(shear),
            bulk: Some(shear),
            born_shear: solid.then_some(1.0),
            realization: solid.then(|| realization.into()),
            moved: None,
            largest: None,
            failed: None,
            settled: solid.then_some(true),
            solver: solid.then_some(crate::moduli::Solver::Qr),
            lsmr_iterations: None,
        }
    }

    /// A sequence in a box of volume 8 critical at `critical` rods, with
    /// `G = (rho - rho_c)^f` at each density (rho_c its own critical
    /// density, or `threshold`).
    fn sequence(
        index: u64,
        critical: usize,
        densities: &[f64],
        g: impl Fn(f64) -> f64,
    ) -> SequenceStiffening {
        SequenceStiffening {
            gamma: 23.0,
            box_len: 2.0,
            index,
            before: side(critical - 1, 0.0, "nearest"),
            at: side(critical, 1e-9, "nearest"),
            grid: densities
                .iter()
                .map(|&d| side((d * 8.0) as usize, g(d), "nearest"))
                .collect(),
            seconds: 0.0,
        }
    }

    #[test]
    fn the_exponent_is_the_log_log_slope_above_the_critical_density() {
        let densities = [30.0, 34.0, 36.0, 40.0, 44.0];
        // Each sequence's own G = (rho - rho_c)^2.5, rho_c = 33, 32.5, 33.5.
        let own: Vec<SequenceStiffening> = [264, 260, 268]
            .iter()
            .enumerate()
            .map(|(i, &c)| {
                let rc = c as f64 / 8.0;
                sequence(i as u64, c, &densities, |d| {
                    if d > rc { (d - rc).powf(2.5) } else { 0.0 }
                })
            })
            .collect();
        let s = &summarize(&own, &densities, &[])[0];
        assert_eq!(s.exponent, None, "no threshold given");
        let e = s.exponent_own.unwrap();
        assert!((e.f - 2.5).abs() < 1e-9, "{e:?}");
        assert_eq!((e.points, e.threshold), (12, None));
        assert!(
            (e.from - 0.5).abs() < 1e-12 && (e.to - 11.5).abs() < 1e-12,
            "{e:?}"
        );
        let (lo, hi) = e.interval.unwrap();
        assert!(
            (lo - 2.5).abs() < 1e-9 && (hi - 2.5).abs() < 1e-9,
            "exact on every resample"
        );
        // The mean G against a common threshold 33: G = (rho - 33)^1.5 in
        // every sequence; a realization from a random start is left out.
        let mut common: Vec<SequenceStiffening> = (0..3)
            .map(|i| {
                sequence(i, 264, &densities, |d| {
                    if d > 33.0 { (d - 33.0).powf(1.5) } else { 0.0 }
                })
            })
            .collect();
        common[0].grid[4] = side(352, 1e3, "projected");
        let s = &summarize(&common, &densities, &[(48.0, 30.0), (23.0, 33.0)])[0];
        let e = s.exponent.unwrap();
        assert!((e.f - 1.5).abs() < 1e-9, "{e:?}");
        // The curve's mean G at 44 leaves the random start out too.
        let top = &s.grid[4];
        assert_eq!((top.measured, top.comparable), (3, 2));
        assert_eq!((top.unsettled, s.unsettled), (0, 0));
        assert!((top.shear.unwrap().mean - 11f64.powf(1.5)).abs() < 1e-9);
        assert_eq!(
            (e.points, e.threshold, e.from, e.to),
            (4, Some(33.0), 1.0, 11.0)
        );
        // Two sequences resisting no strain at 34 count there with G = 0:
        // the mean is 1/3, and the slope through (1, 1/3), (3, 3^1.5),
        // (7, 7^1.5), (11, 11^1.5) is 1.94775.
        for s in &mut common[1..] {
            s.grid[1] = side(272, 0.0, "nearest");
        }
        // Relaxations that ran out of steps are counted, not left out.
        common[0].grid[3].settled = Some(false);
        common[2].at.settled = Some(false);
        let s = &summarize(&common, &densities, &[(23.0, 33.0)])[0];
        assert_eq!(
            (s.grid[3].unsettled, s.grid[3].comparable, s.unsettled),
            (1, 3, 1)
        );
        let e = s.exponent.unwrap();
        assert!((e.f - 1.947_747_158_653_809).abs() < 1e-9, "{e:?}");
    }

    #[test]
    fn the_shear_modulus_at_the_critical_rod_decays_as_a_power_of_the_box() {
        // G at the critical rod = 3 L^-2 in every sequence of boxes 4, 5, 8;
        // a failed critical side and one from a random start are left out.
        let mut all = Vec::new();
        for (l, n) in [(4.0, 2), (5.0, 3), (8.0, 2)] {
            for i in 0..n {
                let mut s = sequence(i, 100, &[], |_| 0.0);
                s.box_len = l;
                s.at = side(100, 3.0 * f64::powi(l, -2), "nearest");
                all.push(s);
            }
        }
        let mut failed = all[0].clone();
        failed.index = 7;
        failed.at.failed = Some("special".into());
        let mut projected = all[0].clone();
        projected.index = 8;
        projected.at = side(100, 1e3, "projected");
        all.extend([failed, projected]);
        let d = shear_decay(&all);
        assert_eq!(d.len(), 1);
        let counts: Vec<(f64, usize)> = d[0].boxes.iter().map(|b| (b.0, b.1)).collect();
        assert_eq!(counts, [(4.0, 2), (5.0, 3), (8.0, 2)]);
        assert!((d[0].boxes[2].2 - 3.0 / 64.0).abs() < 1e-15);
        assert_eq!(d[0].decay.len(), 1, "three boxes: one fit over all");
        let f = &d[0].decay[0];
        assert!((f.exponent - 2.0).abs() < 1e-9, "{f:?}");
        assert!((f.interval.0 - 2.0).abs() < 1e-9 && (f.interval.1 - 2.0).abs() < 1e-9);
        // One box: nothing to fit against the box.
        assert!(shear_decay(&all[..2]).is_empty());
    }

    #[test]
    fn the_geometric_mean_follows_the_typical_sequence_not_the_stiffest() {
        // Per box one sequence at L^-1 and one at L^-3: geometric mean
        // L^-2, the arithmetic one near L^-1 / 2, ruled by the stiffer.
        let mut all = Vec::new();
        for l in [4.0, 6.0, 9.0] {
            for (i, p) in [(0, -1), (1, -3)] {
                let mut s = sequence(i, 100, &[], |_| 0.0);
                s.box_len = l;
                s.at = side(100, f64::powi(l, p), "nearest");
                all.push(s);
            }
        }
        let d = &shear_decay(&all)[0];
        let geo = d.boxes[1].3.unwrap();
        assert!((geo - 1.0 / 36.0).abs() < 1e-15, "{geo}");
        let g = &d.geometric[0];
        assert!((g.exponent - 2.0).abs() < 1e-9, "{g:?}");
        assert!(g.interval.0 < 2.0 && g.interval.1 > 2.0, "{g:?}");
        let a = &d.decay[0];
        assert!(a.exponent > 0.8 && a.exponent < 1.2, "{a:?}");
        // A sequence with no modulus at the rod has no logarithm.
        all[0].at = side(100, 0.0, "nearest");
        let d = &shear_decay(&all)[0];
        assert_eq!(d.boxes[0].3, None);
        assert!(d.geometric.is_empty() && !d.decay.is_empty());
    }

    #[test]
    fn each_box_keeps_the_grid_it_was_measured_on() {
        // Box 2 on four densities, box 3 on two: each box its own points;
        // two parts on one grid pool their sequences into one box.
        let at = |l: f64, index: u64, densities: &[f64]| {
            let mut s = sequence(index, 100, densities, |d| d - 30.0);
            s.box_len = l;
            s
        };
        let wide = [32.0, 34.0, 36.0, 38.0];
        let narrow = [32.0, 34.0];
        let parts = vec![
            (wide.to_vec(), vec![at(2.0, 0, &wide)]),
            (narrow.to_vec(), vec![at(3.0, 0, &narrow)]),
            (wide.to_vec(), vec![at(2.0, 1, &wide)]),
        ];
        let boxes = summarize_grids(parts, &[]);
        let shape: Vec<(f64, usize, usize)> = boxes
            .iter()
            .map(|b| (b.box_len, b.sequences, b.grid.len()))
            .collect();
        assert_eq!(shape, [(2.0, 2, 4), (3.0, 1, 2)]);
        assert_eq!(boxes[0].grid[3].density, 38.0);
        assert!((boxes[0].grid[3].shear.unwrap().mean - 8.0).abs() < 1e-12);
        // Box 2 again on the narrow grid: refused, naming both grids.
        let key = (23.0, 2.0);
        assert!(one_grid_per_box(&[(&wide, key), (&narrow, (23.0, 3.0)), (&wide, key)]).is_ok());
        let err = one_grid_per_box(&[(&wide, key), (&narrow, key)])
            .unwrap_err()
            .to_string();
        assert_eq!(
            err,
            "invalid parameter: box 2 at gamma 23 was measured at densities [32.0, 34.0, 36.0, 38.0] \
             and at [32.0, 34.0]: join a box's measurements only on one grid"
        );
    }
}
