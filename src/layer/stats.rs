//! Quality of the quads of a mixed mesh, and of its skin layer by layer.
//!
//! Layers are found from the cells alone (no data array needed, so any file works): a
//! quad with an edge on the boundary, across which it is no higher than that edge is
//! long, is in layer 0, that edge its bottom; the quad across
//! a layer-k quad's opposite edge is in layer k + 1 with that edge its bottom. A quad's
//! height is the distance between the midpoints of its bottom and top edges; the growth
//! ratio achieved is a quad's height over the height of the quad below it. Quads reached
//! from no wall (above a fan's triangles, say) count in the overall figures only.
//!
//! Figures (as Verdict defines them for quads): scaled Jacobian, the smallest over the
//! corners of the cross product of the two edges over their lengths (1 for a rectangle,
//! ≤ 0 for an inverted corner); equiangle skewness, max((θmax − 90°)/90°, (90° − θmin)/90°);
//! aspect ratio, the mean length of the longer pair of opposite edges over the shorter.

use std::collections::BTreeMap;

use smartmesh_formats::{CellKind, TaggedMesh};

use crate::geometry::plane::{cross, dot, norm, sub, P};

/// Figures of one layer.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LayerLevel {
    /// Quads in the layer.
    pub quads: usize,
    /// Smallest, mean and largest height.
    pub height: [f64; 3],
    /// Smallest, mean and largest ratio to the layer below (none for layer 0).
    pub ratio: Option<[f64; 3]>,
}

/// Quality of the quads.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct QuadQuality {
    /// Quads.
    pub quads: usize,
    /// Quads reached from a wall, by layer.
    pub layers: Vec<LayerLevel>,
    /// Smallest scaled Jacobian.
    pub min_scaled_jacobian: f64,
    /// Largest equiangle skewness.
    pub max_skewness: f64,
    /// Smallest, mean and largest aspect ratio.
    pub aspect_ratio: [f64; 3],
}

/// Scaled Jacobian, skewness and aspect ratio of a quad.
pub fn quad_figures(q: [P; 4]) -> (f64, f64, f64) {
    let mut sj = f64::INFINITY;
    let mut skew: f64 = 0.0;
    for i in 0..4 {
        let a = sub(q[(i + 1) % 4], q[i]);
        let b = sub(q[(i + 3) % 4], q[i]);
        let (la, lb) = (norm(a), norm(b));
        let s = if la * lb > 0.0 { cross(a, b) / (la * lb) } else { 0.0 };
        sj = sj.min(s);
        let ang = cross(a, b).atan2(dot(a, b)).to_degrees();
        let ang = if ang < 0.0 { ang + 360.0 } else { ang };
        skew = skew.max(((ang - 90.0) / 90.0).max((90.0 - ang) / 90.0));
    }
    let l: Vec<f64> = (0..4).map(|i| norm(sub(q[(i + 1) % 4], q[i]))).collect();
    let (p, r) = (0.5 * (l[0] + l[2]), 0.5 * (l[1] + l[3]));
    let ar = if p.min(r) > 0.0 { p.max(r) / p.min(r) } else { f64::INFINITY };
    (sj, skew, ar)
}

fn three(v: &[f64]) -> [f64; 3] {
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    [lo, v.iter().sum::<f64>() / v.len().max(1) as f64, hi]
}

/// The quality of the quads of `mesh`, `None` when it has none.
pub fn quad_quality(mesh: &TaggedMesh) -> Option<QuadQuality> {
    let pts: Vec<P> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
    let quads: Vec<[usize; 4]> = mesh
        .blocks
        .iter()
        .filter(|b| b.kind == CellKind::Quad)
        .flat_map(|b| {
            b.cells().map(|c| [c[0] as usize, c[1] as usize, c[2] as usize, c[3] as usize])
        })
        .collect();
    if quads.is_empty() {
        return None;
    }
    let key = |a: usize, b: usize| [a.min(b), a.max(b)];
    // Edge -> cells using it (quads as `Some(index)`, other surface cells as `None`).
    let mut by_edge: BTreeMap<[usize; 2], Vec<Option<usize>>> = BTreeMap::new();
    for (i, q) in quads.iter().enumerate() {
        for k in 0..4 {
            by_edge.entry(key(q[k], q[(k + 1) % 4])).or_default().push(Some(i));
        }
    }
    for (kind, nodes, _, _) in mesh.cells() {
        if kind == CellKind::Triangle {
            for k in 0..3 {
                by_edge
                    .entry(key(nodes[k] as usize, nodes[(k + 1) % 3] as usize))
                    .or_default()
                    .push(None);
            }
        }
    }
    let mut level: Vec<Option<(usize, usize, f64)>> = vec![None; quads.len()]; // (layer, bottom side, height)
    let height = |q: &[usize; 4], s: usize| -> f64 {
        let mid =
            |a: usize, b: usize| [(pts[a][0] + pts[b][0]) / 2.0, (pts[a][1] + pts[b][1]) / 2.0];
        norm(sub(mid(q[(s + 2) % 4], q[(s + 3) % 4]), mid(q[s], q[(s + 1) % 4])))
    };
    let mut front: Vec<(usize, usize)> = Vec::new();
    for (i, q) in quads.iter().enumerate() {
        // The boundary edge across which the quad is thinnest, if it is thinner than
        // that edge is long (a skin's side is a boundary edge too, but across it a quad
        // is a whole wall edge wide).
        let best = (0..4)
            .filter(|&s| by_edge[&key(q[s], q[(s + 1) % 4])].len() == 1)
            .map(|s| (height(q, s), s))
            .filter(|&(h, s)| h <= norm(sub(pts[q[(s + 1) % 4]], pts[q[s]])))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((h, s)) = best {
            level[i] = Some((0, s, h));
            front.push((i, s));
        }
    }
    let mut below: Vec<Option<usize>> = vec![None; quads.len()];
    let mut k = 0;
    while !front.is_empty() {
        let mut next = Vec::new();
        for (i, s) in front {
            let q = quads[i];
            let top = key(q[(s + 2) % 4], q[(s + 3) % 4]);
            for j in by_edge[&top].iter().flatten().copied() {
                if j == i || level[j].is_some() {
                    continue;
                }
                let r = quads[j];
                if let Some(t) = (0..4).find(|&t| key(r[t], r[(t + 1) % 4]) == top) {
                    level[j] = Some((k + 1, t, height(&r, t)));
                    below[j] = Some(i);
                    next.push((j, t));
                }
            }
        }
        front = next;
        k += 1;
    }
    let mut layers: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
    for (i, l) in level.iter().enumerate() {
        if let Some((k, _, h)) = *l {
            if layers.len() <= k {
                layers.resize(k + 1, (Vec::new(), Vec::new()));
            }
            layers[k].0.push(h);
            if let Some(b) = below[i] {
                let hb = level[b].map_or(0.0, |x| x.2);
                if hb > 0.0 {
                    layers[k].1.push(h / hb);
                }
            }
        }
    }
    let (mut sj, mut sk, mut ar) = (f64::INFINITY, 0.0f64, Vec::with_capacity(quads.len()));
    for q in &quads {
        let (a, b, c) = quad_figures(q.map(|v| pts[v]));
        sj = sj.min(a);
        sk = sk.max(b);
        ar.push(c);
    }
    Some(QuadQuality {
        quads: quads.len(),
        layers: layers
            .into_iter()
            .map(|(h, r)| LayerLevel {
                quads: h.len(),
                height: three(&h),
                ratio: (!r.is_empty()).then(|| three(&r)),
            })
            .collect(),
        min_scaled_jacobian: sj,
        max_skewness: sk,
        aspect_ratio: three(&ar),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_of_a_rectangle_and_a_rhombus() {
        let (sj, sk, ar) = quad_figures([[0.0, 0.0], [4.0, 0.0], [4.0, 1.0], [0.0, 1.0]]);
        assert!((sj - 1.0).abs() < 1e-15 && sk.abs() < 1e-12 && (ar - 4.0).abs() < 1e-15);
        let s = 0.5f64.sqrt();
        let (sj, sk, _) = quad_figures([[0.0, 0.0], [1.0, 0.0], [1.0 + s, s], [s, s]]);
        assert!((sj - s).abs() < 1e-12, "{sj}");
        assert!((sk - 0.5).abs() < 1e-12, "45° corners: skewness 0.5, got {sk}");
    }
}
