//! Post-processing views: `$NodeData`, `$ElementData` and `$ElementNodeData` read into
//! point and cell data (the same layout in 2.2 and 4.1), and every data array written
//! as one.

use super::cursor::{le_f64, le_i32, Cursor};
use super::header::quote_name;
use super::reader::{quoted, Reader};
use super::tags::TagMap;
use crate::text;
use crate::{DataArray, ErrorKind, Position, Result, TaggedMesh, WriteReport};

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum ViewKind {
    Node,
    Element,
    ElementNode,
}

impl ViewKind {
    pub(super) fn section(self) -> &'static str {
        match self {
            ViewKind::Node => "NodeData",
            ViewKind::Element => "ElementData",
            ViewKind::ElementNode => "ElementNodeData",
        }
    }
}

/// The targets of a view's entries in file order: `0, 1, 2, ...` as a count while they
/// are so (a view of every node in node order), a list otherwise.
pub(super) struct Targets {
    identity: usize,
    /// Every target once they are not `0, 1, 2, ...`; empty until then.
    list: Vec<usize>,
    /// Room to make for the list when it is needed.
    hint: usize,
}

impl Targets {
    pub(super) fn with_capacity(hint: usize) -> Self {
        Targets { identity: 0, list: Vec::new(), hint }
    }

    #[inline]
    pub(super) fn push(&mut self, t: usize) {
        if self.list.is_empty() && t == self.identity {
            self.identity += 1;
        } else {
            if self.list.is_empty() {
                self.list.reserve(self.hint.max(self.identity + 1));
                self.list.extend(0..self.identity);
            }
            self.list.push(t);
        }
    }

    pub(super) fn len(&self) -> usize {
        if self.list.is_empty() {
            self.identity
        } else {
            self.list.len()
        }
    }

    /// Whether the targets are `0, 1, 2, ..., len - 1`.
    pub(super) fn is_identity(&self) -> bool {
        self.list.is_empty() || self.list.iter().enumerate().all(|(i, &t)| i == t)
    }

    pub(super) fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.len()).map(move |i| if self.list.is_empty() { i } else { self.list[i] })
    }

    pub(super) fn append(&mut self, other: &Targets) {
        for t in other.iter() {
            self.push(t);
        }
    }
}

/// Binary view entries of `N` values each (a 4-byte tag, then the values): the values
/// as one array, made in a single pass over the table, and each entry's target pushed
/// (a target that `map` lacks is not). Also the first entry whose tag `map` lacks, for
/// the caller to report. Values are kept as they are, NaN included (a data array may
/// hold NaN; the code that uses it refuses what it cannot use).
fn decode_entries<const N: usize>(
    table: &[u8],
    map: &TagMap,
    targets: &mut Targets,
) -> (Vec<f64>, Option<usize>) {
    let rec = 4 + 8 * N;
    let mut bad = None;
    let rows: Vec<[f64; N]> = table
        .chunks_exact(rec)
        .enumerate()
        .map(|(e, ch)| {
            let mut row = [0.0; N];
            let mut ok = true;
            for (j, x) in row.iter_mut().enumerate() {
                *x = le_f64(&ch[4 + 8 * j..12 + 8 * j]);
            }
            match u64::try_from(le_i32(ch)).ok().and_then(|t| map.get(t)) {
                Some(t) => targets.push(t),
                None => ok = false,
            }
            if !ok && bad.is_none() {
                bad = Some(e);
            }
            row
        })
        .collect();
    (rows.into_flattened(), bad)
}

/// One post-processing view as read.
pub(super) struct View {
    pub(super) kind: ViewKind,
    pub(super) name: String,
    /// Where its header is, for errors found when the array is built.
    pub(super) at: Position,
    pub(super) step: i64,
    pub(super) ncomp: usize,
    /// Node positions (file order) or raw cell ids.
    pub(super) targets: Targets,
    /// ElementNodeData: where each entry's values start in `values` (one more than
    /// `targets`); empty otherwise, every entry then has `ncomp` values.
    pub(super) offsets: Vec<usize>,
    pub(super) values: Vec<f64>,
}

impl Reader<'_> {
    /// `$NodeData`, `$ElementData`, `$ElementNodeData` (same layout in 2.2 and 4.1).
    pub(super) fn read_view(&mut self, kind: ViewKind) -> Result<()> {
        let section = kind.section();
        self.view_count += 1;
        // String tags, one per line: the first is the view's name.
        let n_str = self.c.count("number of string tags", 1)?;
        self.c.t.rest_of_line();
        let mut name = None;
        for i in 0..n_str {
            self.c.t.skip_space();
            let at = self.c.here();
            let line = self.c.t.rest_of_line();
            if line.is_empty() {
                return Err(self.c.err_at(
                    at,
                    ErrorKind::UnexpectedEof {
                        context: format!("expected string tag {} of ${section}", i + 1),
                    },
                ));
            }
            if i == 0 {
                let s = quoted(line).unwrap_or(line);
                name = Some(String::from_utf8_lossy(s).into_owned());
            }
        }
        let name = match name {
            Some(n) if !n.is_empty() => n,
            _ => format!("{section}{}", self.view_count),
        };
        let n_real = self.c.count("number of real tags", 2)?;
        for _ in 0..n_real {
            self.c.f64("real tag (the time value)")?;
        }
        let header_at = self.c.mark();
        let n_int = self.c.count("number of integer tags", 2)?;
        if n_int < 3 {
            return Err(self.c.err(ErrorKind::Expected {
                expected: format!("at least 3 integer tags in ${section} (time step, number of components, number of entries)"),
                found: n_int.to_string(),
            }));
        }
        let step = self.c.i64("time step (integer tag 1)")?;
        let ncomp = self.c.usize("number of components (integer tag 2)")?;
        if ncomp == 0 {
            return Err(self.c.err(ErrorKind::Expected {
                expected: "a number of components of at least 1 (1, 3 or 9)".into(),
                found: "0".into(),
            }));
        }
        // Smallest entry: a tag and its values, `1 0\n` in ASCII.
        let min_entry = if self.c.binary {
            ncomp.saturating_mul(8).saturating_add(4)
        } else {
            ncomp.saturating_mul(2).saturating_add(2)
        };
        let min_entry = if kind == ViewKind::ElementNode {
            min_entry.saturating_add(if self.c.binary { 4 } else { 2 })
        } else {
            min_entry
        };
        if ncomp > self.c.remaining().len() {
            return Err(self.c.err(ErrorKind::ImplausibleCount {
                what: format!("${section} number of components"),
                count: ncomp as u64,
                limit: "more than the bytes left in the file".into(),
            }));
        }
        let n = self.c.count("number of entries (integer tag 3)", min_entry)?;
        for _ in 3..n_int {
            self.c.i64("integer tag")?;
        }
        // A view before any mesh section: a data-only file's when that is allowed
        // (node tag t is vertex t − 1 of the mesh it goes with), else refused entry by entry.
        let data_only = kind == ViewKind::Node && !self.saw_mesh && self.allow_data_only;
        self.data_only |= data_only;
        let map = match kind {
            _ if data_only => TagMap::Range { first: 1, len: crate::MAX_POINTS },
            ViewKind::Node => self.take_node_map()?,
            _ => self.take_elem_map()?,
        };
        let hint = if self.saw_mesh {
            ""
        } else {
            " (the file has no mesh before its views: a data-only file, which smartmesh reads as a metric beside its mesh)"
        };
        let what = if kind == ViewKind::Node { "node" } else { "element" };
        let mut targets = Targets::with_capacity(n);
        let mut offsets = Vec::new();
        // Binary entries of 1, 3 or 9 values are decoded into an array of their own.
        let fixed = self.c.binary && kind != ViewKind::ElementNode && matches!(ncomp, 1 | 3 | 9);
        let mut values = if fixed { Vec::new() } else { Vec::with_capacity(n * ncomp) };
        if kind == ViewKind::ElementNode {
            offsets.reserve(n + 1);
            offsets.push(0);
        }
        let unknown = |c: &Cursor, at: Position, tag: i64| {
            c.err_at(at, ErrorKind::Inconsistent(format!("${section} `{name}` gives a value for {what} {tag}, which the mesh does not have{hint}")))
        };
        if self.c.binary && kind != ViewKind::ElementNode {
            // Fixed-size entries (a tag and `ncomp` doubles): the whole table is taken
            // at once and each value checked as it is converted.
            self.c.end_text_line()?;
            let rec = 4 + 8 * ncomp;
            let p0 = self.c.pos();
            let table =
                self.c.take_array(n, rec, "data entries (a 4-byte tag and 8-byte values each)")?;
            let mut bad = None;
            match ncomp {
                1 => (values, bad) = decode_entries::<1>(table, &map, &mut targets),
                3 => (values, bad) = decode_entries::<3>(table, &map, &mut targets),
                9 => (values, bad) = decode_entries::<9>(table, &map, &mut targets),
                _ => {}
            }
            // The first faulty entry, then (when the width is another) every entry checked
            // and converted one after the other; the errors are the same.
            let from = if fixed { bad.unwrap_or(n) } else { 0 };
            for (e, ch) in table.chunks_exact(rec).enumerate().skip(from) {
                let tag = le_i32(ch);
                let target = u64::try_from(tag).ok().and_then(|t| map.get(t)).ok_or_else(|| {
                    unknown(&self.c, Position::Byte((p0 + e * rec) as u64), tag as i64)
                })?;
                values.extend(ch[4..].chunks_exact(8).map(le_f64));
                targets.push(target);
            }
        } else if self.c.binary {
            self.c.end_text_line()?;
            for _ in 0..n {
                let pos = self.c.pos();
                let tag = self.c.bin_i32("the tag of a data entry")?;
                let target = u64::try_from(tag)
                    .ok()
                    .and_then(|t| map.get(t))
                    .ok_or_else(|| unknown(&self.c, Position::Byte(pos as u64), tag as i64))?;
                let mult = if kind == ViewKind::ElementNode {
                    let p = self.c.pos();
                    let m = self.c.bin_i32("the number of nodes of an entry")?;
                    positive_mult(m as i64).ok_or_else(|| {
                        self.c.byte_err(
                            p,
                            ErrorKind::Expected {
                                expected: "a positive number of nodes per element".into(),
                                found: m.to_string(),
                            },
                        )
                    })?
                } else {
                    1
                };
                let k = ncomp * mult;
                let b = self.c.take_array(k, 8, "data values")?;
                values.extend(b.chunks_exact(8).map(le_f64));
                targets.push(target);
                if kind == ViewKind::ElementNode {
                    offsets.push(values.len());
                }
            }
        } else {
            let mut s = self.c.scan();
            for _ in 0..n {
                let tag = self.c.scan_i64(&mut s, "the tag of a data entry")?;
                let line = Position::Line(s.line());
                let target = u64::try_from(tag)
                    .ok()
                    .and_then(|t| map.get(t))
                    .ok_or_else(|| unknown(&self.c, line, tag))?;
                let mult = if kind == ViewKind::ElementNode {
                    let m = self.c.scan_i64(&mut s, "the number of nodes of an entry")?;
                    positive_mult(m).ok_or_else(|| {
                        self.c.err_at(
                            line,
                            ErrorKind::Expected {
                                expected: "a positive number of nodes per element".into(),
                                found: m.to_string(),
                            },
                        )
                    })?
                } else {
                    1
                };
                let k = ncomp * mult;
                if k > s.bytes_left() / 2 + 1 {
                    return Err(self.c.err_at(
                        line,
                        ErrorKind::UnexpectedEof {
                            context: format!("entry of `{name}` with {k} values"),
                        },
                    ));
                }
                for _ in 0..k {
                    values.push(self.c.scan_value(&mut s, "a data value")?);
                }
                targets.push(target);
                if kind == ViewKind::ElementNode {
                    offsets.push(values.len());
                }
            }
            self.c.unscan(&s);
        }
        match kind {
            ViewKind::Node => self.node_map = Some(map),
            _ => self.elem_map = Some(map),
        }
        self.c.expect_end(section)?;
        let view = View { kind, name, at: header_at, step, ncomp, targets, offsets, values };
        // The same view again: another partition of the same step is merged, another
        // step replaces it (the last step in the file is kept).
        if let Some(old) = self.views.iter_mut().find(|v| v.kind == kind && v.name == view.name) {
            if old.step == view.step {
                if old.ncomp != view.ncomp {
                    return Err(self.c.err_at(
                        header_at,
                        ErrorKind::Inconsistent(format!("view `{}` has {} components here and {} in an earlier section of the same step", view.name, view.ncomp, old.ncomp)),
                    ));
                }
                if kind == ViewKind::ElementNode {
                    let base = old.values.len();
                    old.offsets.extend(view.offsets[1..].iter().map(|o| o + base));
                }
                old.targets.append(&view.targets);
                old.values.extend(view.values);
            } else {
                *old = view;
            }
        } else {
            self.views.push(view);
        }
        Ok(())
    }
}

fn positive_mult(m: i64) -> Option<usize> {
    (1..=1 << 16).contains(&m).then_some(m as usize)
}

/// Every point array as `$NodeData` (node tag = index + 1) and every cell array as
/// `$ElementData` (element tag `cell_tag(i)`).
pub(super) fn write_views(
    out: &mut Vec<u8>,
    mesh: &TaggedMesh,
    binary: bool,
    cell_tag: &dyn Fn(usize) -> u64,
    report: &mut WriteReport,
) {
    for (name, a) in &mesh.point_data {
        write_view(out, "NodeData", "point data", name, a, binary, |i| i as u64 + 1, report);
    }
    for (name, a) in &mesh.cell_data {
        write_view(out, "ElementData", "cell data", name, a, binary, cell_tag, report);
    }
}

/// The binary entries of a view of `N` values per item: the 4-byte tag and the values
/// as one record of known size (one capacity check per item). Every item is written;
/// `true` when every value was finite.
fn view_records<const N: usize>(
    out: &mut Vec<u8>,
    a: &DataArray,
    tag: impl Fn(usize) -> u64,
) -> bool {
    let mut rec = [0u8; 76];
    let mut finite = true;
    for (i, v) in a.values.chunks_exact(N).enumerate() {
        rec[..4].copy_from_slice(&(tag(i) as i32).to_le_bytes());
        for (j, x) in v.iter().enumerate() {
            finite &= x.is_finite();
            rec[4 + 8 * j..12 + 8 * j].copy_from_slice(&x.to_le_bytes());
        }
        out.extend_from_slice(&rec[..4 + 8 * N]);
    }
    finite
}

/// A view's section header, up to its number of entries `n`.
fn view_header(out: &mut Vec<u8>, section: &str, quoted: &str, k: usize, n: usize) {
    out.extend_from_slice(b"$");
    out.extend_from_slice(section.as_bytes());
    out.extend_from_slice(b"\n1\n\"");
    out.extend_from_slice(quoted.as_bytes());
    out.extend_from_slice(b"\"\n1\n0\n3\n0\n");
    text::push_int(out, k);
    out.push(b'\n');
    text::push_int(out, n);
    out.push(b'\n');
}

fn view_end(out: &mut Vec<u8>, section: &str, binary: bool) {
    if binary {
        out.push(b'\n');
    }
    out.extend_from_slice(b"$End");
    out.extend_from_slice(section.as_bytes());
    out.push(b'\n');
}

#[allow(clippy::too_many_arguments)]
fn write_view(
    out: &mut Vec<u8>,
    section: &str,
    what: &str,
    name: &str,
    a: &DataArray,
    binary: bool,
    tag: impl Fn(usize) -> u64,
    report: &mut WriteReport,
) {
    // Gmsh's tensors are 9 components: a packed symmetric one is written in full.
    let a = &*a.expanded();
    let k = a.components;
    if !matches!(k, 1 | 3 | 9) {
        report.drop(format!(
            "{what} `{name}` has {k} components: Gmsh draws views of 1, 3 or 9; written as is (Gmsh reads it but may not display it)"
        ));
    }
    // Binary, of a common width: fixed-size records of every item, the values checked
    // finite as they are written (one pass). An array with a NaN or an infinity (rare)
    // is written again below, without those items.
    if binary && matches!(k, 1 | 3 | 9) {
        let start = out.len();
        let mut quoting = WriteReport::default();
        let q = quote_name(name, what, None, &mut quoting);
        view_header(out, section, &q, k, a.len());
        let finite = match k {
            1 => view_records::<1>(out, a, &tag),
            3 => view_records::<3>(out, a, &tag),
            _ => view_records::<9>(out, a, &tag),
        };
        if finite {
            report.dropped.extend(quoting.dropped);
            view_end(out, section, binary);
            return;
        }
        out.truncate(start);
    }
    let items = a.values.chunks_exact(k);
    let n = items.clone().filter(|v| v.iter().all(|x| x.is_finite())).count();
    if n < a.len() {
        report.drop(format!("{what} `{name}`: {} item(s) with NaN or infinite values left out (read back as missing)", a.len() - n));
    }
    let q = quote_name(name, what, None, report);
    view_header(out, section, &q, k, n);
    for (i, v) in items.enumerate() {
        if !v.iter().all(|x| x.is_finite()) {
            continue;
        }
        if binary {
            out.extend_from_slice(&(tag(i) as i32).to_le_bytes());
            for x in v {
                out.extend_from_slice(&x.to_le_bytes());
            }
        } else {
            text::push_int(out, tag(i));
            for &x in v {
                out.push(b' ');
                text::push_f64(out, x);
            }
            out.push(b'\n');
        }
    }
    view_end(out, section, binary);
}
