//! Argument groups that several subcommands share, flattened into each, so
//! a flag means the same thing and has the same default everywhere.

use std::path::PathBuf;

use clap::{ArgAction, Args};
use rgc::engine::RuleSet;
use rgc::moduli;
use rgc::rods::ensemble::{Dist, Ensemble, Orientation};
use rgc::rods::file::{self, Columns, Format, Frame, ReadOptions};
use rgc::rods::{Domain, MIN_GAMMA, Periodic, RodParams};
use rgc::sample::{Rods, SampleOptions};
use rgc::spanning::Criterion;
use rgc::threshold::study::StudySpec;
use rgc::{Error, Result};

/// How much memory a system may use: `sample`, `render`, `truth`,
/// `compress`, and every study (`threshold`, `compare`, `tradeoff`, `bias`).
#[derive(Args)]
pub struct MemoryArgs {
    /// Refuse, before each large step, work that would take the process's resident size past this (the rods, contacts and graph up front; truth's realization and each dense front of its elimination; the compressions; the moduli's projection and sparse QR): bytes, or with a unit (`512M`, `4G`, `1.5GiB`). With or without it, a step is refused that the machine (free memory, a cgroup's limit) or an address-space limit (`ulimit -v`) has no room for.
    #[arg(long, value_name = "SIZE", value_parser = parse_size)]
    pub memory_limit: Option<u64>,
}

/// How long LSMR may relax each strain: `moduli` and `stiffening`.
#[derive(Args)]
pub struct LsmrArgs {
    /// LSMR's iterations per strain at most: where they run out the moduli are upper bounds, said as unsettled (a stiffening measurement made before this was a choice had 1,000).
    #[arg(long, default_value_t = moduli::LSMR_ITERATIONS as u64, value_parser = clap::value_parser!(u64).range(1..=moduli::MAX_LSMR_ITERATIONS as u64))]
    lsmr_iterations: u64,
}

impl LsmrArgs {
    pub fn iterations(&self) -> usize {
        self.lsmr_iterations as usize
    }
}

/// Bytes from `4G`, `512M`, `1.5GiB`, `100000` (binary units).
fn parse_size(s: &str) -> std::result::Result<u64, String> {
    let t = s.trim();
    let split = t.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let scale: u64 = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 1,
        "k" | "kb" | "kib" => 1 << 10,
        "m" | "mb" | "mib" => 1 << 20,
        "g" | "gb" | "gib" => 1 << 30,
        "t" | "tb" | "tib" => 1 << 40,
        other => {
            return Err(format!(
                "unknown unit {other:?} in {s:?} (use K, M, G or T)"
            ));
        }
    };
    let value: f64 = number
        .trim()
        .parse()
        .map_err(|_| format!("not a size: {s:?} (e.g. 4G, 512M or a number of bytes)"))?;
    if !(value.is_finite() && value > 0.0) {
        return Err(format!("a memory limit must be positive, not {s:?}"));
    }
    Ok((value * scale as f64) as u64)
}

/// Which motifs the engine applies: every subcommand that compresses.
#[derive(Args)]
pub struct RuleArgs {
    /// Motif conditions: `paper` is verbatim; `sound` refuses what exact rank refutes (3D2A between planes, 3D4 closing a triangle on a plane, instances whose induced pattern is not rigid).
    #[arg(long, value_enum, default_value_t = RuleSet::Sound)]
    pub rules: RuleSet,
    /// Motif rule files (a file or a directory of `*.json`), used with the base motifs.
    #[arg(long, alias = "motifs")]
    pub rule_files: Vec<PathBuf>,
}

/// How to compress one system: `sample` and `compress`.
#[derive(Args)]
pub struct EngineArgs {
    /// Seed of the random motif order (and of the rods, for `sample`).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Independent compressions; a system is rigid-spanning if any finds a spanning body.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=rgc::engine::MAX_RUNS))]
    pub runs: u64,
    #[command(flatten)]
    pub rules: RuleArgs,
}

/// The rods of one system: read from a file, or generated (`sample`,
/// `render`, `truth`).
#[derive(Args)]
pub struct RodsArgs {
    /// Read the rods from this file instead of generating them ('-': standard input): a CSV with the header x,y,z,dx,dy,dz,length,radius, JSON, or a LAMMPS dump (.dump, .lammpstrj); cores crossing a wall are cut to the box.
    #[arg(long, value_name = "FILE")]
    rods: Option<PathBuf>,
    /// The rods file's format, when its extension does not say.
    #[arg(long, value_enum, requires = "rods")]
    rods_format: Option<Format>,
    /// Which LAMMPS dump column holds each quantity, as KEY=COLUMN or KEY=VALUE pairs over the defaults x=x,y=y,z=z,dx=mux,dy=muy,dz=muz,length=length,radius=radius (e.g. `dx=c_u[1],dy=c_u[2],dz=c_u[3],length=1,radius=0.02`).
    #[arg(long, requires = "rods", value_name = "MAP")]
    lammps_columns: Option<String>,
    /// The snapshot of a LAMMPS dump to read: its index in the file, from 0, or `last` (a dump of several snapshots needs it).
    #[arg(long, requires = "rods", value_name = "N|last")]
    frame: Option<String>,
    /// Read only the atoms of these types from a LAMMPS dump (its `type` column): one type or a list, `2` or `2,3`.
    #[arg(long, requires = "rods", value_delimiter = ',', value_name = "T[,T..]")]
    atom_type: Option<Vec<String>>,
    /// The lowest corner of the box in the rods file's coordinates (X,Y,Z, or one value for all three): the box is [X, X + LX) ... (a JSON `origin` or a dump's low bounds give it too). Default 0; e.g. -L/2 for HOOMD's centred box. Centres are wrapped into the box along periodic axes.
    #[arg(
        long,
        requires = "rods",
        value_delimiter = ',',
        action = ArgAction::Set,
        allow_hyphen_values = true,
        value_name = "O|X,Y,Z"
    )]
    origin: Vec<f64>,
    /// Aspect ratio l / (2r) of generated rods (the radius is the mean length over 2 gamma).
    #[arg(long, allow_hyphen_values = true)]
    gamma: Option<f64>,
    /// Box side L, or sides LX,LY,LZ, in rod lengths (for a rods file: needed unless the file gives it).
    #[arg(
        long = "box",
        value_delimiter = ',',
        action = ArgAction::Set,
        allow_hyphen_values = true,
        value_name = "L|LX,LY,LZ"
    )]
    sides: Vec<f64>,
    /// Number density N / V of generated rods.
    #[arg(long, allow_hyphen_values = true)]
    density: Option<f64>,
    /// Periodic axes: xyz (default), xy (walls at z = 0 and LZ) or none (six walls).
    #[arg(long, value_enum)]
    periodic: Option<Periodic>,
    /// Core lengths of generated rods: VALUE (default 1), uniform:LO,HI or lognormal:MEAN,SD.
    #[arg(long, value_name = "DIST")]
    length: Option<String>,
    /// Radii of generated rods, instead of --gamma: VALUE, uniform:LO,HI or lognormal:MEAN,SD.
    #[arg(long, value_name = "DIST", conflicts_with = "gamma")]
    radius: Option<String>,
    /// Nematic order parameter S of generated rods, in (-0.499, 0.999): orientations follow a Watson distribution about --director (0: isotropic, the default).
    #[arg(long, allow_hyphen_values = true)]
    order: Option<f64>,
    /// The director of aligned rods (default 0,0,1).
    #[arg(
        long,
        value_delimiter = ',',
        action = ArgAction::Set,
        allow_hyphen_values = true,
        requires = "order",
        value_name = "X,Y,Z"
    )]
    director: Option<Vec<f64>>,
}

impl RodsArgs {
    /// Whether any rods were described.
    pub fn given(&self) -> bool {
        self.rods.is_some()
            || self.gamma.is_some()
            || self.radius.is_some()
            || self.density.is_some()
            || !self.sides.is_empty()
    }

    fn sides(&self) -> Result<Option<[f64; 3]>> {
        three(&self.sides, "--box", "one side L or three sides LX,LY,LZ")
    }

    /// The rods these arguments ask for, checked (a file is read and checked now).
    pub fn rods(&self) -> Result<Rods> {
        let sides = self.sides()?;
        if let Some(path) = &self.rods {
            let generated = [
                ("--gamma", self.gamma.is_some()),
                ("--density", self.density.is_some()),
                ("--length", self.length.is_some()),
                ("--radius", self.radius.is_some()),
                ("--order", self.order.is_some()),
            ];
            if let Some((flag, _)) = generated.iter().find(|(_, on)| *on) {
                return Err(Error::Parameter(format!(
                    "{flag} describes generated rods; the rods of {} are read as they are",
                    path.display()
                )));
            }
            let columns = match &self.lammps_columns {
                Some(text) => Columns::parse(text)?,
                None => Columns::default(),
            };
            let opts = ReadOptions {
                format: self.rods_format,
                sides,
                periodic: self.periodic,
                origin: three(&self.origin, "--origin", "one value or three X,Y,Z")?,
                columns,
                frame: self.frame.as_deref().map(Frame::parse).transpose()?,
                types: self.atom_type.clone(),
            };
            let loaded = file::read(path, &opts)?;
            return Ok(Rods::Read {
                path: path.clone(),
                loaded,
            });
        }
        let Some(sides) = sides else {
            return Err(Error::Parameter("generated rods need --box".into()));
        };
        let Some(density) = self.density else {
            return Err(Error::Parameter("generated rods need --density".into()));
        };
        let length = match &self.length {
            Some(text) => Dist::parse(text)?,
            None => Dist::Fixed { value: 1.0 },
        };
        let periodic = self.periodic.unwrap_or_default();
        let orientation = match self.order {
            None => Orientation::Isotropic,
            Some(order) => {
                let director = self.director.clone().unwrap_or_else(|| vec![0.0, 0.0, 1.0]);
                let [x, y, z] = director[..] else {
                    return Err(Error::Parameter(format!(
                        "--director takes three numbers X,Y,Z, got {}",
                        director.len()
                    )));
                };
                Orientation::Aligned {
                    order,
                    director: [x, y, z],
                }
            }
        };
        let radius = match (&self.radius, self.gamma) {
            (Some(text), _) => Dist::parse(text)?,
            (None, Some(gamma)) => {
                let paper = length == Dist::Fixed { value: 1.0 }
                    && sides.iter().all(|&s| s == sides[0])
                    && periodic == Periodic::Xyz
                    && orientation == Orientation::Isotropic;
                if paper {
                    // The paper's ensemble, with its own checks and messages.
                    return Ok(Rods::from(RodParams::new(gamma, sides[0], density)?));
                }
                if !gamma.is_finite() || gamma < MIN_GAMMA {
                    return Err(Error::Parameter(format!(
                        "gamma must be at least {MIN_GAMMA} (a rod at least as long as it is wide), got {}",
                        rgc::error::short(gamma)
                    )));
                }
                Dist::Fixed {
                    value: length.mean() / (2.0 * gamma),
                }
            }
            (None, None) => {
                return Err(Error::Parameter(
                    "generated rods need --gamma or --radius".into(),
                ));
            }
        };
        let ensemble = Ensemble {
            domain: Domain { sides, periodic },
            density,
            length,
            radius,
            orientation,
        };
        ensemble.check()?;
        Ok(Rods::Generated(ensemble))
    }
}

/// One number for all three axes, or three; none when not given.
fn three(v: &[f64], flag: &str, what: &str) -> Result<Option<[f64; 3]>> {
    match v[..] {
        [] => Ok(None),
        [a] => Ok(Some([a; 3])),
        [x, y, z] => Ok(Some([x, y, z])),
        _ => Err(Error::Parameter(format!(
            "{flag} takes {what}, got {} numbers",
            v.len()
        ))),
    }
}

/// One rod system and how to compress it (`sample`, `render`).
#[derive(Args)]
pub struct SystemArgs {
    #[command(flatten)]
    pub rods: RodsArgs,
    #[command(flatten)]
    pub engine: EngineArgs,
    /// Spanning definition: `wrap` (a cluster meets its own periodic image; along walls, joins them) or `faces` (`solid` is for truth studies and `rgc truth` only).
    #[arg(long, value_enum, default_value_t = Criterion::Wrap)]
    pub criterion: Criterion,
    /// Also decide the exact rigidity of the whole system: its true rigid clusters go into the report and --save-vtk, and `render` colours them instead of the bodies.
    #[arg(long)]
    pub truth: bool,
}

impl SystemArgs {
    /// The sample these arguments ask for, checked.
    pub fn options(&self) -> Result<SampleOptions> {
        self.criterion
            .check_clusters("a sample's contacts and bodies")?;
        Ok(SampleOptions {
            rods: self.rods.rods()?,
            seed: self.engine.seed,
            runs: self.engine.runs as usize,
            rules: self.engine.rules.rules,
            criterion: self.criterion,
            truth: self.truth,
        })
    }
}

/// What a threshold study is measured on: `threshold`, and the variants of
/// `compare` and `tradeoff`.
#[derive(Args)]
pub struct StudyArgs {
    /// Aspect ratio l / (2r).
    #[arg(long, allow_hyphen_values = true, default_value_t = 23.0)]
    pub gamma: f64,
    /// Box sides, in rod lengths, comma-separated (at least 3 for the scaling fit).
    #[arg(
        long,
        value_delimiter = ',',
        action = ArgAction::Set,
        allow_hyphen_values = true,
        default_value = "5,6,7,8,10"
    )]
    pub boxes: Vec<f64>,
    /// Monte Carlo sequences (seeded random orders of rods) per box.
    // `--realizations` is the old spelling, kept as a hidden alias for existing scripts.
    #[arg(long, alias = "realizations", default_value_t = 200)]
    pub sequences: u64,
    /// Spanning definition: `wrap` (a cluster meets its own periodic image), `faces`, or, for `--kind truth` only, `solid` (the strain rank reaches the strains of the box; the contact critical number is then the wrapping one).
    #[arg(long, value_enum, default_value_t = Criterion::Wrap)]
    pub criterion: Criterion,
    /// Seed of the rods (sequence seeds derive from it, the box and the index).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Bootstrap resamples for the intervals.
    #[arg(long, default_value_t = 200)]
    pub bootstrap: usize,
}

impl StudyArgs {
    /// The study these arguments describe, with [`StudySpec::new`]'s defaults for the rest.
    pub fn spec(&self) -> StudySpec {
        StudySpec::new(
            self.gamma,
            self.boxes.clone(),
            self.sequences,
            self.criterion,
            self.seed,
        )
    }
}

/// What the variants of `compare` and `tradeoff` share; their studies are
/// smaller by default than `threshold`'s, since they run several.
#[derive(Args)]
#[command(
    mut_arg("boxes", |a| a.default_value("4,5,6")),
    mut_arg("sequences", |a| a.default_value("100")),
)]
pub struct VariantArgs {
    #[command(flatten)]
    pub study: StudyArgs,
    #[command(flatten)]
    pub memory: MemoryArgs,
    /// Where the studies go: one directory each, named by every parameter of its study; rerun to resume.
    #[arg(long, default_value = "results/studies")]
    pub studies: PathBuf,
    /// Where the comparison's JSON, Markdown, CSV and charts go.
    #[arg(long, default_value = "results")]
    pub results: PathBuf,
    /// No progress bars.
    #[arg(long)]
    pub quiet: bool,
    /// Print the experiment as one JSON object (as written to `--results`) and nothing else.
    #[arg(long)]
    pub json: bool,
    /// Replace the experiment's files in `--results` even when another experiment (other gamma, boxes, sequences, variants ...) made them.
    #[arg(long)]
    pub force: bool,
}

/// The extended motif sets that `compare` and `bias` measure.
#[derive(Args)]
pub struct ExtendedArgs {
    /// The extended motif rule files.
    #[arg(
        long = "extended",
        value_delimiter = ',',
        default_value = "motifs/rods-6.json,motifs/rods-8.json,motifs/mixed-4.json"
    )]
    pub files: Vec<PathBuf>,
}

/// The sequences of truth studies a measurement takes (`rgc locality`,
/// `rgc stiffening`), and where it keeps one line per sequence.
#[derive(Args)]
pub struct MeasuredArgs {
    /// Truth study directories (`rgc threshold --kind truth`), finished or in progress.
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Boxes to measure [default: every box of each study].
    #[arg(long, value_delimiter = ',')]
    pub boxes: Vec<f64>,
    /// The first this many sequences of each box.
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u64).range(1..))]
    pub sequences: u64,
    /// The measurement's directory: its spec and one line per sequence (rerun to resume).
    #[arg(long)]
    pub out: PathBuf,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

impl MeasuredArgs {
    /// The study directories as given, for a spec.
    pub fn studies(&self) -> Vec<String> {
        self.dirs.iter().map(|d| d.display().to_string()).collect()
    }
}
