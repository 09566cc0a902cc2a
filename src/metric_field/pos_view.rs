//! A Gmsh post-processing view (`.pos`, the parsed format) read as a metric field, the
//! way `gmsh -bgm X.pos` takes a background mesh. The syntax, the records and their
//! counts are the formats crate's ([`smartmesh_formats::gmsh::pos`]); this module says what a
//! view means as a metric.
//!
//! What is read, and why:
//! - Only the **last** view, as `gmsh -bgm` uses the last view of the file it merges;
//!   of it, the tensor triangles and quadrangles (`TT`, `TQ`, quadrangles split along
//!   their first diagonal) at their first time step. The other records of that view are
//!   read for their syntax and left aside; a view without `TT` or `TQ` is refused (a scalar
//!   or vector view is not a metric).
//! - A view is given at positions, not at a mesh's vertices. Records sharing a node at the
//!   same (x, y) are joined there; where records disagree at a node, the first record in
//!   the file gives it (Gmsh's octree would take whichever element it finds first). Every
//!   node's tensor must be a metric (its xy block finite, symmetric, positive definite).
//! - At a mesh vertex that is a node of the view (bit for bit, as `smartmesh size -o X.pos`
//!   writes the mesh's own vertices in shortest round-trip decimals) the field is that
//!   node's tensor, so the `.pos` carries exactly what a `.vtu` of the same field does.
//!   Elsewhere it is interpolated in the view's triangle holding the vertex, Log-Euclidean
//!   as the remesher interpolates, and outside every triangle at the closest point of the
//!   nearest one. Gmsh interpolates the nine components linearly in the element (within a
//!   tolerance of 0.05 in reference coordinates) and leaves a point outside every element
//!   without a metric; both agree at the view's nodes, and the Log-Euclidean mean keeps
//!   sizes geometric and every tensor SPD.

use std::collections::BTreeMap;
use std::path::Path;

use crate::metric::Sym2;
use smartmesh_formats::gmsh::pos::{self, Element, Field, Item};
use smartmesh_formats::{CellKind, Error, ErrorKind, TaggedMesh, MAX_POINTS};

use super::not_a_metric;

/// The tensor faces of a view: nodes joined by position, one metric per node.
#[derive(Debug, Clone)]
pub(crate) struct View {
    name: String,
    points: Vec<[f64; 2]>,
    tensors: Vec<Sym2>,
    tris: Vec<[usize; 3]>,
    /// Node of each position, keyed on the bits of (x, y) (−0 read as +0).
    index: BTreeMap<(u64, u64), usize>,
}

fn key(p: [f64; 2]) -> (u64, u64) {
    ((p[0] + 0.0).to_bits(), (p[1] + 0.0).to_bits())
}

impl View {
    /// The view's name.
    pub(crate) fn name(&self) -> &str {
        &self.name
    }

    /// The metric at each of `points` (see the module documentation).
    pub(crate) fn at(&self, points: &[[f64; 2]]) -> Vec<Sym2> {
        let mut out = Vec::with_capacity(points.len());
        let mut missing = Vec::new();
        for (i, &p) in points.iter().enumerate() {
            match self.index.get(&key(p)) {
                Some(&n) => out.push(self.tensors[n]),
                None => {
                    missing.push(i);
                    out.push(Sym2::IDENTITY);
                }
            }
        }
        if !missing.is_empty() {
            let (mesh, _) = self.clone().into_mesh();
            let at: Vec<[f64; 2]> = missing.iter().map(|&i| points[i]).collect();
            // The view has one tensor per point and at least one triangle (`parse`
            // refuses it otherwise), the two things the interpolation can refuse.
            if let Ok(values) = super::interpolate::interpolate(&mesh, &self.tensors, &at) {
                for (&i, m) in missing.iter().zip(values) {
                    out[i] = m;
                }
            }
        }
        out
    }

    /// The view as a triangle mesh (z = 0, untagged) and its metric at each point.
    pub(crate) fn into_mesh(self) -> (TaggedMesh, Vec<Sym2>) {
        let mut mesh = TaggedMesh::new();
        mesh.points = self.points.iter().map(|p| [p[0], p[1], 0.0]).collect();
        let block = mesh.block_mut(CellKind::Triangle);
        for t in &self.tris {
            block.push(t, 0, 0);
        }
        (mesh, self.tensors)
    }
}

/// Reads the `.pos` file at `path`.
pub(crate) fn read_path(path: &Path) -> Result<View, Error> {
    let bytes = std::fs::read(path).map_err(|e| Error::from(e).with_path(path))?;
    parse(&bytes).map_err(|e| e.with_path(path))
}

/// One view being read: its name and its tensor faces.
struct Faces {
    name: String,
    points: Vec<[f64; 2]>,
    tensors: Vec<Sym2>,
    tris: Vec<[usize; 3]>,
    index: BTreeMap<(u64, u64), usize>,
}

impl Faces {
    /// Adds a `TT` or `TQ` record (`n` nodes) read at `line`.
    fn add(&mut self, n: usize, coords: &[f64], values: &[f64], line: u64) -> Result<(), Error> {
        let mut ids = [0usize; 4];
        for k in 0..n {
            let p = [coords[3 * k], coords[3 * k + 1]];
            let t = &values[9 * k..9 * k + 9];
            let (a, b, b2, c) = (t[0], t[1], t[3], t[4]);
            if let Some(why) = not_a_metric(a, b, b2, c) {
                return Err(Error::at_line(
                    line,
                    ErrorKind::Inconsistent(format!(
                        "the tensor at node {} of the record is not a metric: [[{a}, {b}], [{b2}, {c}]] is {why}",
                        k + 1
                    )),
                ));
            }
            ids[k] = match self.index.get(&key(p)) {
                Some(&i) => i,
                None => {
                    if self.points.len() >= MAX_POINTS {
                        return Err(Error::at_line(
                            line,
                            ErrorKind::Unsupported(format!(
                                "a view of more than {MAX_POINTS} distinct nodes"
                            )),
                        ));
                    }
                    let i = self.points.len();
                    self.points.push(p);
                    self.tensors.push(Sym2::new(a, 0.5 * (b + b2), c));
                    self.index.insert(key(p), i);
                    i
                }
            };
        }
        let mut push = |t: [usize; 3]| {
            let [a, b, c] = t.map(|i| self.points[i]);
            let d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            // A flat triangle locates nothing (its barycentric coordinates divide by 0).
            if d != 0.0 && d.is_finite() {
                self.tris.push(t);
            }
        };
        push([ids[0], ids[1], ids[2]]);
        if n == 4 {
            push([ids[0], ids[2], ids[3]]);
        }
        Ok(())
    }
}

/// Reads the last view of a `.pos` file's bytes (see the module documentation).
pub(crate) fn parse(bytes: &[u8]) -> Result<View, Error> {
    let mut current: Option<(Faces, u64)> = None;
    let mut last: Option<(Faces, u64)> = None;
    pos::read_bytes(bytes, &mut |item| {
        match item {
            Item::View { name, line } => {
                let faces = Faces {
                    name: name.to_string(),
                    points: Vec::new(),
                    tensors: Vec::new(),
                    tris: Vec::new(),
                    index: BTreeMap::new(),
                };
                current = Some((faces, line));
            }
            Item::Record(r) => {
                let face = matches!(r.element, Element::Triangle | Element::Quadrangle);
                if let (Field::Tensor, true, Some((faces, _))) = (r.field, face, current.as_mut()) {
                    let n = r.element.nodes();
                    faces.add(n, r.coords, &r.values[..9 * n], r.line)?;
                }
            }
            Item::EndView => last = current.take(),
        }
        Ok(())
    })?;
    let Some((faces, line)) = last else {
        return Err(Error::at_line(
            1,
            ErrorKind::Inconsistent(
                "no view: a metric view is `View \"name\" { TT(...){...}; ... };`".into(),
            ),
        ));
    };
    if faces.tris.is_empty() {
        return Err(Error::at_line(
            line,
            ErrorKind::Inconsistent(format!(
                "view `{}` (the last of the file, the one `gmsh -bgm` uses) holds no tensor triangle or quadrangle (TT, TQ) of non-zero area: a scalar or vector view is not a metric",
                faces.name
            )),
        ));
    }
    Ok(View {
        name: faces.name,
        points: faces.points,
        tensors: faces.tensors,
        tris: faces.tris,
        index: faces.index,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: &str = "// a comment\nView \"metric\" {\n\
        TT(0,0,0, 1,0,0, 1,1,0){4,0,0,0,4,0,0,0,1, 16,0,0,0,16,0,0,0,1, 4,1,0,1,4,0,0,0,1};\n\
        /* a quadrangle */ TQ(0,0,0,1,1,0,0,1,0,-1,0.5,0){4,0,0,0,4,0,0,0,1, 9,0,0,0,9,0,0,0,1, 1,0,0,0,1,0,0,0,1, 1,0,0,0,1,0,0,0,1};\n\
        SP(0.5,0.5,0){3};\n};\n";

    #[test]
    fn nodes_are_joined_and_matched_exactly() {
        let v = parse(SQUARE.as_bytes()).unwrap();
        assert_eq!(v.name(), "metric");
        // (0,0), (1,0), (1,1) from TT; (0,1), (-1,0.5) new from TQ; (1,1) keeps TT's.
        assert_eq!(v.points.len(), 5);
        assert_eq!(v.tris.len(), 3);
        let at = v.at(&[[1.0, 0.0], [-0.0, 0.0], [1.0, 1.0]]);
        assert_eq!(at[0], Sym2::new(16.0, 0.0, 16.0));
        assert_eq!(at[1], Sym2::new(4.0, 0.0, 4.0));
        assert_eq!(at[2], Sym2::new(4.0, 1.0, 4.0), "the first record gives a shared node");
    }

    #[test]
    fn between_nodes_the_mean_is_log_euclidean() {
        let v = parse(SQUARE.as_bytes()).unwrap();
        // On the edge (0,0)-(1,0) halfway: sizes 1/2 and 1/4 give 1/√8, metric 8.
        let m = v.at(&[[0.5, 0.0]])[0];
        assert!((m.a - 8.0).abs() < 1e-12 && m.b.abs() < 1e-12 && (m.c - 8.0).abs() < 1e-12);
        // Far outside: the nearest triangle's value at its closest point, (1, 0).
        let m = v.at(&[[5.0, -3.0]])[0];
        assert!((m.a - 16.0).abs() < 1e-9, "{m:?}");
    }

    #[test]
    fn the_last_view_is_taken() {
        let two = format!("{SQUARE}View \"second\" {{ TT(0,0,0,2,0,0,0,2,0){{1,0,0,0,1,0,0,0,1,1,0,0,0,1,0,0,0,1,1,0,0,0,1,0,0,0,1}}; }};");
        let v = parse(two.as_bytes()).unwrap();
        assert_eq!(v.name(), "second");
        let m = v.at(&[[1.0, 0.0]])[0];
        assert!((m.a - 1.0).abs() < 1e-15 && m.b.abs() < 1e-15 && (m.c - 1.0).abs() < 1e-15);
    }

    #[test]
    fn bad_views_name_the_line() {
        // The syntax's own errors are the formats crate's (`gmsh::pos`); these are the
        // metric's, and one of the syntax's to show it comes through with its line.
        let cases: [(&str, u64, &str); 5] = [
            ("", 1, "no view"),
            ("View \"s\" {\nST(0,0,0,1,0,0,0,1,0){1,1,1};\n};", 1, "not a metric"),
            ("View \"s\" {\n\nTT(0,0,0,1,0,0,0,1,0){-1,0,0,0,1,0,0,0,1,1,0,0,0,1,0,0,0,1,1,0,0,0,1,0,0,0,1};};", 3, "not positive definite"),
            ("View \"s\" {\nTT(0,0,0,1,0,0,0,1,0){1,2};\n};", 2, "multiple of 27"),
            ("View \"s\" {\nTT(0,0,0,1,0,0,0,1,0){1,0,0,0,1,0,0,0,1,1,0,0,0,1,0,0,0,1,1,0,0,0,1,0,0,0,1};\n}", 3, "expected `;`"),
        ];
        for (text, line, what) in cases {
            let e = parse(text.as_bytes()).unwrap_err();
            let s = e.to_string();
            assert!(s.contains(what), "{text:?}: {s}");
            assert_eq!(e.at, Some(smartmesh_formats::Position::Line(line)), "{text:?}: {s}");
        }
    }

    #[test]
    fn arbitrary_bytes_never_panic() {
        use smartmesh_test_support::{Generator, SplitMix64};
        let mut g = SplitMix64(17);
        let alphabet = b"View\"{}(),;TQST0123456789.-e/* \n";
        for len in 0..400 {
            let bytes: Vec<u8> = (0..len).map(|_| alphabet[g.below(alphabet.len())]).collect();
            let _ = parse(&bytes);
        }
        for cut in 0..SQUARE.len() {
            let _ = parse(&SQUARE.as_bytes()[..cut]);
        }
    }
}
