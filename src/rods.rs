//! Random soft-core spherocylinders in a periodic cubic box (MODEL §1).
//!
//! Lengths are in units of the core length `l = 1`. Rods are generated one
//! after another from a single seeded stream with a fixed number of draws per
//! rod, so the first `n` rods of a system are exactly the `n`-rod system of the
//! same seed and box: one Monte Carlo sequence is a nested series of systems.

use nalgebra::Vector3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

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
                    "{name} must be a positive finite number, got {v}"
                )));
            }
        }
        if gamma < MIN_GAMMA {
            return Err(Error::Parameter(format!(
                "gamma must be at least {MIN_GAMMA} (a rod at least as long as it is wide), got {gamma}"
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
                "box {box_len} is too small: it must exceed two rod lengths, 2(l + 2r) = {min_box:.4}, \
                 so that two rods touch through at most one periodic image"
            )));
        }
        let n = density * box_len.powi(3);
        if n >= MAX_RODS as f64 {
            return Err(Error::Parameter(format!(
                "density {density} in a box of side {box_len} means {n:.3e} rods, more than the {MAX_RODS} that fit in memory"
            )));
        }
        if p.n_rods() == 0 {
            return Err(Error::Parameter(format!(
                "density {density} in a box of side {box_len} gives no rods (N = round(rho L^3) = 0)"
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

/// One rod: the center of its core segment and the unit vector along it.
/// The core segment is `center + s * axis` for `s` in `[-1/2, 1/2]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rod {
    pub center: Vector3<f64>,
    pub axis: Vector3<f64>,
}

impl Rod {
    /// The point of the axis at parameter `s` (in units of `l`, `|s| <= 1/2` on the core).
    pub fn at(&self, s: f64) -> Vector3<f64> {
        self.center + self.axis * s
    }
}

/// A periodic box of rods.
#[derive(Clone, Debug)]
pub struct RodSystem {
    pub params: RodParams,
    pub rods: Vec<Rod>,
}

impl RodSystem {
    /// Places `params.n_rods()` rods with uniform centers in `[0, L)^3` and
    /// isotropic orientations, reproducibly from `seed`.
    pub fn generate(params: RodParams, seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let l = params.box_len;
        let rods = (0..params.n_rods())
            .map(|_| {
                let center = Vector3::new(
                    rng.random::<f64>() * l,
                    rng.random::<f64>() * l,
                    rng.random::<f64>() * l,
                );
                // Archimedes: z uniform in [-1, 1] and a uniform azimuth give a uniform direction.
                let z = 2.0 * rng.random::<f64>() - 1.0;
                let phi = 2.0 * PI * rng.random::<f64>();
                let rho = (1.0 - z * z).max(0.0).sqrt();
                let axis = Vector3::new(rho * phi.cos(), rho * phi.sin(), z);
                Rod { center, axis }
            })
            .collect();
        RodSystem { params, rods }
    }

    /// Builds a system from given rods (tests, files); axes are normalized.
    pub fn from_rods(params: RodParams, rods: Vec<Rod>) -> Self {
        let rods = rods
            .into_iter()
            .map(|r| Rod {
                center: r.center,
                axis: r.axis.normalize(),
            })
            .collect();
        RodSystem { params, rods }
    }

    pub fn len(&self) -> usize {
        self.rods.len()
    }

    pub fn is_empty(&self) -> bool {
        self.rods.is_empty()
    }

    /// Radius of every rod.
    pub fn radius(&self) -> f64 {
        self.params.radius()
    }

    /// Side of the periodic box.
    pub fn box_len(&self) -> f64 {
        self.params.box_len
    }
}
