//! The rigidity verdict of a pattern over all its realization components
//! (MODEL §3–§4): exact rank over F_p where an exact construction exists,
//! floats with their gap rule and a twin realization otherwise.

use petgraph::unionfind::UnionFind;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use super::construction::{self, Geometry, Realization};
use super::family::{self};
use super::framework::{
    Framework, dof, float_framework, structure, trivial_dimension, trivial_residual,
};
use super::incidence::{Grouping, Incidence};
use super::projection;
use super::rank::structured_rank;
use crate::math::Fp;
use crate::math::float::{FloatRank, RankRule, decide_rank_above, qr_diagonal, singular_values};
use crate::pattern::Pattern;
use crate::{Error, Result};

/// What ranks the rigidity matrix for a verdict: exact arithmetic, or one of two float decompositions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Ranker {
    /// Rank over F_p at exact realizations of every component; a most
    /// generic family that no exact construction reaches is found by
    /// numerical projection and ranked in floats with the gap rule (its
    /// report says [`ComponentReport::projected`]).
    #[default]
    Exact,
    /// Singular values of a float realization (faer).
    Svd,
    /// Column-pivoted QR of a float realization (faer).
    Qr,
}

/// One realization family and the degrees of freedom found on it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ComponentReport {
    /// How the family was built, e.g. `planes {0,1,2} {3,4,5}` or `all coplanar`.
    pub built: String,
    /// Dimension of the family at its sample.
    pub dimension: usize,
    /// Dimension of all realizations at the same sample; larger means a special position.
    pub ambient: usize,
    /// Whether the family is a component (else a special position of a larger one).
    pub component: bool,
    /// Largest rank over the samples.
    pub rank: usize,
    /// Internal degrees of freedom.
    pub dof: usize,
    /// Float checks only: a sample's rank was undecided (its singular values
    /// had no clear gap), so `rank` and `dof` are what the tolerance alone
    /// counted, not a verdict.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub undecided: bool,
    /// The family was found by numerical projection (no exact construction
    /// exists): `rank`, `dof` and `dimension` are float ranks with a clear
    /// gap, not exact ranks over F_p.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub projected: bool,
}

/// The verdict on one pattern.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Verdict {
    /// True when rigid on every component, false when not, `None` when undecided.
    pub rigid: Option<bool>,
    /// The largest internal degrees of freedom over the components.
    pub dof: Option<usize>,
    /// `rigid`, `flexible`, `component-dependent` or `undecided`.
    pub class: String,
    pub components: Vec<ComponentReport>,
    /// Rank on the first component.
    pub rank: usize,
    pub method: Ranker,
    /// Relative singular-value gap around the decided rank (floats only).
    pub gap: Option<f64>,
    /// Why the verdict is undecided, if it is.
    pub note: Option<String>,
}

/// Independent exact realizations per family (the rank is their maximum).
pub const EXACT_SAMPLES: usize = 2;

/// Decides a pattern exactly: realizations of every family over F_p, rank of
/// the rigidity matrix on each, and the verdict over the components.
pub fn check_exact(pattern: &Pattern, seed: u64) -> Result<Verdict> {
    let inc = incidence(pattern)?;
    let (families, forced_built) = family::families(&inc, EXACT_SAMPLES, seed);
    let is_component = family::components(&families);
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5EED);
    let mut components = Vec::new();
    for (fam, &component) in families.iter().zip(&is_component) {
        let (rank, dof) = exact_rank(&inc, &fam.samples, &mut rng);
        components.push(ComponentReport {
            built: fam.grouping.describe(&inc),
            dimension: fam.dimension,
            ambient: fam.ambient,
            component,
            rank,
            dof,
            undecided: false,
            projected: false,
        });
    }
    if forced_built {
        return Ok(verdict(components, true, Ranker::Exact, ""));
    }
    match project_forced(&inc, seed, &mut rng) {
        Ok(report) => {
            components.push(report);
            let dims: Vec<(usize, usize)> = components
                .iter()
                .map(|c| (c.dimension, c.ambient))
                .collect();
            let flags = family::components_by_dimension(&dims);
            for (c, flag) in components.iter_mut().zip(flags) {
                c.component = flag;
            }
            Ok(verdict(components, true, Ranker::Exact, ""))
        }
        Err(why) => Ok(verdict(components, false, Ranker::Exact, &why)),
    }
}

/// The class of [`check_exact`]'s verdict (`rigid`, `flexible`,
/// `component-dependent` or `undecided`), by the same realizations, ranks
/// and random draws, without what the class does not need: the families'
/// dimensions (two Jacobian ranks each), which say which families are
/// components, only when the families disagree. The audit classifies
/// millions of patterns this way.
pub fn exact_class(pattern: &Pattern, seed: u64) -> Result<String> {
    let inc = incidence(pattern)?;
    // First samples only: most families are rigid on their first sample,
    // and a later one is built only for a family that is not.
    let (built, forced_built) = family::realized_first(&inc, seed);
    if !forced_built {
        // The projection draws from the stream the ranks left; rare enough
        // to take the whole verdict.
        return Ok(check_exact(pattern, seed)?.class);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5EED);
    // Every family is ranked, components or not, so that the auxiliary
    // points of each come from the same draws as in `check_exact`.
    let mut dofs = Vec::with_capacity(built.len());
    for b in &built {
        match first_rank(&inc, b, seed, &mut rng) {
            Some(dof) => dofs.push(dof),
            // A later sample that would not build drops its family:
            // all samples, as `check_exact` builds them.
            None => return exact_class_eager(&inc, pattern, seed),
        }
    }
    // Which families are components matters only when they disagree: if
    // every family is rigid (or every one flexible), so is every component.
    // Else their dimensions (two Jacobian ranks each) decide.
    let all_rigid = dofs.iter().all(|&d| d == 0);
    let all_flexible = dofs.iter().all(|&d| d > 0);
    if all_rigid || all_flexible {
        return Ok(class_of(&dofs, true).0.to_string());
    }
    let dims: Vec<(usize, usize)> = built
        .iter()
        .map(|b| family::dimensions(&inc, &b.grouping, &b.first.points))
        .collect();
    Ok(component_class(&dims, &dofs))
}

/// [`exact_class`] with every sample of every family built first.
fn exact_class_eager(inc: &Incidence, pattern: &Pattern, seed: u64) -> Result<String> {
    let (built, forced_built) = family::realized(inc, EXACT_SAMPLES, seed);
    if !forced_built {
        return Ok(check_exact(pattern, seed)?.class);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5EED);
    let dofs: Vec<usize> = built
        .iter()
        .map(|(_, samples)| exact_rank(inc, samples, &mut rng).1)
        .collect();
    let dims: Vec<(usize, usize)> = built
        .iter()
        .map(|(g, samples)| family::dimensions(inc, g, &samples[0].points))
        .collect();
    Ok(component_class(&dims, &dofs))
}

/// The class over the families that are components, by their dimensions.
fn component_class(dims: &[(usize, usize)], dofs: &[usize]) -> String {
    let component_dofs: Vec<usize> = family::components_by_dimension(dims)
        .into_iter()
        .zip(dofs)
        .filter_map(|(component, &dof)| component.then_some(dof))
        .collect();
    class_of(&component_dofs, true).0.to_string()
}

/// [`exact_rank`]'s degrees of freedom for a family of which only the first
/// sample is built: the later samples are built as they are needed, with
/// the seeds [`family::realized`] gives them. `None` when one of them does
/// not build.
fn first_rank(
    inc: &Incidence,
    b: &family::FirstBuilt,
    seed: u64,
    rng: &mut ChaCha8Rng,
) -> Option<usize> {
    let mut best = (0, usize::MAX);
    for s in 0..EXACT_SAMPLES as u64 {
        let later;
        let sample = if s == 0 {
            &b.first
        } else {
            later = b.sample(inc, seed, s).ok()?;
            &later
        };
        best = better(best, sample_rank(inc, sample, rng));
        if best.1 == 0 {
            break;
        }
    }
    Some(best.1)
}

/// The rank and degrees of freedom of one sample, its auxiliary points
/// from `rng`.
fn sample_rank(inc: &Incidence, s: &Realization<Fp>, rng: &mut ChaCha8Rng) -> (usize, usize) {
    let f =
        structure(inc, s, &mut || Fp::random(rng)).expect("the points of each part are distinct");
    let r = structured_rank(&f);
    (
        r,
        (3 * f.points.len()).saturating_sub(r + trivial_dimension(&f.points)),
    )
}

/// The best so far after one more sample's `(rank, dof)`: the largest
/// rank, and the fewest degrees of freedom where the rank grew.
fn better(best: (usize, usize), (r, dof): (usize, usize)) -> (usize, usize) {
    if r > best.0 || best.1 == usize::MAX {
        (r.max(best.0), dof.min(best.1))
    } else {
        best
    }
}

/// The largest rank and smallest degrees of freedom over a family's samples,
/// each ranked exactly; stops at the first rigid sample (no sample can
/// have a larger rank). Auxiliary points come from `rng`.
fn exact_rank(
    inc: &Incidence,
    samples: &[Realization<Fp>],
    rng: &mut ChaCha8Rng,
) -> (usize, usize) {
    let mut best = (0, usize::MAX);
    for s in samples {
        best = better(best, sample_rank(inc, s, rng));
        if best.1 == 0 {
            break;
        }
    }
    best
}

/// What the verdict says when the most generic family was not built.
const FORCED_UNBUILT: &str = "the most generic realization family could not be built exactly";

/// The forced (most generic) grouping by numerical projection, for
/// [`check_exact`] when no exact construction reaches it: a projected
/// realization and its twin ([`TWIN_NUDGE`]) ranked by SVD, and the
/// family's dimensions from the float Jacobian. A report only when every
/// float rank has a clear gap and the twins agree; else why not.
fn project_forced(
    inc: &Incidence,
    seed: u64,
    rng: &mut impl Rng,
) -> std::result::Result<ComponentReport, String> {
    let forced = Grouping::forced(inc);
    let Some((base, twin)) = projection::project_twins(inc, &forced, seed, TWIN_NUDGE) else {
        return Err(format!(
            "{FORCED_UNBUILT}, and numerical projection found no realization of it"
        ));
    };
    let unclear = || format!("{FORCED_UNBUILT}; its numerical projection has no clear float rank");
    let dimension = projection::float_local_dimension(inc, &forced.groups, &base.points);
    let ambient =
        projection::float_local_dimension(inc, &super::incidence::body_planes(inc), &base.points);
    let (Some(dimension), Some(ambient)) = (dimension, ambient) else {
        return Err(unclear());
    };
    let ranked = FamilyRank {
        base: float_rank(inc, base, Ranker::Svd, rng),
        twin: twin.and_then(|t| float_rank(inc, t, Ranker::Svd, rng)),
    };
    let (Some(dof), Some((fr, _))) = (ranked.dof(), ranked.base) else {
        return Err(unclear());
    };
    Ok(ComponentReport {
        built: format!("{}, numerical projection", forced.describe(inc)),
        dimension,
        ambient,
        component: true,
        rank: fr.counted,
        dof,
        undecided: false,
        projected: true,
    })
}

/// How far the twin of a float realization is nudged (every free choice, by
/// up to this much against coordinates of order one): far enough that a
/// realization within `eps << TWIN_NUDGE` of a special position has a twin
/// whose rank differs, near enough that generic ranks agree.
pub const TWIN_NUDGE: f64 = 1e-3;

/// Decides a pattern with float ranks (MODEL §4): the same families and the
/// same exact component analysis as [`check_exact`], a float realization of
/// each family and its twin ([`TWIN_NUDGE`]), their ranks by SVD or pivoted
/// QR. Undecided, rather than a guess, when a spectrum has no clear gap
/// ([`crate::math::float::RankRule`]) or the twins disagree.
/// [`Ranker::Exact`] delegates to [`check_exact`].
pub fn check_float(pattern: &Pattern, method: Ranker, seed: u64) -> Result<Verdict> {
    check_float_in(pattern, method, seed, &Geometry::generic())
}

/// [`check_float`] at realizations drawn by `geometry`: nearly degenerate
/// ones for the stability study.
pub fn check_float_in(
    pattern: &Pattern,
    method: Ranker,
    seed: u64,
    geometry: &Geometry<f64>,
) -> Result<Verdict> {
    if method == Ranker::Exact {
        return check_exact(pattern, seed);
    }
    Ok(float_ranks(pattern, method, seed, geometry)?.verdict())
}

/// The float ranks behind a float verdict.
#[derive(Clone, Debug)]
pub struct FloatRanks {
    /// One report per family: rank and degrees of freedom of the first
    /// realization as counted by the tolerance (see [`ComponentReport::undecided`]).
    pub components: Vec<ComponentReport>,
    /// Per family: the float rank of the realization and of its twin, `None`
    /// where no float realization or matrix could be built.
    pub samples: Vec<[Option<FloatRank>; 2]>,
    /// Whether the most generic family was built exactly.
    pub forced_built: bool,
    pub method: Ranker,
}

impl FloatRanks {
    /// The verdict: undecided when any component is; `gap` is the smallest
    /// over the components' realizations.
    pub fn verdict(&self) -> Verdict {
        let gap = self
            .components
            .iter()
            .zip(&self.samples)
            .filter(|(c, _)| c.component)
            .flat_map(|(_, s)| s.iter().flatten().map(|fr| fr.gap))
            .fold(f64::INFINITY, f64::min);
        let mut v = verdict(self.components.clone(), self.forced_built, self.method, "");
        v.gap = gap.is_finite().then_some(gap);
        v
    }
}

/// Ranks every family of a pattern on a float realization drawn by
/// `geometry` and its twin ([`Ranker::Exact`] is read as SVD). A family is
/// decided when both ranks are and give the same degrees of freedom.
pub fn float_ranks(
    pattern: &Pattern,
    method: Ranker,
    seed: u64,
    geometry: &Geometry<f64>,
) -> Result<FloatRanks> {
    let inc = incidence(pattern)?;
    let (families, forced_built) = family::families(&inc, 1, seed);
    let is_component = family::components(&families);
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0xF10A7);
    let mut components = Vec::new();
    let mut samples = Vec::new();
    for (k, (fam, &component)) in families.iter().zip(&is_component).enumerate() {
        let sample_seed = seed ^ 0xF10A7_u64.wrapping_add(1000 * k as u64);
        let ranked = float_family(&inc, &fam.grouping, method, geometry, sample_seed, &mut rng);
        let (rank, dof) = ranked.base.map_or((0, 0), |(fr, d)| (fr.counted, d));
        components.push(ComponentReport {
            built: fam.grouping.describe(&inc),
            dimension: fam.dimension,
            ambient: fam.ambient,
            component,
            rank,
            dof,
            undecided: ranked.dof().is_none(),
            projected: false,
        });
        samples.push([ranked.base.map(|x| x.0), ranked.twin.map(|x| x.0)]);
    }
    Ok(FloatRanks {
        components,
        samples,
        forced_built,
        method,
    })
}

/// The float ranks of one family: a realization and its twin, each with
/// the degrees of freedom at the rank the tolerance counted (`None` where no
/// realization or matrix could be built).
#[derive(Clone, Copy, Debug)]
pub struct FamilyRank {
    pub base: Option<(FloatRank, usize)>,
    pub twin: Option<(FloatRank, usize)>,
}

impl FamilyRank {
    /// The degrees of freedom when both ranks are decided and agree on them
    /// (a decided rank is the counted one, so the stored degrees are its).
    pub fn dof(&self) -> Option<usize> {
        match (self.base, self.twin) {
            (Some((b, dof_b)), Some((t, dof_t)))
                if b.rank.is_some() && t.rank.is_some() && dof_b == dof_t =>
            {
                Some(dof_b)
            }
            _ => None,
        }
    }
}

/// Builds a float realization of `grouping` by `geometry` and its twin
/// ([`TWIN_NUDGE`]) and ranks both by `method` ([`Ranker::Exact`] is read as SVD).
pub fn float_family(
    inc: &Incidence,
    grouping: &Grouping,
    method: Ranker,
    geometry: &Geometry<f64>,
    seed: u64,
    rng: &mut impl Rng,
) -> FamilyRank {
    let (base, twin) =
        match construction::construct_twins(inc, grouping, geometry, seed, TWIN_NUDGE) {
            Ok((base, twin)) => (Some(base), twin),
            Err(_) => (None, None),
        };
    let mut rank = |s: Option<Realization<f64>>| s.and_then(|s| float_rank(inc, s, method, rng));
    FamilyRank {
        base: rank(base),
        twin: rank(twin),
    }
}

/// The rank of the float rigidity matrix of a sample by `method`, and the
/// degrees of freedom at the rank the tolerance counted. The noise the
/// decision allows for is the roundoff floor or, when larger, how far the
/// trivial motions are from the kernel: the rounding the realization's
/// incidences carry, which lifts true zeros by as much.
fn float_rank(
    inc: &Incidence,
    sample: Realization<f64>,
    method: Ranker,
    rng: &mut impl Rng,
) -> Option<(FloatRank, usize)> {
    let f = float_framework(inc, sample, rng)?;
    let (values, noise) = float_spectrum(&f, method);
    let rule = match method {
        Ranker::Qr => RankRule::QR,
        Ranker::Svd | Ranker::Exact => RankRule::SVD,
    };
    let fr = decide_rank_above(&values, noise, rule);
    Some((fr, dof(&f, fr.counted)))
}

/// The descending spectrum of a float framework by `method` (singular
/// values, or `|R_ii|` of pivoted QR; `[NaN]` when it cannot be computed)
/// and the noise a rank decision must allow for: the roundoff floor
/// `max(m, n) * f64::EPSILON * s_0` or, when larger, [`trivial_residual`].
pub fn float_spectrum(f: &Framework<f64>, method: Ranker) -> (Vec<f64>, f64) {
    let values = match method {
        Ranker::Qr => qr_diagonal(&f.matrix),
        Ranker::Svd | Ranker::Exact => singular_values(&f.matrix),
    };
    let values = values.unwrap_or_else(|| vec![f64::NAN]);
    let s0 = values.first().copied().unwrap_or(0.0);
    let floor = f.matrix.rows.max(f.matrix.cols) as f64 * f64::EPSILON * s0;
    (values, floor.max(trivial_residual(f)))
}

/// The incidence structure of a well-formed, connected pattern.
fn incidence(pattern: &Pattern) -> Result<Incidence> {
    pattern.validate()?;
    if !connected(pattern) {
        return Err(Error::Parameter("the pattern is not connected".into()));
    }
    Ok(Incidence::new(pattern))
}

/// The verdict over the components; `unbuilt` says why the most generic
/// family is missing when `forced_built` is false (empty: it was not built exactly).
fn verdict(
    components: Vec<ComponentReport>,
    forced_built: bool,
    method: Ranker,
    unbuilt: &str,
) -> Verdict {
    let real: Vec<&ComponentReport> = components.iter().filter(|c| c.component).collect();
    let rank = real.first().map_or(0, |c| c.rank);
    let (rigid, class, note) = if real.is_empty() {
        (
            None,
            "undecided",
            Some("no realization could be built".to_string()),
        )
    } else if let Some(c) = real.iter().find(|c| c.undecided) {
        (
            None,
            "undecided",
            Some(format!(
                "the float rank on component `{}` has no clear singular-value gap, \
                 or its float realization could not be built",
                c.built
            )),
        )
    } else {
        let dofs: Vec<usize> = real.iter().map(|c| c.dof).collect();
        let (class, rigid) = class_of(&dofs, forced_built);
        let note = (class == "undecided").then(|| {
            if unbuilt.is_empty() {
                FORCED_UNBUILT.to_string()
            } else {
                unbuilt.to_string()
            }
        });
        (rigid, class, note)
    };
    Verdict {
        rigid,
        dof: real.iter().map(|c| c.dof).max(),
        class: class.to_string(),
        rank,
        components,
        method,
        gap: None,
        note,
    }
}

/// The class of decided components with these degrees of freedom (at least
/// one), and whether rigid: rigid on all only counts when the most generic
/// family was built.
fn class_of(dofs: &[usize], forced_built: bool) -> (&'static str, Option<bool>) {
    let rigid_all = dofs.iter().all(|&d| d == 0);
    let flexible_all = dofs.iter().all(|&d| d > 0);
    match (rigid_all, flexible_all, forced_built) {
        (true, _, true) => ("rigid", Some(true)),
        (true, _, false) => ("undecided", None),
        (false, true, _) => ("flexible", Some(false)),
        (false, false, _) => ("component-dependent", Some(false)),
    }
}

fn connected(p: &Pattern) -> bool {
    let mut components = UnionFind::<usize>::new(p.n_nodes());
    for c in &p.contacts {
        components.union(c.nodes[0] as usize, c.nodes[1] as usize);
    }
    (1..p.n_nodes()).all(|v| components.equiv(0, v))
}
