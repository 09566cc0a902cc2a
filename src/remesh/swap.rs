//! Edge swapping: the diagonal of two triangles that share an unconstrained edge is
//! flipped when that raises the worse of their two metric qualities. Constrained edges
//! (boundaries, interfaces) never flip, so face tags never mix.

use super::work::{key, orient, Work};

/// Relative gain a flip must bring (keeps sweeps from flipping back and forth on ties).
const GAIN: f64 = 1e-6;

/// Sweeps of flips until none is left or `max_sweeps` ran: the first sweep tries the
/// edges around every vertex whose ball changed since the last swap phase (all of them
/// the first time), the next ones only the edges around the vertices a flip touched
/// (sorted, so the order is fixed). Returns the number of flips.
pub fn swap_sweeps(w: &mut Work, max_sweeps: usize, everything: bool) -> usize {
    let mut n = 0;
    let dirty = w.take_dirty();
    let mut todo = if everything { w.edges() } else { w.edges_around(&dirty) };
    let mut touched = vec![false; w.pts.len()];
    for _ in 0..max_sweeps {
        let mut hit: Vec<u32> = Vec::new();
        for &(a, b) in &todo {
            if w.cons.contains_key(&key(a, b)) {
                continue;
            }
            if let Some([c, d]) = swap(w, a, b) {
                n += 1;
                for x in [a, b, c, d] {
                    if !touched[x as usize] {
                        touched[x as usize] = true;
                        hit.push(x);
                    }
                }
            }
        }
        if hit.is_empty() {
            break;
        }
        for &x in &hit {
            touched[x as usize] = false;
        }
        todo = w.edges_around(&hit);
    }
    n
}

/// Flips edge `ab` if allowed and better; the new diagonal's ends when it did.
fn swap(w: &mut Work, a: u32, b: u32) -> Option<[u32; 2]> {
    let (ts, k) = w.edge_tris(a, b);
    if k != 2 {
        return None;
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
        return None;
    }
    let (c, d) = (v1[2], v2[2]);
    if c == d || w.face[t1 as usize] != w.face[t2 as usize] {
        return None;
    }
    let (n1, n2) = ([c, a, d], [d, b, c]);
    let p = |v: [u32; 3]| v.map(|x| w.pts[x as usize]);
    let (q1, q2) = (p(n1), p(n2));
    if orient(q1[0], q1[1], q1[2]) <= 0.0 || orient(q2[0], q2[1], q2[2]) <= 0.0 {
        return None;
    }
    let old = w.quality(t1).min(w.quality(t2));
    let new = w.quality_of(n1).min(w.quality_of(n2));
    if new <= old * (1.0 + GAIN) {
        return None;
    }
    if w.vtris[c as usize].iter().any(|&t| w.tris[t as usize].contains(&d)) {
        return None; // cd is already an edge
    }
    w.tris[t1 as usize] = n1;
    w.tris[t2 as usize] = n2;
    w.detach(b, t1);
    w.vtris[d as usize].push(t1);
    w.detach(a, t2);
    w.vtris[c as usize].push(t2);
    Some([c, d])
}
