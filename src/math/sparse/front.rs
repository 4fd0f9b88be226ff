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
use crate::math::echelon::{Block, Modulus};

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
    let ngroups = own.len() + pattern.len();
    let ncols = ngroups * width;
    let owncols = own.len() * width;
    for (k, &g) in own.iter().chain(&pattern).enumerate() {
        scratch.local[g as usize] = k as u32;
    }
    let nrows: usize = elements.iter().map(|e| e.rows).sum();
    let data = &mut scratch.dense;
    data.clear();
    data.resize(nrows * ncols, 0.0);
    let mut r = 0;
    // Each element is freed as soon as it is copied: the dense tail holds
    // every live row, and would otherwise be held twice at its peak.
    for e in elements {
        let ecols = e.groups.len() * width;
        let places: Vec<usize> = e
            .groups
            .iter()
            .map(|&g| scratch.local[g as usize] as usize * width)
            .collect();
        for row in e.data.chunks_exact(ecols) {
            let dense = &mut data[r * ncols..(r + 1) * ncols];
            for (j, &at) in places.iter().enumerate() {
                for (x, &v) in dense[at..at + width]
                    .iter_mut()
                    .zip(&row[j * width..(j + 1) * width])
                {
                    *x = v as f64;
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
    let top = block.echelon(0, 0, owncols, &mut pivots);
    let mut work = (nrows * ncols * top) as f64;
    let factor = (keep && top > 0).then(|| Factor {
        cols: own
            .iter()
            .chain(&pattern)
            .flat_map(|&g| (0..width as u32).map(move |k| g * width as u32 + k))
            .collect(),
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
        let end = block.echelon(top, owncols, ncols, &mut Vec::new());
        work += ((nrows - top) * ncols * (end - top)) as f64;
        live = (top..end).collect();
    }
    // Each row goes on over the groups it still touches (a row that is zero
    // on a group must not pull that group into later fronts); rows over
    // the same groups, usually all of them, go on as one element.
    let mut left: Vec<Element> = Vec::new();
    let mut touched = Vec::with_capacity(pattern.len());
    for &i in &live {
        let row = &block.data[i * ncols + owncols..(i + 1) * ncols];
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

/// Buffers reused from front to front, and the field's modulus.
pub struct Scratch {
    modulus: Modulus,
    dense: Vec<f64>,
    /// Each group's place in the current front.
    local: Vec<u32>,
}

impl Scratch {
    pub fn new(modulus: Modulus, groups: usize) -> Scratch {
        Scratch {
            modulus,
            dense: Vec::new(),
            local: vec![0; groups],
        }
    }
}

/// A uniformly random vector of the kernel of the factorized matrix over
/// `cols` columns: random values on the columns without a pivot, the
/// pivot columns solved from the last front back to the first.
pub fn kernel_vector<F: Field>(factors: &[Factor], cols: usize, rng: &mut impl Rng) -> Vec<F> {
    let mut x: Vec<F> = (0..cols).map(|_| F::random(rng)).collect();
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
