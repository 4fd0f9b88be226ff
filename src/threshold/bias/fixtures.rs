//! Hand-made records for the tests of bias: the nested protocol's search
//! replayed on a known critical number, and truth undecided.

use crate::threshold::fss::ContactPoint;
use crate::threshold::sequence::{Record, Step};

/// A nested record that [`Record::check`] accepts: the bisection of the
/// nested protocol (first guess `2 n_c`, growth 1.25, then halving)
/// replayed on "spans from `n_r` rods on".
pub fn nested(box_len: f64, index: u64, seed: u64, n_c: usize, n_r: usize) -> Record {
    let (mut lo, mut hi, mut probe) = (n_c - 1, None, 2 * n_c);
    let mut steps = Vec::new();
    loop {
        let n = match hi {
            None => probe,
            Some(h) if h - lo > 1 => lo + (h - lo) / 2,
            Some(_) => break,
        };
        let spans = n >= n_r;
        steps.push(Step::new(n, spans, usize::from(spans)));
        if spans {
            hi = Some(n);
        } else {
            lo = n;
            if hi.is_none() {
                probe = (n as f64 * 1.25).ceil() as usize;
            }
        }
    }
    assert_eq!(hi, Some(n_r), "the search ends at the critical number");
    Record {
        box_len,
        index,
        seed,
        contact_critical: n_c,
        rigid_critical: Some(n_r),
        steps,
        fresh: Some(Step::new(n_r, true, 1)),
        fixed: vec![],
        contacts: vec![ContactPoint {
            density: n_r as f64 / box_len.powi(3),
            c0: 4.0,
            c1: 4.5,
            c2: 5.0,
        }],
        undecided: None,
        seconds: 1.0,
        peak_rss_mib: 0.0,
        cpu_seconds: None,
    }
}

/// A truth record undecided at its first guess (`2 n_c` rods).
pub fn undecided(box_len: f64, index: u64, seed: u64, n_c: usize) -> Record {
    Record {
        rigid_critical: None,
        steps: vec![],
        fresh: None,
        contacts: vec![],
        undecided: Some(2 * n_c),
        ..nested(box_len, index, seed, n_c, 2 * n_c)
    }
}
