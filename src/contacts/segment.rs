//! Closest points of two segments, robust for (nearly) parallel ones, where
//! the textbook 2x2 solve breaks down.

use nalgebra::Vector3;

/// Closest points of two segments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    /// Squared distance between the closest points.
    pub dist2: f64,
    /// Parameter on the first segment.
    pub s: f64,
    /// Parameter on the second segment.
    pub t: f64,
}

/// Below this `|u x v|^2 / (|u|^2 |v|^2)` (an angle under 1e-10 rad) the
/// interior critical point is not evaluated: the boundary then misses the true
/// minimum by at most about the angle itself, far below any length that matters.
const PARALLEL_SIN2: f64 = 1e-20;

/// Closest points of the segments `p + s u`, `s` in `[-hu, hu]`, and
/// `q + t v`, `t` in `[-hv, hv]`, for unit vectors `u` and `v`.
///
/// Robust for (nearly) parallel segments, where the textbook 2x2 solve breaks
/// down: the four edges of the parameter rectangle are each an exact 1-D clamp,
/// the interior critical point is tried only when the system is well
/// conditioned (and then only for `s`, with `t` re-minimized exactly), and the
/// candidate with the smallest directly computed distance wins. Exactly
/// parallel overlapping segments have many minimizers; the first candidate in
/// the fixed order (interior, `s = -hu`, `s = hu`, `t = -hv`, `t = hv`) wins.
pub fn closest_points(
    p: &Vector3<f64>,
    u: &Vector3<f64>,
    hu: f64,
    q: &Vector3<f64>,
    v: &Vector3<f64>,
    hv: f64,
) -> Closest {
    // f(s, t) = |s u - t v - w|^2 with w = q - p.
    let w = q - p;
    let a = u.norm_squared();
    let c = v.norm_squared();
    let b = u.dot(v);
    let d = u.dot(&w);
    let e = v.dot(&w);
    let eval = |s: f64, t: f64| Closest {
        dist2: (u * s - v * t - w).norm_squared(),
        s,
        t,
    };
    let t_for = |s: f64| ((s * b - e) / c).clamp(-hv, hv);
    let s_for = |t: f64| ((t * b + d) / a).clamp(-hu, hu);

    let mut best: Option<Closest> = None;
    let mut offer = |cand: Closest| {
        if best.is_none_or(|b| cand.dist2 < b.dist2) {
            best = Some(cand);
        }
    };
    // Lagrange's identity: |u x v|^2 = a c - b^2, without the cancellation.
    let n = u.cross(v);
    let n2 = n.norm_squared();
    if n2 > PARALLEL_SIN2 * a * c {
        // s of the lines' common perpendicular. Its error grows like
        // eps / angle but lies along the near-flat valley of f, and taking t
        // exactly from s keeps the distance error at rounding level.
        let s = (w.cross(v).dot(&n) / n2).clamp(-hu, hu);
        offer(eval(s, t_for(s)));
    }
    for s in [-hu, hu] {
        offer(eval(s, t_for(s)));
    }
    for t in [-hv, hv] {
        offer(eval(s_for(t), t));
    }
    best.unwrap_or(Closest {
        dist2: f64::NAN,
        s: 0.0,
        t: 0.0,
    })
}
