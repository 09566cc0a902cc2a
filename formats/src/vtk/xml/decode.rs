//! Decoding one `<DataArray>` of a `.vtu` into numbers: its bytes found inline (ASCII
//! text or base64) or in the appended block, raw or in zlib blocks with their header
//! words, then converted to floats, point coordinates or node indices. Every size is
//! checked against what the file announces before anything is allocated.

use super::read::{Format, Spec};
use super::*;

pub(super) struct Appended {
    /// Offset of the byte after `_`.
    pub(super) base: usize,
    /// End of the appended bytes (`</AppendedData>` or the end of the file).
    pub(super) end: usize,
    pub(super) raw: bool,
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

pub(super) struct Decoder<'a> {
    pub(super) d: &'a [u8],
    pub(super) big: bool,
    /// Size of a header word: 4 (UInt32) or 8 (UInt64).
    pub(super) hsize: usize,
    pub(super) zlib: bool,
    pub(super) appended: Option<Appended>,
    /// Sorted offsets of appended arrays, to bound base64 runs.
    pub(super) app_offsets: Vec<usize>,
}

/// Strips whitespace and decodes base64 that may hold several padded runs (VTK
/// encodes a compressed array's header and data separately).
pub(super) fn base64_decode(text: &[u8], at: usize, name: &str) -> Result<Vec<u8>> {
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
pub(super) fn inflate_blocks(
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

    /// The values of an array as `f64`: `expected` values when known; NaN and
    /// infinities refused unless `any` (a data array keeps them, see `decode_f64`).
    pub(super) fn floats(&self, sp: &Spec, expected: Option<usize>, any: bool) -> Result<Vec<f64>> {
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
                if !v.is_finite() && !any {
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
            decode_f64(bytes, sp.ty, self.big, n, &mut out, !any).map_err(|i| {
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
    pub(super) fn items(&self, sp: &Spec, expected: usize) -> Result<(Vec<f64>, Layout)> {
        if sp.format == Format::Ascii || sp.components != 9 {
            return Ok(pack_parsed(self.floats(sp, Some(expected), true)?, sp.components));
        }
        let p = self.payload(sp, expected.checked_mul(sp.ty.size()))?;
        let bytes = p.as_slice();
        let n = bytes.len() / sp.ty.size();
        if n != expected {
            // The plain path's errors, in its order.
            return Ok((self.floats(sp, Some(expected), true)?, Layout::Plain));
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

    pub(super) fn points(&self, sp: &Spec, n: usize) -> Result<Vec<[f64; 3]>> {
        if sp.format == Format::Ascii {
            let flat = self.floats(sp, Some(3 * n), false)?;
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
    pub(super) fn indices(
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
    pub(super) fn ints_into<T>(
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
