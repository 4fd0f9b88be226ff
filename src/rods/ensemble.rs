//! Generated rod systems beyond the paper's: lengths and radii drawn from a
//! distribution, orientations aligned about a director, boxes of any shape
//! and periodicity.
//!
//! Every rod takes its draws from one seeded stream in a fixed order
//! (centre, orientation, length, radius), so the first `n` rods of a seed
//! are the `n`-rod system of that seed: sequences stay nested. A fixed length
//! or radius and the isotropic orientation draw exactly what the paper's
//! ensemble draws, so [`Ensemble::paper`] reproduces every earlier system bit
//! for bit.

use nalgebra::Vector3;
use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

use super::system::{Cut, Domain, MAX_RODS, Rod, RodParams, RodSystem, too_long};
use crate::error::{four, short};
use crate::{Error, Result};

/// A distribution of a positive size (length or radius).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Dist {
    /// Always this value (no draw).
    Fixed { value: f64 },
    /// Uniform on `[lo, hi]` (one draw).
    Uniform { lo: f64, hi: f64 },
    /// Lognormal with this mean and standard deviation (two draws, Box–Muller):
    /// `ln X ~ N(mu, sigma^2)` with `sigma^2 = ln(1 + sd^2 / mean^2)` and
    /// `mu = ln(mean) - sigma^2 / 2`.
    Lognormal { mean: f64, sd: f64 },
}

impl Dist {
    /// Parses `VALUE`, `uniform:LO,HI` or `lognormal:MEAN,SD`, checked.
    pub fn parse(text: &str) -> Result<Self> {
        let bad = |why: &str| {
            Error::Parameter(format!(
                "distribution {text:?}: {why} (expected VALUE, uniform:LO,HI or lognormal:MEAN,SD)"
            ))
        };
        let numbers = |s: &str| -> Result<Vec<f64>> {
            s.split(',')
                .map(|x| {
                    x.trim()
                        .parse::<f64>()
                        .map_err(|_| bad(&format!("{x:?} is not a number")))
                })
                .collect()
        };
        let d = match text.split_once(':') {
            None => Dist::Fixed {
                value: numbers(text)?
                    .first()
                    .copied()
                    .ok_or_else(|| bad("no value"))?,
            },
            Some((kind, rest)) => {
                let v = numbers(rest)?;
                let [a, b] = v[..] else {
                    return Err(bad("two numbers are needed"));
                };
                match kind {
                    "uniform" => Dist::Uniform { lo: a, hi: b },
                    "lognormal" => Dist::Lognormal { mean: a, sd: b },
                    _ => return Err(bad(&format!("unknown kind {kind:?}"))),
                }
            }
        };
        d.check().map_err(|why| bad(&why))?;
        Ok(d)
    }

    /// Why the distribution cannot give positive sizes, if it cannot.
    pub fn check(&self) -> std::result::Result<(), String> {
        let finite_positive = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!(
                    "{name} must be a positive finite number, got {}",
                    short(v)
                ))
            }
        };
        match *self {
            Dist::Fixed { value } => finite_positive("the value", value),
            Dist::Uniform { lo, hi } => {
                finite_positive("the lower end", lo)?;
                finite_positive("the upper end", hi)?;
                if lo > hi {
                    return Err(format!("the lower end {lo} exceeds the upper end {hi}"));
                }
                Ok(())
            }
            Dist::Lognormal { mean, sd } => {
                finite_positive("the mean", mean)?;
                finite_positive("the standard deviation", sd)
            }
        }
    }

    /// The distribution's mean.
    pub fn mean(&self) -> f64 {
        match *self {
            Dist::Fixed { value } => value,
            Dist::Uniform { lo, hi } => 0.5 * (lo + hi),
            Dist::Lognormal { mean, .. } => mean,
        }
    }

    /// The largest value a draw can take; for the lognormal, which has no
    /// largest value, its mean (the drawn rods are checked instead).
    fn bound(&self) -> f64 {
        match *self {
            Dist::Fixed { value } => value,
            Dist::Uniform { hi, .. } => hi,
            Dist::Lognormal { mean, .. } => mean,
        }
    }

    fn log_params(&self) -> (f64, f64) {
        let Dist::Lognormal { mean, sd } = *self else {
            return (self.mean().ln(), 0.0);
        };
        let s2 = (1.0 + (sd / mean).powi(2)).ln();
        (mean.ln() - 0.5 * s2, s2.sqrt())
    }

    fn draw(&self, rng: &mut impl Rng) -> f64 {
        match *self {
            Dist::Fixed { value } => value,
            Dist::Uniform { lo, hi } => lo + (hi - lo) * rng.random::<f64>(),
            Dist::Lognormal { .. } => {
                let (mu, sigma) = self.log_params();
                // Box–Muller; 1 - u keeps the logarithm finite.
                let (u, v) = (1.0 - rng.random::<f64>(), rng.random::<f64>());
                let z = (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos();
                (mu + sigma * z).exp()
            }
        }
    }
}

/// How rod axes are oriented.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Orientation {
    /// Uniform on the sphere (the paper's).
    Isotropic,
    /// Watson (Dimroth–Watson) distribution about `director`: the density of
    /// `t = cos(angle to the director)` is proportional to `exp(kappa t^2)`,
    /// azimuth uniform, with `kappa` chosen so that the nematic order
    /// parameter `S = <P2(t)> = <(3 t^2 - 1) / 2>` is `order`. `order` is in
    /// `(-1/2, 1)`: positive aligns rods along the director, negative lays
    /// them in the plane across it, 0 is isotropic.
    Aligned { order: f64, director: [f64; 3] },
}

impl Orientation {
    /// The Watson concentration `kappa` whose order parameter is `order`.
    fn kappa(order: f64) -> f64 {
        // S(kappa) increases from -1/2 to 1; bisection on a bracket that holds
        // every order parameter the check admits.
        let (mut lo, mut hi) = (-1e4, 1e4);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if watson_order(mid) < order {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    fn check(&self) -> std::result::Result<(), String> {
        let Orientation::Aligned { order, director } = *self else {
            return Ok(());
        };
        if !(order.is_finite() && order > -0.499 && order < 0.999) {
            return Err(format!(
                "the nematic order parameter must lie in (-0.499, 0.999), got {}",
                short(order)
            ));
        }
        let d = Vector3::from(director);
        if !d.iter().all(|x| x.is_finite()) || d.norm_squared() == 0.0 {
            return Err(format!("the director {director:?} is not a direction"));
        }
        Ok(())
    }
}

/// `<P2(t)>` under the density `exp(kappa t^2)` on `[0, 1]`, by composite
/// Simpson quadrature (smooth integrand; 2048 panels give about 1e-12).
fn watson_order(kappa: f64) -> f64 {
    let n = 2048;
    let h = 1.0 / n as f64;
    // Scaled by exp(-max(kappa, 0)) so that large kappa does not overflow.
    let shift = kappa.max(0.0);
    let (mut z, mut m) = (0.0, 0.0);
    for i in 0..=n {
        let t = i as f64 * h;
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        let f = (kappa * t * t - shift).exp();
        z += w * f;
        m += w * f * 0.5 * (3.0 * t * t - 1.0);
    }
    m / z
}

/// Draws `t` in `[0, 1]` with density proportional to `exp(kappa t^2)`, exactly, by rejection.
fn watson_cos(kappa: f64, rng: &mut impl Rng) -> f64 {
    loop {
        if kappa > 1e-9 {
            // Proposal exp(kappa t) >= exp(kappa t^2) on [0, 1], by its inverse
            // distribution function; acceptance exp(kappa (t^2 - t)) is at least 1/2 on average.
            let u = rng.random::<f64>();
            let t = 1.0 + (u + (1.0 - u) * (-kappa).exp()).ln() / kappa;
            let t = t.clamp(0.0, 1.0);
            if rng.random::<f64>() <= (kappa * (t * t - t)).exp() {
                return t;
            }
        } else if kappa < -1e-9 {
            // Proposal |N(0, 1 / (2 |kappa|))|, which is exactly the density
            // on [0, inf): keep draws in [0, 1].
            let (u, v) = (1.0 - rng.random::<f64>(), rng.random::<f64>());
            let z = (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos();
            let t = (z / (2.0 * -kappa).sqrt()).abs();
            if t <= 1.0 {
                return t;
            }
        } else {
            return rng.random::<f64>();
        }
    }
}

/// A recipe for random rod systems: the box, the density and how sizes and
/// orientations are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Ensemble {
    pub domain: Domain,
    /// Rods per unit volume: `N = round(density * volume)`.
    pub density: f64,
    pub length: Dist,
    pub radius: Dist,
    pub orientation: Orientation,
}

impl Ensemble {
    /// The paper's ensemble for `params`: unit rods of radius `1 / (2 gamma)`,
    /// isotropic, in a periodic cube.
    pub fn paper(params: RodParams) -> Self {
        Ensemble {
            domain: Domain::cube(params.box_len),
            density: params.density,
            length: Dist::Fixed { value: 1.0 },
            radius: Dist::Fixed {
                value: params.radius(),
            },
            orientation: Orientation::Isotropic,
        }
    }

    /// Checks the recipe before any work: sizes positive, the order parameter
    /// in range, at least one rod and not too many, and every periodic side
    /// longer than two reaches of the largest rods it can draw (of rods of
    /// the mean size, for a lognormal: [`Ensemble::generate`] checks the
    /// rods it drew).
    pub fn check(&self) -> Result<()> {
        let domain = Domain::new(self.domain.sides, self.domain.periodic)?;
        self.length
            .check()
            .map_err(|e| Error::Parameter(format!("length: {e}")))?;
        self.radius
            .check()
            .map_err(|e| Error::Parameter(format!("radius: {e}")))?;
        self.orientation.check().map_err(Error::Parameter)?;
        let rho = self.density;
        if !rho.is_finite() || rho <= 0.0 {
            return Err(Error::Parameter(format!(
                "density must be a positive finite number, got {}",
                short(rho)
            )));
        }
        let n = rho * domain.volume();
        if n >= MAX_RODS as f64 {
            return Err(Error::Parameter(format!(
                "density {} in a box of volume {} means {n:.3e} rods, more than the {MAX_RODS} that fit in memory",
                short(rho),
                short(domain.volume())
            )));
        }
        if self.n_rods() == 0 {
            return Err(Error::Parameter(format!(
                "density {} in a box of volume {} gives no rods",
                short(rho),
                short(domain.volume())
            )));
        }
        let mean = Rod::new(
            Vector3::zeros(),
            Vector3::x(),
            self.length.mean(),
            self.radius.mean(),
        );
        if let Some(why) = mean.too_wide() {
            return Err(Error::Parameter(format!("rods of the mean size: {why}")));
        }
        let reach = 2.0 * (self.length.bound() + 2.0 * self.radius.bound());
        for k in (0..3).filter(|&k| domain.wraps(k)) {
            if domain.sides[k] <= reach {
                return Err(Error::Parameter(format!(
                    "box side {} along {} is too small: a periodic side must exceed two reaches of the \
                     largest rods drawn, 2 (l + 2r) = {reach:.4}, so that two rods touch through at most one image",
                    short(domain.sides[k]),
                    ["x", "y", "z"][k]
                )));
            }
        }
        Ok(())
    }

    /// Number of rods, `N = round(density * volume)`.
    pub fn n_rods(&self) -> usize {
        (self.density * self.domain.volume()).round() as usize
    }

    /// The system of `seed`, with rods cut at the walls of non-periodic axes
    /// ([`Domain::cut`]; a centre is drawn inside the box, so some of each
    /// rod always is). Call [`Ensemble::check`] first. Fails when a drawn rod
    /// is too long for a periodic side (`L > 2 (l + 2 r)` for every rod),
    /// which only a lognormal's tail can draw.
    pub fn generate(&self, seed: u64) -> Result<RodSystem> {
        let (system, wide) = self.draw(seed);
        if let Some((i, why)) = wide {
            return Err(Error::Parameter(format!(
                "rod {i} was drawn too wide: {why}; use narrower distributions of the length and radius"
            )));
        }
        if let Some((i, k, limit)) = too_long(&self.domain, &system.rods) {
            let r = &system.rods[i];
            return Err(Error::Parameter(format!(
                "rod {i} was drawn with length {} and radius {}: the periodic side {} along {} must exceed \
                 2 (l + 2r) = {}, so that two rods touch through at most one image; use a larger box \
                 or a narrower distribution",
                short(r.length),
                short(r.radius),
                short(self.domain.sides[k]),
                ["x", "y", "z"][k],
                four(limit),
            )));
        }
        Ok(system)
    }

    /// The rods of `seed`, unchecked but for the first rod drawn wider than
    /// long (before a wall cuts it), with why.
    pub(super) fn draw(&self, seed: u64) -> (RodSystem, Option<(usize, String)>) {
        let mut wide = None;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let sides = self.domain.sides;
        let aligned = match self.orientation {
            Orientation::Isotropic => None,
            Orientation::Aligned { order, director } => {
                let d = Vector3::from(director).normalize();
                // Any unit vector across the director, then the third by a cross product.
                let helper = if d.x.abs() < 0.9 {
                    Vector3::x()
                } else {
                    Vector3::y()
                };
                let e1 = d.cross(&helper).normalize();
                Some((Orientation::kappa(order), d, e1, d.cross(&e1)))
            }
        };
        let rods = (0..self.n_rods())
            .map(|i| {
                let center = Vector3::new(
                    rng.random::<f64>() * sides[0],
                    rng.random::<f64>() * sides[1],
                    rng.random::<f64>() * sides[2],
                );
                let axis = match aligned {
                    None => {
                        // Archimedes: z uniform in [-1, 1] and a uniform azimuth give a uniform direction.
                        let z = 2.0 * rng.random::<f64>() - 1.0;
                        let phi = 2.0 * PI * rng.random::<f64>();
                        let rho = (1.0 - z * z).max(0.0).sqrt();
                        Vector3::new(rho * phi.cos(), rho * phi.sin(), z)
                    }
                    Some((kappa, d, e1, e2)) => {
                        let t = watson_cos(kappa, &mut rng);
                        let phi = 2.0 * PI * rng.random::<f64>();
                        let s = (1.0 - t * t).max(0.0).sqrt();
                        // Head and tail are the same rod, so t >= 0 suffices.
                        d * t + (e1 * phi.cos() + e2 * phi.sin()) * s
                    }
                };
                let length = self.length.draw(&mut rng);
                let radius = self.radius.draw(&mut rng);
                let rod = Rod {
                    center,
                    axis,
                    length,
                    radius,
                };
                if wide.is_none() {
                    wide = rod.too_wide().map(|why| (i, why));
                }
                match self.domain.cut(&rod) {
                    Cut::Whole(r) | Cut::Cut(r) => r,
                    // A centre drawn in [0, L) is inside; rounding at a side
                    // equal to the box cannot move it out.
                    Cut::Outside => rod,
                }
            })
            .collect();
        let system = RodSystem {
            domain: self.domain,
            rods,
        };
        (system, wide)
    }
}

impl RodSystem {
    /// The paper's ensemble (MODEL §1): `params.n_rods()` unit rods of
    /// radius `1 / (2 gamma)` with uniform centres in `[0, L)^3` and
    /// isotropic orientations, reproducibly from `seed`.
    pub fn generate(params: RodParams, seed: u64) -> Self {
        // RodParams::new has checked the box against the rods, and gamma.
        Ensemble::paper(params).draw(seed).0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn watson_order_runs_from_planar_to_aligned() {
        assert!(watson_order(0.0).abs() < 1e-12);
        assert!((watson_order(-1e4) + 0.5).abs() < 1e-3);
        assert!(watson_order(1e4) > 0.999);
        for s in [-0.4, -0.1, 0.2, 0.5, 0.9] {
            assert!(
                (watson_order(Orientation::kappa(s)) - s).abs() < 1e-9,
                "{s}"
            );
        }
    }

    #[test]
    fn distributions_parse_and_refuse() {
        assert_eq!(Dist::parse("0.5").unwrap(), Dist::Fixed { value: 0.5 });
        assert_eq!(
            Dist::parse("uniform:0.5,1.5").unwrap(),
            Dist::Uniform { lo: 0.5, hi: 1.5 }
        );
        assert_eq!(
            Dist::parse("lognormal:1,0.3").unwrap(),
            Dist::Lognormal { mean: 1.0, sd: 0.3 }
        );
        for bad in [
            "-1",
            "uniform:2,1",
            "lognormal:1",
            "gauss:1,2",
            "x",
            "uniform:0,1",
        ] {
            assert!(Dist::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn lognormal_draws_have_the_asked_mean_and_spread() {
        let d = Dist::Lognormal { mean: 2.0, sd: 0.5 };
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let n = 200_000;
        let xs: Vec<f64> = (0..n).map(|_| d.draw(&mut rng)).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        // Standard error of the mean 0.5 / sqrt(n) ~ 0.0011.
        assert!((mean - 2.0).abs() < 3.0 * 0.5 / (n as f64).sqrt(), "{mean}");
        assert!((var.sqrt() - 0.5).abs() < 0.01, "{}", var.sqrt());
    }
}
