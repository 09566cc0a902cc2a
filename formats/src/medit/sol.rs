//! Solution files: `SolAtVertices` read into named point-data arrays (see the module
//! documentation of `medit` for the names and the tensor order).

use super::*;

/// Reads a solution file (`.sol` when `binary` is false, `.solb` when true) whose
/// `SolAtVertices` must cover `n_vertices` vertices. Returns the arrays named as in the
/// module documentation (`size`, `vector`, `metric`, `matrix`); an empty map when the
/// file has no solution at vertices.
pub fn read_sol(
    bytes: &[u8],
    n_vertices: usize,
    binary: bool,
) -> Result<BTreeMap<String, DataArray>> {
    let p = parse(bytes, binary)?;
    match p.sol {
        Some(sol) => sol_arrays(sol, p.dim, n_vertices, bytes),
        None => Ok(BTreeMap::new()),
    }
}

/// Reads a solution file given without its mesh (ASCII or binary, told by its first
/// bytes, as [`read`] tells a sibling's): the number of vertices its `SolAtVertices`
/// covers and the arrays of [`read_sol`] for that number, `None` when the file has no
/// solution at vertices. The caller compares the count with its mesh's.
pub fn read_sol_alone(bytes: &[u8]) -> Result<Option<(usize, BTreeMap<String, DataArray>)>> {
    let p = parse(bytes, is_binary(bytes))?;
    match p.sol {
        Some(sol) if !sol.types.is_empty() => {
            let n = sol.n;
            Ok(Some((n, sol_arrays(sol, p.dim, n, bytes)?)))
        }
        _ => Ok(None),
    }
}

/// Names and converts the solutions of a `SolAtVertices` read from `bytes`.
pub(super) fn sol_arrays(
    mut sol: Sol,
    dim: u8,
    n_vertices: usize,
    bytes: &[u8],
) -> Result<BTreeMap<String, DataArray>> {
    let at = sol.at.unwrap_or(Position::Line(1));
    if sol.n != n_vertices {
        return Err(error_at(
            at,
            ErrorKind::Inconsistent(format!(
                "SolAtVertices gives {} vertices, the mesh has {n_vertices}",
                sol.n
            )),
        ));
    }
    let sizes: Vec<usize> = sol.types.iter().map(|&t| sol_size(t, dim).unwrap_or(0)).collect();
    let stride: usize = sizes.iter().sum();
    let n_values = if sol.raw.is_some() { sol.n * stride } else { sol.values.len() };
    if sizes.contains(&0) || n_values != sol.n * stride {
        return Err(error_at(
            at,
            ErrorKind::Inconsistent(format!(
                "SolAtVertices holds {} values, expected {} vertices of {stride}",
                sol.values.len(),
                sol.n
            )),
        ));
    }
    let mut out = BTreeMap::new();
    let mut seen: BTreeMap<&str, usize> = BTreeMap::new();
    let mut offset = 0;
    for (&typ, &size) in sol.types.iter().zip(&sizes) {
        let base = match typ {
            1 => "size",
            2 => "vector",
            3 => "metric",
            _ => "matrix",
        };
        let k = seen.entry(base).or_insert(0);
        *k += 1;
        let name = if *k == 1 { base.to_string() } else { format!("{base}_{k}") };
        let d = dim as usize;
        // A 2D symmetric tensor stays packed as the file has it (m11 m12 m22).
        let packed = typ == 3 && d == 2;
        let comps = if typ == 1 {
            1
        } else if typ == 2 || packed {
            3
        } else {
            9
        };
        // The layout is decided once per field, then each vertex's values are written
        // in place (one pass over the solution, no per-value growth check), decoded
        // from the file's bytes when they were left there.
        let values = match sol.raw {
            Some(start) => {
                let mut values = vec![0.0; comps * sol.n];
                let rows = bytes[start..start + sol.n * stride * 8]
                    .chunks_exact(stride * 8)
                    .map(|r| &r[offset * 8..(offset + size) * 8]);
                convert(
                    &mut values,
                    comps,
                    rows,
                    |r: &&[u8], j| {
                        f64::from_le_bytes(r[8 * j..8 * j + 8].try_into().unwrap_or([0; 8]))
                    },
                    typ,
                    d,
                );
                values
            }
            // Decoded already in the file's order, alone in its rows (the binary reader
            // does so for one such field): the array itself.
            None if stride == size && size == comps && identity_layout(typ, d) => {
                std::mem::take(&mut sol.values)
            }
            None => {
                let mut values = vec![0.0; comps * sol.n];
                convert(
                    &mut values,
                    comps,
                    sol.values.chunks_exact(stride).map(|r| &r[offset..offset + size]),
                    |r: &&[f64], j| r[j],
                    typ,
                    d,
                );
                values
            }
        };
        out.insert(
            name,
            if packed { DataArray::symmetric2(values) } else { DataArray::new(comps, values) },
        );
        offset += size;
    }
    Ok(out)
}

/// Whether a solution of `typ` in dimension `d` is kept with the file's values in the
/// file's order (see [`convert`]).
pub(super) fn identity_layout(typ: u32, d: usize) -> bool {
    matches!((typ, d), (1, _) | (3, 2) | (2, 3) | (4, 3))
}

/// One field's values, vertex by vertex (`rows`, value `j` of a row by `get`), in the
/// layout of its array: `comps` values per vertex.
#[inline(always)]
fn convert<T>(
    out: &mut [f64],
    comps: usize,
    rows: impl Iterator<Item = T>,
    get: impl Fn(&T, usize) -> f64,
    typ: u32,
    d: usize,
) {
    let items = out.chunks_exact_mut(comps).zip(rows);
    // Values are stored one by one: `copy_from_slice` of a small array is a call to
    // `memcpy` per vertex.
    let put = |o: &mut [f64], v: &[f64]| o.iter_mut().zip(v).for_each(|(o, &v)| *o = v);
    match (typ, d) {
        (1, _) => items.for_each(|(o, s)| o[0] = get(&s, 0)),
        (2, 2) => items.for_each(|(o, s)| put(o, &[get(&s, 0), get(&s, 1), 0.0])),
        (2, _) | (3, 2) => items.for_each(|(o, s)| put(o, &[get(&s, 0), get(&s, 1), get(&s, 2)])),
        // libMeshb's 3D order: m11 m12 m22 m13 m23 m33.
        (3, _) => items.for_each(|(o, s)| {
            let m: [f64; 6] = std::array::from_fn(|j| get(&s, j));
            put(o, &[m[0], m[1], m[3], m[1], m[2], m[4], m[3], m[4], m[5]])
        }),
        (_, 2) => items.for_each(|(o, s)| {
            put(o, &[get(&s, 0), get(&s, 1), 0.0, get(&s, 2), get(&s, 3), 0.0, 0.0, 0.0, 1.0])
        }),
        (_, _) => items.for_each(|(o, s)| {
            for (j, v) in o.iter_mut().enumerate() {
                *v = get(&s, j);
            }
        }),
    }
}
