//! Rods, boxes and checked rod systems: the types every other part of
//! `rods` builds on.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

use crate::error::{four, short};
use crate::{Error, Result};

/// Largest number of rods a system may hold (about 400 bytes each through the
/// whole pipeline), so a typo in the density fails fast instead of swapping.
pub const MAX_RODS: usize = 50_000_000;

/// Smallest aspect ratio accepted: a rod at least as long as it is wide
/// (`l >= 2r`). Below it the two caps have more surface than the cylinder
/// (`4 pi r^2 > 2 pi r l` exactly when `gamma < 1`), so most contacts sit on
/// a cap, where every contact meets the core at the same end point
/// (`s = ±1/2`): the model of a rod as a line touched at distinct points
/// along it (MODEL §2, §3) no longer describes the particle.
pub const MIN_GAMMA: f64 = 1.0;

/// The physical parameters of a rod system.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RodParams {
    /// Aspect ratio `gamma = l / (2 r)`.
    pub gamma: f64,
    /// Side `L` of the periodic cubic box.
    pub box_len: f64,
    /// Number density `rho = N / L^3`.
    pub density: f64,
}

impl RodParams {
    /// Validates the parameters: all finite and positive, `gamma` at least
    /// [`MIN_GAMMA`], the box large enough (`L > 2 (l + 2r)`) that two rods
    /// touch through at most one image, and at least one rod.
    pub fn new(gamma: f64, box_len: f64, density: f64) -> Result<Self> {
        for (name, v) in [("gamma", gamma), ("box", box_len), ("density", density)] {
            if !v.is_finite() || v <= 0.0 {
                return Err(Error::Parameter(format!(
                    "{name} must be a positive finite number, got {}",
                    short(v)
                )));
            }
        }
        if gamma < MIN_GAMMA {
            return Err(Error::Parameter(format!(
                "gamma must be at least {MIN_GAMMA} (a rod at least as long as it is wide), got {}",
                short(gamma)
            )));
        }
        let p = RodParams {
            gamma,
            box_len,
            density,
        };
        let min_box = 2.0 * (1.0 + 2.0 * p.radius());
        if box_len <= min_box {
            return Err(Error::Parameter(format!(
                "box {} is too small: it must exceed two rod lengths, 2(l + 2r) = {min_box:.4}, \
                 so that two rods touch through at most one periodic image",
                short(box_len)
            )));
        }
        let n = density * box_len.powi(3);
        if n >= MAX_RODS as f64 {
            return Err(Error::Parameter(format!(
                "density {} in a box of side {} means {n:.3e} rods, more than the {MAX_RODS} that fit in memory",
                short(density),
                short(box_len)
            )));
        }
        if p.n_rods() == 0 {
            return Err(Error::Parameter(format!(
                "density {} in a box of side {} gives no rods (N = round(rho L^3) = 0)",
                short(density),
                short(box_len)
            )));
        }
        Ok(p)
    }

    /// Rod radius `r = 1 / (2 gamma)`.
    pub fn radius(&self) -> f64 {
        0.5 / self.gamma
    }

    /// Number of rods, `N = round(rho L^3)`.
    pub fn n_rods(&self) -> usize {
        (self.density * self.box_len.powi(3)).round() as usize
    }

    /// Isotropic excluded volume of two spherocylinders (Onsager, Philipse):
    /// `V_ex = (4 pi / 3) D^3 + 2 pi D^2 + (pi / 2) D` with `D = 2r`, `l = 1`.
    pub fn excluded_volume(&self) -> f64 {
        excluded_volume(self.gamma)
    }

    /// Expected mean contact number `rho V_ex (N - 1) / N`, exact in expectation.
    pub fn expected_c0(&self) -> f64 {
        let n = self.n_rods() as f64;
        if n < 1.0 {
            return 0.0;
        }
        self.density * self.excluded_volume() * (n - 1.0) / n
    }
}

/// Isotropic excluded volume of two rods of aspect ratio `gamma` (see [`RodParams::excluded_volume`]).
pub fn excluded_volume(gamma: f64) -> f64 {
    let d = 1.0 / gamma;
    4.0 * PI / 3.0 * d.powi(3) + 2.0 * PI * d * d + PI / 2.0 * d
}

/// Excluded volume of two spherocylinders of core lengths `l` and radii `r`,
/// averaged over isotropic orientations: `V_a + V_b + (M_a S_b + M_b S_a) / 4 pi`
/// (the Isihara–Kihara formula for convex bodies), with volume
/// `V = pi r^2 l + 4/3 pi r^3`, surface `S = 2 pi r l + 4 pi r^2` and integral of
/// mean curvature `M = pi l + 4 pi r`. Equal unit rods give [`excluded_volume`].
pub fn pair_excluded_volume(a: &Rod, b: &Rod) -> f64 {
    let (va, sa, ma) = a.measures();
    let (vb, sb, mb) = b.measures();
    va + vb + (ma * sb + mb * sa) / (4.0 * PI)
}

/// One rod: the centre of its core segment, the unit vector along it, the
/// core's length and the radius. The core is `center + s * axis` for `s` in
/// `[-length / 2, length / 2]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rod {
    pub center: Vector3<f64>,
    pub axis: Vector3<f64>,
    pub length: f64,
    pub radius: f64,
}

impl Rod {
    /// A rod with its axis normalized. An axis already of unit length to
    /// rounding is kept as it is, so that rods written out and read back are
    /// the same to the last bit.
    pub fn new(center: Vector3<f64>, axis: Vector3<f64>, length: f64, radius: f64) -> Self {
        let unit = (axis.norm_squared() - 1.0).abs() <= 4.0 * f64::EPSILON;
        Rod {
            center,
            axis: if unit { axis } else { axis.normalize() },
            length,
            radius,
        }
    }

    /// The point of the axis at arc length `s` from the centre (`|s| <= length / 2` on the core).
    pub fn at(&self, s: f64) -> Vector3<f64> {
        self.center + self.axis * s
    }

    /// Volume, surface area and integral of mean curvature of the spherocylinder.
    fn measures(&self) -> (f64, f64, f64) {
        let (l, r) = (self.length, self.radius);
        (
            PI * r * r * (l + 4.0 * r / 3.0),
            2.0 * PI * r * (l + 2.0 * r),
            PI * (l + 4.0 * r),
        )
    }

    /// Why this rod cannot be modelled, if it cannot: [`Rod::malformed`],
    /// or [`Rod::too_wide`]. Checked on every rod as it arrives (a file's
    /// line, a drawn rod, Python's arrays), before a wall cuts its core.
    pub fn defect(&self) -> Option<String> {
        self.malformed().or_else(|| self.too_wide())
    }

    /// Wider than long: an aspect ratio `l / (2r)` below [`MIN_GAMMA`], the
    /// rule `--gamma` follows, for a rod however it is given.
    pub fn too_wide(&self) -> Option<String> {
        let (l, r) = (self.length, self.radius);
        // As given where that is short (a file's 0.6), else four decimals (a drawn 0.2219).
        let shown = |x: f64| {
            let given = short(x);
            if given.contains('e') { four(x) } else { given }
        };
        (l < 2.0 * MIN_GAMMA * r).then(|| {
            format!(
                "radius {} is more than half the length {}: the rod is wider than long \
                 (aspect ratio l / (2r) = {}, at least {MIN_GAMMA} is needed)",
                shown(r),
                shown(l),
                four(l / (2.0 * r))
            )
        })
    }

    /// A non-finite number, a zero direction, or a length or radius that is
    /// not positive.
    pub fn malformed(&self) -> Option<String> {
        let named = [
            ("x", self.center.x),
            ("y", self.center.y),
            ("z", self.center.z),
            ("direction x", self.axis.x),
            ("direction y", self.axis.y),
            ("direction z", self.axis.z),
            ("length", self.length),
            ("radius", self.radius),
        ];
        if let Some((name, v)) = named.iter().find(|(_, v)| !v.is_finite()) {
            return Some(format!("{name} is {v}, not a finite number"));
        }
        if self.axis.norm_squared() == 0.0 {
            return Some("the direction is the zero vector".into());
        }
        if self.length <= 0.0 {
            return Some(format!("length {} is not positive", self.length));
        }
        if self.radius <= 0.0 {
            return Some(format!("radius {} is not positive", self.radius));
        }
        None
    }
}

/// `axis` rotated by the quaternion `(w, x, y, z)` (HOOMD's and LAMMPS's
/// order, scalar first), normalized first: how simulations that store
/// orientations as quaternions give a rod's axis (the body axis rotated
/// into the lab frame). `None` when `q` is not a rotation (zero or not
/// finite).
pub fn rotate(q: [f64; 4], axis: [f64; 3]) -> Option<Vector3<f64>> {
    let (w, v) = (q[0], [q[1], q[2], q[3]]);
    let norm = (w * w + v.iter().map(|x| x * x).sum::<f64>()).sqrt();
    if !(norm.is_finite() && norm > 0.0) {
        return None;
    }
    let (w, v) = (w / norm, Vector3::from(v.map(|x| x / norm)));
    let a = Vector3::from(axis);
    // a' = a + 2w (v x a) + 2 v x (v x a)
    let c = v.cross(&a);
    let cc = v.cross(&c);
    Some(a + 2.0 * w * c + 2.0 * cc)
}

/// Which axes of a box are periodic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Periodic {
    /// All three (the paper's box).
    #[default]
    Xyz,
    /// x and y: a slab with walls at `z = 0` and `z = L_z`.
    Xy,
    /// None: a closed box with six walls.
    None,
}

impl Periodic {
    /// Per axis, whether it is periodic.
    pub fn axes(self) -> [bool; 3] {
        match self {
            Periodic::Xyz => [true; 3],
            Periodic::Xy => [true, true, false],
            Periodic::None => [false; 3],
        }
    }

    /// The name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            Periodic::Xyz => "xyz",
            Periodic::Xy => "xy",
            Periodic::None => "none",
        }
    }
}

/// The box `[0, L_x) x [0, L_y) x [0, L_z)` and which of its axes are
/// periodic. On a periodic axis a rod leaving one face comes back through
/// the other; on the others the faces are walls that cores do not cross
/// (see [`Domain::cut`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Domain {
    pub sides: [f64; 3],
    pub periodic: Periodic,
}

/// How far, relative to `1 + L`, a core may reach past a wall and still count
/// as inside: rounding, not geometry (the contact grid allows for as much).
const WALL_SLACK: f64 = 1e-10;

/// How a rod meets the walls of a box, see [`Domain::cut`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cut {
    /// Its core lies inside: kept as it is.
    Whole(Rod),
    /// Its core crosses a wall: the part inside, with its length and centre.
    Cut(Rod),
    /// No part of its core is inside the box (or its centre is outside a periodic side).
    Outside,
}

impl Domain {
    /// The paper's periodic cube of side `l`.
    pub fn cube(l: f64) -> Self {
        Domain {
            sides: [l; 3],
            periodic: Periodic::Xyz,
        }
    }

    /// A checked box: every side positive and finite.
    pub fn new(sides: [f64; 3], periodic: Periodic) -> Result<Self> {
        if let Some(s) = sides.iter().find(|s| !s.is_finite() || **s <= 0.0) {
            return Err(Error::Parameter(format!(
                "box sides must be positive finite numbers, got {}",
                short(*s)
            )));
        }
        Ok(Domain { sides, periodic })
    }

    pub fn volume(&self) -> f64 {
        self.sides.iter().product()
    }

    /// Whether axis `k` is periodic.
    pub fn wraps(&self, k: usize) -> bool {
        self.periodic.axes()[k]
    }

    /// The box as `LX,LY,LZ`, or `L` for a cube (each side short, as in
    /// every message).
    pub fn describe(&self) -> String {
        let [x, y, z] = self.sides.map(short);
        if x == y && y == z {
            x
        } else {
            format!("{x},{y},{z}")
        }
    }

    /// Places a rod in the box. A centre must lie in `[0, L)` along a
    /// periodic axis; along a wall axis the core is cut to the box, so that
    /// a sample cut out of a larger material keeps the parts of rods it
    /// holds. The caps of a cut core stay round, so a rod touching a wall
    /// may poke out of it by its radius.
    pub fn cut(&self, rod: &Rod) -> Cut {
        let half = 0.5 * rod.length;
        // The part of the core inside the walls, and inside them widened by
        // rounding: a core that reaches past a wall by rounding only (a rod
        // cut before, written out and read back) is whole.
        let (mut lo, mut hi) = (-half, half);
        let (mut lo_w, mut hi_w) = (-half, half);
        for k in 0..3 {
            let (c, u, l) = (rod.center[k], rod.axis[k], self.sides[k]);
            if self.wraps(k) {
                if !(0.0..l).contains(&c) {
                    return Cut::Outside;
                }
                continue;
            }
            if u == 0.0 {
                if !(0.0..=l).contains(&c) {
                    return Cut::Outside;
                }
                continue;
            }
            let tol = WALL_SLACK * (1.0 + l);
            let (a, b) = ((0.0 - c) / u, (l - c) / u);
            lo = lo.max(a.min(b));
            hi = hi.min(a.max(b));
            let (a, b) = ((0.0 - tol - c) / u, (l + tol - c) / u);
            lo_w = lo_w.max(a.min(b));
            hi_w = hi_w.min(a.max(b));
        }
        if lo_w <= -half && hi_w >= half {
            return Cut::Whole(*rod);
        }
        if lo >= hi {
            return Cut::Outside;
        }
        let mut cut = *rod;
        cut.center = rod.at(0.5 * (lo + hi));
        for k in 0..3 {
            let (x, l) = (cut.center[k], self.sides[k]);
            cut.center[k] = if self.wraps(k) {
                // The centre moved along the rod, maybe through a periodic face.
                wrap(x, l)
            } else {
                // A centre computed on the wall may round just outside it.
                x.clamp(0.0, l)
            };
        }
        cut.length = hi - lo;
        Cut::Cut(cut)
    }

    /// Whether an end of the rod's core lies on a wall (to rounding), as
    /// the ends of a core [`Domain::cut`] has cut do.
    fn ends_at_wall(&self, rod: &Rod) -> bool {
        [-0.5, 0.5].iter().any(|&t| {
            let end = rod.at(t * rod.length);
            (0..3).filter(|&k| !self.wraps(k)).any(|k| {
                let (x, l) = (end[k], self.sides[k]);
                let tol = WALL_SLACK * (1.0 + l);
                x.abs() <= tol || (x - l).abs() <= tol
            })
        })
    }
}

/// `x mod l` in `[0, l)` (0 where rounding would give `l`).
pub fn wrap(x: f64, l: f64) -> f64 {
    let y = x - (x / l).floor() * l;
    if (0.0..l).contains(&y) { y } else { 0.0 }
}

/// The rod of largest reach `l + 2r` when some periodic side of `domain` is
/// not longer than twice it (so two rods could touch through two images):
/// that rod, the axis, and `2 (l + 2r)`.
pub(super) fn too_long(domain: &Domain, rods: &[Rod]) -> Option<(usize, usize, f64)> {
    let (rod, reach) = rods
        .iter()
        .map(|r| r.length + 2.0 * r.radius)
        .enumerate()
        .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
    (0..3)
        .find(|&k| domain.wraps(k) && domain.sides[k] <= 2.0 * reach)
        .map(|k| (rod, k, 2.0 * reach))
}

/// A box of rods.
#[derive(Clone, Debug)]
pub struct RodSystem {
    pub domain: Domain,
    pub rods: Vec<Rod>,
}

impl RodSystem {
    /// A checked system: every rod modelled ([`Rod::defect`]; a core cut at
    /// a wall may be shorter than it is wide) and inside the
    /// box (a centre in `[0, L)` along periodic axes, a core within the walls
    /// on the others: [`Domain::cut`] them first), no rod given twice (the
    /// same centre and axis line), and every periodic side longer than two
    /// reaches of the largest rods, `L > 2 (l_max + 2 r_max)`, so that two rods
    /// touch through at most one image. Axes are normalized.
    pub fn new(domain: Domain, rods: Vec<Rod>) -> Result<Self> {
        Self::checked(domain, rods, |i| format!("rod {i}")).map_err(|(rod, why)| match rod {
            Some(i) => Error::Parameter(format!("rod {i}: {why}")),
            None => Error::Parameter(why),
        })
    }

    /// [`RodSystem::new`] that says which rod is at fault (`Some` of its
    /// index) or that the fault is the whole system's (`None`), with the
    /// reason; `name` names a rod by its index in the reason.
    pub fn checked(
        domain: Domain,
        rods: Vec<Rod>,
        name: impl Fn(usize) -> String,
    ) -> std::result::Result<Self, (Option<usize>, String)> {
        let domain =
            Domain::new(domain.sides, domain.periodic).map_err(|e| (None, e.to_string()))?;
        if rods.len() >= MAX_RODS {
            return Err((
                None,
                format!(
                    "{} rods, more than the {MAX_RODS} that fit in memory",
                    rods.len()
                ),
            ));
        }
        let fault = |rod: usize, reason: String| (Some(rod), reason);
        let mut seen = rustc_hash::FxHashMap::default();
        let mut out = Vec::with_capacity(rods.len());
        for (i, rod) in rods.into_iter().enumerate() {
            if let Some(reason) = rod.malformed() {
                return Err(fault(i, reason));
            }
            let rod = Rod::new(rod.center, rod.axis, rod.length, rod.radius);
            // A core cut at a wall may be shorter than it is wide; the rod
            // it was cut from was checked whole.
            if let Some(reason) = rod.too_wide().filter(|_| !domain.ends_at_wall(&rod)) {
                return Err(fault(i, reason));
            }
            match domain.cut(&rod) {
                Cut::Whole(_) => {}
                Cut::Cut(_) => {
                    return Err(fault(
                        i,
                        "the core crosses a wall of the box (cut it first, as reading a file does)"
                            .into(),
                    ));
                }
                Cut::Outside => {
                    return Err(fault(
                        i,
                        format!(
                            "centre ({}, {}, {}) is outside the box {}",
                            rod.center.x,
                            rod.center.y,
                            rod.center.z,
                            domain.describe()
                        ),
                    ));
                }
            }
            // The axis line up to its sign, so that a rod given twice with
            // its direction reversed is caught too.
            let sign = if rod
                .axis
                .iter()
                .find(|&&u| u != 0.0)
                .is_some_and(|&u| u < 0.0)
            {
                -1.0
            } else {
                1.0
            };
            // `+ 0.0` turns -0.0 into 0.0: the two differ bit for bit, and a
            // reversed axis with a zero component would otherwise slip through.
            let key = [rod.center, rod.axis * sign].map(|v| v.map(|u| (u + 0.0).to_bits()));
            if let Some(first) = seen.insert(key, i) {
                return Err(fault(
                    i,
                    format!(
                        "the same rod as {} (same centre and axis line)",
                        name(first)
                    ),
                ));
            }
            out.push(rod);
        }
        if let Some((_, k, limit)) = too_long(&domain, &out) {
            return Err((
                None,
                format!(
                    "box side {} along {} is too small: a periodic side must exceed two reaches \
                     of the largest rods, 2 (l + 2r) = {}, so that two rods touch through at most one image",
                    short(domain.sides[k]),
                    ["x", "y", "z"][k],
                    four(limit),
                ),
            ));
        }
        Ok(RodSystem { domain, rods: out })
    }

    pub fn len(&self) -> usize {
        self.rods.len()
    }

    pub fn is_empty(&self) -> bool {
        self.rods.is_empty()
    }

    /// Rods per unit volume.
    pub fn density(&self) -> f64 {
        self.len() as f64 / self.domain.volume()
    }

    /// The largest radius (0 for no rods).
    pub fn max_radius(&self) -> f64 {
        self.rods.iter().map(|r| r.radius).fold(0.0, f64::max)
    }

    /// The largest core length (0 for no rods).
    pub fn max_length(&self) -> f64 {
        self.rods.iter().map(|r| r.length).fold(0.0, f64::max)
    }

    /// The expected mean contact number `2 E / N` of rods with these lengths
    /// and radii when their centres are uniform in a periodic box and their
    /// orientations isotropic: the pair average of the excluded volume over
    /// the volume, `(2 / (N V)) sum_{i<j} V_ex(i, j)`, in O(N) from sums of
    /// the rods' measures. Equal unit rods give `rho V_ex (N - 1) / N`.
    pub fn expected_isotropic_c0(&self) -> f64 {
        let n = self.len();
        if n < 2 {
            return 0.0;
        }
        let (mut sv, mut ss, mut sm, mut sms) = (0.0, 0.0, 0.0, 0.0);
        for r in &self.rods {
            let (v, s, m) = r.measures();
            sv += v;
            ss += s;
            sm += m;
            sms += m * s;
        }
        let nf = n as f64;
        // sum over ordered pairs i != j of V_ex(i, j).
        let ordered = 2.0 * (nf - 1.0) * sv + 2.0 * (sm * ss - sms) / (4.0 * PI);
        ordered / (nf * self.domain.volume())
    }
}
