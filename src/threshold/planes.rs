//! Where forced planes percolate (MODEL §10), per aspect ratio.
//!
//! The line model puts every 3-clique community, and every rod touching a
//! plane's rods at two points, into one plane. As the density grows these
//! classes merge into one that holds nearly every well-held rod, and then
//! into one that would have to contain three independent box directions:
//! the line model then has no realization at all, and forces a dense 3-D
//! network flat. A rigidity threshold above that transition describes the
//! idealization, not the rods; this scan says where the transition sits.
//!
//! Densities are set by the mean contact number `c = rho V_ex`, so that one
//! grid means the same connectivity at every aspect ratio. At each density
//! the systems are seeds `1..=seeds`; since the first `n` rods of a seed are
//! its `n`-rod system, one seed's systems are nested, each adding rods to
//! the one before, and its curve follows one growing system.
//!
//! Two transition densities, both documented in the written report:
//! * *percolation*: the smallest density at which the mean, over seeds, of
//!   the fraction of heavy rods (2-core rods with three or more contacts
//!   inside the 2-core) that the largest class holds exceeds 1/2,
//!   interpolated linearly between the last grid point at or below 1/2 and
//!   the first above;
//! * *flat*: the smallest grid density at which at least half of the
//!   systems are unrealizable (no interpolation: the share moves in steps of
//!   one seed).
//!
//! Where a system is unrealizable the periodic closure stops early, so its
//! largest class is taken from the closure without images ([`measure`]).

use std::path::Path;
use std::time::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::report::Summary;
use crate::math::stats;
use crate::network::Network;
use crate::output::{self, cell};
use crate::progress::Progress;
use crate::rods::{self, RodParams, RodSystem};
use crate::stamp::{self as envelope, Stamp};
use crate::truth::{Topology, planes, prune};
use crate::{Error, Result};

/// The format tag of `forced-planes.json`.
pub const FORMAT: &str = "rgc-forced-planes/1";

/// The default grid of mean contact numbers: 2 to 6 in steps of 1/4, from
/// below contact percolation (about 1.3 to 1.6) to well above the rigidity
/// thresholds (about 3.1 to 3.2).
pub fn default_contact_numbers() -> Vec<f64> {
    (0..=16).map(|k| 2.0 + 0.25 * f64::from(k)).collect()
}

/// What a scan of several aspect ratios is made of: what the refusal to
/// replace a scan compares.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Parameters {
    pub gammas: Vec<f64>,
    /// Box side per aspect ratio.
    pub boxes: Vec<f64>,
    /// Seeds `1..=seeds` at each density.
    pub seeds: u64,
    /// The grid of mean contact numbers `rho V_ex`.
    pub contact_numbers: Vec<f64>,
}

impl Parameters {
    /// One box for every gamma, or one each.
    pub fn new(
        gammas: Vec<f64>,
        boxes: &[f64],
        seeds: u64,
        contact_numbers: Vec<f64>,
    ) -> Result<Self> {
        let boxes = match boxes {
            [b] => vec![*b; gammas.len()],
            b if b.len() == gammas.len() => b.to_vec(),
            b => {
                return Err(Error::Parameter(format!(
                    "{} boxes for {} aspect ratios: give one box, or one per gamma",
                    b.len(),
                    gammas.len()
                )));
            }
        };
        let p = Parameters {
            gammas,
            boxes,
            seeds,
            contact_numbers,
        };
        p.validate()?;
        Ok(p)
    }

    /// The scan of each aspect ratio, validated.
    pub fn specs(&self) -> Result<Vec<ScanSpec>> {
        self.validate()?;
        Ok(self
            .gammas
            .iter()
            .zip(&self.boxes)
            .map(|(&gamma, &box_len)| {
                ScanSpec::from_contact_numbers(gamma, box_len, &self.contact_numbers, self.seeds)
            })
            .collect())
    }

    /// Checks everything before any work: each aspect ratio once, a box
    /// per aspect ratio, and every system of every scan valid.
    pub fn validate(&self) -> Result<()> {
        if self.gammas.is_empty() {
            return Err(Error::Parameter("no aspect ratio to scan".into()));
        }
        if self.boxes.len() != self.gammas.len() {
            return Err(Error::Parameter(format!(
                "{} boxes for {} aspect ratios",
                self.boxes.len(),
                self.gammas.len()
            )));
        }
        for (i, g) in self.gammas.iter().enumerate() {
            if self.gammas[..i].contains(g) {
                return Err(Error::Parameter(format!("gamma {g} is given twice")));
            }
        }
        if let Some(c) = self
            .contact_numbers
            .iter()
            .find(|c| !(c.is_finite() && **c > 0.0))
        {
            return Err(Error::Parameter(format!(
                "contact numbers must be positive and finite, got {c}"
            )));
        }
        for (&gamma, &box_len) in self.gammas.iter().zip(&self.boxes) {
            // `RodParams::new` checks gamma before the density its V_ex gave.
            ScanSpec::from_contact_numbers(gamma, box_len, &self.contact_numbers, self.seeds)
                .validate()?;
        }
        Ok(())
    }
}

/// The scan of one aspect ratio.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ScanSpec {
    pub gamma: f64,
    #[serde(rename = "box")]
    pub box_len: f64,
    /// Rods per unit volume, increasing.
    pub densities: Vec<f64>,
    /// Seeds `1..=seeds` at each density.
    pub seeds: u64,
}

impl ScanSpec {
    /// The densities `c / V_ex` of the mean contact numbers `contact_numbers`.
    pub fn from_contact_numbers(
        gamma: f64,
        box_len: f64,
        contact_numbers: &[f64],
        seeds: u64,
    ) -> ScanSpec {
        let vex = rods::excluded_volume(gamma);
        ScanSpec {
            gamma,
            box_len,
            densities: contact_numbers.iter().map(|c| c / vex).collect(),
            seeds,
        }
    }

    /// Checks every system's parameters, a seed at least, and densities
    /// that increase (the crossings are read along them).
    pub fn validate(&self) -> Result<()> {
        if self.seeds == 0 {
            return Err(Error::Parameter("at least one seed is needed".into()));
        }
        if self.densities.is_empty() {
            return Err(Error::Parameter("no density to scan".into()));
        }
        if let Some(w) = self.densities.windows(2).find(|w| w[1] <= w[0]) {
            return Err(Error::Parameter(format!(
                "densities must increase, got {} then {}",
                w[0], w[1]
            )));
        }
        for &rho in &self.densities {
            RodParams::new(self.gamma, self.box_len, rho)?;
        }
        Ok(())
    }
}

/// The forced planes of one system.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SystemPlanes {
    pub density: f64,
    pub seed: u64,
    pub rods: usize,
    pub contacts: usize,
    pub core_rods: usize,
    /// Rods of the 2-core with three or more contacts inside it: a rod
    /// with two is in a plane only through a triangle, so these are the
    /// rods whose flattening matters.
    pub heavy_rods: usize,
    /// Forced plane classes (of the closure without images when unrealizable).
    pub classes: usize,
    /// Rods in the largest class. When unrealizable, the largest class of
    /// the closure without images (see [`measure`]).
    pub largest: usize,
    /// Heavy rods in the largest class.
    pub largest_heavy: usize,
    /// `largest_heavy / heavy_rods` (0 without heavy rods).
    pub fraction: f64,
    pub unrealizable: bool,
    /// When unrealizable, the rods of the class when it met its third box
    /// direction (`Unrealizable::rods`), where the periodic closure stopped.
    pub stopped_at: Option<usize>,
}

/// The forced planes of the system of `seed` at `density`.
///
/// When the periodic closure meets a class with three box directions it
/// stops, and the size it reports is where it stopped: often a third of
/// what the class goes on to absorb, so it would hide the very transition
/// measured here. The largest class is then taken from the closure on the
/// contact graph without images (a finite framework: every triangle seeds
/// a plane, a rod touching a class twice joins whatever the images). That
/// closure can only merge more than the periodic one, and where one class
/// contains three box directions "which image of the plane" has no answer
/// left anyway.
pub fn measure(gamma: f64, box_len: f64, density: f64, seed: u64) -> Result<SystemPlanes> {
    let network = Network::detect(RodSystem::generate(
        RodParams::new(gamma, box_len, density)?,
        seed,
    ));
    let graph = &network.graph;
    let core = prune::two_core(graph);
    let heavy: Vec<bool> = (0..graph.n_nodes() as u32)
        .map(|r| {
            core.active[r as usize]
                && graph
                    .neighbors(r)
                    .iter()
                    .filter(|&&(x, _)| core.active[x as usize])
                    .count()
                    >= 3
        })
        .collect();
    let (found_planes, stopped_at) = match planes::forced(&network.topology(), &core.active) {
        Ok(p) => (p, None),
        Err(u) => (
            planes::forced(&Topology::finite(graph), &core.active)
                .expect("without images no class meets a box direction"),
            Some(u.rods),
        ),
    };
    // Classes come largest first.
    let largest = found_planes
        .classes
        .first()
        .map_or(&[][..], |c| &c.rods[..]);
    let largest_heavy = largest.iter().filter(|&&(r, _)| heavy[r as usize]).count();
    let heavy_rods = heavy.iter().filter(|&&h| h).count();
    Ok(SystemPlanes {
        density,
        seed,
        rods: graph.n_nodes(),
        contacts: graph.n_edges(),
        core_rods: core.rods(),
        heavy_rods,
        classes: found_planes.classes.len(),
        largest: largest.len(),
        largest_heavy,
        fraction: if heavy_rods == 0 {
            0.0
        } else {
            largest_heavy as f64 / heavy_rods as f64
        },
        unrealizable: stopped_at.is_some(),
        stopped_at,
    })
}

/// The systems of one density, summarized.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DensityPoint {
    pub density: f64,
    /// `rho V_ex`.
    pub contact_number: f64,
    pub systems: usize,
    pub mean_rods: f64,
    pub mean_heavy_rods: f64,
    pub mean_largest: f64,
    pub mean_fraction: f64,
    /// Standard error of the mean fraction (0 for one seed).
    pub se_fraction: f64,
    pub unrealizable_share: f64,
}

/// Summarizes the `systems` of one density.
pub fn summarize(density: f64, vex: f64, systems: &[SystemPlanes]) -> DensityPoint {
    let n = systems.len();
    let mean = |f: &dyn Fn(&SystemPlanes) -> f64| systems.iter().map(f).sum::<f64>() / n as f64;
    let fractions: Vec<f64> = systems.iter().map(|s| s.fraction).collect();
    let (mean_fraction, sd) = stats::mean_sd(&fractions);
    DensityPoint {
        density,
        contact_number: density * vex,
        systems: n,
        mean_rods: mean(&|s| s.rods as f64),
        mean_heavy_rods: mean(&|s| s.heavy_rods as f64),
        mean_largest: mean(&|s| s.largest as f64),
        mean_fraction,
        se_fraction: sd / (n as f64).sqrt(),
        unrealizable_share: mean(&|s| f64::from(u8::from(s.unrealizable))),
    }
}

/// Where a transition sits on the scanned grid.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Crossing {
    /// Within the scan, at this density and mean contact number `rho V_ex`.
    Within { density: f64, contact_number: f64 },
    /// Already at the first density: it lies at or below the scan.
    AtFirst,
    /// Not reached at the last density.
    NotReached,
}

impl Crossing {
    pub fn density(&self) -> Option<f64> {
        match *self {
            Crossing::Within { density, .. } => Some(density),
            _ => None,
        }
    }

    pub fn contact_number(&self) -> Option<f64> {
        match *self {
            Crossing::Within { contact_number, .. } => Some(contact_number),
            _ => None,
        }
    }
}

/// The smallest density where the mean fraction exceeds 1/2, linearly
/// interpolated from the grid point before (see the module docs).
pub fn percolation(points: &[DensityPoint], vex: f64) -> Crossing {
    let Some(i) = points.iter().position(|p| p.mean_fraction > 0.5) else {
        return Crossing::NotReached;
    };
    if i == 0 {
        return Crossing::AtFirst;
    }
    let (a, b) = (&points[i - 1], &points[i]);
    let t = (0.5 - a.mean_fraction) / (b.mean_fraction - a.mean_fraction);
    let density = a.density + t * (b.density - a.density);
    Crossing::Within {
        density,
        contact_number: density * vex,
    }
}

/// The smallest grid density where at least half the systems are unrealizable.
pub fn flat(points: &[DensityPoint], vex: f64) -> Crossing {
    match points.iter().position(|p| p.unrealizable_share >= 0.5) {
        None => Crossing::NotReached,
        Some(0) => Crossing::AtFirst,
        Some(i) => Crossing::Within {
            density: points[i].density,
            contact_number: points[i].density * vex,
        },
    }
}

/// A threshold committed in `results/`, for reading the transition against.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Committed {
    /// The study directory it was read from.
    pub study: String,
    pub density: f64,
    /// `rho_c V_ex`.
    pub contact_number: f64,
}

/// The committed contact and rigidity (`sound`) thresholds of one gamma.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct References {
    pub contact: Option<Committed>,
    pub rigidity: Option<Committed>,
}

/// Reads `g{gamma}-contact` and `g{gamma}-rigid-sound` in `studies`
/// (their `summary.json`), where they exist.
pub fn references(studies: &Path, gamma: f64) -> Result<References> {
    let read = |name: &str| -> Result<Option<Committed>> {
        let dir = studies.join(format!("g{gamma}-{name}"));
        let path = dir.join("summary.json");
        let Some(text) = envelope::existing(&path)? else {
            return Ok(None);
        };
        let summary: Summary = serde_json::from_str(&text).map_err(|e| Error::Study {
            path: path.clone(),
            reason: format!("not a study summary: {e}"),
        })?;
        let density = summary.fss.threshold.value;
        Ok(Some(Committed {
            study: dir.display().to_string(),
            density,
            contact_number: density * rods::excluded_volume(gamma),
        }))
    };
    Ok(References {
        contact: read("contact")?,
        rigidity: read("rigid-sound")?,
    })
}

/// The scan of one aspect ratio.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GammaScan {
    #[serde(flatten)]
    pub spec: ScanSpec,
    pub excluded_volume: f64,
    pub percolation: Crossing,
    pub flat: Crossing,
    pub references: References,
    pub points: Vec<DensityPoint>,
    /// Every system, density by density, seed by seed.
    pub systems: Vec<SystemPlanes>,
    /// Wall-clock seconds of the scan.
    pub seconds: f64,
}

/// Scans one aspect ratio, the systems in parallel; the result does not
/// depend on the number of threads (the systems are collected in order).
pub fn scan(spec: &ScanSpec, progress: &dyn Progress) -> Result<GammaScan> {
    spec.validate()?;
    let start = Instant::now();
    let jobs: Vec<(f64, u64)> = spec
        .densities
        .iter()
        .flat_map(|&rho| (1..=spec.seeds).map(move |s| (rho, s)))
        .collect();
    progress.start(
        &format!("forced planes, gamma {}", spec.gamma),
        jobs.len() as u64,
    );
    let systems = jobs
        .par_iter()
        .map(|&(rho, seed)| {
            let s = measure(spec.gamma, spec.box_len, rho, seed);
            progress.advance(1);
            s
        })
        .collect::<Result<Vec<_>>>()?;
    progress.finish();
    let vex = rods::excluded_volume(spec.gamma);
    let points: Vec<DensityPoint> = spec
        .densities
        .iter()
        .zip(systems.chunks(spec.seeds as usize))
        .map(|(&rho, chunk)| summarize(rho, vex, chunk))
        .collect();
    Ok(GammaScan {
        spec: spec.clone(),
        excluded_volume: vex,
        percolation: percolation(&points, vex),
        flat: flat(&points, vex),
        references: References::default(),
        points,
        systems,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// What made `forced-planes.json`: the scan's parameters.
pub type Made = envelope::Parameters<Parameters>;

/// The stamp of `forced-planes.json` that `command` writes with `params`.
pub fn stamp(command: &str, params: &Parameters) -> Stamp<Made> {
    Stamp::with_parameters(FORMAT, command, params.clone())
}

/// What `forced-planes.json` holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Report {
    #[serde(flatten)]
    pub stamp: Stamp<Made>,
    /// The two transition densities, in words.
    pub definitions: Definitions,
    pub scans: Vec<GammaScan>,
    pub seconds: f64,
}

/// The definitions of the report's transitions, stored with it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Definitions {
    pub heavy_rods: String,
    pub fraction: String,
    pub percolation: String,
    pub flat: String,
}

impl Default for Definitions {
    fn default() -> Self {
        Definitions {
            heavy_rods: "rods of the 2-core with three or more contacts inside the 2-core".into(),
            fraction: "heavy rods in the largest forced plane class divided by the heavy rods; \
                       when unrealizable (the periodic closure stops), the largest class of the \
                       closure on the contact graph without images"
                .into(),
            percolation: "smallest density where the mean fraction over seeds exceeds 1/2, \
                          linearly interpolated between the grid point before and the first above"
                .into(),
            flat: "smallest grid density where at least half of the systems are unrealizable \
                   (a forced plane class would contain three independent box directions)"
                .into(),
        }
    }
}

/// Scans every aspect ratio of `params` in turn, each with its committed
/// thresholds from the study directories in `studies` (read first, so a
/// bad summary fails before the work).
pub fn run(
    params: &Parameters,
    studies: &Path,
    command: &str,
    progress: &dyn Progress,
) -> Result<Report> {
    let start = Instant::now();
    let specs = params.specs()?;
    let references = params
        .gammas
        .iter()
        .map(|&g| references(studies, g))
        .collect::<Result<Vec<_>>>()?;
    let mut scans = Vec::with_capacity(specs.len());
    for (spec, refs) in specs.iter().zip(references) {
        scans.push(GammaScan {
            references: refs,
            ..scan(spec, progress)?
        });
    }
    Ok(Report {
        stamp: stamp(command, params),
        definitions: Definitions::default(),
        scans,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// One row of `forced-planes.csv`: a density of one aspect ratio.
#[derive(Serialize)]
struct Row {
    #[serde(serialize_with = "cell::display")]
    gamma: f64,
    #[serde(rename = "box", serialize_with = "cell::display")]
    box_len: f64,
    #[serde(serialize_with = "cell::fixed::<6, _>")]
    density: f64,
    #[serde(serialize_with = "cell::fixed::<4, _>")]
    contact_number: f64,
    systems: usize,
    #[serde(serialize_with = "cell::fixed::<2, _>")]
    mean_rods: f64,
    #[serde(serialize_with = "cell::fixed::<2, _>")]
    mean_heavy_rods: f64,
    #[serde(serialize_with = "cell::fixed::<2, _>")]
    mean_largest: f64,
    #[serde(serialize_with = "cell::fixed::<6, _>")]
    mean_fraction: f64,
    #[serde(serialize_with = "cell::fixed::<6, _>")]
    se_fraction: f64,
    #[serde(serialize_with = "cell::fixed::<4, _>")]
    unrealizable_share: f64,
}

/// The per-density table of every aspect ratio.
pub fn csv(report: &Report) -> Vec<u8> {
    output::csv(report.scans.iter().flat_map(|s| {
        s.points.iter().map(|p| Row {
            gamma: s.spec.gamma,
            box_len: s.spec.box_len,
            density: p.density,
            contact_number: p.contact_number,
            systems: p.systems,
            mean_rods: p.mean_rods,
            mean_heavy_rods: p.mean_heavy_rods,
            mean_largest: p.mean_largest,
            mean_fraction: p.mean_fraction,
            se_fraction: p.se_fraction,
            unrealizable_share: p.unrealizable_share,
        })
    }))
}

/// Writes `forced-planes.json` and `forced-planes.csv` into `dir`, atomically.
pub fn write(report: &Report, dir: &Path) -> Result<()> {
    output::write_atomic(&dir.join("forced-planes.json"), envelope::json(report))?;
    output::write_atomic(&dir.join("forced-planes.csv"), csv(report))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(density: f64, mean_fraction: f64, unrealizable_share: f64) -> DensityPoint {
        DensityPoint {
            density,
            contact_number: density / 10.0,
            systems: 4,
            mean_rods: 0.0,
            mean_heavy_rods: 0.0,
            mean_largest: 0.0,
            mean_fraction,
            se_fraction: 0.0,
            unrealizable_share,
        }
    }

    #[test]
    fn percolation_interpolates_between_the_grid_points_around_one_half() {
        let points = [
            point(10.0, 0.1, 0.0),
            point(20.0, 0.3, 0.0),
            point(30.0, 0.7, 0.25),
            point(40.0, 0.4, 0.5),
            point(50.0, 0.9, 1.0),
        ];
        // The first exceedance counts, even if the mean dips after it.
        let c = percolation(&points, 0.1);
        let Crossing::Within {
            density,
            contact_number,
        } = c
        else {
            panic!("{c:?}")
        };
        assert!((density - 25.0).abs() < 1e-12, "{density}");
        assert!((contact_number - 2.5).abs() < 1e-12);
        // Flat: the first grid point with at least half unrealizable, no interpolation.
        assert_eq!(flat(&points, 0.1).density(), Some(40.0));
        assert_eq!(percolation(&points[..2], 0.1), Crossing::NotReached);
        assert_eq!(percolation(&points[2..], 0.1), Crossing::AtFirst);
        assert_eq!(flat(&points[3..], 0.1), Crossing::AtFirst);
        // Exactly 1/2 is not above it.
        assert_eq!(
            percolation(&[point(1.0, 0.5, 0.0)], 0.1),
            Crossing::NotReached
        );
    }

    #[test]
    fn a_summary_has_the_mean_and_its_standard_error() {
        let system = |fraction: f64, unrealizable| SystemPlanes {
            density: 1.0,
            seed: 1,
            rods: 100,
            contacts: 200,
            core_rods: 90,
            heavy_rods: 80,
            classes: 3,
            largest: (80.0 * fraction) as usize,
            largest_heavy: (80.0 * fraction) as usize,
            fraction,
            unrealizable,
            stopped_at: unrealizable.then_some(10),
        };
        let p = summarize(2.0, 0.5, &[system(0.25, false), system(0.75, true)]);
        assert_eq!(p.contact_number, 1.0);
        assert_eq!(p.mean_fraction, 0.5);
        // sd of {0.25, 0.75} is sqrt(1/8); over sqrt(2): 1/4.
        assert!((p.se_fraction - 0.25).abs() < 1e-12);
        assert_eq!(p.unrealizable_share, 0.5);
        assert_eq!(p.mean_largest, 40.0);
    }

    #[test]
    fn the_default_grid_runs_from_2_to_6_in_quarters() {
        let g = default_contact_numbers();
        assert_eq!(g.len(), 17);
        assert_eq!((g[0], g[1], g[16]), (2.0, 2.25, 6.0));
    }
}
