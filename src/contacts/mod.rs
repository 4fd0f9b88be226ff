//! Which rods touch (MODEL §1): an O(N) periodic grid of rod covers over a
//! robust segment–segment distance, with the O(N^2) all-pairs reference.

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

/// Target side of a cover cell, in rod lengths. A rod covers about
/// `1 + 1.5 / side` cells and shares a cell with about
/// `rho (1.5 + side)^2 side / 2` others, against some `13.5 rho (l + 2r)^3`
/// center distances per rod in a cell list with cells longer than a rod: at
/// gamma 98 (density 190) some 25 times fewer pair tests, for a handful of
/// cell entries per rod.
/// Measured (single thread, L = 10): a third of a rod length is near the
/// fastest at gamma 98, density 190; half a rod length would be about a fifth
/// faster at gamma 23, density 40.
const CELL_SIDE: f64 = 1.0 / 3.0;

/// Cells per rod allowed in a sparse system before the grid coarsens, so a
/// huge nearly empty box does not allocate an enormous empty grid.
const CELLS_PER_ROD: f64 = 8.0;

/// A uniform periodic grid of `m^3` cubic cells of side `h = L / m`, each
/// listing the rods whose core, widened by `pad`, may meet it.
///
/// Two rods touch only where their cores come within `2r`, and the midpoint
/// of the closest points is then within `r` of both cores: every cell that
/// holds that midpoint lists both rods. Each pair is therefore tested in a
/// cell it shares, and a contact is kept only in the cell holding its contact
/// point, so it is kept exactly once.
#[derive(Clone, Copy)]
struct Grid {
    m: usize,
    h: f64,
    /// `r` plus a rounding slack: the core is widened to a square tube of this
    /// half-side, which contains the round one of radius `r`.
    pad: f64,
    /// Absolute slack for rounding, in lengths.
    slack: f64,
}

/// Bits of a cover entry that hold the image code, below the rod index.
const IMAGE_BITS: u32 = 6;
const IMAGE_MASK: u32 = (1 << IMAGE_BITS) - 1;

impl Grid {
    /// The grid for a system, or `None` when the box is too small for a rod's
    /// cover to miss the same cell twice (or there are too many rods to pack).
    fn of(geo: &Geometry, n: usize) -> Option<Self> {
        let l = geo.box_len;
        if n > (u32::MAX >> IMAGE_BITS) as usize {
            return None;
        }
        // Rounding of coordinates up to about L is orders of magnitude below this.
        let slack = 1e-9 * (1.0 + l);
        let pad = 0.5 * geo.two_r + slack;
        let by_size = (l / CELL_SIDE).floor();
        let by_count = (CELLS_PER_ROD * n as f64).cbrt().ceil();
        let m = by_size.min(by_count).max(1.0);
        // Cell numbers are stored as u32.
        if !m.is_finite() || m.powi(3) > u32::MAX as f64 {
            return None;
        }
        let h = l / m;
        // A rod's cover spans at most (1 + 2 pad) / h + 2 cells along an axis;
        // fewer than m + 1 keeps each wrapped cell at most once per rod.
        if (1.0 + 2.0 * pad + h) * (1.0 + 1e-9) >= l {
            return None;
        }
        Some(Grid {
            m: m as usize,
            h,
            pad,
            slack,
        })
    }

    fn n_cells(&self) -> usize {
        self.m * self.m * self.m
    }

    /// The wrapped cell of a point in the primary box.
    fn cell_of(&self, p: &Vector3<f64>) -> usize {
        let idx = |x: f64| ((x / self.h) as usize).min(self.m - 1);
        (idx(p.x) * self.m + idx(p.y)) * self.m + idx(p.z)
    }

    /// Unwrapped cell indices whose slabs meet `[lo, hi]`, at most `m` of them.
    fn cells(&self, lo: f64, hi: f64) -> std::ops::RangeInclusive<i64> {
        let a = floor_i64(lo / self.h);
        let b = floor_i64(hi / self.h).min(a.saturating_add(self.m as i64 - 1));
        a..=b
    }

    /// The parameters in `t` where the coordinate `c + t u` lies in the
    /// unwrapped slab `i`, widened by `pad`.
    fn clip(&self, c: f64, u: f64, i: i64, t: (f64, f64)) -> (f64, f64) {
        if u == 0.0 {
            return t;
        }
        let a = (i as f64 * self.h - self.pad - c) / u;
        let b = ((i + 1) as f64 * self.h + self.pad - c) / u;
        (t.0.max(a.min(b)), t.1.min(a.max(b)))
    }

    /// Radius of a ball about a cell's center that holds the cell widened by
    /// `pad`, with slack.
    fn ball(&self) -> f64 {
        (0.5 * self.h + self.pad) * 3f64.sqrt() * (1.0 + 1e-9)
    }

    /// Calls `f(cell, image code)` for every cell that the rod with wrapped
    /// center `c` and axis `u`, widened by `pad`, may meet. Slab by slab
    /// along x, then y, then z, each slab clipping the axis parameter, so the
    /// work is proportional to the cells covered.
    fn cover(&self, c: &Vector3<f64>, u: &Vector3<f64>, mut f: impl FnMut(usize, u32)) {
        let (pad, m) = (self.pad, self.m as i64);
        // Coordinate range of axis k over parameters [t0, t1], widened by pad.
        let span = |k: usize, t0: f64, t1: f64| {
            let (a, b) = (c[k] + t0 * u[k], c[k] + t1 * u[k]);
            (a.min(b) - pad, a.max(b) + pad)
        };
        let clip = |k: usize, i: i64, t0: f64, t1: f64| self.clip(c[k], u[k], i, (t0, t1));
        // Wrapped index and image (-1, 0 or 1) of an unwrapped cell index.
        let wrap = |i: i64| {
            (
                i.rem_euclid(m) as usize,
                (i.div_euclid(m) + 1).clamp(0, 2) as u32,
            )
        };
        let (x0, x1) = span(0, -0.5, 0.5);
        for ix in self.cells(x0, x1) {
            let (ta, tb) = clip(0, ix, -0.5, 0.5);
            if ta > tb {
                continue;
            }
            let (wx, kx) = wrap(ix);
            let (y0, y1) = span(1, ta, tb);
            for iy in self.cells(y0, y1) {
                let (tc, td) = clip(1, iy, ta, tb);
                if tc > td {
                    continue;
                }
                let (wy, ky) = wrap(iy);
                let (z0, z1) = span(2, tc, td);
                for iz in self.cells(z0, z1) {
                    let (wz, kz) = wrap(iz);
                    f((wx * self.m + wy) * self.m + wz, kx << 4 | ky << 2 | kz);
                }
            }
        }
    }
}

/// Counting sort of `(cell, item)` pairs: `items[start[c]..start[c + 1]]`
/// are the items of cell c, in input order.
fn group(n_cells: usize, pairs: &[(u32, u32)]) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; n_cells + 1];
    for &(c, _) in pairs {
        start[c as usize + 1] += 1;
    }
    for c in 0..n_cells {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut items = vec![0u32; pairs.len()];
    for &(c, item) in pairs {
        items[fill[c as usize] as usize] = item;
        fill[c as usize] += 1;
    }
    (start, items)
}

/// The image offset `(i, j, k)` in boxes of an image code, two bits per axis
/// holding `i + 1`, `j + 1` and `k + 1`.
fn image_of(code: u32) -> [i32; 3] {
    let code = code as i32;
    [(code >> 4) - 1, (code >> 2 & 3) - 1, (code & 3) - 1]
}

/// `floor(x)` as an integer (saturating, NaN to 0), without the libm call
/// that `f64::floor` becomes on the baseline x86-64 target.
fn floor_i64(x: f64) -> i64 {
    let i = x as i64;
    if (i as f64) > x { i - 1 } else { i }
}

/// Slack, in axis parameter, for the rounding of the lines' closest parameters.
const PARAM_SLACK: f64 = 1e-7;

/// Whether the pieces `s` of the line `u` and `t` of the line `w + t v`
/// (`u`, `v` unit vectors) may come within `sqrt(cut2)`: a necessary
/// condition, exact up to slack.
///
/// The squared distance of the lines' points at `(s, t)` is the lines'
/// squared distance plus a quadratic form in the offset from the closest
/// parameters `(s*, t*)`, whose smaller eigenvalue is `1 - |u.v|`; so it is
/// at least `dist^2 + (1 - |u.v|) D^2`, with `D` the distance of `(s*, t*)`
/// from the rectangle `s x t`. (Nearly) parallel lines always pass.
fn pieces_may_touch(
    u: &Vector3<f64>,
    v: &Vector3<f64>,
    w: &Vector3<f64>,
    s: (f64, f64),
    t: (f64, f64),
    cut2: f64,
) -> bool {
    let n = u.cross(v);
    let n2 = n.norm_squared();
    if n2 <= 1e-6 {
        return true;
    }
    let beta = u.dot(v);
    let (d, e) = (u.dot(w), v.dot(w));
    let s_star = (d - e * beta) / n2;
    let t_star = (d * beta - e) / n2;
    let wn = w.dot(&n);
    let outside =
        |x: f64, (lo, hi): (f64, f64)| (lo - x).max(x - hi).max(PARAM_SLACK) - PARAM_SLACK;
    let (ds, dt) = (outside(s_star, s), outside(t_star, t));
    // 1 - |beta| without the cancellation, as n2 = (1 - |beta|)(1 + |beta|).
    let lambda = n2 / (1.0 + beta.abs());
    wn * wn / n2 + lambda * (ds * ds + dt * dt) <= cut2
}

/// Per-thread buffers of one cell's rods, moved into the cell's frame.
#[derive(Default)]
struct CellRods {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    ux: Vec<f64>,
    uy: Vec<f64>,
    uz: Vec<f64>,
}

/// All contacts of a rod system in O(N), sorted by rod pair (see [`Contact`]
/// for the conventions).
///
/// Each rod is listed in the cells of a fine periodic grid that its core,
/// widened by `r`, may meet (cells about a third of a rod long); pairs sharing a cell are tested
/// there, and a contact is kept in the one cell holding its contact point.
/// The result does not depend on the number of rayon threads and equals
/// [`detect_all_pairs`].
pub fn detect(system: &RodSystem) -> Vec<Contact> {
    let geo = Geometry::of(system);
    let l = geo.box_len;
    let n = system.len();
    if n < 2 {
        return Vec::new();
    }
    let Some(grid) = Grid::of(&geo, n) else {
        return detect_all_pairs(system);
    };
    let n_cells = grid.n_cells();
    // Rods renumbered in the order of their centers' cells, so that the rods
    // of a cell, and of the cells visited next, lie close in memory.
    let placed: Vec<Placed> = system.rods.iter().map(|r| place(r, l)).collect();
    let homes: Vec<(u32, u32)> = placed
        .iter()
        .enumerate()
        .map(|(i, p)| (grid.cell_of(&p.center) as u32, i as u32))
        .collect();
    let (_, order) = group(n_cells, &homes);
    drop(homes);
    let placed: Vec<Placed> = order.iter().map(|&i| placed[i as usize]).collect();

    // Cover entries `slot << IMAGE_BITS | image code`, grouped by cell:
    // `entries[start[c]..start[c + 1]]` are those of cell c.
    let covered: Vec<(u32, u32)> = placed
        .par_iter()
        .enumerate()
        .fold(Vec::new, |mut out, (i, p)| {
            grid.cover(&p.center, &p.axis, |cell, image| {
                out.push((cell as u32, (i as u32) << IMAGE_BITS | image));
            });
            out
        })
        .collect::<Vec<Vec<(u32, u32)>>>()
        .concat();
    let (start, entries) = group(n_cells, &covered);
    drop(covered);
    let line_cut2 = geo.two_r * geo.two_r * (1.0 + FILTER_SLACK);
    let piece_cut2 = (geo.two_r + grid.slack).powi(2) * (1.0 + FILTER_SLACK);
    let ball = grid.ball();

    let visit_cell = |out: &mut Vec<Contact>, rods: &mut CellRods, cell: usize| {
        let here = &entries[start[cell] as usize..start[cell + 1] as usize];
        if here.len() < 2 {
            return;
        }
        let m = grid.m;
        let centre = Vector3::new(
            ((cell / (m * m)) as f64 + 0.5) * grid.h,
            ((cell / m % m) as f64 + 0.5) * grid.h,
            ((cell % m) as f64 + 0.5) * grid.h,
        );
        // Each rod's image that meets this cell, as coordinate arrays so that
        // the pair loop streams through memory.
        let CellRods {
            x,
            y,
            z,
            ux,
            uy,
            uz,
        } = rods;
        for v in [&mut *x, &mut *y, &mut *z, &mut *ux, &mut *uy, &mut *uz] {
            v.clear();
        }
        for &e in here {
            let p = &placed[(e >> IMAGE_BITS) as usize];
            let c = image(&p.center, image_of(e & IMAGE_MASK).map(|s| -s), l);
            x.push(c.x);
            y.push(c.y);
            z.push(c.z);
            ux.push(p.axis.x);
            uy.push(p.axis.y);
            uz.push(p.axis.z);
        }
        for a in 0..here.len() {
            let (ax, ay, az) = (x[a], y[a], z[a]);
            let (aux, auy, auz) = (ux[a], uy[a], uz[a]);
            let from = a + 1;
            let rest = from..here.len();
            // Pairs whose infinite lines come within 2r, as bit masks over
            // chunks of 64: the test loop has no data-dependent branch (most
            // pairs fail it, and such a branch mispredicts often).
            for (chunk, (((((bx, by), bz), bux), buy), buz)) in x[rest.clone()]
                .chunks(64)
                .zip(y[rest.clone()].chunks(64))
                .zip(z[rest.clone()].chunks(64))
                .zip(ux[rest.clone()].chunks(64))
                .zip(uy[rest.clone()].chunks(64))
                .zip(uz[rest].chunks(64))
                .enumerate()
            {
                let mut mask = 0u64;
                for k in 0..bx.len() {
                    let nx = auy * buz[k] - auz * buy[k];
                    let ny = auz * bux[k] - aux * buz[k];
                    let nz = aux * buy[k] - auy * bux[k];
                    let n2 = nx * nx + ny * ny + nz * nz;
                    let wn = (bx[k] - ax) * nx + (by[k] - ay) * ny + (bz[k] - az) * nz;
                    let near = (n2 <= 1e-6) | (wn * wn <= line_cut2 * n2);
                    mask |= u64::from(near) << k;
                }
                while mask != 0 {
                    let b = from + 64 * chunk + mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    let (ea, eb) = (here[a], here[b]);
                    let (sa, sb) = ((ea >> IMAGE_BITS) as usize, (eb >> IMAGE_BITS) as usize);
                    let (i, j) = (order[sa], order[sb]);
                    // Image of b that meets a here: a sits at its image
                    // `ia`, b at `ib`, relative to their wrapped centers.
                    let (ia, ib) = (image_of(ea & IMAGE_MASK), image_of(eb & IMAGE_MASK));
                    let (pa, pb) = (&placed[sa], &placed[sb]);
                    // Only the pieces of the rods near this cell matter: a
                    // contact kept here has its closest points within `ball`
                    // of the cell's center.
                    let from_a = Vector3::new(x[a], y[a], z[a]);
                    let from_b = Vector3::new(x[b], y[b], z[b]);
                    let piece = |from: &Vector3<f64>, axis: &Vector3<f64>| {
                        let mid = axis.dot(&(centre - from));
                        ((mid - ball).max(-0.5), (mid + ball).min(0.5))
                    };
                    if !pieces_may_touch(
                        &pa.axis,
                        &pb.axis,
                        &(from_b - from_a),
                        piece(&from_a, &pa.axis),
                        piece(&from_b, &pb.axis),
                        piece_cut2,
                    ) {
                        continue;
                    }
                    let hit = match i.cmp(&j) {
                        std::cmp::Ordering::Less => {
                            let shift = std::array::from_fn(|k| ia[k] - ib[k]);
                            geo.touch(i, pa, j, pb, shift)
                        }
                        std::cmp::Ordering::Greater => {
                            let shift = std::array::from_fn(|k| ib[k] - ia[k]);
                            geo.touch(j, pb, i, pa, shift)
                        }
                        // A rod meets a cell through one image only (see `Grid::of`).
                        std::cmp::Ordering::Equal => None,
                    };
                    out.extend(hit.filter(|c| grid.cell_of(&c.point) == cell));
                }
            }
        }
    };
    let mut contacts = (0..n_cells)
        .into_par_iter()
        .with_min_len(64)
        .fold(
            || (Vec::new(), CellRods::default()),
            |(mut out, mut rods), cell| {
                visit_cell(&mut out, &mut rods, cell);
                (out, rods)
            },
        )
        .map(|(out, _)| out)
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
