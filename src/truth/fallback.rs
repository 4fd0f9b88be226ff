//! Truth in floats where no construction order exists (MODEL §10): twin
//! float realizations by numerical projection ([`super::projection`]), the
//! same body-frame matrix as the exact path ([`super::matrix`]) in `f64`,
//! and its rank read off the singular values only where they show a clear
//! gap. The two realizations are independent; their ranks and rigid
//! clusters must agree. Anything less answers "undecided" with the reason.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::answer::TruthOptions;
use super::matrix::{self, Parts, WIDTH};
use super::planes::Planes;
use super::realize::Realization;
use super::{clusters, projection};
use crate::graph::Topology;
use crate::math::float::{RankRule, decide_rank_above, singular_vectors};
use crate::math::matrix::Matrix;
use crate::rigidity::framework::equilibrate;

/// Most columns ranked in floats: the SVD is dense (cubic in the columns;
/// 3,500 columns took 166 s), so larger cores stay undecided.
pub const MAX_COLUMNS: usize = 1500;

/// Smallest ratio of the smallest singular value counted to the largest
/// not counted: besides [`RankRule::SVD`], whose grey zone alone allows a
/// ratio of `1e4`, a whole system asks for a gap as clear as the motifs'
/// non-zero values ever showed (MODEL §4: at least `1.6e6` times the noise).
pub const MIN_GAP: f64 = 1e6;

/// Largest singular value counted as zero, relative to the largest one.
pub const MAX_ZERO: f64 = 1e-8;

/// Float draws per [`TruthOptions::attempts`]: a projection lands on a
/// degenerate branch far more often than an exact draw (before repairs,
/// about half of the starts for K_{4,4}, whose special realizations form
/// larger families than the generic one).
pub const DRAWS_PER_ATTEMPT: usize = 2;

/// A float decision of a whole system.
#[derive(Clone, Debug, PartialEq)]
pub struct FloatTruth {
    pub rank: usize,
    pub rows: usize,
    /// The smaller singular-value gap of the two realizations.
    pub gap: f64,
    /// Rigid clusters of two or more rods, sorted as [`clusters::clusters`].
    pub clusters: Vec<Vec<u32>>,
}

/// One realization ranked.
struct Ranked {
    rank: usize,
    rows: usize,
    gap: f64,
    clusters: Vec<Vec<u32>>,
}

/// Decides the active rods in floats, or says why not.
pub fn decide(
    topo: &Topology,
    planes: &Planes,
    active: &[bool],
    parts: &Parts,
    opts: TruthOptions,
) -> Result<FloatTruth, String> {
    let columns = parts.count * WIDTH;
    if columns > MAX_COLUMNS {
        return Err(format!(
            "{columns} columns, more than the {MAX_COLUMNS} a dense float rank takes"
        ));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
    let draws = opts.attempts.max(1) * DRAWS_PER_ATTEMPT;
    let mut twins: Vec<Ranked> = Vec::with_capacity(2);
    for _twin in 0..2 {
        let mut why = String::new();
        let mut real = None;
        for _ in 0..draws {
            match projection::project(topo, planes, active, &mut rng) {
                Ok(r) => {
                    real = Some(r);
                    break;
                }
                Err(w) => why = w,
            }
        }
        let Some(real) = real else {
            return Err(format!(
                "every one of {draws} float realizations was refused (the last: {why})"
            ));
        };
        twins.push(rank(topo, planes, parts, &real)?);
    }
    let (a, b) = (&twins[0], &twins[1]);
    if a.rank != b.rank {
        return Err(format!(
            "the twin float realizations have ranks {} and {}",
            a.rank, b.rank
        ));
    }
    if a.clusters != b.clusters {
        return Err("the twin float realizations give different rigid clusters".into());
    }
    Ok(FloatTruth {
        rank: a.rank,
        rows: a.rows,
        gap: a.gap.min(b.gap),
        clusters: a.clusters.clone(),
    })
}

/// The float rank of one realization with its gap, and the rigid clusters
/// from the kernel basis the SVD gives with it.
fn rank(
    topo: &Topology,
    planes: &Planes,
    parts: &Parts,
    real: &Realization<f64>,
) -> Result<Ranked, String> {
    let rows = matrix::rows(topo, planes, parts, real, &matrix::StrainColumns::none());
    let cols = parts.count * WIDTH;
    let mut m = Matrix::zeros(rows.len(), cols);
    for (i, row) in rows.iter().enumerate() {
        for &(c, v) in row {
            m.set(i, c as usize, v);
        }
    }
    equilibrate(&mut m);
    let (values, v) = singular_vectors(&m).ok_or("the SVD of the float matrix did not converge")?;
    let s0 = values.first().copied().unwrap_or(0.0);
    // The roundoff floor of the SVD. MODEL §4 takes `max(m, n) eps s0`,
    // calibrated on motifs of tens of columns; a whole system has thousands,
    // where that bound hides gaps the spectrum shows plainly, so the floor
    // grows with the square root of the size, as rounding does in practice,
    // and the gap asked for is wider ([`MIN_GAP`]). Rows have unit length,
    // so a matrix with rows has `s0 >= 1`; one without still has the
    // rounding of its kernel basis.
    let size = m.rows.max(m.cols) as f64;
    let floor = size.sqrt() * f64::EPSILON * s0.max(1.0);
    let noise = floor.max(trivial_residual(topo, parts, real, &m));
    let fr = decide_rank_above(&values, noise, RankRule::SVD);
    let below = values.get(fr.counted).copied().unwrap_or(0.0);
    let unclear = || {
        format!(
            "the float rank has no clear gap ({} values above the tolerance, gap {:.1e}, \
             largest value counted as zero {:.1e} of the largest)",
            fr.counted,
            fr.gap,
            below / s0
        )
    };
    let Some(rank) = fr.rank else {
        return Err(unclear());
    };
    if rank > 0 && (fr.gap < MIN_GAP || below > MAX_ZERO * s0) {
        return Err(unclear());
    }
    let column = |k: usize| {
        v.col(k)
            .try_as_col_major()
            .expect("faer matrices are column-major")
            .as_slice()
    };
    let kernel = clusters::FloatKernel {
        basis: (rank..cols).map(column).collect(),
        errors: (0..rank).map(|i| (noise / values[i], column(i))).collect(),
    };
    let clusters = clusters::float_clusters(topo, parts, real, &kernel)
        .map_err(|why| format!("the float rigid clusters are unclear: {why}"))?;
    Ok(Ranked {
        rank,
        rows: rows.len(),
        gap: fr.gap,
        clusters,
    })
}

/// The largest `|M t| / |t|` over the rigid motions `t` of the system (its
/// translations, and in a finite framework its rotations): zero at an exact
/// realization, the rounding of the float one's incidences here.
fn trivial_residual(
    topo: &Topology,
    parts: &Parts,
    real: &Realization<f64>,
    m: &Matrix<f64>,
) -> f64 {
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut motions: Vec<Vec<f64>> = axes
        .iter()
        .map(|&t| matrix::rigid_motion(parts, real, [0.0; 3], t))
        .collect();
    if topo.shifts.is_none() {
        motions.extend(
            axes.iter()
                .map(|&w| matrix::rigid_motion(parts, real, w, [0.0; 3])),
        );
    }
    motions
        .iter()
        .map(|t| norm(&m.apply(t)) / norm(t).max(f64::MIN_POSITIVE))
        .fold(0.0, f64::max)
}
