//! Gmsh post-processing views in the parsed format (`.pos`): a reader that hands each
//! view and each record to the caller as it reads it, and a writer of one tensor view.
//!
//! Format (Gmsh reference manual, "Post-processing scripting / parsed format"): views
//! `View "name" { ... };` (or `View("name") { ... };`), each a list of records
//! `XY(x1,y1,z1, ..., xn,yn,zn){values};` where X is the field (`S` scalar, `V` vector,
//! `T` tensor: 1, 3 or 9 values per node) and Y the element (`P` point, `L` line, `T`
//! triangle, `Q` quadrangle, `S` tetrahedron, `I` prism, `Y` pyramid, `H` hexahedron);
//! the values may hold several time steps, node after node for each step. `//` and
//! `/* */` are comments. Text records (`T2`, `T3`) are read for their syntax and skipped.
//! Written by hand: no crate reads this format.
//!
//! Reading ([`read_bytes`]) checks the syntax and, of each record, its kind, its
//! coordinate count (3 per node) and its value count (a non-zero multiple of the values
//! per node times the nodes), and that every number is finite; errors name the line. It
//! keeps nothing: what a view means (a background metric for `gmsh -bgm`, a scalar field)
//! is the caller's, which sees [`Item`]s in file order and may stop the reading with an
//! error of its own. Memory stays within one record's numbers.
//!
//! Writing ([`write_tensor_view`]): one view of `TT`/`TQ` records with a 9-component
//! tensor (row-major) at each node, on a mesh's triangles and quadrangles; a mesh with
//! volume cells gets `TS`/`TH`/`TI`/`TY` records on its tetrahedra, hexahedra, prisms and
//! pyramids instead (Gmsh's background mesh in 3D is looked up in volume elements; the
//! faces on their boundary add nothing). Second-order cells are written as their corner
//! cell (a background mesh needs no more), cells of other dimensions carry no record. Numbers are shortest round-trip
//! decimals, which Gmsh's `strtod` reads back exactly.

use crate::text::push_f64;
use crate::{CellKind, DataArray, Error, ErrorKind, TaggedMesh};

/// What a record's values are at each node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Field {
    /// `S`: one value.
    Scalar,
    /// `V`: three values.
    Vector,
    /// `T`: nine values, row-major.
    Tensor,
}

impl Field {
    /// Values per node and time step.
    pub fn components(self) -> usize {
        match self {
            Field::Scalar => 1,
            Field::Vector => 3,
            Field::Tensor => 9,
        }
    }

    fn from_letter(c: u8) -> Option<Field> {
        match c {
            b'S' => Some(Field::Scalar),
            b'V' => Some(Field::Vector),
            b'T' => Some(Field::Tensor),
            _ => None,
        }
    }
}

/// The element a record lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Element {
    /// `P`.
    Point,
    /// `L`.
    Line,
    /// `T`.
    Triangle,
    /// `Q`.
    Quadrangle,
    /// `S`.
    Tetrahedron,
    /// `Y`.
    Pyramid,
    /// `I`.
    Prism,
    /// `H`.
    Hexahedron,
}

impl Element {
    /// Its nodes (the corners, in Gmsh's order).
    pub fn nodes(self) -> usize {
        match self {
            Element::Point => 1,
            Element::Line => 2,
            Element::Triangle => 3,
            Element::Quadrangle | Element::Tetrahedron => 4,
            Element::Pyramid => 5,
            Element::Prism => 6,
            Element::Hexahedron => 8,
        }
    }

    fn from_letter(c: u8) -> Option<Element> {
        match c {
            b'P' => Some(Element::Point),
            b'L' => Some(Element::Line),
            b'T' => Some(Element::Triangle),
            b'Q' => Some(Element::Quadrangle),
            b'S' => Some(Element::Tetrahedron),
            b'Y' => Some(Element::Pyramid),
            b'I' => Some(Element::Prism),
            b'H' => Some(Element::Hexahedron),
            _ => None,
        }
    }
}

/// One record of a view, checked: `coords` holds 3 numbers per node, `values` a non-zero
/// multiple of [`Field::components`] × [`Element::nodes`] (the time steps one after the
/// other, node after node in each).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Record<'a> {
    /// The values' kind.
    pub field: Field,
    /// The element.
    pub element: Element,
    /// x, y, z of each node.
    pub coords: &'a [f64],
    /// The values.
    pub values: &'a [f64],
    /// The line of the record's name.
    pub line: u64,
}

/// What [`read_bytes`] hands over, in file order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Item<'a> {
    /// A view begins: its name, and the line of its `View` keyword.
    View {
        /// The view's name.
        name: &'a str,
        /// The line of `View`.
        line: u64,
    },
    /// A record of the view begun last.
    Record(Record<'a>),
    /// The view begun last ended (its closing `};` read).
    EndView,
}

/// Reads the views of a `.pos` file's bytes, handing each [`Item`] to `visit`; an error
/// from `visit` stops the reading and is returned as it is.
pub fn read_bytes(
    bytes: &[u8],
    visit: &mut dyn FnMut(Item<'_>) -> Result<(), Error>,
) -> Result<(), Error> {
    let mut p = Parser { lex: Lexer { bytes, at: 0, line: 1 }, peeked: None };
    let (mut coords, mut values) = (Vec::new(), Vec::new());
    loop {
        let t = p.bump()?;
        let line = match t {
            None => return Ok(()),
            Some((Token::Ident("View"), line)) => line,
            _ => return Err(Error::expected(p.lex.line, "`View`", describe(&t))),
        };
        let name = match p.bump()? {
            Some((Token::Str(s), _)) => s,
            Some((Token::Punct(b'('), _)) => {
                let t = p.bump()?;
                let Some((Token::Str(s), _)) = t else {
                    return Err(Error::expected(p.lex.line, "the view's name", describe(&t)));
                };
                p.punct(b')')?;
                s
            }
            t => return Err(Error::expected(p.lex.line, "the view's name", describe(&t))),
        };
        p.punct(b'{')?;
        visit(Item::View { name, line })?;
        loop {
            let t = p.bump()?;
            let (ident, line) = match t {
                Some((Token::Punct(b'}'), _)) => break,
                Some((Token::Ident(s), line)) => (s, line),
                _ => return Err(Error::expected(p.lex.line, "a record or `}`", describe(&t))),
            };
            let text = matches!(ident, "T2" | "T3");
            p.punct(b'(')?;
            p.list(b')', false, &mut coords)?;
            p.punct(b'{')?;
            p.list(b'}', text, &mut values)?;
            p.punct(b';')?;
            if text {
                continue;
            }
            let kind = ident.as_bytes();
            let (Some(field), Some(element), 2) = (
                Field::from_letter(kind[0]),
                kind.get(1).copied().and_then(Element::from_letter),
                kind.len(),
            ) else {
                return Err(Error::at_line(
                    line,
                    ErrorKind::Unsupported(format!(
                        "record `{}` (a view holds records such as ST, VT, TT, TQ)",
                        shorten(ident)
                    )),
                ));
            };
            let (n, comps) = (element.nodes(), field.components());
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
            visit(Item::Record(Record { field, element, coords: &coords, values: &values, line }))?;
        }
        p.punct(b';')?;
        visit(Item::EndView)?;
    }
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

    /// Items separated by commas up to `close` (the opening one already read) into `out`
    /// (cleared first): numbers, and strings, skipped, when `strings` (text records).
    fn list(&mut self, close: u8, strings: bool, out: &mut Vec<f64>) -> Result<(), Error> {
        out.clear();
        if matches!(self.peek()?, Some((Token::Punct(p), _)) if *p == close) {
            self.bump()?;
            return Ok(());
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
                Some((Token::Punct(p), _)) if p == close => return Ok(()),
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

/// The bytes of a `.pos` file holding one view `name` of the 9-component point array
/// `tensor` on the volume cells of `mesh` or, when it has none, on its triangles and
/// quadrangles.
pub fn write_tensor_view(
    mesh: &TaggedMesh,
    tensor: &DataArray,
    name: &str,
) -> Result<Vec<u8>, Error> {
    let cannot = |reason: String| {
        Error::new(ErrorKind::CannotWrite { format: "Gmsh post-processing view", reason })
    };
    if tensor.components != 9 || tensor.values.len() != 9 * mesh.points.len() {
        return Err(cannot(format!(
            "a view needs 9 components per mesh vertex ({} vertices, {} values)",
            mesh.points.len(),
            tensor.values.len()
        )));
    }
    if name.contains('"') || name.contains('\n') {
        return Err(cannot(format!("view name {name:?} holds a quote or a newline")));
    }
    let solid = mesh.blocks.iter().any(|b| b.kind.dim() == 3 && !b.is_empty());
    let record = |kind: CellKind| if solid { volume_corners(kind) } else { face_corners(kind) };
    let faces = mesh.blocks.iter().filter(|b| record(b.kind).is_some());
    let records: usize = faces.clone().map(|b| b.len()).sum();
    if records == 0 {
        return Err(cannot("the mesh has no triangle or quadrangle to carry the view".into()));
    }
    let mut out = Vec::with_capacity(64 + records * 3 * 230);
    out.extend_from_slice(b"View \"");
    out.extend_from_slice(name.as_bytes());
    out.extend_from_slice(b"\" {\n");
    for block in faces {
        let Some((tag, corners)) = record(block.kind) else { continue };
        for cell in block.cells() {
            let cell = &cell[..corners];
            out.extend_from_slice(tag);
            out.push(b'(');
            for (k, &v) in cell.iter().enumerate() {
                for (c, &x) in mesh.points[v as usize].iter().enumerate() {
                    if k + c > 0 {
                        out.push(b',');
                    }
                    push_f64(&mut out, x);
                }
            }
            out.extend_from_slice(b"){");
            for (k, &v) in cell.iter().enumerate() {
                let v = v as usize;
                for (c, &x) in tensor.values[9 * v..9 * v + 9].iter().enumerate() {
                    if k + c > 0 {
                        out.push(b',');
                    }
                    push_f64(&mut out, x);
                }
            }
            out.extend_from_slice(b"};\n");
        }
    }
    out.extend_from_slice(b"};\n");
    Ok(out)
}

/// The record tag and number of corners of a volume kind (Gmsh's node order is ours),
/// `None` for other kinds.
fn volume_corners(kind: CellKind) -> Option<(&'static [u8], usize)> {
    match kind.linear() {
        CellKind::Tetra => Some((b"TS", 4)),
        CellKind::Hexa => Some((b"TH", 8)),
        CellKind::Wedge => Some((b"TI", 6)),
        CellKind::Pyramid => Some((b"TY", 5)),
        _ => None,
    }
}

/// The record tag and number of corners of a face kind, `None` for other kinds.
fn face_corners(kind: CellKind) -> Option<(&'static [u8], usize)> {
    match kind {
        CellKind::Triangle | CellKind::Triangle6 => Some((b"TT", 3)),
        CellKind::Quad | CellKind::Quad8 | CellKind::Quad9 => Some((b"TQ", 4)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{CellBlock, Position};

    /// Every item of `text`, owned, or the error.
    fn items(text: &str) -> Result<Vec<String>, Error> {
        let mut out = Vec::new();
        read_bytes(text.as_bytes(), &mut |item| {
            out.push(match item {
                Item::View { name, line } => format!("view {name} at {line}"),
                Item::Record(r) => {
                    format!(
                        "{:?} {:?} {:?} {:?} at {}",
                        r.field, r.element, r.coords, r.values, r.line
                    )
                }
                Item::EndView => "end".into(),
            });
            Ok(())
        })?;
        Ok(out)
    }

    #[test]
    fn views_and_records_come_in_file_order() {
        let text = "// a comment\nView \"a\" {\nST(0,0,0, 1,0,0, 0,1,0){1,2,3};\n\
                    T2(1,2,0){\"text\"};\n/* a\nquadrangle */ VQ(0,0,0,1,0,0,1,1,0,0,1,0)\
                    {1,0,0,1,0,0,1,0,0,1,0,0};\n};\nView(\"b\") {};\n";
        assert_eq!(
            items(text).unwrap(),
            [
                "view a at 2",
                "Scalar Triangle [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] [1.0, 2.0, 3.0] at 3",
                "Vector Quadrangle [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0] \
                 [1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0] at 6",
                "end",
                "view b at 8",
                "end",
            ]
        );
        assert_eq!(items("").unwrap(), Vec::<String>::new());
    }

    #[test]
    fn bad_records_name_the_line() {
        let cases: [(&str, u64, &str); 7] = [
            ("View \"s\" {\nTT(0,0,0,1,0,0){1};\n};", 2, "9 coordinates"),
            ("View \"s\" {\nTT(0,0,0,1,0,0,0,1,0){1,2};\n};", 2, "multiple of 27"),
            ("View \"s\" {\nXX(0,0,0){1};\n};", 2, "record `XX`"),
            ("View \"s\" {\nTT(0,0,0,1,0,0,0,1,0){1e999};\n};", 2, "not a finite number"),
            ("View \"s\" {\n/* open", 2, "comment"),
            ("View \"s\" {\nSP(0,0,0){1};\n}", 3, "expected `;`"),
            ("\n\nview", 3, "expected `View`"),
        ];
        for (text, line, what) in cases {
            let e = items(text).unwrap_err();
            let s = e.to_string();
            assert!(s.contains(what), "{text:?}: {s}");
            assert_eq!(e.at, Some(Position::Line(line)), "{text:?}: {s}");
        }
    }

    #[test]
    fn the_visitor_may_stop_the_reading() {
        let mut seen = 0;
        let e = read_bytes(b"View \"a\" { SP(0,0,0){1}; SP(1,0,0){2}; };", &mut |item| {
            seen += 1;
            match item {
                Item::Record(r) if r.values == [1.0] => {
                    Err(Error::at_line(r.line, ErrorKind::Inconsistent("no".into())))
                }
                _ => Ok(()),
            }
        })
        .unwrap_err();
        assert_eq!((e.at, e.kind.to_string()), (Some(Position::Line(1)), "no".to_string()));
        assert_eq!(seen, 2);
    }

    fn square() -> TaggedMesh {
        let mut m = TaggedMesh {
            points: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            ..TaggedMesh::new()
        };
        let mut b = CellBlock::new(CellKind::Triangle);
        b.push(&[0, 1, 2], 1, 1);
        b.push(&[0, 2, 3], 1, 1);
        m.blocks.push(b);
        let mut l = CellBlock::new(CellKind::Line);
        l.push(&[0, 1], 5, 5);
        m.blocks.push(l);
        m
    }

    #[test]
    fn one_record_per_triangle_with_nine_values_per_node() {
        let m = square();
        let t = DataArray::new(9, (0..36).map(|k| k as f64 / 4.0).collect());
        let text = String::from_utf8(write_tensor_view(&m, &t, "metric").unwrap()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "View \"metric\" {");
        assert_eq!(lines.len(), 4);
        assert!(lines[1].starts_with("TT(0.0,0.0,0.0,1.0,0.0,0.0,1.0,1.0,0.0){0.0,0.25,"));
        let values = lines[2].split('{').nth(1).unwrap().trim_end_matches("};");
        let v: Vec<f64> = values.split(',').map(|s| s.parse().unwrap()).collect();
        // Nodes 0, 2, 3 of the second triangle.
        let expect: Vec<f64> = [0usize, 2, 3]
            .iter()
            .flat_map(|&n| (9 * n..9 * n + 9).map(|k| k as f64 / 4.0))
            .collect();
        assert_eq!(v, expect);
        assert_eq!(lines[3], "};");
    }

    #[test]
    fn what_is_written_reads_back_bit_for_bit() {
        let m = square();
        let t = DataArray::new(9, (0..36).map(|k| (k as f64 + 0.1).sqrt() / 3.0).collect());
        let bytes = write_tensor_view(&m, &t, "metric").unwrap();
        let mut records = Vec::new();
        read_bytes(&bytes, &mut |item| {
            if let Item::Record(r) = item {
                records.push((r.field, r.element, r.coords.to_vec(), r.values.to_vec()));
            }
            Ok(())
        })
        .unwrap();
        assert_eq!(records.len(), 2);
        for ((field, element, coords, values), cell) in records.iter().zip([[0, 1, 2], [0, 2, 3]]) {
            assert_eq!((*field, *element), (Field::Tensor, Element::Triangle));
            let c: Vec<f64> = cell.iter().flat_map(|&v| m.points[v]).collect();
            let v: Vec<f64> =
                cell.iter().flat_map(|&v| t.values[9 * v..9 * v + 9].to_vec()).collect();
            assert_eq!((coords, values), (&c, &v));
        }
    }

    #[test]
    fn wrong_sizes_are_errors() {
        let m = square();
        assert!(write_tensor_view(&m, &DataArray::new(9, vec![1.0; 27]), "m").is_err());
        assert!(write_tensor_view(&m, &DataArray::new(3, vec![1.0; 12]), "m").is_err());
        assert!(write_tensor_view(&m, &DataArray::new(9, vec![1.0; 36]), "a\"b").is_err());
        let mut lines_only = square();
        lines_only.blocks.remove(0);
        assert!(write_tensor_view(&lines_only, &DataArray::new(9, vec![1.0; 36]), "m").is_err());
    }

    #[test]
    fn arbitrary_bytes_never_panic() {
        use smartmesh_test_support::{Generator, SplitMix64};
        let mut g = SplitMix64(17);
        let alphabet = b"View\"{}(),;TQST0123456789.-e/* \n";
        for len in 0..400 {
            let bytes: Vec<u8> = (0..len).map(|_| alphabet[g.below(alphabet.len())]).collect();
            let _ = read_bytes(&bytes, &mut |_| Ok(()));
        }
        let good = b"View \"m\" {\nTT(0,0,0,1,0,0,0,1,0){1,0,0,0,1,0,0,0,1,1,0,0,0,1,0,0,0,1,1,0,0,0,1,0,0,0,1};\n};\n";
        for cut in 0..good.len() {
            let _ = read_bytes(&good[..cut], &mut |_| Ok(()));
        }
    }
}
