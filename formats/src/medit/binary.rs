//! Binary `.meshb` / `.solb`: a 4-byte endianness code (1), a 4-byte version, then
//! keywords as `<code (4 bytes)> <offset of the next keyword>` followed by their data.
//!
//! Sizes by version (libMeshb `ExpFmt`, `GetPos`, `ScaKwdHdr`): reals are 4 bytes in
//! version 1 and 8 after (or as `FloatingPointPrecision` says); offsets are 4 bytes up to
//! version 2 and 8 from version 3; integers (counts, vertex numbers, references) are 4
//! bytes up to version 3 and 8 in version 4. Solution-type headers are always 4-byte words.
//! Arrays are decoded with `chunks_exact`, one monomorphised loop per byte order and
//! integer size.

use crate::error::{Error, ErrorKind, Position, Result};
use crate::text::check_count;

use super::keywords::KEYWORDS;
use super::*;

#[derive(Debug, Clone, Copy)]
struct Fmt {
    le: bool,
    ver: u32,
    real4: bool,
}

impl Fmt {
    fn isz(self) -> usize {
        if self.ver >= 4 {
            8
        } else {
            4
        }
    }
    fn psz(self) -> usize {
        if self.ver >= 3 {
            8
        } else {
            4
        }
    }
    fn rsz(self) -> usize {
        if self.real4 {
            4
        } else {
            8
        }
    }
}

fn truncated(at: usize, what: &str) -> Error {
    Error::at_byte(at as u64, ErrorKind::UnexpectedEof { context: format!("expected {what}") })
}

#[inline(always)]
fn w4<const LE: bool>(b: &[u8]) -> [u8; 4] {
    let mut a = [0u8; 4];
    a.copy_from_slice(&b[..4]);
    if !LE {
        a.reverse();
    }
    a
}

#[inline(always)]
fn w8<const LE: bool>(b: &[u8]) -> [u8; 8] {
    let mut a = [0u8; 8];
    a.copy_from_slice(&b[..8]);
    if !LE {
        a.reverse();
    }
    a
}

#[inline(always)]
fn int_at<const LE: bool, const I8: bool>(b: &[u8]) -> i64 {
    if I8 {
        i64::from_le_bytes(w8::<LE>(b))
    } else {
        i32::from_le_bytes(w4::<LE>(b)) as i64
    }
}

#[inline(always)]
fn real_at<const LE: bool, const R4: bool>(b: &[u8]) -> f64 {
    if R4 {
        f32::from_le_bytes(w4::<LE>(b)) as f64
    } else {
        f64::from_le_bytes(w8::<LE>(b))
    }
}

/// A scalar word of `size` bytes at `at`, bounds checked.
fn scalar(b: &[u8], at: usize, size: usize, le: bool, what: &str) -> Result<i64> {
    let s = b.get(at..at + size).ok_or_else(|| truncated(at, what))?;
    Ok(match (size, le) {
        (4, true) => int_at::<true, false>(s),
        (4, false) => int_at::<false, false>(s),
        (_, true) => int_at::<true, true>(s),
        (_, false) => int_at::<false, true>(s),
    })
}

/// What went wrong in item `i` of an array.
enum Bad {
    Node(usize, i64),
    Ref(usize, i64),
    Coord(usize, f64),
}

/// Decodes `K`-node elements; returns the largest vertex number (0-based) met.
///
/// The records are decoded into arrays of their final length with no test in the
/// loop; the faulty record is looked for only when the folds below say there is one.
#[inline(never)]
fn elements<const LE: bool, const I8: bool, const K: usize>(
    data: &[u8],
    nodes: &mut [NodeIndex],
    refs: &mut [i32],
) -> Result<usize, Bad> {
    let isz = if I8 { 8 } else { 4 };
    let records = data.chunks_exact((K + 1) * isz);
    let n = records.len();
    // One unsigned maximum checks every number: `v - 1` wraps past MAX_POINTS exactly
    // when `v` is below 1 or above MAX_POINTS (no cell can name a vertex past 32-bit
    // connectivity), and is the largest 0-based index otherwise. References need a
    // check only when they are 8 bytes wide.
    let mut top = 0u64;
    let (mut ref_lo, mut ref_hi) = (0i64, 0i64);
    for ((rec, cell), r) in records.zip(nodes.chunks_exact_mut(K)).zip(refs.iter_mut()) {
        for (j, slot) in cell.iter_mut().enumerate() {
            let x = int_at::<LE, I8>(&rec[j * isz..]).wrapping_sub(1) as u64;
            top = top.max(x);
            *slot = x as NodeIndex;
        }
        let v = int_at::<LE, I8>(&rec[K * isz..]);
        if I8 {
            ref_lo = ref_lo.min(v);
            ref_hi = ref_hi.max(v);
        }
        *r = v as i32;
    }
    let node_ok = |v: i64| v >= 1 && v as u64 <= MAX_POINTS as u64;
    let ref_ok = |x: i64| i32::try_from(x).is_ok();
    if top >= MAX_POINTS as u64 || !ref_ok(ref_lo) || !ref_ok(ref_hi) {
        // The first faulty record, and in it the first faulty number, as a loop that
        // stops there would find them.
        for (i, rec) in data.chunks_exact((K + 1) * isz).enumerate() {
            if let Some(v) =
                (0..K).map(|j| int_at::<LE, I8>(&rec[j * isz..])).find(|&v| !node_ok(v))
            {
                return Err(Bad::Node(i, v));
            }
            let x = int_at::<LE, I8>(&rec[K * isz..]);
            if !ref_ok(x) {
                return Err(Bad::Ref(i, x));
            }
        }
    }
    Ok(if n > 0 { top as usize } else { 0 })
}

/// [`elements`] for every byte order, integer size and node count smartmesh reads.
fn elements_any<const LE: bool, const I8: bool>(
    data: &[u8],
    k: usize,
    nodes: &mut [NodeIndex],
    refs: &mut [i32],
) -> Result<usize, Bad> {
    match k {
        2 => elements::<LE, I8, 2>(data, nodes, refs),
        3 => elements::<LE, I8, 3>(data, nodes, refs),
        4 => elements::<LE, I8, 4>(data, nodes, refs),
        5 => elements::<LE, I8, 5>(data, nodes, refs),
        6 => elements::<LE, I8, 6>(data, nodes, refs),
        8 => elements::<LE, I8, 8>(data, nodes, refs),
        9 => elements::<LE, I8, 9>(data, nodes, refs),
        10 => elements::<LE, I8, 10>(data, nodes, refs),
        14 => elements::<LE, I8, 14>(data, nodes, refs),
        18 => elements::<LE, I8, 18>(data, nodes, refs),
        _ => elements::<LE, I8, MAX_NODES>(data, nodes, refs),
    }
}

/// Decodes vertices into `points` (of the final length, zeroed). Their references go to
/// `refs` only when one is not 0: an empty `refs` stands for all 0, what most files
/// hold, and saves an array of fresh memory.
fn vertices<const LE: bool, const I8: bool, const R4: bool>(
    data: &[u8],
    dim: usize,
    points: &mut [[f64; 3]],
    refs: &mut Vec<i32>,
) -> Result<(), Bad> {
    let (isz, rsz) = (if I8 { 8 } else { 4 }, if R4 { 4 } else { 8 });
    let size = dim * rsz + isz;
    // One pass with no test in the loop: finiteness and the range of the references
    // are folded, and the faulty record looked for only when they fail.
    let mut finite = true;
    let (mut lo, mut hi) = (0i64, 0i64);
    for (rec, p) in data.chunks_exact(size).zip(points.iter_mut()) {
        for (c, slot) in p.iter_mut().enumerate().take(dim) {
            let x = real_at::<LE, R4>(&rec[c * rsz..]);
            finite &= x.is_finite();
            *slot = x;
        }
        let r = int_at::<LE, I8>(&rec[dim * rsz..]);
        lo = lo.min(r);
        hi = hi.max(r);
    }
    let ref_ok = |r: i64| i32::try_from(r).is_ok();
    if !finite || !ref_ok(lo) || !ref_ok(hi) {
        for (i, rec) in data.chunks_exact(size).enumerate() {
            if let Some(x) =
                (0..dim).map(|c| real_at::<LE, R4>(&rec[c * rsz..])).find(|x| !x.is_finite())
            {
                return Err(Bad::Coord(i, x));
            }
            let r = int_at::<LE, I8>(&rec[dim * rsz..]);
            if !ref_ok(r) {
                return Err(Bad::Ref(i, r));
            }
        }
    }
    if lo != 0 || hi != 0 {
        refs.extend(data.chunks_exact(size).map(|rec| int_at::<LE, I8>(&rec[dim * rsz..]) as i32));
    }
    Ok(())
}

/// Decodes reals into `out`, checked finite: one pass with no test in the loop, the
/// faulty value looked for only when one was seen.
fn reals<const LE: bool, const R4: bool>(data: &[u8], out: &mut Vec<f64>) -> Result<(), Bad> {
    let rsz = if R4 { 4 } else { 8 };
    let mut finite = true;
    out.extend(data.chunks_exact(rsz).map(|rec| {
        let v = real_at::<LE, R4>(rec);
        finite &= v.is_finite();
        v
    }));
    if finite {
        return Ok(());
    }
    let i = data.chunks_exact(rsz).position(|rec| !real_at::<LE, R4>(rec).is_finite()).unwrap_or(0);
    Err(Bad::Coord(i, real_at::<LE, R4>(&data[i * rsz..])))
}

/// Checks little-endian doubles for finiteness without decoding them into memory.
fn finite_reals(data: &[u8]) -> Result<(), Bad> {
    // A double is finite unless its exponent bits are all ones.
    const EXP: u64 = 0x7ff0_0000_0000_0000;
    let bits = |c: &[u8]| u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]);
    if data.chunks_exact(8).fold(true, |ok, c| ok & (bits(c) & EXP != EXP)) {
        return Ok(());
    }
    let i = data.chunks_exact(8).position(|c| bits(c) & EXP == EXP).unwrap_or(0);
    Err(Bad::Coord(i, f64::from_bits(bits(&data[8 * i..]))))
}

/// Reads the keywords of a binary file.
pub(super) fn read(b: &[u8]) -> Result<Parsed> {
    let code = scalar(b, 0, 4, true, "the endianness code (1)")?;
    let le =
        match code {
            1 => true,
            16777216 => false,
            _ => return Err(Error::at_byte(
                0,
                ErrorKind::Expected {
                    expected:
                        "the endianness code 1 (or 16777216, byte-swapped) of a binary Medit file"
                            .into(),
                    found: code.to_string(),
                },
            )),
        };
    let ver = scalar(b, 4, 4, le, "the version")?;
    if !(1..=4).contains(&ver) {
        return Err(Error::at_byte(
            4,
            ErrorKind::Expected { expected: "version 1, 2, 3 or 4".into(), found: ver.to_string() },
        ));
    }
    let mut f = Fmt { le, ver: ver as u32, real4: ver == 1 };
    let mut p = Parsed::default();
    let mut pos = 8usize;
    while pos < b.len() {
        let code = scalar(b, pos, 4, le, "a keyword code")?;
        let next = scalar(b, pos + 4, f.psz(), le, "the offset of the next keyword")?;
        let data = pos + 4 + f.psz();
        if code == KW_END as i64 {
            break;
        }
        // Offsets only move forward and stay in the file, so the walk ends.
        if next != 0 && (next as u64 <= pos as u64 || next as u64 > b.len() as u64) {
            return Err(Error::at_byte(
                (pos + 4) as u64,
                ErrorKind::Inconsistent(format!(
                    "keyword {code} at byte {pos} gives {next} as the offset of the next keyword, outside bytes {}..={}",
                    pos + 1,
                    b.len()
                )),
            ));
        }
        let limit = if next == 0 { b.len() } else { next as usize };
        let code = usize::try_from(code).ok().filter(|&c| c >= 1 && c < KEYWORDS.len());
        match code {
            Some(KW_DIMENSION) => {
                let d = scalar(b, data, 4, le, "the dimension")?;
                if d != 2 && d != 3 {
                    return Err(Error::at_byte(
                        data as u64,
                        ErrorKind::Expected {
                            expected: "Dimension 2 or 3".into(),
                            found: d.to_string(),
                        },
                    ));
                }
                // Everything read so far was laid out with the first one.
                if p.dim != 0 && p.dim != d as u8 {
                    return Err(Error::at_byte(
                        data as u64,
                        ErrorKind::Inconsistent(format!("Dimension {d} after Dimension {}", p.dim)),
                    ));
                }
                p.dim = d as u8;
            }
            Some(KW_FLOAT_PRECISION) => {
                let bits = scalar(b, data, f.isz(), le, "the floating-point precision")?;
                if bits == 32 || bits == 64 {
                    f.real4 = bits == 32;
                }
            }
            Some(KW_VERTICES) => read_vertices(b, data, limit, f, &mut p)?,
            Some(KW_SOL_AT_VERTICES) => read_sol(b, data, limit, f, &mut p)?,
            Some(c) if element_kind(c).is_some() => read_elements(b, data, limit, f, c, &mut p)?,
            Some(c) if set_target(c).is_some() => read_set(b, data, limit, f, c, &mut p)?,
            Some(c) if is_unsupported(c) && KEYWORDS[c].counted => {
                let n = scalar(b, data, f.isz(), le, "a count")?;
                if n > 0 {
                    return Err(Error::at_byte(
                        pos as u64,
                        ErrorKind::Unsupported(format!(
                            "{n} {}: {UNSUPPORTED_WHY}",
                            KEYWORDS[c].name
                        )),
                    ));
                }
            }
            // Other keywords of the table: skipped by their offset.
            Some(_) => {}
            // Codes outside the table: skipped by their offset like any other.
            None => {}
        }
        if next == 0 {
            break;
        }
        pos = next as usize;
    }
    Ok(p)
}

/// The count after a keyword, checked against the bytes before `limit`.
fn count(
    b: &[u8],
    data: usize,
    limit: usize,
    f: Fmt,
    item_bytes: usize,
    what: &str,
) -> Result<(usize, usize)> {
    let n = scalar(b, data, f.isz(), f.le, &format!("the number of {what}"))?;
    let start = data + f.isz();
    let left = limit.saturating_sub(start);
    let n = usize::try_from(n).map_err(|_| {
        Error::at_byte(
            data as u64,
            ErrorKind::Expected {
                expected: format!("the number of {what} (non-negative)"),
                found: n.to_string(),
            },
        )
    })?;
    check_count(n, left, item_bytes, what).map_err(|k| Error::at_byte(data as u64, k))?;
    Ok((n, start))
}

fn need_dim(p: &Parsed, at: usize, what: &str) -> Result<usize> {
    if p.dim == 0 {
        return Err(Error::at_byte(
            at as u64,
            ErrorKind::Expected {
                expected: format!("Dimension before {what}"),
                found: what.into(),
            },
        ));
    }
    Ok(p.dim as usize)
}

fn read_vertices(b: &[u8], data: usize, limit: usize, f: Fmt, p: &mut Parsed) -> Result<()> {
    let dim = need_dim(p, data, "Vertices")?;
    if p.vertices_read {
        return Err(Error::at_byte(
            data as u64,
            ErrorKind::Inconsistent("a second Vertices keyword".into()),
        ));
    }
    let size = dim * f.rsz() + f.isz();
    let (n, start) = count(b, data, limit, f, size, "vertices")?;
    p.points = vec![[0.0; 3]; n];
    let d = &b[start..start + n * size];
    let r = match (f.le, f.isz() == 8, f.real4) {
        (true, false, false) => vertices::<true, false, false>(d, dim, &mut p.points, &mut p.refs),
        (true, false, true) => vertices::<true, false, true>(d, dim, &mut p.points, &mut p.refs),
        (true, true, false) => vertices::<true, true, false>(d, dim, &mut p.points, &mut p.refs),
        (true, true, true) => vertices::<true, true, true>(d, dim, &mut p.points, &mut p.refs),
        (false, false, false) => {
            vertices::<false, false, false>(d, dim, &mut p.points, &mut p.refs)
        }
        (false, false, true) => vertices::<false, false, true>(d, dim, &mut p.points, &mut p.refs),
        (false, true, false) => vertices::<false, true, false>(d, dim, &mut p.points, &mut p.refs),
        (false, true, true) => vertices::<false, true, true>(d, dim, &mut p.points, &mut p.refs),
    };
    r.map_err(|bad| bad_item(bad, start, size, "vertex", dim * f.rsz(), 0))?;
    p.vertices_read = true;
    Ok(())
}

/// The error for a bad item of an array at `start`, `size` bytes per item; `ref_offset`
/// is where the reference sits in an item.
fn bad_item(
    bad: Bad,
    start: usize,
    size: usize,
    item: &str,
    ref_offset: usize,
    available: usize,
) -> Error {
    let at = |i: usize| (start + i * size) as u64;
    match bad {
        Bad::Node(i, v) => {
            Error::at_byte(at(i), super::bad_number(format!("{item} {}", i + 1), v, available))
        }
        Bad::Ref(i, v) => Error::at_byte(
            at(i) + ref_offset as u64,
            ErrorKind::Expected {
                expected: format!("the reference of {item} {} (a 32-bit integer)", i + 1),
                found: v.to_string(),
            },
        ),
        Bad::Coord(i, v) => Error::at_byte(
            at(i),
            ErrorKind::NonFinite {
                what: format!("a real of {item} {}", i + 1),
                value: v.to_string(),
            },
        ),
    }
}

fn read_elements(
    b: &[u8],
    data: usize,
    limit: usize,
    f: Fmt,
    code: usize,
    p: &mut Parsed,
) -> Result<()> {
    let Some(kind) = element_kind(code) else { return Ok(()) };
    let k = kind.nodes_per_cell();
    let size = (k + 1) * f.isz();
    let (n, start) = count(b, data, limit, f, size, KEYWORDS[code].name)?;
    // Zeroed arrays of the final length, filled in place: fresh pages, touched once.
    let mut e = Elements {
        kind,
        nodes: vec![0; n * k],
        refs: vec![0; n],
        at: Locator::Bytes { start: start as u64, size: size as u64 },
        unchecked: true,
    };
    let d = &b[start..start + n * size];
    let r = match (f.le, f.isz() == 8) {
        (true, false) => elements_any::<true, false>(d, k, &mut e.nodes, &mut e.refs),
        (true, true) => elements_any::<true, true>(d, k, &mut e.nodes, &mut e.refs),
        (false, false) => elements_any::<false, false>(d, k, &mut e.nodes, &mut e.refs),
        (false, true) => elements_any::<false, true>(d, k, &mut e.nodes, &mut e.refs),
    };
    let largest =
        r.map_err(|bad| bad_item(bad, start, size, kind.name(), k * f.isz(), p.points.len()))?;
    // With the vertices known, one comparison settles the upper bound; the full check at
    // the end (which names the element) runs only when it fails or they come later.
    e.unchecked = !p.vertices_read || largest >= p.points.len();
    p.elements.push(e);
    Ok(())
}

fn read_set(
    b: &[u8],
    data: usize,
    limit: usize,
    f: Fmt,
    code: usize,
    p: &mut Parsed,
) -> Result<()> {
    let size = f.isz();
    let name = KEYWORDS[code].name;
    let (n, start) = count(b, data, limit, f, size, name)?;
    let mut s = Set { code, items: Vec::with_capacity(n), at: Vec::with_capacity(n) };
    for i in 0..n {
        let at = start + i * size;
        let v = scalar(b, at, size, f.le, name)?;
        if v < 1 {
            return Err(Error::at_byte(
                at as u64,
                super::bad_number(format!("{name} entry {}", i + 1), v, p.points.len()),
            ));
        }
        s.items.push(usize::try_from(v - 1).unwrap_or(usize::MAX));
        s.at.push(Position::Byte(at as u64));
    }
    p.sets.push(s);
    Ok(())
}

fn read_sol(b: &[u8], data: usize, limit: usize, f: Fmt, p: &mut Parsed) -> Result<()> {
    need_dim(p, data, "SolAtVertices")?;
    let n = scalar(b, data, f.isz(), f.le, "the number of vertices of SolAtVertices")?;
    let n = usize::try_from(n).map_err(|_| {
        Error::at_byte(
            data as u64,
            ErrorKind::Expected {
                expected: "a non-negative number of vertices".into(),
                found: n.to_string(),
            },
        )
    })?;
    let mut at = data + f.isz();
    let nt = scalar(b, at, 4, f.le, "the number of solution types")?;
    let nt = usize::try_from(nt).ok().filter(|&nt| nt <= limit.saturating_sub(at) / 4).ok_or_else(
        || {
            Error::at_byte(
                at as u64,
                ErrorKind::ImplausibleCount {
                    what: "solution types".into(),
                    count: nt as u64,
                    limit: "more than the keyword's bytes".into(),
                },
            )
        },
    )?;
    at += 4;
    let mut types = Vec::with_capacity(nt);
    for _ in 0..nt {
        let ty = scalar(b, at, 4, f.le, "a solution type")?;
        match u32::try_from(ty).ok().filter(|&ty| sol_size(ty, p.dim).is_some()) {
            Some(ty) => types.push(ty),
            None => return Err(Error::at_byte(
                at as u64,
                ErrorKind::Expected {
                    expected:
                        "solution type 1 (scalar), 2 (vector), 3 (symmetric tensor) or 4 (matrix)"
                            .into(),
                    found: ty.to_string(),
                },
            )),
        }
        at += 4;
    }
    let stride: usize = types.iter().map(|&ty| sol_size(ty, p.dim).unwrap_or(0)).sum();
    check_count(n.saturating_mul(stride), limit.saturating_sub(at), f.rsz(), "solution values")
        .map_err(|k| Error::at_byte(data as u64, k))?;
    let d = &b[at..at + n * stride * f.rsz()];
    let mut values = Vec::new();
    let mut raw = None;
    let r = match (f.le, f.real4) {
        // Little-endian doubles (what MMG and smartmesh write). One field that its array
        // keeps in the file's order (MMG's metric or size): decoded once, checked as it
        // is, and moved into the array.
        (true, false) if types.len() == 1 && identity_layout(types[0], p.dim as usize) => {
            values.reserve_exact(n * stride);
            reals::<true, false>(d, &mut values)
        }
        // Several fields, or one rearranged: checked here, left in the file and decoded
        // once, into their arrays.
        (true, false) => {
            raw = Some(at);
            finite_reals(d)
        }
        (true, true) => {
            values.reserve_exact(n * stride);
            reals::<true, true>(d, &mut values)
        }
        (false, false) => {
            values.reserve_exact(n * stride);
            reals::<false, false>(d, &mut values)
        }
        (false, true) => {
            values.reserve_exact(n * stride);
            reals::<false, true>(d, &mut values)
        }
    };
    r.map_err(|bad| bad_item(bad, at, f.rsz(), "solution value", 0, 0))?;
    p.sol = Some(Sol { n, types, values, raw, at: Some(Position::Byte(data as u64)) });
    Ok(())
}

// ---------------------------------------------------------------------------------------
// Writing (little-endian, as libMeshb writes on every current machine)
// ---------------------------------------------------------------------------------------

struct W {
    out: Vec<u8>,
    ver: u32,
}

impl W {
    /// `spare`: memory to write into (cleared first), reused rather than fresh.
    fn new(ver: u32, capacity: usize, spare: Vec<u8>) -> W {
        let mut out = spare;
        out.clear();
        out.reserve(capacity);
        let mut w = W { out, ver };
        w.out.extend_from_slice(&1i32.to_le_bytes());
        w.out.extend_from_slice(&(ver as i32).to_le_bytes());
        w
    }
    /// Starts keyword `code`; returns where its next-keyword offset goes.
    fn begin(&mut self, code: usize) -> usize {
        self.out.extend_from_slice(&(code as i32).to_le_bytes());
        let at = self.out.len();
        self.out.resize(at + if self.ver >= 3 { 8 } else { 4 }, 0);
        at
    }
    /// Ends the keyword begun at `at`: the next one starts here.
    fn end(&mut self, at: usize) {
        let next = self.out.len();
        if self.ver >= 3 {
            self.out[at..at + 8].copy_from_slice(&(next as u64).to_le_bytes());
        } else {
            self.out[at..at + 4].copy_from_slice(&(next as i32).to_le_bytes());
        }
    }
    fn int(&mut self, v: usize) {
        if self.ver >= 4 {
            self.out.extend_from_slice(&(v as i64).to_le_bytes());
        } else {
            self.out.extend_from_slice(&(v as i32).to_le_bytes());
        }
    }
    fn sint(&mut self, v: i32) {
        if self.ver >= 4 {
            self.out.extend_from_slice(&(v as i64).to_le_bytes());
        } else {
            self.out.extend_from_slice(&v.to_le_bytes());
        }
    }
    fn header(&mut self, dim: u8) {
        let at = self.begin(KW_DIMENSION);
        self.out.extend_from_slice(&(dim as i32).to_le_bytes());
        self.end(at);
    }
    fn finish(mut self) -> Vec<u8> {
        // As MMG and libMeshb write it: End's offset points just past itself.
        let at = self.begin(KW_END);
        self.end(at);
        self.out
    }
}

/// The version to write: 2 when offsets and numbers fit in 32 bits, 3 for files past
/// 2 GiB, 4 when numbers need 64 bits.
fn version(bytes_v2: u64, largest_number: u64) -> u32 {
    if largest_number > i32::MAX as u64 {
        4
    } else if bytes_v2 > i32::MAX as u64 {
        3
    } else {
        2
    }
}

/// The file's bytes, and one past the largest node index written (0 when none), which
/// the caller checks against the vertex count.
pub(super) fn write_mesh(m: &Out<'_>, spare: Vec<u8>) -> (Vec<u8>, usize) {
    let dim = m.dim as usize;
    let nv = m.points.len();
    let mut ints = 0u64; // integers after the vertices, counts included
    let mut largest = nv as u64;
    for (code, _) in &m.elements {
        let n = m.count(*code);
        let k = element_kind(*code).map_or(0, |k| k.nodes_per_cell());
        ints += 1 + (n * (k + 1)) as u64;
        largest = largest.max(n as u64);
    }
    for (_, items) in &m.sets {
        ints += 1 + items.len() as u64;
        largest = largest.max(items.iter().copied().max().unwrap_or(0) as u64);
    }
    let keywords = 3 + m.elements.len() + m.sets.len();
    let bytes_v2 = 8 + 12 * keywords as u64 + 4 + (nv * (8 * dim + 4)) as u64 + 4 * ints;
    let ver = version(bytes_v2, largest);
    let mut w =
        W::new(ver, (bytes_v2 as usize).saturating_mul(if ver == 2 { 1 } else { 2 }), spare);
    w.header(m.dim);
    let at = w.begin(KW_VERTICES);
    w.int(nv);
    let refs = m.refs.as_deref();
    match (ver < 4, dim) {
        (true, 2) => vertex_records::<2>(&mut w.out, m.points, refs),
        (true, _) => vertex_records::<3>(&mut w.out, m.points, refs),
        (false, _) => {
            for (i, p) in m.points.iter().enumerate() {
                for c in &p[..dim] {
                    w.out.extend_from_slice(&c.to_le_bytes());
                }
                w.sint(refs.map_or(0, |r| r[i]));
            }
        }
    }
    w.end(at);
    let mut bound = 0;
    for (code, blocks) in &m.elements {
        let at = w.begin(*code);
        w.int(m.count(*code));
        for b in blocks {
            let b_bound = match (ver < 4, b.kind.nodes_per_cell()) {
                (true, 2) => element_records::<2>(&mut w.out, b),
                (true, 3) => element_records::<3>(&mut w.out, b),
                (true, 4) => element_records::<4>(&mut w.out, b),
                // Linear volumes; second-order kinds (Tetra10 reordered) take the loop.
                (true, 5) => element_records::<5>(&mut w.out, b),
                (true, 6) if b.kind == CellKind::Wedge => element_records::<6>(&mut w.out, b),
                (true, 8) => element_records::<8>(&mut w.out, b),
                _ => {
                    let mut b_bound = 0;
                    let order = gmsh_positions(b.kind);
                    for (cell, &r) in b.cells().zip(&b.physical) {
                        for j in 0..cell.len() {
                            let v = cell[order.map_or(j, |o| o[j])];
                            b_bound = b_bound.max(v as usize + 1);
                            w.int(v as usize + 1);
                        }
                        w.sint(r);
                    }
                    b_bound
                }
            };
            bound = bound.max(b_bound);
        }
        w.end(at);
    }
    for (code, items) in &m.sets {
        let at = w.begin(*code);
        w.int(items.len());
        for &v in items {
            w.int(v);
        }
        w.end(at);
    }
    (w.finish(), bound)
}

/// The vertices of a file with 32-bit integers: `D` reals and a reference per vertex,
/// each record assembled on the stack and appended whole (one capacity check per
/// vertex, not per value; this loop and the next are most of a binary write).
fn vertex_records<const D: usize>(out: &mut Vec<u8>, points: &[[f64; 3]], refs: Option<&[i32]>) {
    let len = 8 * D + 4;
    let mut rec = [0u8; 28];
    for (i, p) in points.iter().enumerate() {
        for (c, x) in p[..D].iter().enumerate() {
            rec[8 * c..8 * c + 8].copy_from_slice(&x.to_le_bytes());
        }
        rec[8 * D..len].copy_from_slice(&refs.map_or(0, |r| r[i]).to_le_bytes());
        out.extend_from_slice(&rec[..len]);
    }
}

/// The cells of a block of `K`-node elements in a file with 32-bit integers: 1-based
/// node numbers and the reference, one stack record per cell. Returns one past the
/// largest node index, for the caller to check against the vertex count (whose
/// version choice keeps the numbers of valid nodes within `i32`).
fn element_records<const K: usize>(out: &mut Vec<u8>, b: &CellBlock) -> usize {
    let len = 4 * (K + 1);
    // Room for the largest record this is called for (8 nodes and a reference).
    let mut rec = [0u8; 36];
    let mut largest = 0;
    for (cell, &r) in b.nodes.chunks_exact(K).zip(&b.physical) {
        for (j, &v) in cell.iter().enumerate() {
            largest = largest.max(v);
            rec[4 * j..4 * j + 4].copy_from_slice(&(v.wrapping_add(1) as i32).to_le_bytes());
        }
        rec[4 * K..len].copy_from_slice(&r.to_le_bytes());
        out.extend_from_slice(&rec[..len]);
    }
    if b.nodes.is_empty() {
        0
    } else {
        largest as usize + 1
    }
}

pub(super) fn write_sol(s: &SolOut<'_>) -> Vec<u8> {
    let bytes_v2 = 8 + 12 * 3 + 4 + 4 + 4 * s.types.len() as u64 + 8 * (s.n * s.stride) as u64;
    let ver = version(bytes_v2, s.n as u64);
    let mut w = W::new(ver, bytes_v2 as usize + 16, Vec::new());
    w.header(s.dim);
    let at = w.begin(KW_SOL_AT_VERTICES);
    w.int(s.n);
    w.out.extend_from_slice(&(s.types.len() as i32).to_le_bytes());
    for &ty in s.types {
        w.out.extend_from_slice(&(ty as i32).to_le_bytes());
    }
    match s.single() {
        // One solution (what MMG reads): fixed-size records assembled on the stack.
        Some(Single::Scalar(a)) => sol_records(&mut w.out, a.values.chunks_exact(1), |v| [v[0]]),
        Some(Single::Packed(a)) => {
            sol_records(&mut w.out, a.values.chunks_exact(3), |v| [v[0], v[1], v[2]])
        }
        Some(Single::Tensor2(a)) => sol_records(&mut w.out, a.values.chunks_exact(9), |v| {
            let (m11, m12, m22) = tensor9_to_sym2(v);
            [m11, m12, m22]
        }),
        None => {
            let mut row = Vec::with_capacity(s.stride);
            for v in 0..s.n {
                s.row(v, &mut row);
                for x in &row {
                    w.out.extend_from_slice(&x.to_le_bytes());
                }
            }
        }
    }
    w.end(at);
    w.finish()
}

/// The records of one solution: `R` reals a vertex from each of `items` by `row`, one
/// capacity check per vertex (a row assembled in a `Vec` costs more than the bytes).
#[inline(always)]
fn sol_records<'a, const R: usize>(
    out: &mut Vec<u8>,
    items: impl Iterator<Item = &'a [f64]>,
    row: impl Fn(&[f64]) -> [f64; R],
) {
    let mut rec = [[0u8; 8]; R];
    for item in items {
        for (slot, x) in rec.iter_mut().zip(row(item)) {
            *slot = x.to_le_bytes();
        }
        out.extend_from_slice(rec.as_flattened());
    }
}
