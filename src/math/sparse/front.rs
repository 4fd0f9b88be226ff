//! One dense front: the absorbed elements stacked over the groups they
//! touch, the front's own groups brought to echelon form, and what is left
//! passed on as a new element.
//!
//! The pivot rows are the front's share of the factor, kept only when
//! kernel vectors are wanted (the rank needs just their count). The other
//! rows are now zero on the own columns; those that are not zero at all go
//! on, reduced to echelon form first when they outnumber their columns
//! (then some are dependent, and without the reduction rows would pile up
//! front after front).

use rand::Rng;

use super::quotient::{Element, Gathered};
use crate::math::Field;
use crate::math::echelon::{Block, Modulus, Panel};

/// A front's pivot rows, for back substitution.
#[derive(Clone, Debug)]
pub struct Factor {
    /// The matrix column of each front column.
    pub cols: Vec<u32>,
    /// The front column of each pivot row's leading 1.
    pub pivots: Vec<u32>,
    /// The pivot rows as centred residues, row-major over `cols`.
    pub rows: Vec<f32>,
}

/// What one front did.
pub struct Done {
    pub pivots: usize,
    /// The front's rows and columns.
    pub size: (usize, usize),
    /// Multiply–adds of its echelon steps, at most.
    pub work: f64,
    pub factor: Option<Factor>,
    /// The rows left, grouped by the groups of the pattern they touch.
    pub left: Vec<Element>,
    /// Whether the rows left outnumbered their columns and were reduced.
    pub reduced: bool,
}

/// The rows and columns `front` will have: its elements' rows over the
/// columns of its groups not cleared by [`pin`].
pub fn size(front: &Gathered, scratch: &Scratch) -> (usize, usize) {
    let live = |g: &u32| scratch.width - scratch.dead[*g as usize].count_ones() as usize;
    let cols = front.own.iter().chain(&front.pattern).map(live).sum();
    (front.elements.iter().map(|e| e.rows).sum(), cols)
}

/// Eliminates the own groups of `front` over groups of `width` columns,
/// in `scratch` (reused from front to front).
pub fn eliminate(front: Gathered, width: usize, keep: bool, scratch: &mut Scratch) -> Done {
    let modulus = scratch.modulus;
    let Gathered {
        own,
        pattern,
        elements,
        ..
    } = front;
    // Front columns: the live columns of the own groups, then of the
    // pattern's; `place` gives each group column its front column.
    let groups: Vec<u32> = own.iter().chain(&pattern).copied().collect();
    let mut cols: Vec<u32> = Vec::with_capacity(groups.len() * width);
    let mut owncols = 0;
    for (k, &g) in groups.iter().enumerate() {
        scratch.local[g as usize] = k as u32;
        for j in 0..width {
            let live = scratch.dead[g as usize] & (1 << j) == 0;
            scratch.place[k * width + j] = if live { cols.len() as u32 } else { NONE };
            if live {
                cols.push(g * width as u32 + j as u32);
            }
        }
        if k + 1 == own.len() {
            owncols = cols.len();
        }
    }
    let ncols = cols.len();
    let nrows: usize = elements.iter().map(|e| e.rows).sum();
    let data = &mut scratch.dense;
    data.clear();
    data.resize(nrows * ncols, 0.0);
    let mut r = 0;
    // Each element is freed as soon as it is copied: the dense tail holds
    // every live row, and would otherwise be held twice at its peak.
    for e in elements {
        let ecols = e.groups.len() * width;
        let places: Vec<u32> = e
            .groups
            .iter()
            .flat_map(|&g| {
                let k = scratch.local[g as usize] as usize;
                scratch.place[k * width..(k + 1) * width].iter().copied()
            })
            .collect();
        for row in e.data.chunks_exact(ecols) {
            let dense = &mut data[r * ncols..(r + 1) * ncols];
            for (&at, &v) in places.iter().zip(row) {
                if at != NONE {
                    dense[at as usize] = v as f64;
                } else {
                    debug_assert_eq!(v, 0.0, "a cleared column");
                }
            }
            r += 1;
        }
    }
    let mut block = Block {
        data,
        rows: nrows,
        cols: ncols,
        modulus,
    };
    let mut pivots = Vec::new();
    let top = block.echelon_in(0, 0, owncols, &mut pivots, &mut scratch.panel);
    let mut work = (nrows * ncols * top) as f64;
    let factor = (keep && top > 0).then(|| Factor {
        cols: cols.clone(),
        pivots: pivots.iter().map(|&p| p as u32).collect(),
        rows: block.data[..top * ncols]
            .iter()
            .map(|&x| x as f32)
            .collect(),
    });
    let rest = ncols - owncols;
    let mut live: Vec<usize> = (top..nrows)
        .filter(|&i| !block.is_zero_row(i, owncols))
        .collect();
    let reduced = live.len() > rest;
    if reduced {
        let end = block.echelon_in(top, owncols, ncols, &mut Vec::new(), &mut scratch.panel);
        work += ((nrows - top) * ncols * (end - top)) as f64;
        live = (top..end).collect();
    }
    // Each row goes on over the groups it still touches (a row that is zero
    // on a group must not pull that group into later fronts); rows over
    // the same groups, usually all of them, go on as one element.
    let mut left: Vec<Element> = Vec::new();
    let mut touched = Vec::with_capacity(pattern.len());
    let mut full = vec![0.0; pattern.len() * width];
    let places = &scratch.place[own.len() * width..groups.len() * width];
    for &i in &live {
        let row = &block.data[i * ncols..(i + 1) * ncols];
        for (x, &at) in full.iter_mut().zip(places) {
            *x = if at == NONE { 0.0 } else { row[at as usize] };
        }
        let row = &full;
        touched.clear();
        touched.extend(
            row.chunks_exact(width)
                .enumerate()
                .filter(|(_, vals)| vals.iter().any(|&v| v != 0.0))
                .map(|(j, _)| j),
        );
        let groups: Vec<u32> = touched.iter().map(|&j| pattern[j]).collect();
        let e = match left.iter_mut().find(|e| e.groups == groups) {
            Some(e) => e,
            None => {
                left.push(Element {
                    groups,
                    rows: 0,
                    data: Vec::new(),
                });
                left.last_mut().expect("just pushed")
            }
        };
        for &j in &touched {
            e.data
                .extend(row[j * width..(j + 1) * width].iter().map(|&v| v as f32));
        }
        e.rows += 1;
    }
    Done {
        pivots: top,
        size: (nrows, ncols),
        work,
        factor,
        left,
        reduced,
    }
}

/// A group column that is not in the front (cleared before the order).
const NONE: u32 = u32::MAX;

/// Buffers reused from front to front, the field's modulus, and the columns
/// cleared by [`pin`].
pub struct Scratch {
    modulus: Modulus,
    width: usize,
    dense: Vec<f64>,
    /// Each group's place in the current front.
    local: Vec<u32>,
    /// Each group column's front column in the current front, or [`NONE`].
    place: Vec<u32>,
    /// Per group, a bit per column cleared by [`pin`].
    dead: Vec<u64>,
    panel: Panel,
}

impl Scratch {
    /// Bytes a front of `rows` x `cols` adds to the dense buffer, which
    /// keeps the largest front so far.
    pub fn growth(&self, rows: usize, cols: usize) -> usize {
        (rows * cols).saturating_sub(self.dense.capacity()) * 8
    }

    pub fn new(modulus: Modulus, groups: usize, width: usize) -> Scratch {
        assert!(width <= 64, "at most 64 columns per group, not {width}");
        Scratch {
            modulus,
            width,
            dense: Vec::new(),
            local: vec![0; groups],
            place: vec![NONE; groups * width],
            dead: vec![0; groups],
            panel: Panel::default(),
        }
    }
}

/// The rows of one group only, eliminated before the order starts.
pub struct Pinned {
    pub group: u32,
    /// The group columns of the pivots, and the pivot rows over the
    /// group's columns (each 1 at its pivot and zero before it).
    pub pivots: Vec<usize>,
    pub rows: Vec<f64>,
    pub factor: Option<Factor>,
}

/// Brings an element over a single group to echelon form. Its pivot
/// columns are then cleared from every other element of the group
/// ([`super::quotient::Quotient::clear_columns`]) and left out of every
/// front: a rod's spin row takes one of its six columns for good, which
/// makes every front holding the rod a column and a row smaller (a sixth
/// of the dense work is in those columns, cubed).
pub fn pin(e: Element, keep: bool, scratch: &mut Scratch) -> Pinned {
    let width = scratch.width;
    let [g] = e.groups[..] else {
        panic!("pin takes an element over one group, not {:?}", e.groups);
    };
    let mut data: Vec<f64> = e.data.iter().map(|&v| v as f64).collect();
    let mut pivots = Vec::new();
    let mut block = Block {
        data: &mut data,
        rows: e.rows,
        cols: width,
        modulus: scratch.modulus,
    };
    let top = block.echelon_in(0, 0, width, &mut pivots, &mut scratch.panel);
    data.truncate(top * width);
    for &c in &pivots {
        scratch.dead[g as usize] |= 1 << c;
    }
    let factor = (keep && top > 0).then(|| Factor {
        cols: (0..width as u32).map(|k| g * width as u32 + k).collect(),
        pivots: pivots.iter().map(|&p| p as u32).collect(),
        rows: data.iter().map(|&x| x as f32).collect(),
    });
    Pinned {
        group: g,
        pivots,
        rows: data,
        factor,
    }
}

/// Rows over one group's `width` columns (row-major) brought to echelon
/// form: the independent rows, and how many.
pub fn reduce(rows: &[f32], scratch: &mut Scratch) -> (Vec<f32>, usize) {
    let width = scratch.width;
    let mut data: Vec<f64> = rows.iter().map(|&v| v as f64).collect();
    let mut block = Block {
        data: &mut data,
        rows: rows.len() / width,
        cols: width,
        modulus: scratch.modulus,
    };
    let top = block.echelon_in(0, 0, width, &mut Vec::new(), &mut scratch.panel);
    let kept = data[..top * width].iter().map(|&x| x as f32).collect();
    (kept, top)
}

/// A uniformly random vector of the kernel of the factorized matrix over
/// `cols` columns with every column from `free` on held at zero: random
/// values on the other columns without a pivot, the pivot columns solved
/// from the last front back to the first.
pub fn kernel_vector<F: Field>(
    factors: &[Factor],
    cols: usize,
    free: usize,
    rng: &mut impl Rng,
) -> Vec<F> {
    let mut x: Vec<F> = (0..cols)
        .map(|c| if c < free { F::random(rng) } else { F::zero() })
        .collect();
    for f in factors.iter().rev() {
        let n = f.cols.len();
        for (t, &p) in f.pivots.iter().enumerate().rev() {
            let row = &f.rows[t * n..(t + 1) * n];
            let p = p as usize;
            let sum = row[p + 1..]
                .iter()
                .zip(&f.cols[p + 1..])
                .filter(|&(&v, _)| v != 0.0)
                .fold(F::zero(), |acc, (&v, &c)| {
                    acc + F::from_i64(v as i64) * x[c as usize]
                });
            x[f.cols[p] as usize] = -sum;
        }
    }
    x
}
