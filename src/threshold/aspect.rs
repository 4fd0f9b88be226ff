//! Thresholds across aspect ratios against the inverse excluded volume (the
//! paper's Fig. D): finished studies side by side, and the two fits
//! `rho_c = c / V_ex` (exponent fixed to 1, the excluded-volume argument)
//! and the free power law `rho_c = A (1/V_ex)^m`, which says how far the
//! rods are from that limit.

use std::path::{Path, PathBuf};

use serde::{Serialize, Serializer};

use super::fss::{ContactFits, Estimate, LinearFit};
use super::report;
use super::sequence::Kind;
use crate::{Error, Result};

/// One finished study: a row of the CSV, in its column order.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AspectRow {
    #[serde(serialize_with = "plain")]
    pub gamma: f64,
    /// `1 / V_ex`, per rod length cubed.
    #[serde(serialize_with = "six")]
    pub inv_vex: f64,
    #[serde(serialize_with = "six")]
    pub threshold: f64,
    #[serde(serialize_with = "six_or_empty")]
    pub threshold_lo: Option<f64>,
    #[serde(serialize_with = "six_or_empty")]
    pub threshold_hi: Option<f64>,
    /// `rho_c V_ex`: the mean contact number at the threshold.
    #[serde(serialize_with = "six")]
    pub threshold_times_vex: f64,
    #[serde(serialize_with = "six")]
    pub nu: f64,
    /// The study directory, as given.
    pub study: String,
    pub kind: Kind,
}

impl AspectRow {
    /// The threshold with its interval, as the fits and the chart take it.
    pub fn estimate(&self) -> Estimate {
        Estimate {
            value: self.threshold,
            lo: self.threshold_lo,
            hi: self.threshold_hi,
        }
    }
}

/// `rho_c = A (1/V_ex)^m`, fitted by least squares on the logarithms.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PowerLaw {
    pub a: f64,
    pub m: f64,
    /// The interval of `m` the thresholds' intervals give (see [`fit`]).
    pub m_interval: Option<(f64, f64)>,
    /// R² of the fit on the logarithms.
    pub r2: f64,
}

/// The two fits of the threshold against `1/V_ex`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct VexFit {
    /// `c` of `rho_c = c / V_ex`: the geometric mean of `rho_c V_ex`.
    pub fixed: f64,
    /// The interval of `c` the thresholds' intervals give.
    pub fixed_interval: Option<(f64, f64)>,
    /// The free power law; absent with fewer than two distinct `V_ex`.
    pub free: Option<PowerLaw>,
}

/// Maxwell's isostatic count for rods: a rod has 5 degrees of freedom and
/// a contact removes 3 shared by two rods, so `5 = 3c/2` at `c = 10/3`. It
/// counts the contacts of rods that can bear load, the 2-core's `c2`.
pub const MAXWELL: f64 = 10.0 / 3.0;

/// The mean contact numbers at a study's threshold: each the line fitted to
/// its sequences' contact points, evaluated at the threshold (the interval
/// is the line at the ends of the threshold's interval), over all boxes
/// (`box_len` empty) or in one.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ContactRow {
    pub kind: Kind,
    #[serde(serialize_with = "plain")]
    pub gamma: f64,
    #[serde(rename = "box", serialize_with = "plain_or_empty")]
    pub box_len: Option<f64>,
    pub points: usize,
    #[serde(serialize_with = "six")]
    pub c0: f64,
    #[serde(serialize_with = "six_or_empty")]
    pub c0_lo: Option<f64>,
    #[serde(serialize_with = "six_or_empty")]
    pub c0_hi: Option<f64>,
    #[serde(serialize_with = "six")]
    pub c1: f64,
    #[serde(serialize_with = "six_or_empty")]
    pub c1_lo: Option<f64>,
    #[serde(serialize_with = "six_or_empty")]
    pub c1_hi: Option<f64>,
    #[serde(serialize_with = "six")]
    pub c2: f64,
    #[serde(serialize_with = "six_or_empty")]
    pub c2_lo: Option<f64>,
    #[serde(serialize_with = "six_or_empty")]
    pub c2_hi: Option<f64>,
    /// `c2 - 10/3`: below zero, the threshold lies below Maxwell's count.
    #[serde(serialize_with = "six")]
    pub c2_minus_maxwell: f64,
}

impl ContactRow {
    fn of(kind: Kind, gamma: f64, f: &ContactFits) -> ContactRow {
        let e = |l: &LinearFit| l.at_threshold;
        let (c0, c1, c2) = (e(&f.c0), e(&f.c1), e(&f.c2));
        // The interval is the line at the threshold's ends: order it.
        let lo = |e: Estimate| e.lo.zip(e.hi).map(|(a, b)| a.min(b));
        let hi = |e: Estimate| e.lo.zip(e.hi).map(|(a, b)| a.max(b));
        ContactRow {
            kind,
            gamma,
            box_len: f.box_len,
            points: f.points,
            c0: c0.value,
            c0_lo: lo(c0),
            c0_hi: hi(c0),
            c1: c1.value,
            c1_lo: lo(c1),
            c1_hi: hi(c1),
            c2: c2.value,
            c2_lo: lo(c2),
            c2_hi: hi(c2),
            c2_minus_maxwell: c2.value - MAXWELL,
        }
    }
}

/// Finished studies of one kind at several aspect ratios, and their fits.
#[derive(Clone, Debug, PartialEq)]
pub struct AspectRatios {
    pub kind: Kind,
    pub rows: Vec<AspectRow>,
    pub fit: VexFit,
    /// Contact numbers at each study's threshold, over all boxes, then per box.
    pub contacts: Vec<ContactRow>,
}

impl AspectRatios {
    /// The rows as `(gamma, 1/V_ex, threshold)`, as [`fit`] and the chart take them.
    pub fn points(&self) -> Vec<(f64, f64, Estimate)> {
        points(&self.rows)
    }
}

fn points(rows: &[AspectRow]) -> Vec<(f64, f64, Estimate)> {
    rows.iter()
        .map(|r| (r.gamma, r.inv_vex, r.estimate()))
        .collect()
}

/// Reads the `summary.json` of each study directory (all of one kind: a
/// contact and a rigidity threshold do not go on one line) and fits them.
pub fn read(studies: &[PathBuf]) -> Result<AspectRatios> {
    let mut rows = Vec::new();
    let mut contacts = Vec::new();
    let mut kind = None;
    for dir in studies {
        let s = report::read_summary(dir)?;
        if kind.is_some_and(|k| k != s.study.kind) {
            return Err(Error::Parameter(format!(
                "{} is a {:?} study; the others are {:?}",
                dir.display(),
                s.study.kind,
                kind.unwrap_or_default()
            )));
        }
        kind = Some(s.study.kind);
        if let Some(c) = &s.fss.contact_numbers {
            let of = |f| ContactRow::of(s.study.kind, s.study.gamma, f);
            contacts.extend([&c.pooled].into_iter().chain(&c.per_box).map(of));
        }
        let t = s.fss.threshold;
        rows.push(AspectRow {
            gamma: s.study.gamma,
            inv_vex: 1.0 / s.excluded_volume,
            threshold: t.value,
            threshold_lo: t.lo,
            threshold_hi: t.hi,
            threshold_times_vex: s.threshold_times_vex,
            nu: s.fss.nu.value,
            study: dir.display().to_string(),
            kind: s.study.kind,
        });
    }
    Ok(AspectRatios {
        kind: kind.unwrap_or_default(),
        fit: fit(&points(&rows))?,
        rows,
        contacts,
    })
}

/// Fits `points` as `(gamma, 1/V_ex, threshold)`: both must be positive and
/// finite, since the fits live on log-log axes.
///
/// Both fits are linear in the log thresholds, and the thresholds of
/// different studies are independent, so their intervals carry over
/// linearly: a fit parameter `sum_i w_i ln rho_i` gets the half-width
/// `sqrt(sum_i (w_i h_i)^2)` at the studies' confidence, `h_i` being half
/// the width of study i's interval on the log scale. There is no interval
/// when a study has none.
pub fn fit(points: &[(f64, f64, Estimate)]) -> Result<VexFit> {
    if points.is_empty() {
        return Err(Error::Parameter(
            "no thresholds to fit against 1/V_ex".into(),
        ));
    }
    if let Some(p) = points
        .iter()
        .find(|p| !(p.1 > 0.0 && p.2.value > 0.0 && p.1.is_finite() && p.2.value.is_finite()))
    {
        return Err(Error::Parameter(format!(
            "threshold {} at 1/V_ex = {} (gamma {}) cannot go on log axes",
            p.2.value, p.1, p.0
        )));
    }
    let n = points.len();
    let lx: Vec<f64> = points.iter().map(|p| p.1.ln()).collect();
    let ly: Vec<f64> = points.iter().map(|p| p.2.value.ln()).collect();
    let half: Option<Vec<f64>> = points
        .iter()
        .map(|p| match (p.2.lo, p.2.hi) {
            (Some(lo), Some(hi)) if lo > 0.0 && hi >= lo => Some((hi.ln() - lo.ln()) / 2.0),
            _ => None,
        })
        .collect();
    // The half-width of `sum_i w_i ln rho_i`.
    let spread = |w: &[f64]| {
        half.as_ref().map(|h| {
            w.iter()
                .zip(h)
                .map(|(w, h)| (w * h).powi(2))
                .sum::<f64>()
                .sqrt()
        })
    };
    let ln_fixed = ly.iter().zip(&lx).map(|(y, x)| y - x).sum::<f64>() / n as f64;
    let fixed_interval =
        spread(&vec![1.0 / n as f64; n]).map(|h| ((ln_fixed - h).exp(), (ln_fixed + h).exp()));
    let mean_x = lx.iter().sum::<f64>() / n as f64;
    let sxx: f64 = lx.iter().map(|x| (x - mean_x).powi(2)).sum();
    let slope_weights: Vec<f64> = lx.iter().map(|x| (x - mean_x) / sxx).collect();
    let points: Vec<(f64, f64)> = lx.iter().copied().zip(ly).collect();
    let free = crate::math::stats::line(&points).map(|fit| {
        let b = &fit.beta;
        PowerLaw {
            a: b[0].exp(),
            m: b[1],
            m_interval: spread(&slope_weights).map(|h| (b[1] - h, b[1] + h)),
            r2: fit.r2,
        }
    });
    Ok(VexFit {
        fixed: ln_fixed.exp(),
        fixed_interval,
        free,
    })
}

/// One kind's studies, their fits and contact numbers, as `rgc
/// aspect-ratios` writes them.
#[derive(Serialize)]
struct AspectFile<'a> {
    kind: Kind,
    rows: &'a [AspectRow],
    fit: &'a VexFit,
    contacts: &'a [ContactRow],
    /// Studies of other kinds drawn beside these.
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    beside: Vec<AspectFile<'a>>,
}

impl<'a> AspectFile<'a> {
    fn of(r: &'a AspectRatios) -> Self {
        AspectFile {
            kind: r.kind,
            rows: &r.rows,
            fit: &r.fit,
            contacts: &r.contacts,
            beside: Vec::new(),
        }
    }
}

/// Writes the rows, fits and contact numbers of `all[0]` as JSON, with the
/// other kinds' (drawn beside them) under `beside`.
pub fn write_json(path: &Path, all: &[AspectRatios]) -> Result<()> {
    let Some((first, rest)) = all.split_first() else {
        return Err(Error::Parameter("no thresholds to write".into()));
    };
    let file = AspectFile {
        beside: rest.iter().map(AspectFile::of).collect(),
        ..AspectFile::of(first)
    };
    crate::output::write_atomic(
        path,
        serde_json::to_string_pretty(&file).expect("fits serialize") + "\n",
    )
}

/// Writes the rows as CSV with a header (fields quoted where they need it).
pub fn write_csv(path: &Path, rows: &[AspectRow]) -> Result<()> {
    crate::output::write_csv(path, rows)
}

/// Writes the contact numbers at every threshold as CSV and as a Markdown
/// table against Maxwell's count.
pub fn write_contacts(csv: &Path, md: &Path, all: &[AspectRatios]) -> Result<()> {
    let rows: Vec<&ContactRow> = all.iter().flat_map(|r| &r.contacts).collect();
    crate::output::write_csv(csv, rows.iter().copied())?;
    crate::output::write_atomic(md, contacts_markdown(&rows))
}

/// The contact numbers at each threshold, one row per study and box.
pub fn contacts_markdown(rows: &[&ContactRow]) -> String {
    let show = |v: f64, lo: Option<f64>, hi: Option<f64>| match lo.zip(hi) {
        Some((lo, hi)) => format!("{v:.3} [{lo:.3}, {hi:.3}]"),
        None => format!("{v:.3}"),
    };
    let mut s = String::from("# Mean contact numbers at the threshold\n\n");
    s += "`c0` over all rods, `c1` over rods with a contact, `c2` over the 2-core (rods with two or more contacts after rods with one are pruned, repeatedly): each the line fitted to the sequences' contact points, at the threshold, with the line at the ends of the threshold's interval. Maxwell's isostatic count for rods (5 degrees of freedom per rod, 3 constraints per contact shared by two rods) is `c = 10/3`, and it applies to the rods that can bear load: `c2`.\n\n";
    s += "| kind | gamma | box | points | c0 | c1 | c2 | c2 - 10/3 |\n|---|---|---|---|---|---|---|---|\n";
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {:+.3} |\n",
            match r.kind {
                Kind::Contact => "contact",
                Kind::Rigid => "3D-RGC",
                Kind::Truth => "truth",
            },
            r.gamma,
            r.box_len.map_or("all".into(), |l| l.to_string()),
            r.points,
            show(r.c0, r.c0_lo, r.c0_hi),
            show(r.c1, r.c1_lo, r.c1_hi),
            show(r.c2, r.c2_lo, r.c2_hi),
            r.c2_minus_maxwell
        );
    }
    s
}

/// Six decimals, as the other tables of `results/` print their densities.
fn six<S: Serializer>(x: &f64, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_str(&format!("{x:.6}"))
}

fn six_or_empty<S: Serializer>(x: &Option<f64>, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_str(&x.map_or(String::new(), |v| format!("{v:.6}")))
}

/// As written on the command line (`23`, not `23.0`).
fn plain<S: Serializer>(x: &f64, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_str(&x.to_string())
}

fn plain_or_empty<S: Serializer>(x: &Option<f64>, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_str(&x.map_or(String::new(), |v| v.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(inv_vex: f64, value: f64) -> (f64, f64, Estimate) {
        let e = Estimate {
            value,
            lo: None,
            hi: None,
        };
        (1.0, inv_vex, e)
    }

    #[test]
    fn contact_rows_order_their_intervals_and_measure_from_maxwell() {
        let line = |value: f64, lo: f64, hi: f64| LinearFit {
            intercept: 0.0,
            slope: 0.0,
            r2: 1.0,
            at_threshold: Estimate {
                value,
                lo: Some(lo),
                hi: Some(hi),
            },
        };
        // c1 falls with density here: the line at the threshold's low end is its high end.
        let f = ContactFits {
            box_len: Some(5.0),
            points: 7,
            c0: line(2.6, 2.5, 2.7),
            c1: line(2.9, 3.0, 2.8),
            c2: line(3.5, 3.4, 3.6),
        };
        let r = ContactRow::of(Kind::Truth, 23.0, &f);
        assert_eq!((r.c1_lo, r.c1_hi), (Some(2.8), Some(3.0)));
        assert_eq!((r.c2_lo, r.c2_hi), (Some(3.4), Some(3.6)));
        assert!((r.c2_minus_maxwell - (3.5 - 10.0 / 3.0)).abs() < 1e-15);
        let md = contacts_markdown(&[&r]);
        assert!(
            md.contains("| truth | 23 | 5 | 7 | 2.600 [2.500, 2.700] | 2.900 [2.800, 3.000] | 3.500 [3.400, 3.600] | +0.167 |"),
            "{md}"
        );
    }

    #[test]
    fn an_exact_power_law_is_recovered() {
        let points: Vec<_> = [0.5, 1.0, 4.0]
            .iter()
            .map(|&x: &f64| at(x, 3.0 * x.powf(0.9)))
            .collect();
        let f = fit(&points).unwrap();
        let p = f.free.unwrap();
        assert!(
            (p.a - 3.0).abs() < 1e-9 && (p.m - 0.9).abs() < 1e-9,
            "{p:?}"
        );
        assert!((p.r2 - 1.0).abs() < 1e-12);
        // The fixed exponent's c is the geometric mean of rho_c V_ex.
        let c = points
            .iter()
            .map(|p| (p.2.value / p.1).ln())
            .sum::<f64>()
            .exp()
            .powf(1.0 / 3.0);
        assert!((f.fixed - c).abs() < 1e-12);
        assert!(f.fixed_interval.is_none() && p.m_interval.is_none());
    }

    /// An interval carries over as the linear propagation says: a
    /// threshold at the middle `1/V_ex` does not move the slope, one at an
    /// end moves it by its log half-width over the spread of `ln 1/V_ex`.
    #[test]
    fn threshold_intervals_carry_over_to_the_exponent() {
        let e = std::f64::consts::E;
        let point = |x: f64, h: f64| {
            let value = 2.0 * x;
            let e = Estimate {
                value,
                lo: Some(value * (-h).exp()),
                hi: Some(value * h.exp()),
            };
            (1.0, x, e)
        };
        // ln x = -1, 0, 1: slope weights -1/2, 0, 1/2.
        let f = fit(&[point(1.0 / e, 0.0), point(1.0, 0.3), point(e, 0.1)]).unwrap();
        let p = f.free.unwrap();
        assert!((p.m - 1.0).abs() < 1e-12, "{p:?}");
        let (lo, hi) = p.m_interval.unwrap();
        assert!((hi - lo - 2.0 * 0.05).abs() < 1e-12, "{lo} {hi}");
        let (clo, chi) = f.fixed_interval.unwrap();
        let h = (0.3f64.powi(2) + 0.1f64.powi(2)).sqrt() / 3.0;
        assert!((chi.ln() - clo.ln() - 2.0 * h).abs() < 1e-12);
        assert!(clo < f.fixed && f.fixed < chi);
    }

    #[test]
    fn one_aspect_ratio_has_no_free_fit_and_bad_points_are_named() {
        assert!(fit(&[at(0.2, 10.0)]).unwrap().free.is_none());
        let err = fit(&[at(0.2, 10.0), at(0.0, 5.0)]).unwrap_err();
        assert!(err.to_string().contains("cannot go on log axes"), "{err}");
        assert!(fit(&[]).is_err());
    }

    #[test]
    fn study_paths_with_commas_are_quoted() {
        let row = AspectRow {
            gamma: 23.0,
            inv_vex: 0.5,
            threshold: 19.25,
            threshold_lo: None,
            threshold_hi: Some(20.0),
            threshold_times_vex: 1.5,
            nu: 0.9,
            study: "runs/a,b".into(),
            kind: Kind::Truth,
        };
        let path = std::env::temp_dir().join(format!("rgc-aspect-{}.csv", std::process::id()));
        write_csv(&path, &[row]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert_eq!(
            text,
            "gamma,inv_vex,threshold,threshold_lo,threshold_hi,threshold_times_vex,nu,study,kind\n\
             23,0.500000,19.250000,,20.000000,1.500000,0.900000,\"runs/a,b\",truth\n"
        );
    }
}
