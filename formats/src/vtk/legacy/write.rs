//! Writing a legacy file (versions 4.2 and 5.1, ASCII or binary).

use crate::{Error, ErrorKind, NodeIndex, Result, TaggedMesh, WriteOptions, Written};

use crate::vtk::{offsets, push_num, put, Plan, GEOMETRICAL, PHYSICAL};

use super::encode_name;

/// Writes a legacy file.
pub(crate) fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    let v51 = match opts.vtk.legacy_version {
        (4, 2) => false,
        (5, 1) => true,
        (a, b) => {
            return Err(Error::new(ErrorKind::CannotWrite {
                format: "VTK legacy",
                reason: format!("file version {a}.{b}: smartmesh writes 4.2 and 5.1"),
            }))
        }
    };
    let binary = opts.vtk.legacy_binary;
    let mut plan = Plan::new(mesh, "VTK legacy");
    let np = mesh.points.len();
    let nc = mesh.num_cells();
    let nconn: usize = mesh.blocks.iter().map(|b| b.nodes.len()).sum();
    if !v51 && nconn + nc > i32::MAX as usize {
        return Err(Error::new(ErrorKind::CannotWrite {
            format: "VTK legacy 4.2",
            reason: "more than 2^31 cell list entries; write version 5.1".into(),
        }));
    }
    let data_values = plan.point_arrays.iter().map(|(_, a)| a.values.len()).sum::<usize>()
        + plan.cell_arrays.iter().map(|(_, a)| a.values.len()).sum::<usize>();
    let per_value = if binary { 8 } else { 20 };
    let mut out = Vec::with_capacity(
        512 + np * 3 * per_value + (nconn + nc) * 8 + nc * 24 + data_values * per_value,
    );

    out.extend_from_slice(if v51 {
        b"# vtk DataFile Version 5.1\n"
    } else {
        b"# vtk DataFile Version 4.2\n"
    });
    out.extend_from_slice(b"written by smartmesh\n");
    out.extend_from_slice(if binary { b"BINARY\n" } else { b"ASCII\n" });
    out.extend_from_slice(b"DATASET UNSTRUCTURED_GRID\n");

    out.extend_from_slice(b"POINTS ");
    crate::text::push_int(&mut out, np);
    out.extend_from_slice(b" double\n");
    if binary {
        put(&mut out, mesh.points.as_flattened(), f64::to_be_bytes);
        out.push(b'\n');
    } else {
        for p in &mesh.points {
            push_num(&mut out, p[0]);
            out.push(b' ');
            push_num(&mut out, p[1]);
            out.push(b' ');
            push_num(&mut out, p[2]);
            out.push(b'\n');
        }
    }

    if v51 {
        let offs = offsets(mesh);
        out.extend_from_slice(b"CELLS ");
        crate::text::push_int(&mut out, nc + 1);
        out.push(b' ');
        crate::text::push_int(&mut out, nconn);
        out.extend_from_slice(b"\nOFFSETS vtktypeint64\n");
        if binary {
            put(&mut out, &offs, |o| (o as i64).to_be_bytes());
            out.push(b'\n');
        } else {
            for o in &offs {
                crate::text::push_int(&mut out, *o);
                out.push(b'\n');
            }
        }
        out.extend_from_slice(b"CONNECTIVITY vtktypeint64\n");
        for b in &mesh.blocks {
            if binary {
                put(&mut out, &b.nodes, |v| (v as i64).to_be_bytes());
            } else {
                for cell in b.cells() {
                    for (j, &v) in cell.iter().enumerate() {
                        if j > 0 {
                            out.push(b' ');
                        }
                        crate::text::push_int(&mut out, v);
                    }
                    out.push(b'\n');
                }
            }
        }
        if binary {
            out.push(b'\n');
        }
    } else {
        out.extend_from_slice(b"CELLS ");
        crate::text::push_int(&mut out, nc);
        out.push(b' ');
        crate::text::push_int(&mut out, nc + nconn);
        out.push(b'\n');
        for b in &mesh.blocks {
            let k = b.kind.nodes_per_cell();
            if binary {
                match k {
                    2 => cell_records::<2, 3>(&mut out, &b.nodes),
                    3 => cell_records::<3, 4>(&mut out, &b.nodes),
                    4 => cell_records::<4, 5>(&mut out, &b.nodes),
                    _ => {
                        for cell in b.cells() {
                            out.extend_from_slice(&(k as i32).to_be_bytes());
                            for &v in cell {
                                out.extend_from_slice(&(v as i32).to_be_bytes());
                            }
                        }
                    }
                }
                continue;
            }
            for cell in b.cells() {
                crate::text::push_int(&mut out, k);
                for &v in cell {
                    out.push(b' ');
                    crate::text::push_int(&mut out, v);
                }
                out.push(b'\n');
            }
        }
        if binary {
            out.push(b'\n');
        }
    }

    out.extend_from_slice(b"CELL_TYPES ");
    crate::text::push_int(&mut out, nc);
    out.push(b'\n');
    for b in &mesh.blocks {
        let t = crate::vtk::vtk_type_of(b.kind) as i32;
        if binary {
            for _ in 0..b.len() {
                out.extend_from_slice(&t.to_be_bytes());
            }
        } else {
            for _ in 0..b.len() {
                crate::text::push_int(&mut out, t);
                out.push(b'\n');
            }
        }
    }
    if binary {
        out.push(b'\n');
    }

    // Tag names: meshio's `field_data` layout, one `[tag, dim]` array per name, as
    // dataset field data. After CELL_TYPES rather than right after DATASET: VTK reads
    // it in either place, meshio's reader only here (after DATASET it files the arrays
    // under the dataset's own keywords and drops them).
    if !plan.names.is_empty() {
        out.extend_from_slice(b"FIELD FieldData ");
        crate::text::push_int(&mut out, plan.names.len());
        out.push(b'\n');
        for &(name, tag, dim) in &plan.names {
            encode_name(&mut out, name);
            out.extend_from_slice(b" 1 2 int\n");
            if binary {
                put(&mut out, &[tag, dim as i32], i32::to_be_bytes);
            } else {
                crate::text::push_int(&mut out, tag);
                out.push(b' ');
                crate::text::push_int(&mut out, dim);
            }
            out.push(b'\n');
        }
    }

    // Cell data: the tags and the cell arrays, all as field arrays (as VTK writes
    // arrays that are not the active attributes).
    out.extend_from_slice(b"CELL_DATA ");
    crate::text::push_int(&mut out, nc);
    out.extend_from_slice(b"\nFIELD FieldData ");
    crate::text::push_int(&mut out, 2 + plan.cell_arrays.len());
    out.push(b'\n');
    for (name, tags) in [(PHYSICAL, &plan.physical), (GEOMETRICAL, &plan.geometrical)] {
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(b" 1 ");
        crate::text::push_int(&mut out, nc);
        out.extend_from_slice(b" int\n");
        write_ints(&mut out, tags, binary);
    }
    for (name, a) in &plan.cell_arrays {
        write_field_array(&mut out, name, a, binary);
    }

    // Point data: the active tensor as TENSORS (9 values per point, which ParaView's
    // Tensor Glyph uses), every other array as a field array with its own count.
    if !plan.point_arrays.is_empty() {
        out.extend_from_slice(b"POINT_DATA ");
        crate::text::push_int(&mut out, np);
        out.push(b'\n');
        if let Some(tname) = plan.tensor {
            let a = &plan
                .point_arrays
                .iter()
                .find(|(n, _)| *n == tname)
                .expect("the tensor is one of the point arrays")
                .1;
            out.extend_from_slice(b"TENSORS ");
            encode_name(&mut out, tname);
            out.extend_from_slice(b" double\n");
            write_floats(&mut out, &a.values, 9, binary);
        }
        let rest: Vec<_> =
            plan.point_arrays.iter().filter(|(n, _)| Some(*n) != plan.tensor).collect();
        if !rest.is_empty() {
            out.extend_from_slice(b"FIELD FieldData ");
            crate::text::push_int(&mut out, rest.len());
            out.push(b'\n');
            for (name, a) in rest {
                write_field_array(&mut out, name, a, binary);
            }
        }
    }
    let report = std::mem::take(&mut plan.report);
    Ok(Written { main: out, siblings: Vec::new(), report })
}

/// The binary `K i1 .. iK` records (`R = K + 1` big-endian words) of cells of `K`
/// nodes, one stack record a cell appended whole (no zeroing pass over the output).
fn cell_records<const K: usize, const R: usize>(out: &mut Vec<u8>, nodes: &[NodeIndex]) {
    let mut rec = [[0u8; 4]; R];
    rec[0] = (K as i32).to_be_bytes();
    for cell in nodes.chunks_exact(K) {
        for (w, &v) in rec[1..].iter_mut().zip(cell) {
            *w = (v as i32).to_be_bytes();
        }
        out.extend_from_slice(rec.as_flattened());
    }
}

fn write_ints(out: &mut Vec<u8>, v: &[i32], binary: bool) {
    if binary {
        put(out, v, i32::to_be_bytes);
    } else {
        for x in v {
            crate::text::push_int(out, *x);
            out.push(b'\n');
        }
    }
    if binary {
        out.push(b'\n');
    }
}

fn write_floats(out: &mut Vec<u8>, v: &[f64], per_line: usize, binary: bool) {
    if binary {
        put(out, v, f64::to_be_bytes);
        out.push(b'\n');
    } else {
        for item in v.chunks(per_line.max(1)) {
            for (j, &x) in item.iter().enumerate() {
                if j > 0 {
                    out.push(b' ');
                }
                push_num(out, x);
            }
            out.push(b'\n');
        }
    }
}

fn write_field_array(out: &mut Vec<u8>, name: &str, a: &crate::DataArray, binary: bool) {
    encode_name(out, name);
    out.push(b' ');
    crate::text::push_int(out, a.components);
    out.push(b' ');
    crate::text::push_int(out, a.len());
    out.extend_from_slice(b" double\n");
    write_floats(out, &a.values, a.components, binary);
}
