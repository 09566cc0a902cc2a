//! VTK XML `UnstructuredGrid` (`.vtu`).
//!
//! The XML layer is a small scanner rather than an XML crate: a `.vtu` is a handful of
//! elements around large text or binary payloads, and appended raw data (arbitrary
//! bytes after `<AppendedData encoding="raw">_`) is not well-formed XML, which general
//! XML readers (vtkio's quick-xml among them) refuse. Arrays are decoded after the scan,
//! once the appended block is located.
//!
//! Binary layout (VTK File Formats, "Appended Data" and compressed data): every binary
//! array starts with a header of `header_type` words in the file's byte order. Without
//! compression: `[nbytes]` then the bytes. With zlib: `[nblocks, block_size,
//! last_block_size, csize_1 .. csize_n]` then each block deflated on its own
//! (`last_block_size` is 0 when the last block is full). Inline (`format="binary"`)
//! arrays are base64; VTK encodes a compressed array's header and its blocks as two
//! base64 runs, each padded, so the decoder restarts after any padding.
//!
//! Blocks are independent, which lets both directions use every core; the bytes do not
//! depend on the thread count.

use std::borrow::Cow;

use base64::engine::general_purpose::{GeneralPurpose, GeneralPurposeConfig};
use base64::engine::DecodePaddingMode;
use base64::Engine as _;
use flate2::{Compress, Compression, Decompress, FlushCompress, FlushDecompress, Status};

use crate::error::Position;
use crate::text::Tokens;
use crate::{
    Error, ErrorKind, Layout, NodeIndex, Result, TaggedMesh, VtuEncoding, WriteOptions, Written,
    MAX_POINTS,
};

use super::{
    decode_f64, decode_i64, decode_indices, decode_ints_as, decode_items, decode_points, offsets,
    pack_parsed, push_num, put, tag_slot, threads, Grid, Named, Plan, Scalar, GEOMETRICAL,
    PHYSICAL,
};

/// Standard alphabet, padding optional and accepted where it stands.
const B64: GeneralPurpose = GeneralPurpose::new(
    &base64::alphabet::STANDARD,
    GeneralPurposeConfig::new()
        .with_decode_padding_mode(DecodePaddingMode::Indifferent)
        .with_decode_allow_trailing_bits(true),
);

/// VTK's default block size for compressed arrays (`vtkXMLWriter::BlockSize`).
const BLOCK: usize = 32768;

/// Deflate cannot expand data more than 1032:1 (a 258-byte match in two bits is its
/// best); a block whose header claims more than this per compressed byte is lying, and
/// is refused before anything is allocated.
const MAX_INFLATE_RATIO: usize = 1032;

/// Most bytes read for an array whose size no count gives (a `<FieldData>` array
/// without `NumberOfTuples`): the arrays smartmesh reads there hold two numbers.
const UNCOUNTED_MAX: usize = 1 << 16;

fn at(pos: usize) -> Option<Position> {
    Some(Position::Byte(pos as u64))
}

fn err(pos: usize, kind: ErrorKind) -> Error {
    Error::at_byte(pos as u64, kind)
}

use crate::text::show;

// ---------------------------------------------------------------------------------
// A minimal XML scanner.

struct Tag<'a> {
    name: &'a [u8],
    attrs: Vec<(&'a [u8], &'a [u8])>,
    /// `<.../>`.
    empty: bool,
    /// Offset of `<`.
    at: usize,
    /// Offset just past `>`.
    end: usize,
}

impl<'a> Tag<'a> {
    fn attr(&self, name: &str) -> Option<&'a [u8]> {
        self.attrs.iter().find(|(k, _)| *k == name.as_bytes()).map(|(_, v)| *v)
    }

    fn attr_str(&self, name: &str) -> Option<String> {
        self.attr(name).map(unescape)
    }

    fn attr_usize(&self, name: &str) -> Result<Option<usize>> {
        match self.attr(name) {
            None => Ok(None),
            Some(v) => match crate::text::parse_i64(crate::text::trim(v)) {
                Some(n) if n >= 0 => Ok(Some(n as usize)),
                _ => Err(err(
                    self.at,
                    ErrorKind::Expected {
                        expected: format!("a non-negative integer in {name}="),
                        found: show(v),
                    },
                )),
            },
        }
    }
}

enum Ev<'a> {
    Start(Tag<'a>),
    End(&'a [u8], usize),
    Eof,
}

struct Scan<'a> {
    d: &'a [u8],
    pos: usize,
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    memchr::memmem::find(hay, needle)
}

impl<'a> Scan<'a> {
    fn next(&mut self) -> Result<Ev<'a>> {
        loop {
            let Some(lt) = memchr::memchr(b'<', &self.d[self.pos..]) else {
                self.pos = self.d.len();
                return Ok(Ev::Eof);
            };
            let start = self.pos + lt;
            let rest = &self.d[start..];
            let skip_to = |close: &[u8], what: &str| -> Result<usize> {
                find(rest, close).map(|i| start + i + close.len()).ok_or_else(|| {
                    err(start, ErrorKind::UnexpectedEof { context: format!("unterminated {what}") })
                })
            };
            if rest.starts_with(b"<?") {
                self.pos = skip_to(b"?>", "processing instruction")?;
                continue;
            }
            if rest.starts_with(b"<!--") {
                self.pos = skip_to(b"-->", "comment")?;
                continue;
            }
            if rest.starts_with(b"<!") {
                self.pos = skip_to(b">", "declaration")?;
                continue;
            }
            if rest.starts_with(b"</") {
                let close = skip_to(b">", "end tag")?;
                let name = crate::text::trim(&self.d[start + 2..close - 1]);
                self.pos = close;
                return Ok(Ev::End(name, start));
            }
            return self.start_tag(start).map(Ev::Start);
        }
    }

    fn start_tag(&mut self, start: usize) -> Result<Tag<'a>> {
        let d = self.d;
        let mut i = start + 1;
        let is_space = |c: u8| matches!(c, b' ' | b'\t' | b'\r' | b'\n');
        while i < d.len() && !is_space(d[i]) && d[i] != b'>' && d[i] != b'/' {
            i += 1;
        }
        let name = &d[start + 1..i];
        if name.is_empty() {
            return Err(err(
                start,
                ErrorKind::Expected {
                    expected: "an element name after `<`".into(),
                    found: show(&d[start..(start + 20).min(d.len())]),
                },
            ));
        }
        let mut attrs = Vec::new();
        loop {
            while i < d.len() && is_space(d[i]) {
                i += 1;
            }
            match d.get(i) {
                None => {
                    return Err(err(
                        start,
                        ErrorKind::UnexpectedEof {
                            context: format!("in the start tag <{}", String::from_utf8_lossy(name)),
                        },
                    ))
                }
                Some(b'>') => {
                    self.pos = i + 1;
                    return Ok(Tag { name, attrs, empty: false, at: start, end: i + 1 });
                }
                Some(b'/') if d.get(i + 1) == Some(&b'>') => {
                    self.pos = i + 2;
                    return Ok(Tag { name, attrs, empty: true, at: start, end: i + 2 });
                }
                _ => {}
            }
            let k0 = i;
            while i < d.len() && d[i] != b'=' && !is_space(d[i]) && d[i] != b'>' {
                i += 1;
            }
            let key = &d[k0..i];
            while i < d.len() && is_space(d[i]) {
                i += 1;
            }
            if d.get(i) != Some(&b'=') {
                return Err(err(
                    k0,
                    ErrorKind::Expected {
                        expected: format!("`=` after attribute {}", show(key)),
                        found: show(&d[i.min(d.len())..(i + 10).min(d.len())]),
                    },
                ));
            }
            i += 1;
            while i < d.len() && is_space(d[i]) {
                i += 1;
            }
            let q = match d.get(i) {
                Some(&q @ (b'"' | b'\'')) => q,
                _ => {
                    return Err(err(
                        i.min(d.len()),
                        ErrorKind::Expected {
                            expected: format!("a quoted value for attribute {}", show(key)),
                            found: show(&d[i.min(d.len())..(i + 10).min(d.len())]),
                        },
                    ))
                }
            };
            let v0 = i + 1;
            let Some(len) = memchr::memchr(q, &d[v0..]) else {
                return Err(err(
                    i,
                    ErrorKind::UnexpectedEof {
                        context: format!("in the value of attribute {}", show(key)),
                    },
                ));
            };
            attrs.push((key, &d[v0..v0 + len]));
            i = v0 + len + 1;
        }
    }

    /// Skips the content of an element whose start tag was just read.
    fn skip_subtree(&mut self, tag: &Tag<'a>) -> Result<()> {
        if tag.empty {
            return Ok(());
        }
        let mut depth = 1usize;
        loop {
            match self.next()? {
                Ev::Start(t) if !t.empty => depth += 1,
                Ev::Start(_) => {}
                Ev::End(..) => {
                    depth -= 1;
                    if depth == 0 {
                        return Ok(());
                    }
                }
                Ev::Eof => {
                    return Err(err(
                        tag.at,
                        ErrorKind::UnexpectedEof {
                            context: format!(
                                "element <{}> is not closed",
                                String::from_utf8_lossy(tag.name)
                            ),
                        },
                    ))
                }
            }
        }
    }
}

/// Decodes the five XML entities and numeric character references.
fn unescape(v: &[u8]) -> String {
    let s = String::from_utf8_lossy(v);
    if !s.contains('&') {
        return s.into_owned();
    }
    let mut out = String::with_capacity(s.len());
    let mut rest = &*s;
    while let Some(i) = rest.find('&') {
        out.push_str(&rest[..i]);
        rest = &rest[i..];
        let Some(semi) = rest.find(';') else { break };
        let ent = &rest[1..semi];
        let ch = match ent {
            "amp" => Some('&'),
            "lt" => Some('<'),
            "gt" => Some('>'),
            "quot" => Some('"'),
            "apos" => Some('\''),
            _ if ent.starts_with("#x") || ent.starts_with("#X") => {
                u32::from_str_radix(&ent[2..], 16).ok().and_then(char::from_u32)
            }
            _ if ent.starts_with('#') => ent[1..].parse().ok().and_then(char::from_u32),
            _ => None,
        };
        match ch {
            Some(c) => {
                out.push(c);
                rest = &rest[semi + 1..];
            }
            None => {
                out.push('&');
                rest = &rest[1..];
            }
        }
    }
    out.push_str(rest);
    out
}

fn escape(out: &mut Vec<u8>, s: &str) {
    for &b in s.as_bytes() {
        match b {
            b'&' => out.extend_from_slice(b"&amp;"),
            b'<' => out.extend_from_slice(b"&lt;"),
            b'>' => out.extend_from_slice(b"&gt;"),
            b'"' => out.extend_from_slice(b"&quot;"),
            b'\'' => out.extend_from_slice(b"&apos;"),
            b'\n' => out.extend_from_slice(b"&#10;"),
            b'\t' => out.extend_from_slice(b"&#9;"),
            b'\r' => out.extend_from_slice(b"&#13;"),
            _ => out.push(b),
        }
    }
}

// ---------------------------------------------------------------------------------
// Reading.

#[derive(Clone, Copy, PartialEq)]
enum Format {
    Ascii,
    Binary,
    Appended,
}

/// A `<DataArray>` found by the scan, decoded later.
struct Spec {
    name: String,
    ty: Scalar,
    components: usize,
    format: Format,
    offset: usize,
    tuples: Option<usize>,
    /// The inline text (ascii or base64).
    text: (usize, usize),
    at: usize,
}

struct Appended {
    /// Offset of the byte after `_`.
    base: usize,
    /// End of the appended bytes (`</AppendedData>` or the end of the file).
    end: usize,
    raw: bool,
}

/// The bytes of one array: a slice of the file, or of a decoded/inflated buffer.
struct Payload<'a> {
    bytes: Cow<'a, [u8]>,
    start: usize,
    len: usize,
}

impl Payload<'_> {
    fn as_slice(&self) -> &[u8] {
        &self.bytes[self.start..self.start + self.len]
    }
}

struct Decoder<'a> {
    d: &'a [u8],
    big: bool,
    /// Size of a header word: 4 (UInt32) or 8 (UInt64).
    hsize: usize,
    zlib: bool,
    appended: Option<Appended>,
    /// Sorted offsets of appended arrays, to bound base64 runs.
    app_offsets: Vec<usize>,
}

/// The `<DataArray>`s of a container. In `<FieldData>` arrays of other than numeric
/// types (ParaView writes strings there) are skipped: they cannot name a tag.
fn read_array_specs<'a>(s: &mut Scan<'a>, container: &Tag<'a>, out: &mut Vec<Spec>) -> Result<()> {
    if container.empty {
        return Ok(());
    }
    let field = container.name == b"FieldData";
    loop {
        match s.next()? {
            Ev::Start(t) if t.name == b"DataArray" => {
                match spec(&t, s.d) {
                    Ok(sp) => out.push(sp),
                    Err(e) if field && matches!(e.kind, ErrorKind::Unsupported(_)) => {}
                    Err(e) => return Err(e),
                }
                s.skip_subtree(&t)?;
            }
            Ev::Start(t) => s.skip_subtree(&t)?,
            Ev::End(name, _) if name == container.name => return Ok(()),
            Ev::End(name, pos) => {
                return Err(err(
                    pos,
                    ErrorKind::Expected {
                        expected: format!("</{}>", String::from_utf8_lossy(container.name)),
                        found: format!("</{}>", String::from_utf8_lossy(name)),
                    },
                ))
            }
            Ev::Eof => {
                return Err(err(
                    container.at,
                    ErrorKind::UnexpectedEof {
                        context: format!(
                            "<{}> is not closed",
                            String::from_utf8_lossy(container.name)
                        ),
                    },
                ))
            }
        }
    }
}

fn spec(t: &Tag<'_>, d: &[u8]) -> Result<Spec> {
    let name = t.attr_str("Name").unwrap_or_default();
    let ty_name = t.attr_str("type").ok_or_else(|| {
        err(
            t.at,
            ErrorKind::Expected {
                expected: format!("a type= attribute on DataArray `{name}`"),
                found: "none".into(),
            },
        )
    })?;
    let ty = Scalar::from_xml(&ty_name).ok_or_else(|| {
        err(t.at, ErrorKind::Unsupported(format!("DataArray `{name}` of type {ty_name}: smartmesh reads Int8..Int64, UInt8..UInt64, Float32 and Float64")))
    })?;
    let components = t.attr_usize("NumberOfComponents")?.unwrap_or(1);
    if components == 0 {
        return Err(err(
            t.at,
            ErrorKind::Expected {
                expected: format!("NumberOfComponents of `{name}` at least 1"),
                found: "0".into(),
            },
        ));
    }
    let format = match t.attr("format") {
        Some(b"ascii") => Format::Ascii,
        Some(b"binary") => Format::Binary,
        Some(b"appended") => Format::Appended,
        other => {
            return Err(err(
                t.at,
                ErrorKind::Expected {
                    expected: format!("format=\"ascii\", \"binary\" or \"appended\" on `{name}`"),
                    found: show(other.unwrap_or(b"nothing")),
                },
            ))
        }
    };
    let offset = t.attr_usize("offset")?.unwrap_or(0);
    if format == Format::Appended && t.attr("offset").is_none() {
        return Err(err(
            t.at,
            ErrorKind::Expected {
                expected: format!("an offset= attribute on appended DataArray `{name}`"),
                found: "none".into(),
            },
        ));
    }
    let tuples = t.attr_usize("NumberOfTuples")?;
    let text = if t.empty {
        (t.end, t.end)
    } else {
        let len = memchr::memchr(b'<', &d[t.end..]).unwrap_or(d.len() - t.end);
        (t.end, t.end + len)
    };
    Ok(Spec { name, ty, components, format, offset, tuples, text, at: t.at })
}

/// Strips whitespace and decodes base64 that may hold several padded runs (VTK
/// encodes a compressed array's header and data separately).
fn base64_decode(text: &[u8], at: usize, name: &str) -> Result<Vec<u8>> {
    // Writers put the whole run on one line: then no copy is needed.
    let trimmed = text.trim_ascii();
    let clean: Cow<'_, [u8]> = if trimmed.iter().any(|c| c.is_ascii_whitespace()) {
        Cow::Owned(trimmed.iter().copied().filter(|c| !c.is_ascii_whitespace()).collect())
    } else {
        Cow::Borrowed(trimmed)
    };
    let mut out = Vec::with_capacity(clean.len() / 4 * 3 + 3);
    let mut s = 0;
    while s < clean.len() {
        let end = match memchr::memchr(b'=', &clean[s..]) {
            // The run ends with the 4-character group that holds its padding.
            Some(p) => (s + (p / 4 + 1) * 4).min(clean.len()),
            None => clean.len(),
        };
        B64.decode_vec(&clean[s..end], &mut out).map_err(|e| {
            err(
                at,
                ErrorKind::Expected {
                    expected: format!("base64 data in DataArray `{name}`"),
                    found: format!("{e} (in run starting at character {s})"),
                },
            )
        })?;
        s = end;
    }
    Ok(out)
}

/// Inflates one block into exactly `out.len()` bytes.
fn inflate(input: &[u8], out: &mut [u8]) -> bool {
    let mut z = Decompress::new(true);
    matches!(z.decompress(input, out, FlushDecompress::Finish), Ok(Status::StreamEnd))
        && z.total_out() as usize == out.len()
}

/// Inflates independent blocks into consecutive `block`-sized slices of `out`, on
/// several threads when it pays. Returns the index of a block that failed.
fn inflate_blocks(
    blocks: &[&[u8]],
    out: &mut [u8],
    block: usize,
) -> std::result::Result<(), usize> {
    let total = out.len();
    let mut jobs: Vec<(usize, &[u8], &mut [u8])> = blocks
        .iter()
        .zip(out.chunks_mut(block.max(1)))
        .enumerate()
        .map(|(i, (b, o))| (i, *b, o))
        .collect();
    let nt = threads().min(jobs.len());
    let run = |group: &mut [(usize, &[u8], &mut [u8])]| -> std::result::Result<(), usize> {
        for (i, input, output) in group.iter_mut() {
            if !inflate(input, output) {
                return Err(*i);
            }
        }
        Ok(())
    };
    if nt <= 1 || total < (1 << 20) {
        return run(&mut jobs);
    }
    let per = jobs.len().div_ceil(nt);
    std::thread::scope(|s| {
        let handles: Vec<_> = jobs.chunks_mut(per).map(|g| s.spawn(move || run(g))).collect();
        let mut res = Ok(());
        for h in handles {
            let r = h.join().unwrap_or(Err(0));
            if res.is_ok() {
                res = r;
            }
        }
        res
    })
}

impl<'a> Decoder<'a> {
    fn word(&self, b: &[u8]) -> u64 {
        match (self.hsize, self.big) {
            (4, false) => u32::from_le_bytes(b[..4].try_into().expect("4")) as u64,
            (4, true) => u32::from_be_bytes(b[..4].try_into().expect("4")) as u64,
            (_, false) => u64::from_le_bytes(b[..8].try_into().expect("8")),
            (_, true) => u64::from_be_bytes(b[..8].try_into().expect("8")),
        }
    }

    /// Refuses an array whose size no count gives (`expected` is `None`) when it
    /// announces more than [`UNCOUNTED_MAX`] bytes, before anything is allocated.
    fn within_uncounted(
        &self,
        sp: &Spec,
        expected: Option<usize>,
        total: u128,
        at0: usize,
    ) -> Result<()> {
        if expected.is_none() && total > UNCOUNTED_MAX as u128 {
            return Err(err(
                at0,
                ErrorKind::ImplausibleCount {
                    what: format!("DataArray `{}` (bytes, without NumberOfTuples)", sp.name),
                    count: total.min(u64::MAX as u128) as u64,
                    limit: format!(
                        "an array whose size no count gives is read up to {UNCOUNTED_MAX} bytes; give its NumberOfTuples"
                    ),
                },
            ));
        }
        Ok(())
    }

    /// The bytes of a binary or appended array, decoded and inflated, checked to be
    /// `expected` bytes when that is known (at most [`UNCOUNTED_MAX`] when not).
    fn payload(&self, sp: &Spec, expected: Option<usize>) -> Result<Payload<'a>> {
        let (src, at0): (Cow<'a, [u8]>, usize) = match sp.format {
            Format::Binary => (
                Cow::Owned(base64_decode(&self.d[sp.text.0..sp.text.1], sp.text.0, &sp.name)?),
                sp.text.0,
            ),
            Format::Appended => {
                let ap = self.appended.as_ref().ok_or_else(|| {
                    err(
                        sp.at,
                        ErrorKind::Expected {
                            expected: format!(
                                "an <AppendedData> element for appended array `{}`",
                                sp.name
                            ),
                            found: "none".into(),
                        },
                    )
                })?;
                let start = ap.base.checked_add(sp.offset).filter(|&s| s <= ap.end).ok_or_else(|| {
                    err(
                        sp.at,
                        ErrorKind::UnexpectedEof {
                            context: format!(
                                "appended array `{}` starts at offset {}, but the appended data has {} bytes",
                                sp.name,
                                sp.offset,
                                ap.end - ap.base
                            ),
                        },
                    )
                })?;
                if ap.raw {
                    (Cow::Borrowed(&self.d[start..ap.end]), start)
                } else {
                    let next = self
                        .app_offsets
                        .iter()
                        .copied()
                        .find(|&o| o > sp.offset)
                        .map_or(ap.end, |o| (ap.base + o).min(ap.end));
                    (Cow::Owned(base64_decode(&self.d[start..next], start, &sp.name)?), start)
                }
            }
            Format::Ascii => unreachable!("ascii arrays are parsed as text"),
        };
        let hs = self.hsize;
        let short = |what: &str| {
            err(
                at0,
                ErrorKind::UnexpectedEof { context: format!("{what} of DataArray `{}`", sp.name) },
            )
        };
        if src.len() < hs {
            return Err(short("header"));
        }
        if !self.zlib {
            let n = self.word(&src);
            self.within_uncounted(sp, expected, n as u128, at0)?;
            if let Some(e) = expected {
                if n != e as u64 {
                    return Err(err(
                        at0,
                        ErrorKind::Inconsistent(format!(
                            "DataArray `{}` holds {n} bytes, expected {e}",
                            sp.name
                        )),
                    ));
                }
            }
            if n > (src.len() - hs) as u64 {
                return Err(err(
                    at0,
                    ErrorKind::UnexpectedEof {
                        context: format!(
                            "DataArray `{}` announces {n} bytes, {} remain",
                            sp.name,
                            src.len() - hs
                        ),
                    },
                ));
            }
            return Ok(Payload { bytes: src, start: hs, len: n as usize });
        }
        // [nblocks, block size, last block size, compressed sizes...]
        if src.len() < 3 * hs {
            return Err(short("compression header"));
        }
        let nb = self.word(&src);
        let bs = self.word(&src[hs..]);
        let last = self.word(&src[2 * hs..]);
        let hlen = nb
            .checked_add(3)
            .and_then(|k| k.checked_mul(hs as u64))
            .filter(|&l| l <= src.len() as u64)
            .ok_or_else(|| {
                err(
                    at0,
                    ErrorKind::ImplausibleCount {
                        what: format!("compressed blocks of `{}`", sp.name),
                        count: nb,
                        limit: format!("{} bytes of data", src.len()),
                    },
                )
            })? as usize;
        let mut csizes = Vec::with_capacity(nb as usize);
        let mut csum = 0u64;
        for i in 0..nb as usize {
            let c = self.word(&src[(3 + i) * hs..]);
            csum = csum.saturating_add(c);
            csizes.push(c);
        }
        if csum > (src.len() - hlen) as u64 {
            return Err(err(
                at0,
                ErrorKind::UnexpectedEof {
                    context: format!(
                        "compressed blocks of `{}` need {csum} bytes, {} remain",
                        sp.name,
                        src.len() - hlen
                    ),
                },
            ));
        }
        if last > bs || (nb > 0 && bs == 0) {
            return Err(err(
                at0,
                ErrorKind::Inconsistent(format!(
                    "compression header of `{}`: last block of {last} bytes, blocks of {bs}",
                    sp.name
                )),
            ));
        }
        let total = match nb {
            0 => 0u128,
            _ if last == 0 => nb as u128 * bs as u128,
            _ => (nb as u128 - 1) * bs as u128 + last as u128,
        };
        // Each block on its own: a block of `c` compressed bytes inflates to at most
        // `MAX_INFLATE_RATIO * c` (no slack, so a header of empty blocks claims nothing).
        for (i, &c) in csizes.iter().enumerate() {
            let size = if i + 1 == csizes.len() && last != 0 { last } else { bs };
            if size as u128 > c as u128 * MAX_INFLATE_RATIO as u128 {
                return Err(err(
                    at0,
                    ErrorKind::ImplausibleCount {
                        what: format!("uncompressed bytes of block {} of `{}`", i + 1, sp.name),
                        count: size,
                        limit: format!(
                            "zlib expands {c} compressed bytes to {} at most",
                            c as u128 * MAX_INFLATE_RATIO as u128
                        ),
                    },
                ));
            }
        }
        self.within_uncounted(sp, expected, total, at0)?;
        if let Some(e) = expected {
            if total != e as u128 {
                return Err(err(
                    at0,
                    ErrorKind::Inconsistent(format!(
                        "DataArray `{}` holds {total} bytes, expected {e}",
                        sp.name
                    )),
                ));
            }
        }
        let total = total as usize;
        let mut blocks = Vec::with_capacity(csizes.len());
        let mut p = hlen;
        for c in csizes {
            blocks.push(&src[p..p + c as usize]);
            p += c as usize;
        }
        let mut out = vec![0u8; total];
        inflate_blocks(&blocks, &mut out, bs as usize).map_err(|i| {
            err(
                at0,
                ErrorKind::Expected {
                    expected: format!("zlib data in block {i} of `{}`", sp.name),
                    found: "a corrupt or short stream".into(),
                },
            )
        })?;
        Ok(Payload { bytes: Cow::Owned(out), start: 0, len: total })
    }

    /// The values of an array as `f64`: `expected` values when known.
    fn floats(&self, sp: &Spec, expected: Option<usize>) -> Result<Vec<f64>> {
        let mut out = Vec::new();
        if sp.format == Format::Ascii {
            let text = &self.d[sp.text.0..sp.text.1];
            if let Some(e) = expected {
                crate::text::check_count(e, text.len() + 1, 2, &format!("DataArray `{}`", sp.name))
                    .map_err(|k| err(sp.text.0, k))?;
                out.reserve(e);
            }
            let mut t = Tokens::new(text);
            while let Some(tok) = t.next() {
                let pos = sp.text.0 + t.pos() - tok.len();
                let v = crate::text::parse_f64(tok).map_err(|_| {
                    err(
                        pos,
                        ErrorKind::Expected {
                            expected: format!("a number in DataArray `{}`", sp.name),
                            found: show(tok),
                        },
                    )
                })?;
                if !v.is_finite() {
                    return Err(err(
                        pos,
                        ErrorKind::NonFinite {
                            what: format!("value {} of `{}`", out.len(), sp.name),
                            value: show(tok),
                        },
                    ));
                }
                out.push(v);
            }
        } else {
            let p = self.payload(sp, expected.and_then(|e| e.checked_mul(sp.ty.size())))?;
            let bytes = p.as_slice();
            let n = bytes.len() / sp.ty.size();
            decode_f64(bytes, sp.ty, self.big, n, &mut out).map_err(|i| {
                err(
                    sp.at,
                    ErrorKind::NonFinite {
                        what: format!("value {i} of `{}`", sp.name),
                        value: "NaN or infinity".into(),
                    },
                )
            })?;
        }
        if let Some(e) = expected {
            if out.len() != e {
                return Err(err(
                    sp.at,
                    ErrorKind::Inconsistent(format!(
                        "DataArray `{}` has {} values, expected {e}",
                        sp.name,
                        out.len()
                    )),
                ));
            }
        }
        Ok(out)
    }

    /// The `expected` values of a point or cell array, 9-component binary ones packed
    /// where they can be ([`decode_items`]).
    fn items(&self, sp: &Spec, expected: usize) -> Result<(Vec<f64>, Layout)> {
        if sp.format == Format::Ascii || sp.components != 9 {
            return Ok(pack_parsed(self.floats(sp, Some(expected))?, sp.components));
        }
        let p = self.payload(sp, expected.checked_mul(sp.ty.size()))?;
        let bytes = p.as_slice();
        let n = bytes.len() / sp.ty.size();
        if n != expected {
            // The plain path's errors, in its order.
            return Ok((self.floats(sp, Some(expected))?, Layout::Plain));
        }
        decode_items(bytes, sp.ty, self.big, n, sp.components).map_err(|i| {
            err(
                sp.at,
                ErrorKind::NonFinite {
                    what: format!("value {i} of `{}`", sp.name),
                    value: "NaN or infinity".into(),
                },
            )
        })
    }

    fn points(&self, sp: &Spec, n: usize) -> Result<Vec<[f64; 3]>> {
        if sp.format == Format::Ascii {
            let flat = self.floats(sp, Some(3 * n))?;
            return Ok(flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect());
        }
        let p = self.payload(sp, (3 * n).checked_mul(sp.ty.size()))?;
        decode_points(p.as_slice(), sp.ty, self.big, n).map_err(|i| {
            err(
                sp.at,
                ErrorKind::NonFinite {
                    what: format!("coordinate {} of point {}", i % 3, i / 3),
                    value: "NaN or infinity".into(),
                },
            )
        })
    }

    /// `expected` point indices, each below `limit`.
    fn indices(
        &self,
        sp: &Spec,
        expected: usize,
        limit: usize,
        offsets: &[usize],
    ) -> Result<Vec<NodeIndex>> {
        let bad = |i: usize, v: i64| {
            let c = offsets.partition_point(|&o| o <= i).saturating_sub(1);
            err(
                sp.at,
                ErrorKind::IndexOutOfRange {
                    what: format!("cell {c} in `{}`", sp.name),
                    index: v,
                    available: limit,
                },
            )
        };
        if sp.format == Format::Ascii {
            let v = self.ints(sp, expected)?;
            if let Some(i) =
                v.iter().position(|&x| x < 0 || x as u64 >= limit.min(MAX_POINTS) as u64)
            {
                return Err(bad(i, v[i]));
            }
            return Ok(v.into_iter().map(|x| x as NodeIndex).collect());
        }
        let p = self.payload(sp, expected.checked_mul(sp.ty.size()))?;
        decode_indices(p.as_slice(), sp.ty, self.big, expected, limit).map_err(|(i, v)| {
            if v == -1 && sp.ty.is_float() {
                err(
                    sp.at,
                    ErrorKind::Expected {
                        expected: format!("integers in `{}`", sp.name),
                        found: format!("value {i} is not one"),
                    },
                )
            } else {
                bad(i, v)
            }
        })
    }

    /// `expected` integers converted by `conv` as they are decoded, appended to `out`;
    /// `what` says in an error what a refused value should have been.
    fn ints_into<T>(
        &self,
        sp: &Spec,
        expected: usize,
        out: &mut Vec<T>,
        what: &str,
        conv: impl Fn(i64) -> Option<T>,
    ) -> Result<()> {
        let refused = |i: usize, v: String| {
            err(
                sp.at,
                ErrorKind::Expected {
                    expected: format!("{what} for value {i} of `{}`", sp.name),
                    found: v,
                },
            )
        };
        if sp.format == Format::Ascii {
            let v = self.ints(sp, expected)?;
            out.reserve(v.len());
            for (i, x) in v.into_iter().enumerate() {
                out.push(conv(x).ok_or_else(|| refused(i, x.to_string()))?);
            }
            return Ok(());
        }
        let p = self.payload(sp, expected.checked_mul(sp.ty.size()))?;
        let bytes = p.as_slice();
        if bytes.len() != expected * sp.ty.size() {
            return Err(err(
                sp.at,
                ErrorKind::Inconsistent(format!(
                    "DataArray `{}` has {} values, expected {expected}",
                    sp.name,
                    bytes.len() / sp.ty.size()
                )),
            ));
        }
        let start = out.len();
        decode_ints_as(bytes, sp.ty, self.big, expected, out, &conv).map_err(|i| {
            // Say what the refused value was (decoded once more, on the error path only).
            let mut v = Vec::new();
            let shown = match decode_i64(
                &bytes[i * sp.ty.size()..(i + 1) * sp.ty.size()],
                sp.ty,
                self.big,
                1,
                &mut v,
            ) {
                Ok(()) => v[0].to_string(),
                Err(_) => "not an integer".into(),
            };
            out.truncate(start);
            refused(i, shown)
        })
    }

    fn ints(&self, sp: &Spec, expected: usize) -> Result<Vec<i64>> {
        let mut out = Vec::new();
        if sp.format == Format::Ascii {
            let text = &self.d[sp.text.0..sp.text.1];
            crate::text::check_count(
                expected,
                text.len() + 1,
                2,
                &format!("DataArray `{}`", sp.name),
            )
            .map_err(|k| err(sp.text.0, k))?;
            out.reserve(expected);
            let mut t = Tokens::new(text);
            while let Some(tok) = t.next() {
                let v = crate::text::parse_i64(tok).ok_or_else(|| {
                    err(
                        sp.text.0 + t.pos() - tok.len(),
                        ErrorKind::Expected {
                            expected: format!("an integer in DataArray `{}`", sp.name),
                            found: show(tok),
                        },
                    )
                })?;
                out.push(v);
            }
        } else {
            let p = self.payload(sp, expected.checked_mul(sp.ty.size()))?;
            let bytes = p.as_slice();
            let n = bytes.len() / sp.ty.size();
            decode_i64(bytes, sp.ty, self.big, n, &mut out).map_err(|i| {
                err(
                    sp.at,
                    ErrorKind::Expected {
                        expected: format!("integers in `{}`", sp.name),
                        found: format!("value {i} is not one"),
                    },
                )
            })?;
        }
        if out.len() != expected {
            return Err(err(
                sp.at,
                ErrorKind::Inconsistent(format!(
                    "DataArray `{}` has {} values, expected {expected}",
                    sp.name,
                    out.len()
                )),
            ));
        }
        Ok(out)
    }
}

/// Reads a `.vtu` file.
pub(crate) fn read(d: &[u8]) -> Result<TaggedMesh> {
    let mut s = Scan { d, pos: 0 };
    let root = match s.next()? {
        Ev::Start(t) => t,
        Ev::End(_, p) => {
            return Err(err(
                p,
                ErrorKind::Expected { expected: "<VTKFile>".into(), found: "an end tag".into() },
            ))
        }
        Ev::Eof => {
            return Err(err(
                d.len(),
                ErrorKind::UnexpectedEof { context: "expected <VTKFile>".into() },
            ))
        }
    };
    if root.name != b"VTKFile" {
        return Err(err(
            root.at,
            ErrorKind::Expected {
                expected: "<VTKFile>".into(),
                found: format!("<{}>", String::from_utf8_lossy(root.name)),
            },
        ));
    }
    match root.attr("type") {
        Some(b"UnstructuredGrid") => {}
        other => {
            return Err(err(
                root.at,
                ErrorKind::Unsupported(format!(
                    "VTK XML type {}: smartmesh reads UnstructuredGrid (.vtu)",
                    show(other.unwrap_or(b"(none)"))
                )),
            ))
        }
    }
    let big = match root.attr("byte_order") {
        None | Some(b"LittleEndian") => false,
        Some(b"BigEndian") => true,
        Some(o) => {
            return Err(err(
                root.at,
                ErrorKind::Expected {
                    expected: "byte_order=\"LittleEndian\" or \"BigEndian\"".into(),
                    found: show(o),
                },
            ))
        }
    };
    let hsize = match root.attr("header_type") {
        None | Some(b"UInt32") => 4,
        Some(b"UInt64") => 8,
        Some(o) => {
            return Err(err(
                root.at,
                ErrorKind::Expected {
                    expected: "header_type=\"UInt32\" or \"UInt64\"".into(),
                    found: show(o),
                },
            ))
        }
    };
    let zlib = match root.attr("compressor") {
        None | Some(b"") => false,
        Some(b"vtkZLibDataCompressor") => true,
        Some(o) => {
            return Err(err(
                root.at,
                ErrorKind::Unsupported(format!(
                    "compressor {}: smartmesh reads zlib (vtkZLibDataCompressor) only",
                    show(o)
                )),
            ))
        }
    };

    let (mut field, mut point, mut cell, mut pts, mut cells) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut piece: Option<(usize, usize, usize)> = None;
    let mut appended = None;
    loop {
        match s.next()? {
            Ev::Start(t) if t.name == b"UnstructuredGrid" => {}
            Ev::Start(t) if t.name == b"FieldData" => read_array_specs(&mut s, &t, &mut field)?,
            Ev::Start(t) if t.name == b"Piece" => {
                if piece.is_some() {
                    return Err(err(
                        t.at,
                        ErrorKind::Unsupported(
                            "several <Piece> elements: smartmesh reads one-piece .vtu files".into(),
                        ),
                    ));
                }
                let np = t.attr_usize("NumberOfPoints")?.unwrap_or(0);
                let nc = t.attr_usize("NumberOfCells")?.unwrap_or(0);
                piece = Some((np, nc, t.at));
                if t.empty {
                    continue;
                }
                loop {
                    match s.next()? {
                        Ev::Start(c) => match c.name {
                            b"PointData" => read_array_specs(&mut s, &c, &mut point)?,
                            b"CellData" => read_array_specs(&mut s, &c, &mut cell)?,
                            b"Points" => {
                                read_array_specs(&mut s, &c, &mut pts)?;
                                // VTK leaves the coordinates unnamed; messages name them.
                                for sp in pts.iter_mut().filter(|sp| sp.name.is_empty()) {
                                    sp.name = "Points".into();
                                }
                            }
                            b"Cells" => read_array_specs(&mut s, &c, &mut cells)?,
                            _ => s.skip_subtree(&c)?,
                        },
                        Ev::End(b"Piece", _) => break,
                        Ev::End(n, p) => {
                            return Err(err(
                                p,
                                ErrorKind::Expected {
                                    expected: "</Piece>".into(),
                                    found: format!("</{}>", String::from_utf8_lossy(n)),
                                },
                            ))
                        }
                        Ev::Eof => {
                            return Err(err(
                                t.at,
                                ErrorKind::UnexpectedEof {
                                    context: "<Piece> is not closed".into(),
                                },
                            ))
                        }
                    }
                }
            }
            Ev::Start(t) if t.name == b"AppendedData" => {
                let raw = match t.attr("encoding") {
                    Some(b"raw") => true,
                    Some(b"base64") | None => false,
                    Some(o) => {
                        return Err(err(
                            t.at,
                            ErrorKind::Expected {
                                expected: "encoding=\"raw\" or \"base64\"".into(),
                                found: show(o),
                            },
                        ))
                    }
                };
                // The data starts after `_`; raw bytes may contain anything, so the
                // scan stops here.
                let us = memchr::memchr(b'_', &d[t.end..]).map(|i| t.end + i).ok_or_else(|| {
                    err(
                        t.end,
                        ErrorKind::Expected {
                            expected: "`_` before the appended data".into(),
                            found: "none".into(),
                        },
                    )
                })?;
                let base = us + 1;
                let end = memchr::memmem::rfind(&d[base..], b"</AppendedData>")
                    .map_or(d.len(), |i| base + i);
                let end = if raw { end } else { base + crate::text::trim(&d[base..end]).len() };
                appended = Some(Appended { base, end, raw });
                break;
            }
            Ev::Start(t) => s.skip_subtree(&t)?,
            Ev::End(b"UnstructuredGrid", _) => {}
            Ev::End(b"VTKFile", _) | Ev::Eof => break,
            Ev::End(n, p) => {
                return Err(err(
                    p,
                    ErrorKind::Expected {
                        expected: "</UnstructuredGrid> or </VTKFile>".into(),
                        found: format!("</{}>", String::from_utf8_lossy(n)),
                    },
                ))
            }
        }
    }
    let Some((np, nc, piece_at)) = piece else {
        return Err(err(
            root.at,
            ErrorKind::Expected {
                expected: "a <Piece> in <UnstructuredGrid>".into(),
                found: "none".into(),
            },
        ));
    };
    // Piece sizes are attacker-controlled: each array is checked against its bytes
    // before it is allocated, and an empty file cannot claim a billion points.
    // A point needs 3 bytes of data and a cell 1 even at zlib's best ratio.
    for (n, what, per) in [(np, "NumberOfPoints", 3), (nc, "NumberOfCells", 1)] {
        let most = d.len().saturating_mul(MAX_INFLATE_RATIO) / per;
        if n > most {
            return Err(err(
                piece_at,
                ErrorKind::ImplausibleCount {
                    what: what.into(),
                    count: n as u64,
                    limit: format!(
                        "a file of {} bytes holds at most {most}, even compressed at zlib's 1032:1",
                        d.len()
                    ),
                },
            ));
        }
    }

    let mut app_offsets: Vec<usize> = field
        .iter()
        .chain(&point)
        .chain(&cell)
        .chain(&pts)
        .chain(&cells)
        .filter(|s| s.format == Format::Appended)
        .map(|s| s.offset)
        .collect();
    app_offsets.sort_unstable();
    app_offsets.dedup();
    let dec = Decoder { d, big, hsize, zlib, appended, app_offsets };

    let mut g = Grid::default();
    let empty_points = Spec {
        name: "Points".into(),
        ty: Scalar::F64,
        components: 3,
        format: Format::Ascii,
        offset: 0,
        tuples: None,
        text: (0, 0),
        at: piece_at,
    };
    let p = match pts.first() {
        Some(p) => p,
        None if np == 0 => &empty_points,
        None => {
            return Err(err(
                piece_at,
                ErrorKind::Expected {
                    expected: "a <Points> DataArray".into(),
                    found: "none".into(),
                },
            ))
        }
    };
    if p.components != 3 && np > 0 {
        return Err(err(
            p.at,
            ErrorKind::Expected {
                expected: "3 components in Points".into(),
                found: p.components.to_string(),
            },
        ));
    }
    g.points = dec.points(p, np)?;
    let values = |n: usize, sp: &Spec| {
        n.checked_mul(sp.components).ok_or_else(|| {
            err(
                sp.at,
                ErrorKind::ImplausibleCount {
                    what: format!("values of `{}`", sp.name),
                    count: sp.components as u64,
                    limit: "too many components".into(),
                },
            )
        })
    };

    let find = |name: &str| cells.iter().find(|s| s.name == name);
    if nc > 0 || !cells.is_empty() {
        let missing = |n: &str| {
            err(
                piece_at,
                ErrorKind::Expected {
                    expected: format!("a `{n}` DataArray in <Cells>"),
                    found: "none".into(),
                },
            )
        };
        let ty = find("types").ok_or_else(|| missing("types"))?;
        // Types and offsets are decoded straight into their final arrays.
        dec.ints_into(ty, nc, &mut g.types, "a VTK cell type (0 to 255)", |t| {
            u8::try_from(t).ok()
        })?;
        g.types_at = at(ty.at);
        let off = find("offsets").ok_or_else(|| missing("offsets"))?;
        g.offsets = Vec::with_capacity(nc + 1);
        g.offsets.push(0);
        dec.ints_into(off, nc, &mut g.offsets, "a cell end offset (0 or more)", |e| {
            usize::try_from(e).ok()
        })?;
        // Each cell smartmesh reads has at most 9 nodes; a larger step is refused by the
        // cell check, but must not drive an allocation here.
        let bad_step = |w: &[usize]| w[1] < w[0] || w[1] - w[0] > 64;
        if g.offsets.windows(2).any(bad_step) {
            let i = g.offsets.windows(2).position(bad_step).unwrap_or(0);
            let (prev, e) = (g.offsets[i], g.offsets[i + 1]);
            return Err(err(
                off.at,
                ErrorKind::Inconsistent(format!("offsets must rise by the node count of each cell; cell {i} ends at {e} after {prev}")),
            ));
        }
        let prev = *g.offsets.last().unwrap_or(&0);
        let con = find("connectivity").ok_or_else(|| missing("connectivity"))?;
        g.connectivity = dec.indices(con, prev, np, &g.offsets)?;
        g.cells_at = at(con.at);
    } else {
        g.offsets = vec![0];
    }
    for sp in &point {
        let (values, layout) = dec.items(sp, values(np, sp)?)?;
        g.point_arrays.push(Named::new(
            sp.name.clone(),
            sp.components,
            values,
            layout,
            Position::Byte(sp.at as u64),
        ));
    }
    for sp in &cell {
        // Integer cell tag arrays go straight into 32-bit tags (no f64 copy of them).
        if sp.components == 1 && !sp.ty.is_float() && tag_slot(&sp.name).is_some() {
            let mut tags = Vec::new();
            dec.ints_into(sp, values(nc, sp)?, &mut tags, "a 32-bit integer tag", |v| {
                i32::try_from(v).ok()
            })?;
            g.cell_tags.push((sp.name.clone(), tags, Position::Byte(sp.at as u64)));
            continue;
        }
        let (values, layout) = dec.items(sp, values(nc, sp)?)?;
        g.cell_arrays.push(Named::new(
            sp.name.clone(),
            sp.components,
            values,
            layout,
            Position::Byte(sp.at as u64),
        ));
    }
    for sp in &field {
        // Field arrays other than numbers (strings) are skipped by `spec` refusing
        // them; the tuple count is optional. Only arrays of two values can name a tag
        // (`into_mesh`), so the others are not decoded at all.
        // Without a count, one that announces more than `UNCOUNTED_MAX` bytes is
        // skipped before anything is allocated.
        let count = sp.tuples.and_then(|t| t.checked_mul(sp.components));
        if count.is_some_and(|n| n != 2) {
            continue;
        }
        let values = match dec.floats(sp, count) {
            Err(e) if count.is_none() && matches!(e.kind, ErrorKind::ImplausibleCount { .. }) => {
                continue
            }
            r => r?,
        };
        g.field_arrays.push(Named::new(
            sp.name.clone(),
            sp.components,
            values,
            Layout::Plain,
            Position::Byte(sp.at as u64),
        ));
    }
    g.into_mesh()
}

// ---------------------------------------------------------------------------------
// Writing.

/// Deflates `data` in independent `BLOCK`-sized blocks, on several threads for large
/// arrays. Level 1: on mesh data it gives files within a few percent of level 6 in a
/// fraction of the time.
fn deflate_blocks(data: &[u8]) -> Vec<Vec<u8>> {
    let one = |chunk: &[u8]| -> Vec<u8> {
        let mut z = Compress::new(Compression::new(1), true);
        let mut out = Vec::with_capacity(chunk.len() + chunk.len() / 8 + 64);
        loop {
            let before = z.total_in() as usize;
            let st =
                z.compress_vec(&chunk[before.min(chunk.len())..], &mut out, FlushCompress::Finish);
            match st {
                Ok(Status::StreamEnd) => return out,
                _ => out.reserve(out.capacity().max(64)),
            }
        }
    };
    let chunks: Vec<&[u8]> = data.chunks(BLOCK).collect();
    let nt = threads().min(chunks.len());
    if nt <= 1 || data.len() < (1 << 20) {
        return chunks.into_iter().map(one).collect();
    }
    let per = chunks.len().div_ceil(nt);
    std::thread::scope(|s| {
        let handles: Vec<_> = chunks
            .chunks(per)
            .map(|g| s.spawn(move || g.iter().map(|c| one(c)).collect::<Vec<_>>()))
            .collect();
        // A compression thread cannot fail; a panic would be a bug in flate2.
        handles.into_iter().flat_map(|h| h.join().expect("compression thread")).collect()
    })
}

/// Writes the bytes of one array into the buffer it is given.
type RawWriter<'a> = Box<dyn FnOnce(&mut Vec<u8>) + 'a>;

struct Writer<'a> {
    out: Vec<u8>,
    enc: VtuEncoding,
    compress: bool,
    /// Compressed appended data, built as the arrays come.
    app: Vec<u8>,
    /// Length of the appended data so far (the next array's `offset`).
    app_len: usize,
    /// Uncompressed appended arrays, written straight into `out` after the XML (their
    /// offsets follow from their sizes), which saves copying them twice.
    deferred: Vec<(usize, RawWriter<'a>)>,
}

impl<'a> Writer<'a> {
    /// `buf` holds 8 bytes of room for a UInt64 header, then the array's bytes. Writes
    /// the header words (little-endian) and the data as an inline or appended binary
    /// array: for inline base64, header and data are encoded separately when
    /// compressed (as VTK does) and as one run when not.
    fn binary_payload(&mut self, mut buf: Vec<u8>) {
        let n = buf.len() - 8;
        if self.compress {
            let blocks = deflate_blocks(&buf[8..]);
            let mut header = Vec::with_capacity(8 * (3 + blocks.len()));
            for w in [blocks.len() as u64, BLOCK as u64, (n % BLOCK) as u64] {
                header.extend_from_slice(&w.to_le_bytes());
            }
            for b in &blocks {
                header.extend_from_slice(&(b.len() as u64).to_le_bytes());
            }
            if self.enc == VtuEncoding::Appended {
                self.app.extend_from_slice(&header);
                for b in &blocks {
                    self.app.extend_from_slice(b);
                }
                self.app_len = self.app.len();
            } else {
                self.out.extend_from_slice(b"          ");
                push_base64(&mut self.out, &header);
                push_base64(&mut self.out, &blocks.concat());
                self.out.push(b'\n');
            }
        } else {
            buf[..8].copy_from_slice(&(n as u64).to_le_bytes());
            self.out.extend_from_slice(b"          ");
            push_base64(&mut self.out, &buf);
            self.out.push(b'\n');
        }
    }

    /// One `<DataArray>`: `ascii` writes the values as text, `raw` as `nbytes`
    /// little-endian bytes.
    fn array(
        &mut self,
        ty: &str,
        name: &str,
        components: usize,
        nbytes: usize,
        ascii: impl FnOnce(&mut Vec<u8>),
        raw: impl FnOnce(&mut Vec<u8>) + 'a,
    ) {
        let o = &mut self.out;
        o.extend_from_slice(b"        <DataArray type=\"");
        o.extend_from_slice(ty.as_bytes());
        o.extend_from_slice(b"\" Name=\"");
        escape(o, name);
        o.push(b'"');
        if components != 1 {
            o.extend_from_slice(b" NumberOfComponents=\"");
            crate::text::push_int(o, components);
            o.push(b'"');
        }
        match self.enc {
            VtuEncoding::Ascii => {
                o.extend_from_slice(b" format=\"ascii\">\n");
                ascii(o);
                o.extend_from_slice(b"        </DataArray>\n");
            }
            VtuEncoding::Binary => {
                o.extend_from_slice(b" format=\"binary\">\n");
                let mut buf = Vec::with_capacity(8 + nbytes);
                buf.extend_from_slice(&[0; 8]);
                raw(&mut buf);
                self.binary_payload(buf);
                self.out.extend_from_slice(b"        </DataArray>\n");
            }
            VtuEncoding::Appended => {
                o.extend_from_slice(b" format=\"appended\" offset=\"");
                crate::text::push_int(o, self.app_len);
                o.extend_from_slice(b"\"/>\n");
                if self.compress {
                    let mut buf = Vec::with_capacity(8 + nbytes);
                    buf.extend_from_slice(&[0; 8]);
                    raw(&mut buf);
                    self.binary_payload(buf);
                } else {
                    self.app_len += 8 + nbytes;
                    self.deferred.push((nbytes, Box::new(raw)));
                }
            }
        }
    }

    /// The appended block, after the XML.
    fn finish_appended(&mut self) {
        self.out.extend_from_slice(b"  <AppendedData encoding=\"raw\">\n   _");
        if self.compress {
            self.out.extend_from_slice(&self.app);
        } else {
            self.out.reserve(self.app_len + 64);
            for (nbytes, raw) in std::mem::take(&mut self.deferred) {
                self.out.extend_from_slice(&(nbytes as u64).to_le_bytes());
                let start = self.out.len();
                raw(&mut self.out);
                debug_assert_eq!(self.out.len() - start, nbytes, "appended array size");
            }
        }
        self.out.extend_from_slice(b"\n  </AppendedData>\n");
    }

    fn f64_array(&mut self, name: &str, components: usize, values: &'a [f64]) {
        self.array(
            "Float64",
            name,
            components,
            values.len() * 8,
            |o| {
                for item in values.chunks(components.max(1)) {
                    o.extend_from_slice(b"          ");
                    for (j, &v) in item.iter().enumerate() {
                        if j > 0 {
                            o.push(b' ');
                        }
                        push_num(o, v);
                    }
                    o.push(b'\n');
                }
            },
            |o| put(o, values, f64::to_le_bytes),
        );
    }

    fn i32_array(&mut self, name: &str, values: &'a [i32]) {
        self.array(
            "Int32",
            name,
            1,
            values.len() * 4,
            |o| {
                for &v in values {
                    o.extend_from_slice(b"          ");
                    crate::text::push_int(o, v);
                    o.push(b'\n');
                }
            },
            |o| put(o, values, i32::to_le_bytes),
        );
    }
}

fn push_base64(out: &mut Vec<u8>, data: &[u8]) {
    let start = out.len();
    let n = base64::encoded_len(data.len(), true).unwrap_or(0);
    out.resize(start + n, 0);
    let written = base64::engine::general_purpose::STANDARD
        .encode_slice(data, &mut out[start..])
        .unwrap_or(0);
    out.truncate(start + written);
}

/// Writes a `.vtu` file.
pub(crate) fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    let mut plan = Plan::new(mesh, "VTK XML");
    let enc = opts.vtk.vtu_encoding;
    let compress = opts.vtk.compress && enc != VtuEncoding::Ascii;
    let np = mesh.points.len();
    let nc = mesh.num_cells();
    let nconn: usize = mesh.blocks.iter().map(|b| b.nodes.len()).sum();
    let data_values = plan.point_arrays.iter().map(|(_, a)| a.values.len()).sum::<usize>()
        + plan.cell_arrays.iter().map(|(_, a)| a.values.len()).sum::<usize>();
    let raw_bytes = np * 24 + nconn * 8 + nc * 17 + data_values * 8;
    let cap = match (enc, compress) {
        (VtuEncoding::Ascii, _) => raw_bytes * 2,
        (_, true) => raw_bytes / 2,
        (VtuEncoding::Binary, false) => raw_bytes * 4 / 3 + 4096,
        (VtuEncoding::Appended, false) => raw_bytes + 4096,
    };
    // Declared before the writer, which borrows it until the appended data is out.
    let offs = offsets(mesh);
    let mut w = Writer {
        out: Vec::with_capacity(cap),
        enc,
        compress,
        app: Vec::new(),
        app_len: 0,
        deferred: Vec::new(),
    };

    let o = &mut w.out;
    o.extend_from_slice(b"<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"");
    if compress {
        o.extend_from_slice(b" compressor=\"vtkZLibDataCompressor\"");
    }
    o.extend_from_slice(b">\n  <UnstructuredGrid>\n");
    // Tag names: meshio's `field_data` layout, one `[tag, dim]` array per name,
    // always ascii (a few numbers).
    if !plan.names.is_empty() {
        o.extend_from_slice(b"    <FieldData>\n");
        for &(name, tag, dim) in &plan.names {
            o.extend_from_slice(b"      <DataArray type=\"Int32\" Name=\"");
            escape(o, name);
            o.extend_from_slice(b"\" NumberOfTuples=\"2\" format=\"ascii\">\n        ");
            crate::text::push_int(o, tag);
            o.push(b' ');
            crate::text::push_int(o, dim);
            o.extend_from_slice(b"\n      </DataArray>\n");
        }
        o.extend_from_slice(b"    </FieldData>\n");
    }
    o.extend_from_slice(b"    <Piece NumberOfPoints=\"");
    crate::text::push_int(o, np);
    o.extend_from_slice(b"\" NumberOfCells=\"");
    crate::text::push_int(o, nc);
    o.extend_from_slice(b"\">\n");

    if !plan.point_arrays.is_empty() {
        w.out.extend_from_slice(b"      <PointData");
        if let Some(t) = plan.tensor {
            w.out.extend_from_slice(b" Tensors=\"");
            escape(&mut w.out, t);
            w.out.push(b'"');
        }
        w.out.extend_from_slice(b">\n");
        for (name, a) in &plan.point_arrays {
            w.f64_array(name, a.components, &a.values);
        }
        w.out.extend_from_slice(b"      </PointData>\n");
    }
    w.out.extend_from_slice(b"      <CellData Scalars=\"gmsh:physical\">\n");
    w.i32_array(PHYSICAL, &plan.physical);
    w.i32_array(GEOMETRICAL, &plan.geometrical);
    for (name, a) in &plan.cell_arrays {
        w.f64_array(name, a.components, &a.values);
    }
    w.out.extend_from_slice(b"      </CellData>\n      <Points>\n");
    let flat: &[[f64; 3]] = &mesh.points;
    w.array(
        "Float64",
        "Points",
        3,
        np * 24,
        |o| {
            for p in flat {
                o.extend_from_slice(b"          ");
                push_num(o, p[0]);
                o.push(b' ');
                push_num(o, p[1]);
                o.push(b' ');
                push_num(o, p[2]);
                o.push(b'\n');
            }
        },
        |o| put(o, flat.as_flattened(), f64::to_le_bytes),
    );
    w.out.extend_from_slice(b"      </Points>\n      <Cells>\n");
    w.array(
        "Int64",
        "connectivity",
        1,
        nconn * 8,
        |o| {
            for b in &mesh.blocks {
                for cell in b.cells() {
                    o.extend_from_slice(b"          ");
                    for (j, &v) in cell.iter().enumerate() {
                        if j > 0 {
                            o.push(b' ');
                        }
                        crate::text::push_int(o, v);
                    }
                    o.push(b'\n');
                }
            }
        },
        |o| {
            o.reserve(nconn * 8);
            for b in &mesh.blocks {
                put(o, &b.nodes, |v| (v as i64).to_le_bytes());
            }
        },
    );
    w.array(
        "Int64",
        "offsets",
        1,
        nc * 8,
        |o| {
            for &v in &offs[1..] {
                o.extend_from_slice(b"          ");
                crate::text::push_int(o, v);
                o.push(b'\n');
            }
        },
        |o| put(o, &offs[1..], |v| (v as i64).to_le_bytes()),
    );
    w.array(
        "UInt8",
        "types",
        1,
        nc,
        |o| {
            for b in &mesh.blocks {
                let t = b.kind.vtk_type();
                for _ in 0..b.len() {
                    o.extend_from_slice(b"          ");
                    crate::text::push_int(o, t);
                    o.push(b'\n');
                }
            }
        },
        |o| {
            for b in &mesh.blocks {
                o.extend(std::iter::repeat(b.kind.vtk_type()).take(b.len()));
            }
        },
    );
    w.out.extend_from_slice(b"      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n");
    if enc == VtuEncoding::Appended {
        w.finish_appended();
    }
    w.out.extend_from_slice(b"</VTKFile>\n");
    let report = std::mem::take(&mut plan.report);
    Ok(Written { main: w.out, siblings: Vec::new(), report })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_with_padding_between_runs() {
        let mut s = Vec::new();
        push_base64(&mut s, b"ab");
        push_base64(&mut s, b"cdef");
        assert_eq!(base64_decode(&s, 0, "x").unwrap(), b"abcdef");
    }

    #[test]
    fn entities_are_decoded() {
        assert_eq!(unescape(b"a&amp;b&lt;&#65;&#x42;&bogus;"), "a&b<AB&bogus;");
        let mut o = Vec::new();
        escape(&mut o, "a<\"b\"&");
        assert_eq!(unescape(&o), "a<\"b\"&");
    }

    #[test]
    fn blocks_round_trip() {
        let data: Vec<u8> = (0..200_000u32).flat_map(|i| (i % 977).to_le_bytes()).collect();
        let blocks = deflate_blocks(&data);
        let refs: Vec<&[u8]> = blocks.iter().map(|b| b.as_slice()).collect();
        let mut out = vec![0u8; data.len()];
        inflate_blocks(&refs, &mut out, BLOCK).unwrap();
        assert_eq!(out, data);
    }
}
