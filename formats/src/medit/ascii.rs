//! ASCII `.mesh` / `.sol`: keywords by name, numbers as whitespace-separated tokens
//! (records may span lines), `#` comments.

use crate::error::{Error, ErrorKind, Position, Result};
use crate::scan::Scan;
use crate::text::{push_f64, push_int, Tokens};

use super::keywords::{Keyword, KEYWORDS};
use super::*;

/// Reads the keywords of an ASCII file.
pub(super) fn read(bytes: &[u8]) -> Result<Parsed> {
    let bytes = crate::text::lone_cr_as_newline(bytes);
    let mut t = Tokens::with_comments(&bytes, b'#');
    let mut p = Parsed::default();
    while let Some(tok) = t.next() {
        let line = t.line();
        if lookup(tok).is_none() && p.sol.is_some() && tok[0].is_ascii_alphabetic() {
            // A solver's own keywords after the solution (MMG's `naca-multiSols.sol`:
            // `CFL`, `Model`, `Residu`...): skipped, as MMG skips what it does not know,
            // up to the next keyword of the table; the read report names them.
            skip_unknown(&mut t, &mut p, tok, line);
            continue;
        }
        let Some(code) = lookup(tok) else {
            let what = if tok[0].is_ascii_alphabetic() {
                "a keyword of libMeshb's table"
            } else {
                "a keyword"
            };
            return Err(t.expected(what, tok));
        };
        match code {
            KW_END => break,
            KW_VERSION => {
                let v = t.i64("the version after MeshVersionFormatted")?;
                if !(1..=4).contains(&v) {
                    return Err(Error::expected(
                        t.line(),
                        "MeshVersionFormatted 1, 2, 3 or 4",
                        v.to_string(),
                    ));
                }
            }
            KW_DIMENSION => {
                let d = t.i64("the dimension")?;
                if d != 2 && d != 3 {
                    return Err(Error::expected(t.line(), "Dimension 2 or 3", d.to_string()));
                }
                // Everything read so far was laid out with the first one.
                if p.dim != 0 && p.dim != d as u8 {
                    return Err(Error::at_line(
                        t.line(),
                        ErrorKind::Inconsistent(format!("Dimension {d} after Dimension {}", p.dim)),
                    ));
                }
                p.dim = d as u8;
            }
            KW_VERTICES => read_vertices(&mut t, &mut p, line)?,
            KW_SOL_AT_VERTICES => read_sol(&mut t, &mut p, line)?,
            _ => {
                if let Some(kind) = element_kind(code) {
                    read_elements(&mut t, &mut p, kind, line)?;
                } else if set_target(code).is_some() {
                    read_set(&mut t, &mut p, code)?;
                } else {
                    let n = skip(&mut t, &KEYWORDS[code], p.dim, line)?;
                    if n > 0 && is_unsupported(code) {
                        return Err(Error::at_line(
                            line,
                            ErrorKind::Unsupported(format!(
                                "{n} {}: {UNSUPPORTED_WHY}",
                                KEYWORDS[code].name
                            )),
                        ));
                    }
                }
            }
        }
    }
    Ok(p)
}

/// Skips the unknown keyword `name` (read at `line`) and every token after it up to the
/// next keyword of libMeshb's table (or the end), noting each unknown keyword met.
fn skip_unknown(t: &mut Tokens<'_>, p: &mut Parsed, name: &[u8], line: u64) {
    p.skipped.push((String::from_utf8_lossy(name).into_owned(), line));
    loop {
        let mut ahead = t.clone();
        let Some(tok) = ahead.next() else { break };
        if lookup(tok).is_some() {
            break;
        }
        if tok[0].is_ascii_alphabetic() {
            p.skipped.push((String::from_utf8_lossy(tok).into_owned(), ahead.line()));
        }
        *t = ahead;
    }
}

fn need_dim(p: &Parsed, line: u64, what: &str) -> Result<usize> {
    if p.dim == 0 {
        return Err(Error::expected(line, format!("Dimension before {what}"), what));
    }
    Ok(p.dim as usize)
}

/// A reference: an integer that fits in 32 bits.
#[inline]
fn reference(t: &mut Tokens<'_>, what: &str) -> Result<i32> {
    let v = t.i64(what)?;
    i32::try_from(v)
        .map_err(|_| Error::expected(t.line(), format!("{what} (a 32-bit integer)"), v.to_string()))
}

fn read_vertices(t: &mut Tokens<'_>, p: &mut Parsed, line: u64) -> Result<()> {
    let dim = need_dim(p, line, "Vertices")?;
    if p.vertices_read {
        return Err(Error::at_line(
            line,
            ErrorKind::Inconsistent("a second Vertices keyword".into()),
        ));
    }
    let n = t.count("number of vertices", 2 * (dim + 1))?;
    p.points.reserve_exact(n);
    p.refs.reserve_exact(n);
    let mut i = 0;
    while i < n {
        i += fast_vertices(t, p, dim, n - i);
        if i == n {
            break;
        }
        // The general path, for a record the fast path left (and its error, if any).
        let x = t.f64("x coordinate of a vertex")?;
        let y = t.f64("y coordinate of a vertex")?;
        let z = if dim == 3 { t.f64("z coordinate of a vertex")? } else { 0.0 };
        p.points.push([x, y, z]);
        p.refs.push(reference(t, "vertex reference")?);
        i += 1;
    }
    p.vertices_read = true;
    Ok(())
}

/// Reads up to `max` vertices of plain numbers; returns how many, with the tokenizer
/// moved past them.
fn fast_vertices(t: &mut Tokens<'_>, p: &mut Parsed, dim: usize, max: usize) -> usize {
    let mut s = Scan::new(t.data(), t.pos());
    let (mut done, mut end) = (0, t.pos());
    while done < max {
        let mut c = [0.0; 3];
        for slot in c.iter_mut().take(dim) {
            s.ws();
            match s.f64() {
                Some(v) => *slot = v,
                None => return finish(t, end, done),
            }
        }
        s.ws();
        let Some(r) = s.int().and_then(|r| i32::try_from(r).ok()) else {
            return finish(t, end, done);
        };
        p.points.push(c);
        p.refs.push(r);
        done += 1;
        end = s.pos;
    }
    finish(t, end, done)
}

fn finish(t: &mut Tokens<'_>, end: usize, done: usize) -> usize {
    t.seek(end);
    done
}

fn read_elements(t: &mut Tokens<'_>, p: &mut Parsed, kind: CellKind, line: u64) -> Result<()> {
    let k = kind.nodes_per_cell();
    let name = KEYWORDS[element_code(kind)].name;
    let n = t.count(&format!("number of {name}"), 2 * (k + 1))?;
    // The vertex count is known when Vertices came first, as it does in every file MMG
    // or libMeshb writes; otherwise the numbers are checked at the end.
    // Past MAX_POINTS no cell can name a vertex (32-bit connectivity).
    let nv = if p.vertices_read { p.points.len() } else { MAX_POINTS }.min(MAX_POINTS);
    let mut e = Elements {
        kind,
        nodes: Vec::with_capacity(n * k),
        refs: Vec::with_capacity(n),
        at: Locator::Line(line),
        unchecked: !p.vertices_read,
    };
    let mut i = 0;
    while i < n {
        i += fast_elements(t, &mut e, k, nv, n - i);
        if i == n {
            break;
        }
        // The general path, for a record the fast path left (and its error, if any).
        for _ in 0..k {
            let v = t.i64("vertex number")?;
            if v < 1 || v as u64 > nv as u64 {
                return Err(t.error(super::bad_number(
                    format!("{} {} ({name})", kind.name(), i + 1),
                    v,
                    if p.vertices_read { nv } else { 0 },
                )));
            }
            e.nodes.push((v - 1) as NodeIndex);
        }
        e.refs.push(reference(t, "element reference")?);
        i += 1;
    }
    p.elements.push(e);
    Ok(())
}

/// Reads up to `max` elements of plain numbers in range; returns how many, with the
/// tokenizer moved past them.
fn fast_elements(t: &mut Tokens<'_>, e: &mut Elements, k: usize, nv: usize, max: usize) -> usize {
    let mut s = Scan::new(t.data(), t.pos());
    let (mut done, mut end) = (0, t.pos());
    let mut v = [0 as NodeIndex; MAX_NODES];
    while done < max {
        for slot in v.iter_mut().take(k) {
            s.ws();
            match s.int() {
                Some(x) if x >= 1 && x as u64 <= nv as u64 => *slot = (x - 1) as NodeIndex,
                _ => return finish(t, end, done),
            }
        }
        s.ws();
        let Some(r) = s.int().and_then(|r| i32::try_from(r).ok()) else {
            return finish(t, end, done);
        };
        e.nodes.extend_from_slice(&v[..k]);
        e.refs.push(r);
        done += 1;
        end = s.pos;
    }
    finish(t, end, done)
}

fn read_set(t: &mut Tokens<'_>, p: &mut Parsed, code: usize) -> Result<()> {
    let name = KEYWORDS[code].name;
    let n = t.count(&format!("number of {name}"), 2)?;
    let mut s = Set { code, items: Vec::with_capacity(n), at: Vec::with_capacity(n) };
    for _ in 0..n {
        let v = t.i64("a number in a set keyword")?;
        if v < 1 {
            return Err(t.error(super::bad_number(
                format!("{name} entry {}", s.items.len() + 1),
                v,
                p.points.len(),
            )));
        }
        s.items.push(usize::try_from(v - 1).unwrap_or(usize::MAX));
        s.at.push(Position::Line(t.line()));
    }
    p.sets.push(s);
    Ok(())
}

/// The solution-type header `<#types> <type>...`; types are checked.
fn sol_types(t: &mut Tokens<'_>, dim: u8, name: &str) -> Result<Vec<u32>> {
    let nt = t.count(&format!("number of solution types of {name}"), 2)?;
    let mut types = Vec::with_capacity(nt);
    for _ in 0..nt {
        let ty = t.i64("solution type")?;
        match u32::try_from(ty).ok().filter(|&ty| sol_size(ty, dim).is_some()) {
            Some(ty) => types.push(ty),
            None => {
                return Err(Error::expected(
                    t.line(),
                    "solution type 1 (scalar), 2 (vector), 3 (symmetric tensor) or 4 (matrix)",
                    ty.to_string(),
                ))
            }
        }
    }
    Ok(types)
}

fn read_sol(t: &mut Tokens<'_>, p: &mut Parsed, line: u64) -> Result<()> {
    need_dim(p, line, "SolAtVertices")?;
    let n = t.count("number of vertices of SolAtVertices", 2)?;
    let types = sol_types(t, p.dim, "SolAtVertices")?;
    let stride: usize = types.iter().map(|&ty| sol_size(ty, p.dim).unwrap_or(0)).sum();
    crate::text::check_count(n.saturating_mul(stride), t.remaining().len(), 2, "solution values")
        .map_err(|k| Error::at_line(line, k))?;
    let mut values = Vec::with_capacity(n * stride);
    while values.len() < n * stride {
        fast_reals(t, &mut values, n * stride);
        if values.len() < n * stride {
            values.push(t.f64("a solution value")?);
        }
    }
    p.sol = Some(Sol { n, types, values, raw: None, at: Some(Position::Line(line)) });
    Ok(())
}

/// Reads plain reals until `values` holds `total`; stops early at anything else.
fn fast_reals(t: &mut Tokens<'_>, values: &mut Vec<f64>, total: usize) {
    let mut s = Scan::new(t.data(), t.pos());
    let mut end = t.pos();
    while values.len() < total {
        s.ws();
        match s.f64() {
            Some(v) => values.push(v),
            None => break,
        }
        end = s.pos;
    }
    t.seek(end);
}

/// Skips a keyword smartmesh does not use, by its layout; returns its item count.
fn skip(t: &mut Tokens<'_>, kw: &Keyword, dim: u8, line: u64) -> Result<usize> {
    let unknown = || {
        Error::at_line(
            line,
            ErrorKind::Unsupported(format!(
                "keyword {} (layout `{}`, which smartmesh cannot skip in ASCII)",
                kw.name, kw.layout
            )),
        )
    };
    let layout = kw.layout.as_bytes();
    if dim == 0 && layout.iter().any(|c| matches!(c, b'd' | b's' | b'h')) {
        return Err(Error::expected(line, format!("Dimension before {}", kw.name), kw.name));
    }
    // Fields of one item: numbers (repeated per dimension or per solution real), and
    // whole-line strings.
    let fields = |sol: usize| -> Result<(usize, usize)> {
        let (mut numbers, mut strings) = (0usize, 0usize);
        let mut rest = layout;
        while let [c, tail @ ..] = rest {
            let (repeat, field, tail) = match (c, tail) {
                (b'd', [f, tail @ ..]) => (dim as usize, *f, tail),
                (b's' | b'h', [f, tail @ ..]) => (sol, *f, tail),
                _ => (1, *c, tail),
            };
            match field {
                b'i' | b'r' => numbers = numbers.saturating_add(repeat),
                b'c' => strings += repeat,
                _ => return Err(unknown()),
            }
            rest = tail;
        }
        Ok((numbers, strings))
    };
    fields(0)?;
    // As libMeshb reads the header: the count, then for solutions the types (and for
    // high-order solutions the degree and node count).
    let n = if kw.counted { t.count(&format!("number of {}", kw.name), 2)? } else { 1 };
    let mut sol = 0;
    if matches!(layout, b"sr" | b"hr") {
        let types = sol_types(t, dim, kw.name)?;
        sol = types.iter().map(|&ty| sol_size(ty, dim).unwrap_or(0)).sum::<usize>();
        if layout == b"hr" {
            t.i64("degree")?;
            let nodes = t.count("number of nodes", 1)?;
            sol = sol.saturating_mul(nodes);
        }
    }
    let (numbers, strings) = fields(sol)?;
    crate::text::check_count(n.saturating_mul(numbers), t.remaining().len(), 2, kw.name)
        .map_err(|k| Error::at_line(line, k))?;
    for _ in 0..n {
        for _ in 0..numbers {
            t.token("a number")?;
        }
        for _ in 0..strings {
            t.skip_space();
            t.rest_of_line();
        }
    }
    Ok(n)
}

// ---------------------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------------------

fn header(out: &mut Vec<u8>, dim: u8) {
    out.extend_from_slice(b"MeshVersionFormatted 2\n\nDimension ");
    push_int(out, dim);
    out.extend_from_slice(b"\n\n");
}

fn keyword(out: &mut Vec<u8>, code: usize, n: usize) {
    out.extend_from_slice(KEYWORDS[code].name.as_bytes());
    out.push(b'\n');
    push_int(out, n);
    out.push(b'\n');
}

pub(super) fn write_mesh(m: &Out<'_>) -> Vec<u8> {
    let ncells: usize = m
        .elements
        .iter()
        .flat_map(|(_, b)| b.iter())
        .map(|b| b.physical.len() * (b.kind.nodes_per_cell() + 1))
        .sum();
    let mut out = Vec::with_capacity(m.points.len() * (26 * m.dim as usize + 4) + ncells * 9 + 256);
    header(&mut out, m.dim);
    keyword(&mut out, KW_VERTICES, m.points.len());
    for (i, p) in m.points.iter().enumerate() {
        for c in &p[..m.dim as usize] {
            push_f64(&mut out, *c);
            out.push(b' ');
        }
        push_int(&mut out, m.refs.as_ref().map_or(0, |r| r[i]));
        out.push(b'\n');
    }
    for (code, blocks) in &m.elements {
        out.push(b'\n');
        keyword(&mut out, *code, m.count(*code));
        for b in blocks {
            let order = gmsh_positions(b.kind);
            for (cell, &r) in b.cells().zip(&b.physical) {
                for j in 0..cell.len() {
                    push_int(&mut out, cell[order.map_or(j, |o| o[j])] + 1);
                    out.push(b' ');
                }
                push_int(&mut out, r);
                out.push(b'\n');
            }
        }
    }
    for (code, items) in &m.sets {
        out.push(b'\n');
        keyword(&mut out, *code, items.len());
        for &v in items {
            push_int(&mut out, v);
            out.push(b'\n');
        }
    }
    out.extend_from_slice(b"\nEnd\n");
    out
}

pub(super) fn write_sol(s: &SolOut<'_>) -> Vec<u8> {
    let mut out = Vec::with_capacity(s.n * s.stride * 25 + 128);
    header(&mut out, s.dim);
    keyword(&mut out, KW_SOL_AT_VERTICES, s.n);
    push_int(&mut out, s.types.len());
    for &ty in s.types {
        out.push(b' ');
        push_int(&mut out, ty);
    }
    out.push(b'\n');
    let mut row = Vec::with_capacity(s.stride);
    for v in 0..s.n {
        s.row(v, &mut row);
        for (j, v) in row.iter().enumerate() {
            if j > 0 {
                out.push(b' ');
            }
            push_f64(&mut out, *v);
        }
        out.push(b'\n');
    }
    out.extend_from_slice(b"\nEnd\n");
    out
}
