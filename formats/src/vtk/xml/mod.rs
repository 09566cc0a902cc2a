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

mod decode;
mod parallel;
mod pieces;
mod read;
mod write;

pub(crate) use read::read;
pub(crate) use write::write;

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

#[cfg(test)]
mod tests {
    use super::decode::{base64_decode, inflate_blocks};
    use super::write::{deflate_blocks, push_base64};
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
