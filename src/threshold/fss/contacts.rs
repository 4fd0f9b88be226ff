//! Contact numbers at the threshold (MODEL §8): `c0, c1, c2` fitted as
//! straight lines against density, per box size and pooled, and read at the
//! threshold and the ends of its interval.

use serde::{Deserialize, Serialize};

use super::boxes::{BoxData, ContactPoint};
use super::estimate::Estimate;
use crate::math::stats;

/// A straight line `c = intercept + slope * rho` and its prediction at the threshold.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LinearFit {
    pub intercept: f64,
    pub slope: f64,
    pub r2: f64,
    /// The line at the threshold; the interval is the line at the ends of
    /// the threshold's interval (the paper's way).
    pub at_threshold: Estimate,
}

/// Contact numbers against density over the contact points of one box
/// size (`box_len`) or of all box sizes pooled (`box_len = None`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactFits {
    pub box_len: Option<f64>,
    pub points: usize,
    pub c0: LinearFit,
    pub c1: LinearFit,
    pub c2: LinearFit,
}

/// Contact numbers at the threshold: the pooled fit is the headline.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactNumbers {
    pub pooled: ContactFits,
    pub per_box: Vec<ContactFits>,
}

/// A straight line through `(rho, c)` points, `None` with fewer than two
/// distinct densities.
fn line(points: &[(f64, f64)], threshold: &Estimate) -> Option<LinearFit> {
    let stats::Fit { beta, r2, .. } = stats::line(points)?;
    // A contact number is never negative: the line read far below the
    // densities it was fitted on stops at 0.
    let at = |rho: f64| (beta[0] + beta[1] * rho).max(0.0);
    let interval = threshold
        .lo
        .zip(threshold.hi)
        .map(|(lo, hi)| (at(lo).min(at(hi)), at(lo).max(at(hi))));
    Some(LinearFit {
        intercept: beta[0],
        slope: beta[1],
        r2,
        at_threshold: Estimate::with(at(threshold.value), interval),
    })
}

fn contact_fits(
    box_len: Option<f64>,
    points: &[ContactPoint],
    threshold: &Estimate,
) -> Option<ContactFits> {
    let col = |f: fn(&ContactPoint) -> f64| -> Vec<(f64, f64)> {
        points.iter().map(|p| (p.density, f(p))).collect()
    };
    Some(ContactFits {
        box_len,
        points: points.len(),
        c0: line(&col(|p| p.c0), threshold)?,
        c1: line(&col(|p| p.c1), threshold)?,
        c2: line(&col(|p| p.c2), threshold)?,
    })
}

/// Linear fits of `c0, c1, c2` against density, pooled and per box size;
/// missing or unusable contact points are warnings, not errors.
pub(super) fn contact_numbers(
    data: &[&BoxData],
    threshold: &Estimate,
    warnings: &mut Vec<String>,
) -> Option<ContactNumbers> {
    let finite = |p: &&ContactPoint| [p.density, p.c0, p.c1, p.c2].iter().all(|v| v.is_finite());
    let points = |b: &BoxData| -> Vec<ContactPoint> {
        b.observations
            .iter()
            .flat_map(|o| o.contacts.iter())
            .filter(finite)
            .copied()
            .collect()
    };
    let mut per_box = Vec::new();
    let mut pooled = Vec::new();
    for b in data {
        let pts = points(b);
        if pts.is_empty() {
            continue;
        }
        match contact_fits(Some(b.box_len), &pts, threshold) {
            Some(f) => per_box.push(f),
            None => warnings.push(format!(
                "box L={}: contact points at fewer than 2 distinct densities; no contact-number fit",
                b.box_len
            )),
        }
        pooled.extend(pts);
    }
    if pooled.is_empty() {
        warnings
            .push("no contact points: contact numbers at the threshold are not reported".into());
        return None;
    }
    match contact_fits(None, &pooled, threshold) {
        Some(pooled) => Some(ContactNumbers { pooled, per_box }),
        None => {
            warnings.push(
                "contact points at fewer than 2 distinct densities: contact numbers at the threshold are not reported"
                    .into(),
            );
            None
        }
    }
}
