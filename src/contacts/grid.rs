//! The O(N) detector: a periodic grid of cells, each rod listed in the
//! cells its cover may reach, and the pair test run on rods that share a
//! cell.

use nalgebra::Vector3;
use rayon::prelude::*;

use super::pair::{Contact, FILTER_SLACK, Geometry, Offset, Placed, detect_all_pairs};
use crate::rods::RodSystem;

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

/// A uniform grid of `m_x m_y m_z` cells of sides `h_k = L_k / m_k`, each
/// listing the rods whose core, widened by the rod's radius (plus a rounding
/// slack), may meet it. Along a periodic axis the grid wraps; along a wall
/// axis it stops at the walls, since cores lie inside them (see
/// [`crate::rods::Domain::cut`]) and so do the contact points between them.
///
/// Two rods touch only where their cores come within `r_a + r_b`, and the
/// contact point (see [`Contact::point`]) is then within `r_a` of one core and
/// `r_b` of the other: every cell that holds that point lists both rods. Each
/// pair is therefore tested in a cell it shares, and a contact is kept only in
/// the cell holding its contact point, so it is kept exactly once.
#[derive(Clone, Copy)]
struct Grid {
    m: [usize; 3],
    h: [f64; 3],
    wraps: [bool; 3],
    /// Absolute slack for rounding, in lengths, added to each rod's radius:
    /// the core is widened to a square tube of this half-side, which contains
    /// the round one.
    slack: f64,
    /// The largest widening, for the bound on a contact's distance from a cell.
    max_pad: f64,
}

/// Bits of a cover entry that hold the image code, below the rod index.
const IMAGE_BITS: u32 = 6;
const IMAGE_MASK: u32 = (1 << IMAGE_BITS) - 1;

impl Grid {
    /// The grid for a system, or `None` when a periodic side is too small for
    /// a rod's cover to miss the same cell twice (or there are too many rods to pack).
    fn of(geo: &Geometry, n: usize) -> Option<Self> {
        let sides = geo.space.sides;
        if n > (u32::MAX >> IMAGE_BITS) as usize {
            return None;
        }
        let big = sides.iter().copied().fold(0.0, f64::max);
        // Rounding of coordinates up to about L is orders of magnitude below this.
        let slack = 1e-9 * (1.0 + big);
        let max_pad = 0.5 * geo.two_r + slack;
        let volume: f64 = sides.iter().product();
        let per_length = (CELLS_PER_ROD * n as f64 / volume).cbrt();
        let side = CELL_SIDE * geo.mean_len;
        let mut m = [1usize; 3];
        let mut h = [0.0; 3];
        for k in 0..3 {
            let l = sides[k];
            let by_size = (l / side).floor();
            let by_count = (l * per_length).ceil();
            let mk = by_size.min(by_count).max(1.0);
            if !mk.is_finite() || mk > u32::MAX as f64 {
                return None;
            }
            m[k] = mk as usize;
            h[k] = l / mk;
            // A rod's cover spans at most (l + 2 pad) / h + 2 cells along an
            // axis; fewer than m + 1 keeps each wrapped cell at most once per rod.
            if geo.space.wraps[k] && (geo.max_len + 2.0 * max_pad + h[k]) * (1.0 + 1e-9) >= l {
                return None;
            }
        }
        // Cell numbers are stored as u32.
        if (m[0] as f64) * (m[1] as f64) * (m[2] as f64) > u32::MAX as f64 {
            return None;
        }
        Some(Grid {
            m,
            h,
            wraps: geo.space.wraps,
            slack,
            max_pad,
        })
    }

    fn n_cells(&self) -> usize {
        self.m.iter().product()
    }

    fn index(&self, i: [usize; 3]) -> usize {
        (i[0] * self.m[1] + i[1]) * self.m[2] + i[2]
    }

    /// The cell of a point in the box.
    fn cell_of(&self, p: &Vector3<f64>) -> usize {
        let idx = |k: usize| ((p[k] / self.h[k]) as usize).min(self.m[k] - 1);
        self.index([idx(0), idx(1), idx(2)])
    }

    /// The center of a cell.
    fn center(&self, cell: usize) -> Vector3<f64> {
        let (m, h) = (self.m, self.h);
        let i = [cell / (m[1] * m[2]), cell / m[2] % m[1], cell % m[2]];
        Vector3::from_fn(|k, _| (i[k] as f64 + 0.5) * h[k])
    }

    /// Unwrapped cell indices along axis `k` whose slabs meet `[lo, hi]`, at
    /// most `m_k` of them; along a wall axis, only the box's own cells.
    fn cells(&self, k: usize, lo: f64, hi: f64) -> std::ops::RangeInclusive<i64> {
        let m = self.m[k] as i64;
        let a = floor_i64(lo / self.h[k]);
        let b = floor_i64(hi / self.h[k]);
        if self.wraps[k] {
            a..=b.min(a.saturating_add(m - 1))
        } else {
            a.max(0)..=b.min(m - 1)
        }
    }

    /// The parameters in `t` where the coordinate `c + t u` lies in the
    /// unwrapped slab `i` of axis `k`, widened by `pad`.
    fn clip(&self, k: usize, c: f64, u: f64, i: i64, pad: f64, t: (f64, f64)) -> (f64, f64) {
        if u == 0.0 {
            return t;
        }
        let h = self.h[k];
        let a = (i as f64 * h - pad - c) / u;
        let b = ((i + 1) as f64 * h + pad - c) / u;
        (t.0.max(a.min(b)), t.1.min(a.max(b)))
    }

    /// Radius of a ball about a cell's center that holds the cell widened by
    /// the largest pad, with slack.
    fn ball(&self) -> f64 {
        let half = Vector3::from_fn(|k, _| 0.5 * self.h[k] + self.max_pad);
        half.norm() * (1.0 + 1e-9)
    }

    /// Calls `f(cell, image code)` for every cell that the rod with wrapped
    /// center `c`, axis `u`, half-length `half` and radius `r` may meet,
    /// widened. Slab by slab along x, then y, then z, each slab clipping the
    /// axis parameter, so the work is proportional to the cells covered.
    fn cover(
        &self,
        c: &Vector3<f64>,
        u: &Vector3<f64>,
        half: f64,
        r: f64,
        mut f: impl FnMut(usize, u32),
    ) {
        let pad = r + self.slack;
        // Coordinate range of axis k over parameters [t0, t1], widened by pad.
        let span = |k: usize, t0: f64, t1: f64| {
            let (a, b) = (c[k] + t0 * u[k], c[k] + t1 * u[k]);
            (a.min(b) - pad, a.max(b) + pad)
        };
        let clip = |k: usize, i: i64, t0: f64, t1: f64| self.clip(k, c[k], u[k], i, pad, (t0, t1));
        // Wrapped index and image (-1, 0 or 1) of an unwrapped cell index.
        let wrap = |k: usize, i: i64| {
            let m = self.m[k] as i64;
            (
                i.rem_euclid(m) as usize,
                (i.div_euclid(m) + 1).clamp(0, 2) as u32,
            )
        };
        let (x0, x1) = span(0, -half, half);
        for ix in self.cells(0, x0, x1) {
            let (ta, tb) = clip(0, ix, -half, half);
            if ta > tb {
                continue;
            }
            let (wx, kx) = wrap(0, ix);
            let (y0, y1) = span(1, ta, tb);
            for iy in self.cells(1, y0, y1) {
                let (tc, td) = clip(1, iy, ta, tb);
                if tc > td {
                    continue;
                }
                let (wy, ky) = wrap(1, iy);
                let (z0, z1) = span(2, tc, td);
                for iz in self.cells(2, z0, z1) {
                    let (wz, kz) = wrap(2, iz);
                    f(self.index([wx, wy, wz]), kx << 4 | ky << 2 | kz);
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
fn image_of(code: u32) -> Offset {
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
/// Each rod is listed in the cells of a fine grid that its core, widened by
/// its radius, may meet (cells about a third of a mean rod long); pairs
/// sharing a cell are tested there, and a contact is kept in the one cell
/// holding its contact point.
/// The result does not depend on the number of rayon threads and equals
/// [`detect_all_pairs`].
pub fn detect(system: &RodSystem) -> Vec<Contact> {
    let geo = Geometry::of(system);
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
    let placed: Vec<Placed> = system.rods.iter().map(|r| geo.place(r)).collect();
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
            grid.cover(&p.center, &p.axis, p.half, p.radius, |cell, image| {
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
        let centre = grid.center(cell);
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
            let c = geo
                .space
                .image(&p.center, image_of(e & IMAGE_MASK).map(|s| -s));
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
                    let piece = |from: &Vector3<f64>, p: &Placed| {
                        let mid = p.axis.dot(&(centre - from));
                        ((mid - ball).max(-p.half), (mid + ball).min(p.half))
                    };
                    if !pieces_may_touch(
                        &pa.axis,
                        &pb.axis,
                        &(from_b - from_a),
                        piece(&from_a, pa),
                        piece(&from_b, pb),
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
