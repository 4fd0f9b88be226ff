//! One pair of rods: the box as the detectors see it, each rod placed in
//! it, whether two placed rods touch and the contact they make; and the
//! O(N^2) all-pairs reference built on that test alone.

use nalgebra::Vector3;

use super::segment::closest_points;
use crate::rods::{Rod, RodSystem};

/// Relative slack of the cheap necessary-condition filters, so that they never
/// reject a pair that the exact segment distance would accept.
pub(super) const FILTER_SLACK: f64 = 1e-9;

/// One contact between two rods.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The two rods, `rods[0] < rods[1]`.
    pub rods: [u32; 2],
    /// Arc length from each rod's centre to its closest point, in
    /// `[-length / 2, length / 2]`.
    pub params: [f64; 2],
    /// Contact point, wrapped into the box along periodic axes: on the
    /// segment of the two closest points, splitting it in the ratio of the
    /// radii (the midpoint for equal rods), so that it lies within each
    /// rod's radius of its core.
    pub point: Vector3<f64>,
    /// Periodic image of `rods[1]` that touches `rods[0]`: its center is
    /// shifted by `shift[k] * L_k` along each axis (0 along walls).
    pub shift: Offset,
}

/// A periodic image, in box sides along each axis: where a contact is made
/// (here), and what truth's topology reads per edge.
pub type Offset = [i32; 3];

/// The box as the detectors see it.
#[derive(Clone, Copy)]
pub(super) struct Space {
    pub(super) sides: [f64; 3],
    pub(super) wraps: [bool; 3],
}

impl Space {
    /// A center wrapped into the primary box along periodic axes, and which
    /// image of the box the stored center lies in (`center = wrapped + image * L`).
    pub(super) fn wrap_center(&self, center: &Vector3<f64>) -> (Vector3<f64>, Offset) {
        let mut out = *center;
        let mut image = [0i32; 3];
        for k in 0..3 {
            let (x, l) = (center[k], self.sides[k]);
            if !self.wraps[k] || (0.0..l).contains(&x) {
                continue;
            }
            let m = (x / l).floor();
            let mut y = x - m * l;
            let mut m = m as i32;
            if y >= l {
                y -= l;
                m = m.saturating_add(1);
            } else if y < 0.0 {
                y += l;
                m = m.saturating_sub(1);
            }
            out[k] = y.clamp(0.0, l);
            image[k] = m;
        }
        (out, image)
    }

    /// `x mod L_k` in `[0, L_k)` along a periodic axis, `x` along a wall axis.
    pub(super) fn wrap_coord(&self, x: f64, k: usize) -> f64 {
        if !self.wraps[k] {
            return x;
        }
        crate::rods::wrap(x, self.sides[k])
    }

    /// The image of a (wrapped) center shifted by `shift` boxes. Both
    /// detectors build it with this one expression so that they agree to the last bit.
    pub(super) fn image(&self, center: &Vector3<f64>, shift: Offset) -> Vector3<f64> {
        let l = self.sides;
        center
            + Vector3::new(
                shift[0] as f64 * l[0],
                shift[1] as f64 * l[1],
                shift[2] as f64 * l[2],
            )
    }
}

/// What the detectors need per rod: wrapped center, axis, the image of the
/// stored center, half the core length and the radius.
#[derive(Clone, Copy)]
pub(super) struct Placed {
    pub(super) center: Vector3<f64>,
    pub(super) axis: Vector3<f64>,
    pub(super) image: Offset,
    pub(super) half: f64,
    pub(super) radius: f64,
}

/// Geometry shared by the detectors.
#[derive(Clone, Copy)]
pub(super) struct Geometry {
    pub(super) space: Space,
    /// Twice the largest radius: no two rods touch farther apart than this.
    pub(super) two_r: f64,
    /// The largest core length.
    pub(super) max_len: f64,
    /// The mean core length, which sets the grid's cells.
    pub(super) mean_len: f64,
}

impl Geometry {
    pub(super) fn of(system: &RodSystem) -> Self {
        let n = system.len().max(1) as f64;
        Geometry {
            space: Space {
                sides: system.domain.sides,
                wraps: system.domain.periodic.axes(),
            },
            two_r: 2.0 * system.max_radius(),
            max_len: system.max_length(),
            mean_len: system.rods.iter().map(|r| r.length).sum::<f64>() / n,
        }
    }

    pub(super) fn place(&self, rod: &Rod) -> Placed {
        let (center, image) = self.space.wrap_center(&rod.center);
        Placed {
            center,
            axis: rod.axis,
            image,
            half: 0.5 * rod.length,
            radius: rod.radius,
        }
    }

    /// Tests rods `lo < hi` where `shift` (relative to the wrapped centers) is
    /// the image of `hi` that can touch `lo`. The single decision procedure of
    /// both detectors, so their outputs are identical.
    pub(super) fn touch(
        &self,
        lo: u32,
        a: &Placed,
        hi: u32,
        b: &Placed,
        shift: Offset,
    ) -> Option<Contact> {
        let p = a.center;
        let q = self.space.image(&b.center, shift);
        let w = q - p;
        // Rods touch iff their cores come within the sum of the radii.
        let two_r = a.radius + b.radius;
        let reach = a.half + b.half + two_r;
        if w.norm_squared() > reach * reach * (1.0 + FILTER_SLACK) {
            return None;
        }
        // The distance of the infinite lines bounds the segment distance from
        // below and rejects most candidates without the full computation.
        let n = a.axis.cross(&b.axis);
        let n2 = n.norm_squared();
        if n2 > 1e-6 {
            let wn = w.dot(&n);
            if wn * wn > two_r * two_r * n2 * (1.0 + FILTER_SLACK) {
                return None;
            }
        }
        let cp = closest_points(&p, &a.axis, a.half, &q, &b.axis, b.half);
        if cp.dist2 >= two_r * two_r {
            return None;
        }
        let (pa, pb) = (p + a.axis * cp.s, q + b.axis * cp.t);
        let mid = if a.radius == b.radius {
            (pa + pb) * 0.5
        } else {
            pa + (pb - pa) * (a.radius / two_r)
        };
        let point = Vector3::new(
            self.space.wrap_coord(mid.x, 0),
            self.space.wrap_coord(mid.y, 1),
            self.space.wrap_coord(mid.z, 2),
        );
        // Translate the shift between wrapped centers into one between stored centers.
        let shift = std::array::from_fn(|k| {
            shift[k]
                .saturating_add(a.image[k])
                .saturating_sub(b.image[k])
        });
        Some(Contact {
            rods: [lo, hi],
            params: [cp.s, cp.t],
            point,
            shift,
        })
    }
}

/// All contacts by testing every pair: the O(N^2) reference for [`super::grid::detect`],
/// with the same conventions and bit-identical output.
pub fn detect_all_pairs(system: &RodSystem) -> Vec<Contact> {
    let geo = Geometry::of(system);
    let Space { sides, wraps } = geo.space;
    let placed: Vec<Placed> = system.rods.iter().map(|r| geo.place(r)).collect();
    let mut contacts = Vec::new();
    for (i, a) in placed.iter().enumerate() {
        for (j, b) in placed.iter().enumerate().skip(i + 1) {
            let d = b.center - a.center;
            // Minimum image along periodic axes: the only image of j that can
            // touch i (L > 2(l + 2r)).
            let shift = std::array::from_fn(|k| {
                if wraps[k] {
                    -(d[k] / sides[k]).round() as i32
                } else {
                    0
                }
            });
            contacts.extend(geo.touch(i as u32, a, j as u32, b, shift));
        }
    }
    contacts
}
