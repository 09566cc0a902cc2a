//! Writing a `.vtu`: the arrays of the grid in the chosen encoding, zlib blocks
//! deflated on every core, the XML around them.

use super::*;

/// Deflates `data` in independent `BLOCK`-sized blocks, on several threads for large
/// arrays. Level 1: on mesh data it gives files within a few percent of level 6 in a
/// fraction of the time.
pub(super) fn deflate_blocks(data: &[u8]) -> Vec<Vec<u8>> {
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

pub(super) fn push_base64(out: &mut Vec<u8>, data: &[u8]) {
    let start = out.len();
    let n = base64::encoded_len(data.len(), true).unwrap_or(0);
    out.resize(start + n, 0);
    let written = base64::engine::general_purpose::STANDARD
        .encode_slice(data, &mut out[start..])
        .unwrap_or(0);
    out.truncate(start + written);
}

/// Writes a `.vtu` file, or a `.vtp` (PolyData) one when `poly`: the mesh then holds
/// vertices, lines and polygons only, in that order (`vtk::poly_order`).
/// `spare`: memory to write the file into (cleared first), reused rather than fresh.
pub(crate) fn write(
    mesh: &TaggedMesh,
    opts: &WriteOptions,
    poly: bool,
    mut spare: Vec<u8>,
) -> Result<Written> {
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
    // Declared before the writer, which borrows them until the appended data is out:
    // the cell lists, one for an UnstructuredGrid, PolyData's vertices, lines and
    // polygons (with the blocks of each, and their offsets).
    let lists: Vec<(&str, &[crate::CellBlock], Vec<u64>)> = if poly {
        let mut lists = Vec::new();
        let mut start = 0;
        for (name, dim) in [("Verts", 0), ("Lines", 1), ("Polys", 2)] {
            let end =
                start + mesh.blocks[start..].iter().take_while(|b| b.kind.dim() == dim).count();
            let blocks = &mesh.blocks[start..end];
            lists.push((name, blocks, block_offsets(blocks)));
            start = end;
        }
        lists
    } else {
        vec![("Cells", &mesh.blocks[..], offsets(mesh))]
    };
    spare.clear();
    spare.reserve(cap);
    let mut w =
        Writer { out: spare, enc, compress, app: Vec::new(), app_len: 0, deferred: Vec::new() };

    let o = &mut w.out;
    let dataset: &[u8] = if poly { b"PolyData" } else { b"UnstructuredGrid" };
    o.extend_from_slice(b"<?xml version=\"1.0\"?>\n<VTKFile type=\"");
    o.extend_from_slice(dataset);
    o.extend_from_slice(b"\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"");
    if compress {
        o.extend_from_slice(b" compressor=\"vtkZLibDataCompressor\"");
    }
    o.extend_from_slice(b">\n  <");
    o.extend_from_slice(dataset);
    o.extend_from_slice(b">\n");
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
    if poly {
        for ((_, blocks, _), attr) in lists.iter().zip([
            &b"\" NumberOfVerts=\""[..],
            b"\" NumberOfLines=\"",
            b"\" NumberOfPolys=\"",
        ]) {
            o.extend_from_slice(attr);
            crate::text::push_int(o, blocks.iter().map(crate::CellBlock::len).sum::<usize>());
        }
        o.extend_from_slice(b"\" NumberOfStrips=\"0\">\n");
    } else {
        o.extend_from_slice(b"\" NumberOfCells=\"");
        crate::text::push_int(o, nc);
        o.extend_from_slice(b"\">\n");
    }

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
    w.out.extend_from_slice(b"      </Points>\n");
    for (name, blocks, offs) in &lists {
        let (blocks, offs): (&[crate::CellBlock], &[u64]) = (blocks, offs);
        let n = offs.len() - 1;
        let nconn = offs[n] as usize;
        w.out.extend_from_slice(b"      <");
        w.out.extend_from_slice(name.as_bytes());
        w.out.extend_from_slice(b">\n");
        w.array(
            "Int64",
            "connectivity",
            1,
            nconn * 8,
            move |o| {
                for b in blocks {
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
            move |o| {
                o.reserve(nconn * 8);
                for b in blocks {
                    put(o, &b.nodes, |v| (v as i64).to_le_bytes());
                }
            },
        );
        w.array(
            "Int64",
            "offsets",
            1,
            n * 8,
            move |o| {
                for &v in &offs[1..] {
                    o.extend_from_slice(b"          ");
                    crate::text::push_int(o, v);
                    o.push(b'\n');
                }
            },
            move |o| put(o, &offs[1..], |v| (v as i64).to_le_bytes()),
        );
        if !poly {
            w.array(
                "UInt8",
                "types",
                1,
                n,
                move |o| {
                    for b in blocks {
                        let t = crate::vtk::vtk_type_of(b.kind);
                        for _ in 0..b.len() {
                            o.extend_from_slice(b"          ");
                            crate::text::push_int(o, t);
                            o.push(b'\n');
                        }
                    }
                },
                move |o| {
                    for b in blocks {
                        o.extend(std::iter::repeat(crate::vtk::vtk_type_of(b.kind)).take(b.len()));
                    }
                },
            );
        }
        w.out.extend_from_slice(b"      </");
        w.out.extend_from_slice(name.as_bytes());
        w.out.extend_from_slice(b">\n");
    }
    w.out.extend_from_slice(b"    </Piece>\n  </");
    w.out.extend_from_slice(dataset);
    w.out.extend_from_slice(b">\n");
    if enc == VtuEncoding::Appended {
        w.finish_appended();
    }
    w.out.extend_from_slice(b"</VTKFile>\n");
    let report = std::mem::take(&mut plan.report);
    Ok(Written { main: w.out, siblings: Vec::new(), report })
}

/// Offsets (`ncells + 1`, from 0) of the cells of `blocks`.
fn block_offsets(blocks: &[crate::CellBlock]) -> Vec<u64> {
    let mut offs = vec![0u64];
    let mut o = 0u64;
    for b in blocks {
        let k = b.kind.nodes_per_cell() as u64;
        offs.extend((0..b.len()).map(|_| {
            o += k;
            o
        }));
    }
    offs
}
