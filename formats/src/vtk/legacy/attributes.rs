//! The data arrays of a legacy file: `FIELD` arrays and the attributes (`SCALARS`,
//! `VECTORS`, `TENSORS`...) of the point and cell data sections.

use crate::text::{check_count, show};
use crate::{ErrorKind, Result};

use super::decode_name;
use super::read::{Reader, Section};
use crate::vtk::{tag_slot, Scalar};

impl<'a> Reader<'a> {
    pub(super) fn read_field(&mut self) -> Result<()> {
        let _field_name = self.word("a field name")?;
        let k = self.count("field arrays", 8, 8)?;
        let mut i = 0;
        while i < k {
            let at = self.here();
            let raw = self.word("an array name")?;
            if raw.eq_ignore_ascii_case(b"METADATA") {
                self.skip_metadata();
                continue;
            }
            i += 1;
            if raw == b"NULL_ARRAY" {
                continue;
            }
            let name = decode_name(raw);
            let comps = self.usize("a component count")?;
            let tuples = self.usize("a tuple count")?;
            let tyw = self.word("a data type")?;
            let Some(ty) = Scalar::from_legacy(tyw) else {
                return Err(self.err(ErrorKind::Unsupported(format!(
                    "field array `{name}` of type {}: smartmesh reads numeric arrays",
                    show(tyw)
                ))));
            };
            if comps == 0 {
                return Err(self.err(ErrorKind::Expected {
                    expected: format!("at least one component in `{name}`"),
                    found: "0".into(),
                }));
            }
            match self.section {
                Section::Point | Section::Cell if tuples != self.items => {
                    return Err(self.err(ErrorKind::Inconsistent(format!(
                        "field array `{name}` has {tuples} tuples in a section of {}",
                        self.items
                    ))));
                }
                _ => {}
            }
            let n = comps
                .checked_mul(tuples)
                .ok_or_else(|| self.err(ErrorKind::Inconsistent("array too large".into())))?;
            check_count(
                n,
                self.t.remaining().len(),
                if self.binary { ty.size() } else { 2 },
                &name,
            )
            .map_err(|k| self.err(k))?;
            self.end_header();
            // A binary 32-bit cell tag array (how smartmesh and Gmsh write them) goes
            // straight into tags: every i32 is a tag, so there is nothing to check.
            if self.binary
                && self.section == Section::Cell
                && comps == 1
                && ty == Scalar::I32
                && tag_slot(&name).is_some()
            {
                let bytes = self.binary_bytes(n, ty, "cell tags")?;
                let tags = bytes
                    .chunks_exact(4)
                    .map(|c| i32::from_be_bytes(c.try_into().expect("4 bytes")))
                    .collect();
                self.grid.cell_tags.push((name, tags, at));
                continue;
            }
            self.float_array(name, comps, n, ty, at)?;
        }
        Ok(())
    }

    pub(super) fn read_attribute(&mut self, key: &'a [u8]) -> Result<()> {
        const KEYWORDS: [&[u8]; 11] = [
            b"SCALARS",
            b"VECTORS",
            b"NORMALS",
            b"TENSORS",
            b"TENSORS6",
            b"TEXTURE_COORDINATES",
            b"GLOBAL_IDS",
            b"PEDIGREE_IDS",
            b"COLOR_SCALARS",
            b"LOOKUP_TABLE",
            b"FIELD",
        ];
        let k = key.to_ascii_uppercase();
        if KEYWORDS.contains(&k.as_slice()) {
            self.need_section(key)?;
        }
        let at = self.here();
        match k.as_slice() {
            b"SCALARS" => {
                let name = decode_name(self.word("an array name")?);
                let ty = self.scalar()?;
                let comps = if self.t.at_line_end() { 1 } else { self.usize("a component count")? };
                if !(1..=4).contains(&comps) {
                    return Err(self.err(ErrorKind::Expected { expected: "1 to 4 components".into(), found: comps.to_string() }));
                }
                if self.take_word(b"LOOKUP_TABLE") {
                    self.word("a lookup table name")?;
                }
                self.end_header();
                self.attribute(name, comps, ty, at)
            }
            b"VECTORS" | b"NORMALS" => {
                let name = decode_name(self.word("an array name")?);
                let ty = self.scalar()?;
                self.end_header();
                self.attribute(name, 3, ty, at)
            }
            b"TENSORS" | b"TENSORS6" => {
                let name = decode_name(self.word("an array name")?);
                let ty = self.scalar()?;
                self.end_header();
                if k == b"TENSORS" {
                    self.attribute(name, 9, ty, at)
                } else {
                    // XX YY ZZ XY YZ XZ, widened to the row-major 9 components that
                    // tensors travel as.
                    let n = self.items;
                    check_count(n, self.t.remaining().len(), 6 * if self.binary { ty.size() } else { 2 }, &name).map_err(|k| self.err(k))?;
                    let mut six = Vec::new();
                    self.data_floats(6 * n, ty, &format!("value of `{name}`"), &mut six)?;
                    let values = six.chunks_exact(6).flat_map(|s| [s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2]]).collect();
                    self.push_array(name, 9, values, at);
                    Ok(())
                }
            }
            b"TEXTURE_COORDINATES" => {
                let name = decode_name(self.word("an array name")?);
                let dim = self.usize("a dimension")?;
                if !(1..=3).contains(&dim) {
                    return Err(self.err(ErrorKind::Expected { expected: "1 to 3 texture dimensions".into(), found: dim.to_string() }));
                }
                let ty = self.scalar()?;
                self.end_header();
                self.attribute(name, dim, ty, at)
            }
            b"GLOBAL_IDS" | b"PEDIGREE_IDS" => {
                let name = decode_name(self.word("an array name")?);
                let ty = self.scalar()?;
                self.end_header();
                self.attribute(name, 1, ty, at)
            }
            b"COLOR_SCALARS" => {
                // Floats in [0, 1] in ASCII files, unsigned chars in binary ones.
                let name = decode_name(self.word("an array name")?);
                let comps = self.usize("a component count")?;
                if !(1..=4).contains(&comps) {
                    return Err(self.err(ErrorKind::Expected { expected: "1 to 4 components".into(), found: comps.to_string() }));
                }
                self.end_header();
                if self.binary {
                    self.attribute(name, comps, Scalar::U8, at)?;
                    let last = match self.section {
                        Section::Point => self.grid.point_arrays.last_mut(),
                        _ => self.grid.cell_arrays.last_mut(),
                    };
                    if let Some(a) = last {
                        a.values.iter_mut().for_each(|v| *v /= 255.0);
                    }
                    Ok(())
                } else {
                    self.attribute(name, comps, Scalar::F64, at)
                }
            }
            b"LOOKUP_TABLE" => {
                // A colour table for SCALARS: not mesh data, skipped.
                self.word("a lookup table name")?;
                let n = self.count("lookup table entries", 8, 4)?;
                self.end_header();
                let mut skip = Vec::new();
                if self.binary {
                    self.binary_bytes(4 * n, Scalar::U8, "lookup table")?;
                } else {
                    self.floats(4 * n, Scalar::F64, "lookup table value", &mut skip)?;
                }
                Ok(())
            }
            _ => Err(self.err(ErrorKind::Expected {
                expected: "a VTK legacy keyword (POINTS, CELLS, CELL_TYPES, POINT_DATA, CELL_DATA, SCALARS, VECTORS, TENSORS, FIELD...)".into(),
                found: show(key),
            })),
        }
    }
}
