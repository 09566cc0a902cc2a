//! Parsing a Fluent mesh file into its sections, before any cell is rebuilt (`build`).
//!
//! The file is a list of Scheme-like sections `(INDEX ...)`. Read: `(2 ND)`; nodes
//! `(10 (zone first last type [ND])(x y [z] ...))`; cells `(12 (zone first last type
//! elem-type)[(types...)])`; faces `(13 (zone first last bc-type face-type)(n0 n1 ...
//! c0 c1 ...))` (face-type 0 or 5: each face's node count first); zone names `(45 (id
//! type name)())` and `(39 ...)`; periodic face pairs `(18 (first last zone shadow)(f s
//! ...))`. Every other ASCII section is skipped by its balanced
//! parentheses (strings may hold parentheses). Binary variants: 20xx (single precision:
//! f32 nodes, i32 integers) and 30xx (f64 nodes; i32 integers as Fluent writes them,
//! or i64 as meshio's writer does: the width whose data is followed by `)` and `End of
//! Binary Section` is taken). Little-endian throughout.
//!
//! meshio's writer puts each cell's nodes in a cell section (`(12 (1 0 n 1 2)(...))`,
//! no faces): such cells are kept as they are ([`Raw::node_cells`]).
//!
//! Every count is checked against the bytes left before anything is allocated for it.

use crate::{Error, ErrorKind, Result};

/// The sections read, indices as in the file (1-based nodes, cells, faces).
#[derive(Debug, Default)]
pub(super) struct Raw {
    pub dim: Option<u8>,
    /// Node zones: (first id, coordinates `nd` per node, nd).
    pub nodes: Vec<(u64, Vec<f64>, usize)>,
    /// Declared total cell count (`(12 (0 first last 0))`).
    pub declared_cells: Option<u64>,
    /// Cell zones: (zone, first, last).
    pub cell_zones: Vec<(u32, u64, u64)>,
    /// Faces: node ids (1-based) flat, a start per face (plus one), c0, c1 (0 none).
    pub face_nodes: Vec<u64>,
    pub face_start: Vec<usize>,
    pub c0: Vec<u64>,
    pub c1: Vec<u64>,
    pub face_zone: Vec<u32>,
    /// Each face section's first face (index into `c0`) and the line of its header.
    pub face_lines: Vec<(usize, u64)>,
    /// Face zones: zone → bc-type code.
    pub face_zones: Vec<(u32, u64)>,
    /// Cells given by their nodes (meshio): (zone, elem-type, nodes flat 1-based).
    pub node_cells: Vec<(u32, u64, Vec<u64>)>,
    /// Zone names: (zone, type word, name).
    pub names: Vec<(u32, String, String)>,
    /// Periodic face pairs `(18 ...)`: (header line, periodic zone, shadow zone, pairs of
    /// 1-based face indices).
    pub periodic: Vec<PeriodicSection>,
}

/// A periodic face-pair section: its header line, the periodic and the shadow zone,
/// the pairs of 1-based face indices.
pub(super) type PeriodicSection = (u64, u32, u32, Vec<(u64, u64)>);

/// How the integers and floats of a section's data are written.
#[derive(Clone, Copy)]
enum Enc {
    Ascii,
    /// Integer width and float width in bytes.
    Bin(usize, usize),
}

struct Cur<'a> {
    b: &'a [u8],
    pos: usize,
    /// The line of a position already counted, so that counting lines stays linear.
    seen: std::cell::Cell<(usize, u64)>,
}

fn is_delim(c: u8) -> bool {
    c.is_ascii_whitespace() || c == b'(' || c == b')'
}

impl<'a> Cur<'a> {
    fn line(&self) -> u64 {
        let pos = self.pos.min(self.b.len());
        let (mut from, mut line) = self.seen.get();
        if from > pos {
            (from, line) = (0, 1);
        }
        line += self.b[from..pos].iter().filter(|&&c| c == b'\n').count() as u64;
        self.seen.set((pos, line));
        line
    }
    fn found(&self) -> String {
        let rest = &self.b[self.pos.min(self.b.len())..];
        if rest.is_empty() {
            return "the end of the file".into();
        }
        let n = rest.iter().take(24).position(|&c| c == b'\n').unwrap_or(rest.len().min(24));
        format!("`{}`", String::from_utf8_lossy(&rest[..n.max(1)]))
    }
    fn expected(&self, what: impl Into<String>) -> Error {
        Error::expected(self.line(), what, self.found())
    }
    fn ws(&mut self) {
        while self.pos < self.b.len() && self.b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }
    fn eat(&mut self, c: u8) -> Result<()> {
        self.ws();
        if self.b.get(self.pos) == Some(&c) {
            self.pos += 1;
            Ok(())
        } else {
            Err(self.expected(format!("`{}`", c as char)))
        }
    }
    fn peek(&mut self) -> Option<u8> {
        self.ws();
        self.b.get(self.pos).copied()
    }
    fn word(&mut self) -> &'a [u8] {
        self.ws();
        let start = self.pos;
        while self.pos < self.b.len() && !is_delim(self.b[self.pos]) {
            self.pos += 1;
        }
        &self.b[start..self.pos]
    }
    fn number(&mut self, radix: u32, what: &str) -> Result<u64> {
        let save = self.pos;
        let w = self.word();
        std::str::from_utf8(w).ok().and_then(|s| u64::from_str_radix(s, radix).ok()).ok_or_else(
            || {
                self.pos = save;
                self.ws();
                self.expected(format!(
                    "{what} ({} integer)",
                    if radix == 16 { "hexadecimal" } else { "decimal" }
                ))
            },
        )
    }
    fn left(&self) -> usize {
        self.b.len().saturating_sub(self.pos)
    }
    /// Skips to the `)` closing a parenthesis already opened, `depth` deep.
    fn skip_balanced(&mut self, mut depth: usize) -> Result<()> {
        let start = self.line();
        while let Some(&c) = self.b.get(self.pos) {
            self.pos += 1;
            match c {
                b'(' => depth += 1,
                b')' => {
                    depth -= 1;
                    if depth == 0 {
                        return Ok(());
                    }
                }
                b'"' => {
                    while self.b.get(self.pos).is_some_and(|&c| c != b'"') {
                        self.pos += 1;
                    }
                    self.pos += 1;
                }
                _ => {}
            }
        }
        Err(Error::at_line(
            start,
            ErrorKind::UnexpectedEof { context: "a section opened here is never closed".into() },
        ))
    }
    fn int(&mut self, enc: Enc, what: &str) -> Result<u64> {
        match enc {
            Enc::Ascii => self.number(16, what),
            Enc::Bin(w, _) => {
                let Some(s) = self.b.get(self.pos..self.pos + w) else {
                    return Err(Error::at_byte(
                        self.pos as u64,
                        ErrorKind::UnexpectedEof { context: format!("binary {what}") },
                    ));
                };
                let v = if w == 4 {
                    i32::from_le_bytes([s[0], s[1], s[2], s[3]]) as i64
                } else {
                    i64::from_le_bytes([s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7]])
                };
                if v < 0 {
                    return Err(Error::at_byte(
                        self.pos as u64,
                        ErrorKind::Expected {
                            expected: format!("{what} (a non-negative integer)"),
                            found: v.to_string(),
                        },
                    ));
                }
                self.pos += w;
                Ok(v as u64)
            }
        }
    }
    fn float(&mut self, enc: Enc) -> Result<f64> {
        let v = match enc {
            Enc::Ascii => {
                let save = self.pos;
                let w = self.word();
                match std::str::from_utf8(w).ok().and_then(|s| s.parse::<f64>().ok()) {
                    Some(v) => v,
                    None => {
                        self.pos = save;
                        self.ws();
                        return Err(self.expected("a coordinate"));
                    }
                }
            }
            Enc::Bin(_, w) => {
                let Some(s) = self.b.get(self.pos..self.pos + w) else {
                    return Err(Error::at_byte(
                        self.pos as u64,
                        ErrorKind::UnexpectedEof { context: "binary coordinates".into() },
                    ));
                };
                self.pos += w;
                if w == 4 {
                    f32::from_le_bytes([s[0], s[1], s[2], s[3]]) as f64
                } else {
                    f64::from_le_bytes([s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7]])
                }
            }
        };
        if !v.is_finite() {
            return Err(Error::at_line(
                self.line(),
                ErrorKind::NonFinite { what: "a coordinate".into(), value: v.to_string() },
            ));
        }
        Ok(v)
    }
    /// The end of a section's data and of the section: `))`, or for a binary one
    /// `)` `End of Binary Section N` `)`. Whatever stands between the data's `)` and the
    /// section's is skipped: `foamMeshToFluent` writes `(12 (...)(types...)())`.
    /// A binary section is closed strictly (`)` then the marker or `)`): that is how
    /// the integer width of a 30xx section is told (see [`with_width`]).
    fn close_data(&mut self, enc: Enc) -> Result<()> {
        self.eat(b')')?;
        self.ws();
        if self.b[self.pos..].starts_with(b"End of Binary Section") {
            self.pos += b"End of Binary Section".len();
            self.number(10, "the section index")?;
            return self.eat(b')');
        }
        match enc {
            Enc::Bin(..) => self.eat(b')'),
            Enc::Ascii => self.skip_balanced(1),
        }
    }
    /// Refuses `n` items of at least `min` bytes each when fewer bytes are left.
    fn check_count(&self, what: &str, n: u64, min: usize) -> Result<()> {
        if n.saturating_mul(min as u64) > self.left() as u64 {
            return Err(Error::at_line(
                self.line(),
                ErrorKind::ImplausibleCount {
                    what: what.into(),
                    count: n,
                    limit: format!("{} bytes are left", self.left()),
                },
            ));
        }
        Ok(())
    }
    /// A section header `(a b c ...)` of hexadecimal integers.
    fn header(&mut self, what: &str) -> Result<Vec<u64>> {
        self.eat(b'(')?;
        let mut h = Vec::new();
        while self.peek() != Some(b')') {
            if h.len() == 8 {
                return Err(self.expected(format!("`)` closing the {what} header")));
            }
            h.push(self.number(16, &format!("an integer of the {what} header"))?);
        }
        self.pos += 1;
        Ok(h)
    }
}

/// Parses every section of `bytes`.
pub(super) fn parse(bytes: &[u8]) -> Result<Raw> {
    let mut c = Cur { b: bytes, pos: 0, seen: std::cell::Cell::new((0, 1)) };
    let mut raw = Raw::default();
    while c.peek().is_some() {
        c.eat(b'(')?;
        let index = c.number(10, "a section index")?;
        match index {
            2 => {
                let d = c.number(10, "the dimension")?;
                if !(d == 2 || d == 3) {
                    return Err(c.expected("dimension 2 or 3"));
                }
                raw.dim = Some(d as u8);
                c.skip_balanced(1)?;
            }
            10 | 2010 | 3010 => nodes(&mut c, &mut raw, index)?,
            12 | 2012 | 3012 => with_width(&mut c, &mut raw, index, cells)?,
            13 | 2013 | 3013 => with_width(&mut c, &mut raw, index, faces)?,
            39 | 45 => zone_name(&mut c, &mut raw)?,
            18 => periodic(&mut c, &mut raw)?,
            i if i >= 2000 => {
                return Err(Error::new(ErrorKind::Unsupported(format!(
                    "binary section {i} (line {}): only nodes, cells and faces are read in binary",
                    c.line()
                ))))
            }
            _ => c.skip_balanced(1)?,
        }
    }
    Ok(raw)
}

type Section = fn(&mut Cur<'_>, &mut Raw, Enc) -> Result<()>;

/// Runs `f` on a section whose integer width is 4 (20xx), or 4 else 8 (30xx: the
/// width after which the data closes), or ASCII.
fn with_width(c: &mut Cur<'_>, raw: &mut Raw, index: u64, f: Section) -> Result<()> {
    match index {
        i if i < 2000 => f(c, raw, Enc::Ascii),
        i if i < 3000 => f(c, raw, Enc::Bin(4, 4)),
        _ => {
            let (save, len) = (c.pos, raw_len(raw));
            match f(c, raw, Enc::Bin(4, 8)) {
                Ok(()) => Ok(()),
                Err(first) => {
                    c.pos = save;
                    truncate(raw, len);
                    f(c, raw, Enc::Bin(8, 8)).map_err(|_| first)
                }
            }
        }
    }
}

fn raw_len(raw: &Raw) -> (usize, usize, usize, usize, usize) {
    let r = raw;
    (
        r.face_start.len(),
        r.face_nodes.len(),
        r.cell_zones.len(),
        r.node_cells.len(),
        r.face_zones.len(),
    )
}

fn truncate(raw: &mut Raw, (f, n, z, nc, fz): (usize, usize, usize, usize, usize)) {
    raw.face_start.truncate(f);
    raw.c0.truncate(f);
    raw.c1.truncate(f);
    raw.face_zone.truncate(f);
    raw.face_nodes.truncate(n);
    raw.cell_zones.truncate(z);
    raw.node_cells.truncate(nc);
    raw.face_zones.truncate(fz);
    raw.face_lines.truncate(fz);
}

/// `first..=last` of a header, its count checked.
fn range(c: &Cur<'_>, h: &[u64], what: &str) -> Result<(u64, u64)> {
    let (first, last) = (h[1], h[2]);
    if last.saturating_add(1) < first {
        return Err(c.expected(format!("{what}: a last index not before the first ({first:x})")));
    }
    // An empty section has last = first - 1.
    Ok((first, last.saturating_add(1) - first))
}

fn nodes(c: &mut Cur<'_>, raw: &mut Raw, index: u64) -> Result<()> {
    let h = c.header("node section")?;
    if h.len() < 4 {
        return Err(c.expected("a node header `(zone first last type [ND])`"));
    }
    let nd = match h.get(4) {
        Some(&d) => d as usize,
        None => raw.dim.unwrap_or(3) as usize,
    };
    if !(nd == 2 || nd == 3) {
        return Err(c.expected("a node dimension of 2 or 3"));
    }
    let (first, n) = range(c, &h, "node section")?;
    if c.peek() == Some(b')') {
        c.pos += 1;
        return Ok(()); // a declaration: the total only
    }
    let enc = match index {
        10 => Enc::Ascii,
        2010 => Enc::Bin(4, 4),
        _ => Enc::Bin(4, 8),
    };
    let min = match enc {
        Enc::Ascii => 2,
        Enc::Bin(_, w) => w,
    };
    c.check_count("the node section", n.saturating_mul(nd as u64), min)?;
    c.eat(b'(')?;
    if let Enc::Bin(..) = enc {
        // The binary data starts right after `(`, perhaps after one newline.
        if c.b.get(c.pos) == Some(&b'\n') && c.left() as u64 > n * (nd * min) as u64 {
            c.pos += 1;
        }
    }
    let mut xs = Vec::with_capacity((n as usize) * nd);
    for _ in 0..n as usize * nd {
        xs.push(c.float(enc)?);
    }
    c.close_data(enc)?;
    raw.nodes.push((first, xs, nd));
    Ok(())
}

fn cells(c: &mut Cur<'_>, raw: &mut Raw, enc: Enc) -> Result<()> {
    let h = c.header("cell section")?;
    if h.len() < 4 {
        return Err(c.expected("a cell header `(zone first last type elem-type)`"));
    }
    let (first, n) = range(c, &h, "cell section")?;
    let zone = u32::try_from(h[0]).map_err(|_| c.expected("a zone id below 2^32"))?;
    let et = h.get(4).copied().unwrap_or(0);
    if zone == 0 {
        raw.declared_cells = Some(n);
    } else {
        raw.cell_zones.push((zone, first, n));
    }
    if c.peek() == Some(b')') {
        c.pos += 1;
        return Ok(());
    }
    c.eat(b'(')?;
    let min = if let Enc::Bin(w, _) = enc { w } else { 2 };
    let per = match et {
        0 => 1, // a type per cell
        1 => 3,
        2 | 3 => 4,
        4 => 8,
        5 => 5,
        6 => 6,
        _ => return Err(c.expected("cell element type 0 to 6 with data")),
    };
    c.check_count("the cell section", n.saturating_mul(per), min)?;
    if let Enc::Bin(..) = enc {
        if c.b.get(c.pos) == Some(&b'\n') && c.left() as u64 > n * per * min as u64 {
            c.pos += 1;
        }
    }
    let mut list = Vec::with_capacity((n * per) as usize);
    for _ in 0..n * per {
        list.push(c.int(enc, "a cell's node or type")?);
    }
    c.close_data(enc)?;
    if et != 0 {
        raw.node_cells.push((zone, et, list));
    }
    Ok(())
}

fn faces(c: &mut Cur<'_>, raw: &mut Raw, enc: Enc) -> Result<()> {
    let line = c.line();
    let h = c.header("face section")?;
    if h.len() < 4 {
        return Err(c.expected("a face header `(zone first last bc-type face-type)`"));
    }
    let (_, n) = range(c, &h, "face section")?;
    let zone = u32::try_from(h[0]).map_err(|_| c.expected("a zone id below 2^32"))?;
    if c.peek() == Some(b')') {
        c.pos += 1;
        return Ok(());
    }
    let ft = h.get(4).copied().unwrap_or(0);
    let fixed = match ft {
        0 | 5 => None,
        2..=4 => Some(ft),
        _ => return Err(c.expected("face type 0, 2, 3, 4 or 5")),
    };
    c.eat(b'(')?;
    let min = if let Enc::Bin(w, _) = enc { w } else { 2 };
    c.check_count("the face section", n.saturating_mul(4), min)?;
    if let Enc::Bin(..) = enc {
        if c.b.get(c.pos) == Some(&b'\n') && c.left() as u64 > n * 4 * min as u64 {
            c.pos += 1;
        }
    }
    raw.face_zones.push((zone, h[3]));
    raw.face_lines.push((raw.c0.len(), line));
    for _ in 0..n {
        let k = match fixed {
            Some(k) => k,
            None => {
                let k = c.int(enc, "a face's node count")?;
                if !(2..=64).contains(&k) {
                    return Err(c.expected("a face node count of 2 to 64"));
                }
                k
            }
        };
        for _ in 0..k {
            let v = c.int(enc, "a face's node")?;
            raw.face_nodes.push(v);
        }
        raw.c0.push(c.int(enc, "a face's cell c0")?);
        raw.c1.push(c.int(enc, "a face's cell c1")?);
        raw.face_start.push(raw.face_nodes.len());
        raw.face_zone.push(zone);
    }
    c.close_data(enc)
}

/// `(18 (first last periodic-zone shadow-zone)(f s ...))`: the face pairs of a
/// periodic zone and its shadow, hexadecimal.
fn periodic(c: &mut Cur<'_>, raw: &mut Raw) -> Result<()> {
    let line = c.line();
    let h = c.header("periodic face-pair section")?;
    if h.len() != 4 {
        return Err(c.expected("a periodic header `(first last periodic-zone shadow-zone)`"));
    }
    if h[1].saturating_add(1) < h[0] {
        return Err(c.expected("a periodic header whose last index is not before its first"));
    }
    let n = h[1].saturating_add(1) - h[0];
    let zone = |v: u64| u32::try_from(v).map_err(|_| c.expected("a zone id below 2^32"));
    let (pz, sz) = (zone(h[2])?, zone(h[3])?);
    c.eat(b'(')?;
    c.check_count("the periodic face pairs", n.saturating_mul(2), 2)?;
    let mut pairs = Vec::with_capacity(n as usize);
    for _ in 0..n {
        let f = c.number(16, "a periodic face")?;
        let s = c.number(16, "its shadow face")?;
        pairs.push((f, s));
    }
    c.skip_balanced(2)?;
    raw.periodic.push((line, pz, sz, pairs));
    Ok(())
}

fn zone_name(c: &mut Cur<'_>, raw: &mut Raw) -> Result<()> {
    c.eat(b'(')?;
    let id = c.number(10, "a zone id")?;
    let id = u32::try_from(id).map_err(|_| c.expected("a zone id below 2^32"))?;
    let kind = String::from_utf8_lossy(c.word()).into_owned();
    let name = String::from_utf8_lossy(c.word()).into_owned();
    if kind.is_empty() || name.is_empty() {
        return Err(c.expected("a zone's type and name"));
    }
    c.skip_balanced(2)?;
    raw.names.push((id, kind, name));
    Ok(())
}
