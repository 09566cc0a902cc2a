//! The analytic 3D metric the 3D metric tests share, written without the library: sizes
//! 0.4, 0.2 and 0.05 + 0.1 x along a frame turned 0.7 rad about (1, 2, 3), so that no
//! axis is a coordinate axis and a tensor read in the wrong order shows.

use smartmesh::metric::Sym3;

/// The rotation by `angle` about the unit axis along `axis`, its columns the frame.
pub(crate) fn frame(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let [x, y, z] = axis.map(|a| a / n);
    let (c, s) = (angle.cos(), angle.sin());
    let t = 1.0 - c;
    let r = [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ];
    // The columns of r, an orthonormal frame.
    [0, 1, 2].map(|j| [r[0][j], r[1][j], r[2][j]])
}

/// The field: sizes 0.4, 0.2 and 0.05 + 0.1 x along a frame turned 0.7 rad about
/// (1, 2, 3), written as M = Σ eᵢ eᵢᵀ / hᵢ² without the library.
pub(crate) fn analytic(p: [f64; 3]) -> Sym3 {
    let f = frame([1.0, 2.0, 3.0], 0.7);
    let h = [0.4, 0.2, 0.05 + 0.1 * p[0]];
    let mut m = [[0.0; 3]; 3];
    for k in 0..3 {
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += f[k][i] * f[k][j] / (h[k] * h[k]);
            }
        }
    }
    Sym3 { xx: m[0][0], xy: m[0][1], yy: m[1][1], xz: m[0][2], yz: m[1][2], zz: m[2][2] }
}

/// The UGAWG metric length of the edge from `pa` to `pb` in [`analytic`]: the log-mean
/// (la − lb)/ln(la/lb) of its lengths in the metrics at its ends.
pub(crate) fn edge_length(pa: [f64; 3], pb: [f64; 3]) -> f64 {
    let e = [pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]];
    let l = |m: Sym3| {
        let r = m.rows();
        (0..3).map(|i| (0..3).map(|j| e[i] * r[i][j] * e[j]).sum::<f64>()).sum::<f64>().sqrt()
    };
    let (la, lb) = (l(analytic(pa)), l(analytic(pb)));
    if (la / lb - 1.0).abs() < 1e-9 {
        0.5 * (la + lb)
    } else {
        (la - lb) / (la / lb).ln()
    }
}

/// The metric lengths of the edges of the cells of `kind` in `mesh` (each once), sorted.
pub(crate) fn edge_lengths(
    mesh: &smartmesh::formats::TaggedMesh,
    kind: smartmesh::formats::CellKind,
) -> Vec<f64> {
    let mut edges = std::collections::BTreeSet::new();
    for (k, n, _, _) in mesh.cells() {
        if k != kind {
            continue;
        }
        for i in 0..n.len() {
            for j in i + 1..n.len() {
                edges.insert((n[i].min(n[j]), n[i].max(n[j])));
            }
        }
    }
    let mut out: Vec<f64> = edges
        .iter()
        .map(|&(a, b)| edge_length(mesh.points[a as usize], mesh.points[b as usize]))
        .collect();
    out.sort_by(f64::total_cmp);
    out
}
