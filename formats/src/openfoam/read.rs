//! Reading back an OpenFOAM case (a 3D one, without `empty` or `wedge` patches, is
//! handed to `read3d` with its zones). A 2D OpenFOAM case: a `constant/polyMesh` (ASCII or binary, little-endian
//! with 32-bit labels) one cell thick along
//! z, as [`super::write_case`] writes it and as `extrudeMesh` or Gmsh's export make
//! them.
//!
//! What it becomes: each cell's face on the lowest plane (z = min z of the `empty`
//! patches' faces) is a triangle or a quad, counter-clockwise seen from +z; its points
//! are the 2D points, in their polyMesh order; each face of a non-`empty` patch that
//! has two points on that plane is a line cell, whose tag is the patch's (patches
//! numbered 1, 2, … in file order, `tag<N>` read back as tag N without a name, the
//! others named by the patch name); the cells get tag 1. Refused, naming the file and
//! line: other binary layouts, a case without `empty` patches or not extruded along z, a cell
//! with other than one face on the lowest plane, faces of more than 4 points there,
//! counts past the bytes left, indices out of range.

use std::path::Path;

use crate::text::{check_count, parse_f64, parse_i64, show};
use crate::{CellKind, Error, ErrorKind, Result, TaggedMesh};

/// A cursor over the tokens of an OpenFOAM file: words and numbers, and the
/// punctuation `( ) { } ;` as tokens of their own; `//` and `/* */` comments skipped.
pub(super) struct Lexer<'a> {
    d: &'a [u8],
    pos: usize,
    line: u64,
}

impl<'a> Lexer<'a> {
    fn new(d: &'a [u8]) -> Self {
        Lexer { d, pos: 0, line: 1 }
    }

    fn skip(&mut self) {
        while self.pos < self.d.len() {
            match self.d[self.pos] {
                b'\n' => {
                    self.line += 1;
                    self.pos += 1;
                }
                c if c.is_ascii_whitespace() => self.pos += 1,
                b'/' if self.d.get(self.pos + 1) == Some(&b'/') => {
                    while self.pos < self.d.len() && self.d[self.pos] != b'\n' {
                        self.pos += 1;
                    }
                }
                b'/' if self.d.get(self.pos + 1) == Some(&b'*') => {
                    self.pos += 2;
                    while self.pos < self.d.len()
                        && !(self.d[self.pos] == b'*' && self.d.get(self.pos + 1) == Some(&b'/'))
                    {
                        self.line += u64::from(self.d[self.pos] == b'\n');
                        self.pos += 1;
                    }
                    self.pos = (self.pos + 2).min(self.d.len());
                }
                _ => break,
            }
        }
    }

    fn next(&mut self) -> Option<&'a [u8]> {
        self.skip();
        let start = self.pos;
        match self.d.get(self.pos)? {
            b'(' | b')' | b'{' | b'}' | b';' => self.pos += 1,
            // A quoted string is one token, `;` and blanks inside it included.
            b'"' => {
                self.pos += 1;
                while self.pos < self.d.len() && self.d[self.pos] != b'"' {
                    self.line += u64::from(self.d[self.pos] == b'\n');
                    self.pos += 1;
                }
                self.pos = (self.pos + 1).min(self.d.len());
            }
            _ => {
                while self.pos < self.d.len()
                    && !self.d[self.pos].is_ascii_whitespace()
                    && !b"(){};".contains(&self.d[self.pos])
                {
                    self.pos += 1;
                }
            }
        }
        Some(&self.d[start..self.pos])
    }

    fn token(&mut self, what: &str) -> Result<&'a [u8]> {
        self.next().ok_or_else(|| {
            Error::at_line(
                self.line,
                ErrorKind::UnexpectedEof { context: format!("expected {what}") },
            )
        })
    }

    fn expect(&mut self, p: &str) -> Result<()> {
        let t = self.token(&format!("`{p}`"))?;
        if t == p.as_bytes() {
            Ok(())
        } else {
            Err(Error::expected(self.line, format!("`{p}`"), show(t)))
        }
    }

    fn int(&mut self, what: &str) -> Result<i64> {
        let t = self.token(what)?;
        parse_i64(t).ok_or_else(|| Error::expected(self.line, what, show(t)))
    }

    fn label(&mut self, what: &str, below: usize) -> Result<u32> {
        let v = self.int(what)?;
        if v < 0 || v as u64 >= below as u64 {
            return Err(Error::at_line(
                self.line,
                ErrorKind::IndexOutOfRange { what: what.into(), index: v, available: below },
            ));
        }
        Ok(v as u32)
    }

    fn f64(&mut self, what: &str) -> Result<f64> {
        let t = self.token(what)?;
        match parse_f64(t) {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(Error::at_line(
                self.line,
                ErrorKind::NonFinite { what: what.into(), value: show(t) },
            )),
            Err(()) => Err(Error::expected(self.line, what, show(t))),
        }
    }

    /// The `FoamFile { … }` header, if there is one: whether the lists are binary, and
    /// the class. Binary files must be little-endian with 32-bit labels and 64-bit
    /// scalars (OpenFOAM's default build).
    fn header(&mut self) -> Result<Header> {
        let mut h = Header { binary: false, class: Vec::new() };
        let save = (self.pos, self.line);
        if self.next() != Some(b"FoamFile") {
            (self.pos, self.line) = save;
            return Ok(h);
        }
        self.expect("{")?;
        let mut arch: Option<Vec<u8>> = None;
        loop {
            let key = self.token("`}` closing FoamFile")?;
            if key == b"}" {
                break;
            }
            let mut value = Vec::new();
            loop {
                let t = self.token("`;`")?;
                if t == b";" {
                    break;
                }
                value.push(t);
            }
            let first = value.first().copied().unwrap_or(b"");
            match key {
                b"format" => match first {
                    b"ascii" => {}
                    b"binary" => h.binary = true,
                    _ => {
                        return Err(Error::expected(
                            self.line,
                            "`format ascii;` or `format binary;`",
                            show(first),
                        ))
                    }
                },
                b"class" => h.class = first.to_vec(),
                b"arch" => arch = Some(first.to_vec()),
                _ => {}
            }
        }
        if h.binary {
            let a = arch.unwrap_or_default();
            let words = String::from_utf8_lossy(&a).trim_matches('"').to_string();
            let ok = words.split(';').all(|w| matches!(w, "LSB" | "label=32" | "scalar=64" | ""));
            if !ok || !words.contains("LSB") {
                return Err(Error::at_line(
                    self.line,
                    ErrorKind::Unsupported(format!(
                        "binary polyMesh files of arch `{words}` (smartmesh reads \"LSB;label=32;scalar=64\")"
                    )),
                ));
            }
        }
        Ok(h)
    }

    /// The bytes of a binary list of `n` items of `size` bytes: `n(` bytes `)`, or `0()`.
    fn raw(&mut self, what: &str, size: usize) -> Result<(usize, &'a [u8])> {
        let n = self.count(what, size)?;
        self.expect("(")?;
        let end = self.pos + n * size;
        if end > self.d.len() {
            return Err(Error::at_line(
                self.line,
                ErrorKind::UnexpectedEof { context: format!("{what}: {n} items") },
            ));
        }
        let bytes = &self.d[self.pos..end];
        self.pos = end;
        self.expect(")")?;
        Ok((n, bytes))
    }

    /// A list of labels below `below`, ASCII or binary.
    fn labels(&mut self, binary: bool, what: &str, below: usize) -> Result<Vec<u32>> {
        if binary {
            let line = self.line;
            let (_, bytes) = self.raw(what, 4)?;
            return bytes
                .chunks_exact(4)
                .map(|c| {
                    let v = i32::from_le_bytes([c[0], c[1], c[2], c[3]]) as i64;
                    if v < 0 || v as u64 >= below as u64 {
                        Err(Error::at_line(
                            line,
                            ErrorKind::IndexOutOfRange {
                                what: what.into(),
                                index: v,
                                available: below,
                            },
                        ))
                    } else {
                        Ok(v as u32)
                    }
                })
                .collect();
        }
        let n = self.count(what, 2)?;
        self.expect("(")?;
        let mut v = Vec::with_capacity(n);
        for _ in 0..n {
            v.push(self.label(what, below)?);
        }
        self.expect(")")?;
        Ok(v)
    }

    /// A list's count, checked against the bytes left.
    fn count(&mut self, what: &str, min_bytes: usize) -> Result<usize> {
        let n = self.int(what)?;
        if n < 0 {
            return Err(Error::expected(
                self.line,
                format!("{what} (a non-negative integer)"),
                n.to_string(),
            ));
        }
        check_count(n as usize, self.d.len() - self.pos, min_bytes, what)
            .map_err(|k| Error::at_line(self.line, k))
    }
}

/// What a file's `FoamFile` header says.
struct Header {
    binary: bool,
    class: Vec<u8>,
}

/// One patch of `boundary`.
pub(super) struct PatchInfo {
    pub(super) name: String,
    pub(super) kind: String,
    pub(super) n_faces: usize,
    pub(super) start: usize,
}

/// Reads the 2D mesh of the case directory `case`.
pub fn read_case(case: &Path) -> Result<TaggedMesh> {
    let dir = case.join("constant").join("polyMesh");
    read_poly_mesh(
        |name| {
            let p = dir.join(name);
            std::fs::read(&p).map_err(|e| Error::new(ErrorKind::Unreadable(e)).with_path(&p))
        },
        &dir,
    )
}

/// Reads the 2D mesh of the polyMesh files `file(name)` gives (`points`, `faces`,
/// `owner`, `neighbour`, `boundary`); errors name them in `dir`.
pub fn read_poly_mesh(file: impl Fn(&str) -> Result<Vec<u8>>, dir: &Path) -> Result<TaggedMesh> {
    let at = |name: &str| dir.join(name);

    let bytes = file("points")?;
    let points = (|| {
        let mut l = Lexer::new(&bytes);
        if l.header()?.binary {
            let line = l.line;
            let (_, bytes) = l.raw("the number of points", 24)?;
            return bytes
                .chunks_exact(24)
                .map(|c| {
                    let v: [f64; 3] = std::array::from_fn(|k| {
                        f64::from_le_bytes(c[8 * k..8 * k + 8].try_into().unwrap_or([0; 8]))
                    });
                    if v.iter().all(|x| x.is_finite()) {
                        Ok(v)
                    } else {
                        Err(Error::at_line(
                            line,
                            ErrorKind::NonFinite {
                                what: "a point".into(),
                                value: format!("{v:?}"),
                            },
                        ))
                    }
                })
                .collect();
        }
        let n = l.count("the number of points", 7)?;
        l.expect("(")?;
        let mut pts = Vec::with_capacity(n);
        for _ in 0..n {
            l.expect("(")?;
            pts.push([l.f64("x")?, l.f64("y")?, l.f64("z")?]);
            l.expect(")")?;
        }
        l.expect(")")?;
        Ok(pts)
    })()
    .map_err(|e: Error| e.with_path(at("points")))?;

    let bytes = file("faces")?;
    let faces = (|| {
        let mut l = Lexer::new(&bytes);
        let h = l.header()?;
        if h.class == b"faceCompactList" {
            // The offsets of each face's labels, then the labels.
            let line = l.line;
            let offsets = l.labels(h.binary, "a face offset", usize::MAX)?;
            let flat = l.labels(h.binary, "a face's point", points.len())?;
            let mut faces = Vec::with_capacity(offsets.len().saturating_sub(1));
            for w in offsets.windows(2) {
                let (a, b) = (w[0] as usize, w[1] as usize);
                if a > b || b > flat.len() || b - a < 3 {
                    return Err(Error::at_line(
                        line,
                        ErrorKind::Inconsistent(format!(
                            "face offsets {a} to {b} in a list of {} labels",
                            flat.len()
                        )),
                    ));
                }
                faces.push(flat[a..b].to_vec());
            }
            return Ok(faces);
        }
        if h.binary {
            return Err(Error::expected(
                l.line,
                "`class faceCompactList;` in a binary faces file",
                String::from_utf8_lossy(&h.class).into_owned(),
            ));
        }
        let n = l.count("the number of faces", 8)?;
        l.expect("(")?;
        let mut faces: Vec<Vec<u32>> = Vec::with_capacity(n);
        for _ in 0..n {
            let k = l.count("the number of points of a face", 2)?;
            if k < 3 {
                return Err(Error::expected(l.line, "a face of 3 points or more", format!("{k}")));
            }
            l.expect("(")?;
            let mut f = Vec::with_capacity(k);
            for _ in 0..k {
                f.push(l.label("a face's point", points.len())?);
            }
            l.expect(")")?;
            faces.push(f);
        }
        l.expect(")")?;
        Ok(faces)
    })()
    .map_err(|e: Error| e.with_path(at("faces")))?;

    let labels = |name: &str| -> Result<Vec<u32>> {
        let bytes = file(name)?;
        (|| {
            let mut l = Lexer::new(&bytes);
            let binary = l.header()?.binary;
            l.labels(binary, "a cell", u32::MAX as usize)
        })()
        .map_err(|e: Error| e.with_path(at(name)))
    };
    let owner = labels("owner")?;
    let neighbour = labels("neighbour")?;
    if owner.len() != faces.len() || neighbour.len() > faces.len() {
        return Err(Error::new(ErrorKind::Inconsistent(format!(
            "{} faces, {} owners and {} neighbours",
            faces.len(),
            owner.len(),
            neighbour.len()
        )))
        .with_path(at("owner")));
    }
    let n_cells = owner.iter().chain(&neighbour).map(|&c| c as usize + 1).max().unwrap_or(0);
    // Every cell owns a face: more cells than faces is a label out of range, refused
    // before anything is allocated per cell.
    if n_cells > owner.len() {
        return Err(Error::new(ErrorKind::Inconsistent(format!(
            "a cell label {} where {} faces can make at most {} cells",
            n_cells - 1,
            owner.len(),
            owner.len()
        )))
        .with_path(at("owner")));
    }

    let bytes = file("boundary")?;
    let patches = (|| {
        let mut l = Lexer::new(&bytes);
        l.header()?;
        let n = l.count("the number of patches", 8)?;
        l.expect("(")?;
        let mut patches = Vec::with_capacity(n);
        for _ in 0..n {
            let name = String::from_utf8_lossy(l.token("a patch name")?).into_owned();
            l.expect("{")?;
            let (mut kind, mut n_faces, mut start) = (None, None, None);
            loop {
                let key = l.token("`}` closing a patch")?;
                if key == b"}" {
                    break;
                }
                let mut value = Vec::new();
                loop {
                    let t = l.token("`;`")?;
                    if t == b";" {
                        break;
                    }
                    value.push(t);
                }
                let first = value.first().copied().unwrap_or(b"");
                match key {
                    b"type" => kind = Some(String::from_utf8_lossy(first).into_owned()),
                    b"nFaces" | b"startFace" => {
                        let v = parse_i64(first)
                            .filter(|&v| v >= 0 && v as usize <= faces.len())
                            .ok_or_else(|| l.expected_count(key, first, faces.len()))?
                            as usize;
                        if key == b"nFaces" {
                            n_faces = Some(v);
                        } else {
                            start = Some(v);
                        }
                    }
                    _ => {}
                }
            }
            let (Some(kind), Some(n_faces), Some(start)) = (kind, n_faces, start) else {
                return Err(Error::expected(
                    l.line,
                    format!("`type`, `nFaces` and `startFace` in patch `{name}`"),
                    "fewer",
                ));
            };
            if start + n_faces > faces.len() {
                return Err(Error::at_line(
                    l.line,
                    ErrorKind::Inconsistent(format!(
                        "patch `{name}` ends past the {} faces",
                        faces.len()
                    )),
                ));
            }
            patches.push(PatchInfo { name, kind, n_faces, start });
        }
        l.expect(")")?;
        Ok(patches)
    })()
    .map_err(|e: Error| e.with_path(at("boundary")))?;

    // A case with no `empty` or `wedge` patch is 3D: its cells are read as they are.
    if !patches.iter().any(|p| p.kind == "empty" || p.kind == "wedge") {
        let mut zones = Vec::new();
        for (name, key, below) in
            [("cellZones", "cellLabels", n_cells), ("faceZones", "faceLabels", neighbour.len())]
        {
            zones.push(match file(name) {
                Ok(bytes) => parse_zones(&bytes, key, below).map_err(|e| e.with_path(at(name)))?,
                Err(e) if is_missing(&e) => Vec::new(),
                Err(e) => return Err(e),
            });
        }
        let mesh = super::read3d::to_3d(
            &super::read3d::Poly {
                points: &points,
                faces: &faces,
                owner: &owner,
                neighbour: &neighbour,
                n_cells,
            },
            &patches,
            &zones[0],
            &zones[1],
        );
        return mesh.map_err(|reason| {
            Error::new(ErrorKind::Unsupported(format!("this 3D case: {reason}"))).with_path(dir)
        });
    }
    to_2d(&points, &faces, &owner, n_cells, &patches).map_err(|reason| {
        Error::new(ErrorKind::Unsupported(format!("this case as a 2D mesh: {reason}")))
            .with_path(dir)
    })
}

/// Whether reading a file failed because it is not there (an optional zones file).
fn is_missing(e: &Error) -> bool {
    matches!(&e.kind, ErrorKind::Unreadable(io) if io.kind() == std::io::ErrorKind::NotFound)
}

/// The zones of a `cellZones` or `faceZones` file: each zone's name and the labels
/// under `key` (below `below`); other entries (`type`, `flipMap`) are left.
fn parse_zones(bytes: &[u8], key: &str, below: usize) -> Result<Vec<(String, Vec<u32>)>> {
    let mut l = Lexer::new(bytes);
    let binary = l.header()?.binary;
    let n = l.count("the number of zones", 8)?;
    l.expect("(")?;
    let mut zones = Vec::with_capacity(n);
    for _ in 0..n {
        let name = String::from_utf8_lossy(l.token("a zone name")?).into_owned();
        l.expect("{")?;
        let mut items = None;
        loop {
            let k = l.token("`}` closing a zone")?;
            if k == b"}" {
                break;
            }
            if k == key.as_bytes() {
                let save = (l.pos, l.line);
                if !l.token("a list")?.starts_with(b"List<") {
                    (l.pos, l.line) = save;
                }
                items = Some(l.labels(binary, key, below)?);
                l.expect(";")?;
                continue;
            }
            loop {
                if l.token("`;`")? == b";" {
                    break;
                }
            }
        }
        let items = items
            .ok_or_else(|| Error::expected(l.line, format!("`{key}` in zone `{name}`"), "none"))?;
        zones.push((name, items));
    }
    l.expect(")")?;
    Ok(zones)
}

impl Lexer<'_> {
    fn expected_count(&self, key: &[u8], found: &[u8], faces: usize) -> Error {
        Error::expected(
            self.line,
            format!("`{}` a count of at most {faces} faces", String::from_utf8_lossy(key)),
            show(found),
        )
    }
}

/// The 2D mesh of an extruded polyMesh (see the module's header).
fn to_2d(
    points: &[[f64; 3]],
    faces: &[Vec<u32>],
    owner: &[u32],
    n_cells: usize,
    patches: &[PatchInfo],
) -> std::result::Result<TaggedMesh, String> {
    let empty: Vec<&PatchInfo> = patches.iter().filter(|p| p.kind == "empty").collect();
    if empty.is_empty() {
        let what = if patches.iter().any(|p| p.kind == "wedge") {
            "it is an axisymmetric wedge, which smartmesh does not read back yet"
        } else {
            "it has no `empty` patch (front and back of a one-cell-thick case)"
        };
        return Err(what.into());
    }
    let zmin = empty
        .iter()
        .flat_map(|p| &faces[p.start..p.start + p.n_faces])
        .flatten()
        .map(|&v| points[v as usize][2])
        .fold(f64::INFINITY, f64::min);
    let on_base = |v: u32| points[v as usize][2] == zmin;
    let mut base: Vec<Option<&Vec<u32>>> = vec![None; n_cells];
    for p in &empty {
        for fi in p.start..p.start + p.n_faces {
            let f = &faces[fi];
            if !f.iter().all(|&v| on_base(v)) {
                continue;
            }
            let c = owner[fi] as usize;
            if base[c].is_some() {
                return Err(format!("cell {c} has two faces on the plane z = {zmin}"));
            }
            if f.len() > 4 {
                return Err(format!(
                    "cell {c}'s face on z = {zmin} has {} points (triangles and quads only)",
                    f.len()
                ));
            }
            base[c] = Some(f);
        }
    }
    if let Some(c) = base.iter().position(Option::is_none) {
        return Err(format!(
            "cell {c} has no face on the plane z = {zmin}: the case is not extruded along z"
        ));
    }
    // 2D points: those of the base faces, in polyMesh order.
    let mut new_of = vec![u32::MAX; points.len()];
    for f in base.iter().flatten() {
        for &v in f.iter() {
            new_of[v as usize] = 0;
        }
    }
    let mut mesh = TaggedMesh::new();
    for (i, slot) in new_of.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = mesh.points.len() as u32;
            mesh.points.push([points[i][0], points[i][1], 0.0]);
        }
    }
    for f in base.iter().flatten() {
        // The base face points out of the cell, down: reversed, it is counter-clockwise.
        let c: Vec<u32> = std::iter::once(f[0])
            .chain(f[1..].iter().rev().copied())
            .map(|v| new_of[v as usize])
            .collect();
        let kind = if c.len() == 3 { CellKind::Triangle } else { CellKind::Quad };
        mesh.block_mut(kind).push(&c, 1, 1);
    }
    // Lines from the other patches, tagged by patch.
    let named: Vec<&PatchInfo> = patches.iter().filter(|p| p.kind != "empty").collect();
    let generated = |n: &str| -> Option<i32> {
        let d = n.strip_prefix("tag")?;
        let v: i32 = d.parse().ok()?;
        (v >= 0 && v.to_string() == d).then_some(v)
    };
    let taken: std::collections::BTreeSet<i32> =
        named.iter().filter_map(|p| generated(&p.name)).collect();
    let mut next = 1;
    for p in named {
        let tag = match generated(&p.name) {
            Some(t) => t,
            None => {
                while taken.contains(&next) {
                    next += 1;
                }
                next += 1;
                mesh.tag_names.insert((1, next - 1), p.name.clone());
                next - 1
            }
        };
        for f in &faces[p.start..p.start + p.n_faces] {
            let on: Vec<u32> = f.iter().copied().filter(|&v| on_base(v)).collect();
            if on.len() != 2 {
                return Err(format!(
                    "a face of patch `{}` has {} points on z = {zmin}, not 2",
                    p.name,
                    on.len()
                ));
            }
            // The face [a, b, b', a'] runs a → b on the base.
            let k = f.iter().position(|&v| v == on[0]).unwrap_or(0);
            let (a, b) =
                if on_base(f[(k + 1) % f.len()]) { (on[0], on[1]) } else { (on[1], on[0]) };
            let (a, b) = (new_of[a as usize], new_of[b as usize]);
            if a == u32::MAX || b == u32::MAX {
                return Err(format!("a face of patch `{}` is on no cell's base", p.name));
            }
            mesh.block_mut(CellKind::Line).push(&[a, b], tag, tag);
        }
    }
    Ok(mesh)
}
