//! A Gmsh post-processing view (`.pos`, the parsed format) read as a metric field, the
//! way `gmsh -bgm X.pos` takes a background mesh.
//!
//! Format (Gmsh reference manual, "Post-processing scripting / parsed format"): views
//! `View "name" { ... };`, each a list of records `XY(x1,y1,z1, ..., xn,yn,zn){values};`
//! where X is the field (`S` scalar, `V` vector, `T` tensor: 1, 3 or 9 values per node)
//! and Y the element (`P` point, `L` line, `T` triangle, `Q` quadrangle, `S`
//! tetrahedron, `I` prism, `Y` pyramid, `H` hexahedron); the values may hold several time
//! steps, node after node for each step. `//` and `/* */` are comments. Text records
//! (`T2`, `T3`) are skipped. Written by hand: no crate reads this format.
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

use crate::formats::{CellKind, Error, ErrorKind, TaggedMesh, MAX_POINTS};
use crate::metric::Sym2;

use super::not_a_metric;

/// The tensor faces of a view: nodes joined by position, one metric per node.
#[derive(Debug, Clone)]
pub struct View {
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
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The metric at each of `points` (see the module documentation).
    pub fn at(&self, points: &[[f64; 2]]) -> Vec<Sym2> {
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
    pub fn into_mesh(self) -> (TaggedMesh, Vec<Sym2>) {
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
pub fn read_path(path: &Path) -> Result<View, Error> {
    let bytes = std::fs::read(path).map_err(|e| Error::from(e).with_path(path))?;
    parse(&bytes).map_err(|e| e.with_path(path))
}

/// A token of the parsed format.
#[derive(Debug, Clone, PartialEq)]
enum Token<'a> {
    Ident(&'a str),
    Str(&'a str),
    Number(f64),
    Punct(u8),
}

/// Splits the file into tokens with their line numbers.
struct Lexer<'a> {
    bytes: &'a [u8],
    at: usize,
    line: u64,
}

impl<'a> Lexer<'a> {
    fn next(&mut self) -> Result<Option<(Token<'a>, u64)>, Error> {
        let b = self.bytes;
        loop {
            while self.at < b.len() && b[self.at].is_ascii_whitespace() {
                if b[self.at] == b'\n' {
                    self.line += 1;
                }
                self.at += 1;
            }
            if b[self.at..].starts_with(b"//") {
                while self.at < b.len() && b[self.at] != b'\n' {
                    self.at += 1;
                }
            } else if b[self.at..].starts_with(b"/*") {
                let start = self.line;
                self.at += 2;
                loop {
                    if self.at + 1 >= b.len() {
                        return Err(Error::at_line(
                            start,
                            ErrorKind::UnexpectedEof { context: "a comment opened here".into() },
                        ));
                    }
                    if &b[self.at..self.at + 2] == b"*/" {
                        self.at += 2;
                        break;
                    }
                    if b[self.at] == b'\n' {
                        self.line += 1;
                    }
                    self.at += 1;
                }
            } else {
                break;
            }
        }
        let Some(&c) = b.get(self.at) else { return Ok(None) };
        let line = self.line;
        let start = self.at;
        let token = if c.is_ascii_alphabetic() || c == b'_' {
            while self.at < b.len() && (b[self.at].is_ascii_alphanumeric() || b[self.at] == b'_') {
                self.at += 1;
            }
            Token::Ident(std::str::from_utf8(&b[start..self.at]).unwrap_or(""))
        } else if c == b'"' {
            self.at += 1;
            while self.at < b.len() && b[self.at] != b'"' && b[self.at] != b'\n' {
                self.at += 1;
            }
            if b.get(self.at) != Some(&b'"') {
                return Err(Error::expected(line, "a closing `\"`", "the end of the line"));
            }
            self.at += 1;
            Token::Str(std::str::from_utf8(&b[start + 1..self.at - 1]).map_err(|_| {
                Error::at_line(line, ErrorKind::Inconsistent("a string that is not UTF-8".into()))
            })?)
        } else if c.is_ascii_digit() || matches!(c, b'-' | b'+' | b'.') {
            while self.at < b.len()
                && (b[self.at].is_ascii_alphanumeric() || matches!(b[self.at], b'-' | b'+' | b'.'))
            {
                self.at += 1;
            }
            let text = std::str::from_utf8(&b[start..self.at]).unwrap_or("");
            let v: f64 = text
                .parse()
                .map_err(|_| Error::expected(line, "a number", format!("`{}`", shorten(text))))?;
            if !v.is_finite() {
                return Err(Error::at_line(
                    line,
                    ErrorKind::NonFinite { what: "a view value".into(), value: shorten(text) },
                ));
            }
            Token::Number(v)
        } else if b"(){},;".contains(&c) {
            self.at += 1;
            Token::Punct(c)
        } else {
            return Err(Error::expected(
                line,
                "a record, a number or one of ( ) { } , ;",
                format!("byte 0x{c:02x}"),
            ));
        };
        Ok(Some((token, line)))
    }
}

/// At most 40 characters of `s`, for messages.
fn shorten(s: &str) -> String {
    if s.chars().count() <= 40 {
        s.to_string()
    } else {
        s.chars().take(40).collect::<String>() + "…"
    }
}

fn describe(t: &Option<(Token<'_>, u64)>) -> String {
    match t {
        None => "the end of the file".into(),
        Some((Token::Ident(s), _)) => format!("`{}`", shorten(s)),
        Some((Token::Str(s), _)) => format!("\"{}\"", shorten(s)),
        Some((Token::Number(v), _)) => format!("the number {v}"),
        Some((Token::Punct(c), _)) => format!("`{}`", *c as char),
    }
}

struct Parser<'a> {
    lex: Lexer<'a>,
    peeked: Option<Option<(Token<'a>, u64)>>,
}

impl<'a> Parser<'a> {
    fn peek(&mut self) -> Result<&Option<(Token<'a>, u64)>, Error> {
        if self.peeked.is_none() {
            self.peeked = Some(self.lex.next()?);
        }
        Ok(self.peeked.as_ref().unwrap_or(&None))
    }

    fn bump(&mut self) -> Result<Option<(Token<'a>, u64)>, Error> {
        match self.peeked.take() {
            Some(t) => Ok(t),
            None => self.lex.next(),
        }
    }

    fn punct(&mut self, c: u8) -> Result<u64, Error> {
        let t = self.bump()?;
        match t {
            Some((Token::Punct(p), line)) if p == c => Ok(line),
            _ => Err(Error::expected(self.lex.line, format!("`{}`", c as char), describe(&t))),
        }
    }

    /// Items separated by commas up to `close` (the opening one already read): numbers,
    /// and strings when `strings` (text records).
    fn list(&mut self, close: u8, strings: bool) -> Result<Vec<f64>, Error> {
        let mut out = Vec::new();
        if matches!(self.peek()?, Some((Token::Punct(p), _)) if *p == close) {
            self.bump()?;
            return Ok(out);
        }
        loop {
            let t = self.bump()?;
            match t {
                Some((Token::Number(v), _)) => out.push(v),
                Some((Token::Str(_), _)) if strings => {}
                _ => return Err(Error::expected(self.lex.line, "a number", describe(&t))),
            }
            let t = self.bump()?;
            match t {
                Some((Token::Punct(b','), _)) => {}
                Some((Token::Punct(p), _)) if p == close => return Ok(out),
                _ => {
                    return Err(Error::expected(
                        self.lex.line,
                        format!("`,` or `{}`", close as char),
                        describe(&t),
                    ))
                }
            }
        }
    }
}

/// Values per node of a record's field letter.
fn components(field: u8) -> Option<usize> {
    match field {
        b'S' => Some(1),
        b'V' => Some(3),
        b'T' => Some(9),
        _ => None,
    }
}

/// Nodes of a record's element letter.
fn nodes(element: u8) -> Option<usize> {
    match element {
        b'P' => Some(1),
        b'L' => Some(2),
        b'T' => Some(3),
        b'Q' | b'S' => Some(4),
        b'Y' => Some(5),
        b'I' => Some(6),
        b'H' => Some(8),
        _ => None,
    }
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
pub fn parse(bytes: &[u8]) -> Result<View, Error> {
    let mut p = Parser { lex: Lexer { bytes, at: 0, line: 1 }, peeked: None };
    let mut last: Option<(Faces, u64)> = None;
    loop {
        let t = p.bump()?;
        let line = match t {
            None => break,
            Some((Token::Ident("View"), line)) => line,
            _ => return Err(Error::expected(p.lex.line, "`View`", describe(&t))),
        };
        let name = match p.bump()? {
            Some((Token::Str(s), _)) => s.to_string(),
            Some((Token::Punct(b'('), _)) => {
                let t = p.bump()?;
                let Some((Token::Str(s), _)) = t else {
                    return Err(Error::expected(p.lex.line, "the view's name", describe(&t)));
                };
                p.punct(b')')?;
                s.to_string()
            }
            t => return Err(Error::expected(p.lex.line, "the view's name", describe(&t))),
        };
        p.punct(b'{')?;
        let mut faces = Faces {
            name,
            points: Vec::new(),
            tensors: Vec::new(),
            tris: Vec::new(),
            index: BTreeMap::new(),
        };
        loop {
            let t = p.bump()?;
            let (ident, line) = match t {
                Some((Token::Punct(b'}'), _)) => break,
                Some((Token::Ident(s), line)) => (s, line),
                _ => return Err(Error::expected(p.lex.line, "a record or `}`", describe(&t))),
            };
            let text = matches!(ident, "T2" | "T3");
            p.punct(b'(')?;
            let coords = p.list(b')', false)?;
            p.punct(b'{')?;
            let values = p.list(b'}', text)?;
            p.punct(b';')?;
            if text {
                continue;
            }
            let kind = ident.as_bytes();
            let (Some(comps), Some(n), 2) =
                (components(kind[0]), kind.get(1).copied().and_then(nodes), kind.len())
            else {
                return Err(Error::at_line(
                    line,
                    ErrorKind::Unsupported(format!(
                        "record `{}` (a view holds records such as ST, VT, TT, TQ)",
                        shorten(ident)
                    )),
                ));
            };
            if coords.len() != 3 * n {
                return Err(Error::expected(
                    line,
                    format!("{} coordinates in a `{ident}` record", 3 * n),
                    coords.len().to_string(),
                ));
            }
            if values.is_empty() || values.len() % (n * comps) != 0 {
                return Err(Error::expected(
                    line,
                    format!("a multiple of {} values in a `{ident}` record", n * comps),
                    values.len().to_string(),
                ));
            }
            if comps == 9 && (n == 3 || n == 4) && kind[1] != b'S' {
                faces.add(n, &coords, &values[..9 * n], line)?;
            }
        }
        p.punct(b';')?;
        last = Some((faces, line));
    }
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
        let cases: [(&str, u64, &str); 8] = [
            ("", 1, "no view"),
            ("View \"s\" {\nST(0,0,0,1,0,0,0,1,0){1,1,1};\n};", 1, "not a metric"),
            ("View \"s\" {\nTT(0,0,0,1,0,0){1};\n};", 2, "9 coordinates"),
            ("View \"s\" {\n\nTT(0,0,0,1,0,0,0,1,0){-1,0,0,0,1,0,0,0,1,1,0,0,0,1,0,0,0,1,1,0,0,0,1,0,0,0,1};};", 3, "not positive definite"),
            ("View \"s\" {\nTT(0,0,0,1,0,0,0,1,0){1,2};\n};", 2, "multiple of 27"),
            ("View \"s\" {\nXX(0,0,0){1};\n};", 2, "record `XX`"),
            ("View \"s\" {\nTT(0,0,0,1,0,0,0,1,0){1e999};\n};", 2, "not a finite number"),
            ("View \"s\" {\n/* open", 2, "comment"),
        ];
        for (text, line, what) in cases {
            let e = parse(text.as_bytes()).unwrap_err();
            let s = e.to_string();
            assert!(s.contains(what), "{text:?}: {s}");
            assert_eq!(e.at, Some(crate::formats::Position::Line(line)), "{text:?}: {s}");
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
