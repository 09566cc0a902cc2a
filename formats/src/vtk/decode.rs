//! VTK's numeric types and the decoding of binary arrays, shared by both readers.

use crate::{Layout, NodeIndex, MAX_POINTS};

/// A numeric type of a VTK array.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
}

impl Scalar {
    pub(crate) const fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::I64 | Scalar::U64 | Scalar::F64 => 8,
        }
    }

    pub(crate) const fn is_float(self) -> bool {
        matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// The legacy type names (`vtkDataWriter`), case-insensitive. `long` is taken as
    /// 8 bytes, as VTK writes it on 64-bit Linux and macOS.
    pub(crate) fn from_legacy(name: &[u8]) -> Option<Scalar> {
        let n = String::from_utf8_lossy(name).to_ascii_lowercase();
        Some(match n.as_str() {
            "char" | "signed_char" => Scalar::I8,
            "unsigned_char" => Scalar::U8,
            "short" => Scalar::I16,
            "unsigned_short" => Scalar::U16,
            "int" => Scalar::I32,
            "unsigned_int" => Scalar::U32,
            "long" | "vtktypeint64" | "vtkidtype" => Scalar::I64,
            "unsigned_long" | "vtktypeuint64" => Scalar::U64,
            "float" => Scalar::F32,
            "double" => Scalar::F64,
            _ => return None,
        })
    }

    /// The XML `type` attribute values.
    pub(crate) fn from_xml(name: &str) -> Option<Scalar> {
        Some(match name {
            "Int8" | "Char" => Scalar::I8,
            "UInt8" | "UChar" => Scalar::U8,
            "Int16" => Scalar::I16,
            "UInt16" => Scalar::U16,
            "Int32" => Scalar::I32,
            "UInt32" => Scalar::U32,
            "Int64" | "IdType" => Scalar::I64,
            "UInt64" => Scalar::U64,
            "Float32" => Scalar::F32,
            "Float64" => Scalar::F64,
            _ => return None,
        })
    }
}

/// Decodes `n` values of type `ty` from `bytes` (which holds at least `n * ty.size()`
/// bytes) as `f64`, appending to `out`. Integers wider than 53 bits lose precision as
/// any reader of doubles would. With `finite_only` (coordinates, tags), returns the
/// index of the first non-finite value; data arrays keep NaN and infinities as they
/// are (VTK and meshio read them), for the code that uses an array to refuse.
pub(crate) fn decode_f64(
    bytes: &[u8],
    ty: Scalar,
    big: bool,
    n: usize,
    out: &mut Vec<f64>,
    finite_only: bool,
) -> std::result::Result<(), usize> {
    let bytes = &bytes[..n * ty.size()];
    let start = out.len();
    out.reserve(n);
    // Floats are checked while they are converted (one pass over the data, which is
    // what a large tensor array costs): `finite` stays true only if every value is;
    // the position of the first bad one is looked for only when one was seen.
    let mut finite = true;
    macro_rules! conv {
        ($t:ty, $w:expr) => {{
            if big {
                out.extend(
                    bytes
                        .chunks_exact($w)
                        .map(|c| <$t>::from_be_bytes(c.try_into().expect("chunk")) as f64),
                );
            } else {
                out.extend(
                    bytes
                        .chunks_exact($w)
                        .map(|c| <$t>::from_le_bytes(c.try_into().expect("chunk")) as f64),
                );
            }
        }};
        (float $t:ty, $w:expr) => {{
            let mut f = |v: $t| {
                finite &= v.is_finite();
                v as f64
            };
            if big {
                out.extend(
                    bytes
                        .chunks_exact($w)
                        .map(|c| f(<$t>::from_be_bytes(c.try_into().expect("chunk")))),
                );
            } else {
                out.extend(
                    bytes
                        .chunks_exact($w)
                        .map(|c| f(<$t>::from_le_bytes(c.try_into().expect("chunk")))),
                );
            }
        }};
    }
    match ty {
        Scalar::I8 => conv!(i8, 1),
        Scalar::U8 => conv!(u8, 1),
        Scalar::I16 => conv!(i16, 2),
        Scalar::U16 => conv!(u16, 2),
        Scalar::I32 => conv!(i32, 4),
        Scalar::U32 => conv!(u32, 4),
        Scalar::I64 => conv!(i64, 8),
        Scalar::U64 => conv!(u64, 8),
        Scalar::F32 => conv!(float f32, 4),
        Scalar::F64 => conv!(float f64, 8),
    }
    if !finite && finite_only {
        return Err(out[start..].iter().position(|v| !v.is_finite()).unwrap_or(0));
    }
    Ok(())
}

/// Decodes `n` integers of type `ty` from `bytes`, appending to `out`. Floating-point
/// arrays are accepted when every value is integral (some writers store ids as
/// doubles); otherwise the index of the first bad value is returned.
pub(crate) fn decode_i64(
    bytes: &[u8],
    ty: Scalar,
    big: bool,
    n: usize,
    out: &mut Vec<i64>,
) -> std::result::Result<(), usize> {
    let bytes = &bytes[..n * ty.size()];
    out.reserve(n);
    macro_rules! conv {
        ($t:ty, $w:expr) => {{
            if big {
                out.extend(
                    bytes
                        .chunks_exact($w)
                        .map(|c| <$t>::from_be_bytes(c.try_into().expect("chunk")) as i64),
                );
            } else {
                out.extend(
                    bytes
                        .chunks_exact($w)
                        .map(|c| <$t>::from_le_bytes(c.try_into().expect("chunk")) as i64),
                );
            }
        }};
    }
    match ty {
        Scalar::I8 => conv!(i8, 1),
        Scalar::U8 => conv!(u8, 1),
        Scalar::I16 => conv!(i16, 2),
        Scalar::U16 => conv!(u16, 2),
        Scalar::I32 => conv!(i32, 4),
        Scalar::U32 => conv!(u32, 4),
        Scalar::I64 => conv!(i64, 8),
        Scalar::U64 => {
            for (i, c) in bytes.chunks_exact(8).enumerate() {
                let v = if big {
                    u64::from_be_bytes(c.try_into().expect("chunk"))
                } else {
                    u64::from_le_bytes(c.try_into().expect("chunk"))
                };
                out.push(i64::try_from(v).map_err(|_| i)?);
            }
        }
        Scalar::F32 | Scalar::F64 => {
            let mut tmp = Vec::new();
            decode_f64(bytes, ty, big, n, &mut tmp, true)?;
            for (i, v) in tmp.into_iter().enumerate() {
                if v.fract() != 0.0 || v.abs() > 9.0e15 {
                    return Err(i);
                }
                out.push(v as i64);
            }
        }
    }
    Ok(())
}

/// Decodes `n` integers of type `ty` from `bytes` straight into their final type,
/// appending to `out`: `conv` takes each value and refuses (with `None`) what its
/// type cannot hold. Saves the `i64` array that [`decode_i64`] would fill for arrays
/// such as cell types and offsets. Returns the index of the first refused value.
pub(crate) fn decode_ints_as<T>(
    bytes: &[u8],
    ty: Scalar,
    big: bool,
    n: usize,
    out: &mut Vec<T>,
    conv: impl Fn(i64) -> Option<T>,
) -> std::result::Result<(), usize> {
    let bytes = &bytes[..n * ty.size()];
    out.reserve(n);
    macro_rules! conv {
        ($t:ty, $w:expr) => {{
            for (i, c) in bytes.chunks_exact($w).enumerate() {
                let c = c.try_into().expect("chunk");
                let v = if big { <$t>::from_be_bytes(c) } else { <$t>::from_le_bytes(c) };
                out.push(i64::try_from(v).ok().and_then(&conv).ok_or(i)?);
            }
        }};
    }
    match ty {
        Scalar::I8 => conv!(i8, 1),
        Scalar::U8 => conv!(u8, 1),
        Scalar::I16 => conv!(i16, 2),
        Scalar::U16 => conv!(u16, 2),
        Scalar::I32 => conv!(i32, 4),
        Scalar::U32 => conv!(u32, 4),
        Scalar::I64 => conv!(i64, 8),
        Scalar::U64 => conv!(u64, 8),
        Scalar::F32 | Scalar::F64 => {
            let mut tmp = Vec::new();
            decode_i64(bytes, ty, big, n, &mut tmp)?;
            for (i, v) in tmp.into_iter().enumerate() {
                out.push(conv(v).ok_or(i)?);
            }
        }
    }
    Ok(())
}

/// Decodes the `n` values of a binary array of `components` floats per item. An array of
/// 9-component items that are all 2D symmetric tensors with the implied third row and
/// column, `[m11 m12 0; m12 m22 0; 0 0 1]` bit for bit (a 2D metric padded with zz = 1,
/// as the public VTK fixtures and the Medit solutions written out carry it), is kept
/// packed as [`Layout::Symmetric2`]: a third of the memory, which a large read would
/// otherwise spend most of its time faulting in, and the same values once expanded.
/// Returns the values and their layout, or the index of the first non-finite value.
pub(crate) fn decode_items(
    bytes: &[u8],
    ty: Scalar,
    big: bool,
    n: usize,
    components: usize,
) -> std::result::Result<(Vec<f64>, Layout), usize> {
    if components == 9 && n % 9 == 0 {
        if let Some(packed) = pack_symmetric2(&bytes[..n * ty.size()], ty, big) {
            return Ok((packed, Layout::Symmetric2));
        }
    }
    let mut out = Vec::new();
    decode_f64(bytes, ty, big, n, &mut out, false)?;
    Ok((out, Layout::Plain))
}

/// [`decode_items`] for values already parsed (an ASCII array): packed when they fit,
/// so that a file's tensors have one layout whatever its encoding.
pub(crate) fn pack_parsed(values: Vec<f64>, components: usize) -> (Vec<f64>, Layout) {
    if components == 9 && values.len() % 9 == 0 {
        if let Some(packed) = pack_rows(values.chunks_exact(9), |r, j| r[j]) {
            return (packed, Layout::Symmetric2);
        }
    }
    (values, Layout::Plain)
}

/// The packed `m11 m12 m22` of 9-component float items, when every item is a finite 2D
/// symmetric tensor with the implied third row and column (see [`decode_items`]).
fn pack_symmetric2(bytes: &[u8], ty: Scalar, big: bool) -> Option<Vec<f64>> {
    let f64_le =
        |r: &[u8], j: usize| f64::from_le_bytes(r[8 * j..8 * j + 8].try_into().expect("8 bytes"));
    let f64_be =
        |r: &[u8], j: usize| f64::from_be_bytes(r[8 * j..8 * j + 8].try_into().expect("8 bytes"));
    let f32_le = |r: &[u8], j: usize| {
        f32::from_le_bytes(r[4 * j..4 * j + 4].try_into().expect("4 bytes")) as f64
    };
    let f32_be = |r: &[u8], j: usize| {
        f32::from_be_bytes(r[4 * j..4 * j + 4].try_into().expect("4 bytes")) as f64
    };
    match (ty, big) {
        (Scalar::F64, false) => pack_rows(bytes.chunks_exact(72), f64_le),
        (Scalar::F64, true) => pack_rows(bytes.chunks_exact(72), f64_be),
        (Scalar::F32, false) => pack_rows(bytes.chunks_exact(36), f32_le),
        (Scalar::F32, true) => pack_rows(bytes.chunks_exact(36), f32_be),
        _ => None,
    }
}

/// Packs 9-value rows (value `j` of a row by `get`) when every one fits.
#[inline(always)]
fn pack_rows<R: Copy>(
    rows: impl ExactSizeIterator<Item = R> + Clone,
    get: impl Fn(R, usize) -> f64,
) -> Option<Vec<f64>> {
    let item = |r: R| -> ([f64; 3], bool) {
        let m: [f64; 9] = std::array::from_fn(|j| get(r, j));
        // Zeros compared by their bits: a -0.0 would not come back from the packing.
        let zero = |x: f64| x.to_bits() == 0;
        let fits = m[3].to_bits() == m[1].to_bits()
            && zero(m[2])
            && zero(m[5])
            && zero(m[6])
            && zero(m[7])
            && m[8] == 1.0;
        ([m[0], m[1], m[4]], fits & m[0].is_finite() & m[1].is_finite() & m[4].is_finite())
    };
    // A first item that does not fit (a 3D tensor, a non-finite value, which the plain
    // decoder reports) costs no allocation.
    if !item(rows.clone().next()?).1 {
        return None;
    }
    let mut out = vec![0.0; 3 * rows.len()];
    let mut all = true;
    for (o, r) in out.chunks_exact_mut(3).zip(rows) {
        let (v, fits) = item(r);
        o[0] = v[0];
        o[1] = v[1];
        o[2] = v[2];
        all &= fits;
    }
    all.then_some(out)
}

/// Decodes `n` points (3 values each) straight into `[f64; 3]`, the hot path of
/// every binary reader. Returns the index of the first non-finite value.
pub(crate) fn decode_points(
    bytes: &[u8],
    ty: Scalar,
    big: bool,
    n: usize,
) -> std::result::Result<Vec<[f64; 3]>, usize> {
    let bytes = &bytes[..3 * n * ty.size()];
    let pts: Vec<[f64; 3]> = if ty == Scalar::F64 {
        let f = |c: &[u8]| {
            if big {
                f64::from_be_bytes(c.try_into().expect("8"))
            } else {
                f64::from_le_bytes(c.try_into().expect("8"))
            }
        };
        bytes.chunks_exact(24).map(|c| [f(&c[..8]), f(&c[8..16]), f(&c[16..])]).collect()
    } else {
        let mut flat = Vec::new();
        decode_f64(bytes, ty, big, 3 * n, &mut flat, true)?;
        flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
    };
    match pts.as_flattened().iter().position(|v| !v.is_finite()) {
        Some(i) => Err(i),
        None => Ok(pts),
    }
}

/// Decodes `n` point indices, each checked to be in `0..limit`; on failure, the
/// position and value of the first bad one.
pub(crate) fn decode_indices(
    bytes: &[u8],
    ty: Scalar,
    big: bool,
    n: usize,
    limit: usize,
) -> std::result::Result<Vec<NodeIndex>, (usize, i64)> {
    let bytes = &bytes[..n * ty.size()];
    // Cells address at most MAX_POINTS points. A value that is negative or past
    // `NodeIndex` saturates to `NodeIndex::MAX`, which no limit admits, so one
    // comparison per value checks the range; the value is decoded again for the error.
    let limit = limit.min(MAX_POINTS);
    let sat = |v: i64| NodeIndex::try_from(v).unwrap_or(NodeIndex::MAX);
    let out: Vec<NodeIndex> = match (ty, big) {
        (Scalar::I64, false) => bytes
            .chunks_exact(8)
            .map(|c| sat(i64::from_le_bytes(c.try_into().expect("8"))))
            .collect(),
        (Scalar::I64, true) => bytes
            .chunks_exact(8)
            .map(|c| sat(i64::from_be_bytes(c.try_into().expect("8"))))
            .collect(),
        (Scalar::I32, false) => bytes
            .chunks_exact(4)
            .map(|c| sat(i32::from_le_bytes(c.try_into().expect("4")) as i64))
            .collect(),
        (Scalar::I32, true) => bytes
            .chunks_exact(4)
            .map(|c| sat(i32::from_be_bytes(c.try_into().expect("4")) as i64))
            .collect(),
        _ => {
            let mut v = Vec::new();
            decode_i64(bytes, ty, big, n, &mut v).map_err(|i| (i, -1))?;
            if let Some(i) = v.iter().position(|&x| x < 0 || x as u64 >= limit as u64) {
                return Err((i, v[i]));
            }
            return Ok(v.into_iter().map(|x| x as NodeIndex).collect());
        }
    };
    match out.iter().position(|&v| v as usize >= limit) {
        Some(i) => {
            let mut one = Vec::new();
            decode_i64(&bytes[i * ty.size()..(i + 1) * ty.size()], ty, big, 1, &mut one)
                .map_err(|_| (i, -1))?;
            Err((i, one.first().copied().unwrap_or(-1)))
        }
        None => Ok(out),
    }
}
