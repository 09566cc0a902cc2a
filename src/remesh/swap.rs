//! Edge swapping: the diagonal of two triangles that share an unconstrained edge is
//! flipped when that raises the worse of their two metric qualities. Constrained edges
//! (boundaries, interfaces) never flip, so face tags never mix.

use super::work::{key, orient, Work};

/// Relative gain a flip must bring (keeps sweeps from flipping back and forth on ties).
const GAIN: f64 = 1e-6;

/// One sweep over every unconstrained edge, in edge order. Returns the number of flips.
pub fn swap_sweep(w: &mut Work) -> usize {
    let mut n = 0;
    for (a, b) in w.edges() {
        if w.cons.contains_key(&key(a, b)) {
            continue;
        }
        if swap(w, a, b) {
            n += 1;
        }
    }
    n
}

/// Flips edge `ab` if allowed and better.
fn swap(w: &mut Work, a: u32, b: u32) -> bool {
    let (ts, k) = w.edge_tris(a, b);
    if k != 2 {
        return false;
    }
    // Orient so that t1 = (a, b, c) and t2 = (b, a, d).
    let rot = |v: [u32; 3], x: u32| -> [u32; 3] {
        let i = v.iter().position(|&y| y == x).unwrap_or(0);
        [v[i], v[(i + 1) % 3], v[(i + 2) % 3]]
    };
    let (mut t1, mut t2) = (ts[0], ts[1]);
    let mut v1 = rot(w.tris[t1 as usize], a);
    if v1[1] != b {
        std::mem::swap(&mut t1, &mut t2);
        v1 = rot(w.tris[t1 as usize], a);
    }
    let v2 = rot(w.tris[t2 as usize], b);
    if v1[1] != b || v2[1] != a {
        return false;
    }
    let (c, d) = (v1[2], v2[2]);
    if c == d || w.face[t1 as usize] != w.face[t2 as usize] {
        return false;
    }
    let (n1, n2) = ([c, a, d], [d, b, c]);
    let p = |v: [u32; 3]| v.map(|x| w.pts[x as usize]);
    let (q1, q2) = (p(n1), p(n2));
    if orient(q1[0], q1[1], q1[2]) <= 0.0 || orient(q2[0], q2[1], q2[2]) <= 0.0 {
        return false;
    }
    let old = w.quality(t1).min(w.quality(t2));
    let new = w.quality_of(n1).min(w.quality_of(n2));
    if new <= old * (1.0 + GAIN) {
        return false;
    }
    if w.vtris[c as usize].iter().any(|&t| w.tris[t as usize].contains(&d)) {
        return false; // cd is already an edge
    }
    w.tris[t1 as usize] = n1;
    w.tris[t2 as usize] = n2;
    w.detach(b, t1);
    w.vtris[d as usize].push(t1);
    w.detach(a, t2);
    w.vtris[c as usize].push(t2);
    true
}
