//! Which rods touch (MODEL §1): an O(N) periodic cell list over a robust
//! segment–segment distance, with the O(N^2) all-pairs reference.

mod segment;

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::rods::{Rod, RodSystem};
pub use segment::{Closest, closest_points};

/// Relative slack of the cheap necessary-condition filters, so that they never
/// reject a pair that the exact segment distance would accept.
const FILTER_SLACK: f64 = 1e-9;

/// One contact between two rods.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The two rods, `rods[0] < rods[1]`.
    pub rods: [u32; 2],
    /// Axis parameter of the closest point on each rod, in `[-1/2, 1/2]`.
    pub params: [f64; 2],
    /// Contact point: midpoint of the two closest points, wrapped into the primary box.
    pub point: Vector3<f64>,
    /// Periodic image of `rods[1]` that touches `rods[0]`: its center is
    /// shifted by `shift * L`.
    pub shift: [i32; 3],
}

/// A center wrapped into the primary box, and which image of the box the
/// stored center lies in (`center = wrapped + image * L`).
fn wrap_center(center: &Vector3<f64>, l: f64) -> (Vector3<f64>, [i32; 3]) {
    let mut out = *center;
    let mut image = [0i32; 3];
    for k in 0..3 {
        let x = center[k];
        if (0.0..l).contains(&x) {
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

/// `x mod L` in `[0, L)`.
fn wrap_coord(x: f64, l: f64) -> f64 {
    let y = x - (x / l).floor() * l;
    if y >= l || y < 0.0 { 0.0 } else { y }
}

/// The image of a (wrapped) center shifted by `shift` boxes. Both detectors
/// build it with this one expression so that they agree to the last bit.
fn image(center: &Vector3<f64>, shift: [i32; 3], l: f64) -> Vector3<f64> {
    center + Vector3::new(shift[0] as f64, shift[1] as f64, shift[2] as f64) * l
}

/// What the detectors need per rod: wrapped center, axis, and the image of
/// the stored center.
#[derive(Clone, Copy)]
struct Placed {
    center: Vector3<f64>,
    axis: Vector3<f64>,
    image: [i32; 3],
}

/// Geometry shared by the detectors.
#[derive(Clone, Copy)]
struct Geometry {
    box_len: f64,
    /// `(2r)^2`: rods touch iff the core distance squared is below this.
    touch2: f64,
    /// Squared largest center distance of touching rods, `(l + 2r)^2`, with slack.
    reach2: f64,
    two_r: f64,
}

impl Geometry {
    fn of(system: &RodSystem) -> Self {
        let r = system.radius();
        let reach = 1.0 + 2.0 * r;
        Geometry {
            box_len: system.box_len(),
            touch2: 4.0 * r * r,
            reach2: reach * reach * (1.0 + FILTER_SLACK),
            two_r: 2.0 * r,
        }
    }

    /// Tests rods `lo < hi` where `shift` (relative to the wrapped centers) is
    /// the image of `hi` that can touch `lo`. The single decision procedure of
    /// both detectors, so their outputs are identical.
    fn touch(&self, lo: u32, a: &Placed, hi: u32, b: &Placed, shift: [i32; 3]) -> Option<Contact> {
        let l = self.box_len;
        let p = a.center;
        let q = image(&b.center, shift, l);
        let w = q - p;
        if w.norm_squared() > self.reach2 {
            return None;
        }
        // The distance of the infinite lines bounds the segment distance from
        // below and rejects most candidates without the full computation.
        let n = a.axis.cross(&b.axis);
        let n2 = n.norm_squared();
        if n2 > 1e-6 {
            let wn = w.dot(&n);
            if wn * wn > self.two_r * self.two_r * n2 * (1.0 + FILTER_SLACK) {
                return None;
            }
        }
        let cp = closest_points(&p, &a.axis, &q, &b.axis);
        let touching = cp.dist2 < self.touch2;
        if !touching {
            return None;
        }
        let mid = (p + a.axis * cp.s + q + b.axis * cp.t) * 0.5;
        let point = Vector3::new(
            wrap_coord(mid.x, l),
            wrap_coord(mid.y, l),
            wrap_coord(mid.z, l),
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

fn place(rod: &Rod, l: f64) -> Placed {
    let (center, image) = wrap_center(&rod.center, l);
    Placed {
        center,
        axis: rod.axis,
        image,
    }
}

/// The 13 neighbour offsets that, with the cell itself, visit every
/// unordered pair of adjacent cells exactly once.
const FORWARD: [[i32; 3]; 13] = [
    [0, 0, 1],
    [0, 1, -1],
    [0, 1, 0],
    [0, 1, 1],
    [1, -1, -1],
    [1, -1, 0],
    [1, -1, 1],
    [1, 0, -1],
    [1, 0, 0],
    [1, 0, 1],
    [1, 1, -1],
    [1, 1, 0],
    [1, 1, 1],
];

/// All contacts of a rod system in O(N) with a periodic cell list, sorted by
/// rod pair (see [`Contact`] for the conventions).
///
/// Cells have side at least `l + 2r`, the largest center distance of touching
/// rods, so touching rods sit in the same or adjacent cells. The result does
/// not depend on the number of rayon threads and equals [`detect_all_pairs`].
pub fn detect(system: &RodSystem) -> Vec<Contact> {
    let geo = Geometry::of(system);
    let l = geo.box_len;
    let n = system.len();
    let reach = 1.0 + geo.two_r;
    // Cells no smaller than needed, and no more cells than about 2N, so a
    // sparse system in a huge box does not allocate an enormous empty grid.
    let by_size = (l / reach).floor();
    let by_count = (2.0 * n as f64).cbrt().ceil();
    let m = by_size.min(by_count);
    if m.is_nan() || m < 3.0 {
        return detect_all_pairs(system);
    }
    let m = m as usize;
    let n_cells = m * m * m;

    let placed: Vec<Placed> = system.rods.iter().map(|r| place(r, l)).collect();
    let cell_of: Vec<u32> = placed
        .iter()
        .map(|p| {
            let idx = |x: f64| ((x / l * m as f64) as usize).min(m - 1);
            ((idx(p.center.x) * m + idx(p.center.y)) * m + idx(p.center.z)) as u32
        })
        .collect();
    // Counting sort: `start[c]..start[c + 1]` are the sorted slots of cell c.
    let mut start = vec![0u32; n_cells + 1];
    for &c in &cell_of {
        start[c as usize + 1] += 1;
    }
    for c in 0..n_cells {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut order = vec![0u32; n];
    for (i, &c) in cell_of.iter().enumerate() {
        order[fill[c as usize] as usize] = i as u32;
        fill[c as usize] += 1;
    }
    // Rods in cell order, coordinates also in separate arrays so that the
    // inner distance loop streams through memory.
    let sorted: Vec<Placed> = order.iter().map(|&i| placed[i as usize]).collect();
    drop(placed);
    let xs: Vec<f64> = sorted.iter().map(|p| p.center.x).collect();
    let ys: Vec<f64> = sorted.iter().map(|p| p.center.y).collect();
    let zs: Vec<f64> = sorted.iter().map(|p| p.center.z).collect();
    let line_cut2 = geo.two_r * geo.two_r * (1.0 + FILTER_SLACK);

    let visit_cell = |out: &mut Vec<Contact>, cell: usize| {
        let (ix, iy, iz) = (cell / (m * m), (cell / m) % m, cell % m);
        let own = start[cell] as usize..start[cell + 1] as usize;
        if own.is_empty() {
            return;
        }
        for off in std::iter::once([0, 0, 0]).chain(FORWARD) {
            // Neighbour cell and the image shift that makes it adjacent.
            let mut shift = [0i32; 3];
            let mut nc = [0usize; 3];
            for (k, base) in [ix, iy, iz].into_iter().enumerate() {
                let mut c = base as i64 + off[k] as i64;
                if c < 0 {
                    c += m as i64;
                    shift[k] = -1;
                } else if c >= m as i64 {
                    c -= m as i64;
                    shift[k] = 1;
                }
                nc[k] = c as usize;
            }
            let other = (nc[0] * m + nc[1]) * m + nc[2];
            let same = other == cell;
            let theirs = start[other] as usize..start[other + 1] as usize;
            let sv = Vector3::new(shift[0] as f64, shift[1] as f64, shift[2] as f64) * l;
            let back = shift.map(|s| -s);
            for a in own.clone() {
                let pa = &sorted[a];
                let (ax, ay, az) = (xs[a] - sv.x, ys[a] - sv.y, zs[a] - sv.z);
                let from = if same { a + 1 } else { theirs.start };
                // Hits as bit masks over chunks of 64: the distance loop has
                // no data-dependent branch (most rods are out of reach, and
                // such a branch mispredicts often), and only hits are visited.
                let (bx, by, bz) = (
                    &xs[from..theirs.end],
                    &ys[from..theirs.end],
                    &zs[from..theirs.end],
                );
                for (chunk, ((cx, cy), cz)) in bx
                    .chunks(64)
                    .zip(by.chunks(64))
                    .zip(bz.chunks(64))
                    .enumerate()
                {
                    let mut mask = 0u64;
                    for (k, ((x, y), z)) in cx.iter().zip(cy).zip(cz).enumerate() {
                        let (dx, dy, dz) = (x - ax, y - ay, z - az);
                        mask |= u64::from(dx * dx + dy * dy + dz * dz <= geo.reach2) << k;
                    }
                    while mask != 0 {
                        let b = from + 64 * chunk + mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        let pb = &sorted[b];
                        // Distance of the infinite lines: a cheap lower bound.
                        let n = pa.axis.cross(&pb.axis);
                        let n2 = n.norm_squared();
                        if n2 > 1e-6 {
                            let wn = (pb.center + sv - pa.center).dot(&n);
                            if wn * wn > line_cut2 * n2 {
                                continue;
                            }
                        }
                        let (i, j) = (order[a], order[b]);
                        let hit = if i < j {
                            geo.touch(i, pa, j, pb, shift)
                        } else {
                            geo.touch(j, pb, i, pa, back)
                        };
                        out.extend(hit);
                    }
                }
            }
        }
    };
    let mut contacts = (0..n_cells)
        .into_par_iter()
        .with_min_len(16)
        .fold(Vec::new, |mut out, cell| {
            visit_cell(&mut out, cell);
            out
        })
        .reduce(Vec::new, |mut a, mut b| {
            a.append(&mut b);
            a
        });
    contacts.sort_unstable_by_key(|c| c.rods);
    contacts
}

/// All contacts by testing every pair: the O(N^2) reference for [`detect`],
/// with the same conventions and bit-identical output.
pub fn detect_all_pairs(system: &RodSystem) -> Vec<Contact> {
    let geo = Geometry::of(system);
    let l = geo.box_len;
    let placed: Vec<Placed> = system.rods.iter().map(|r| place(r, l)).collect();
    let mut contacts = Vec::new();
    for (i, a) in placed.iter().enumerate() {
        for (j, b) in placed.iter().enumerate().skip(i + 1) {
            let d = b.center - a.center;
            // Minimum image: the only image of j that can touch i (L > 2(l + 2r)).
            let shift = std::array::from_fn(|k| -(d[k] / l).round() as i32);
            contacts.extend(geo.touch(i as u32, a, j as u32, b, shift));
        }
    }
    contacts
}
