//! Legacy `.vtk`: `DATASET UNSTRUCTURED_GRID`, ASCII or big-endian BINARY, file
//! versions 2.0–4.2 (`CELLS n size`, each cell `k i1 .. ik`) and 5.1 (`CELLS n+1 m`
//! followed by `OFFSETS` and `CONNECTIVITY` arrays, as VTK 9 writes).
//!
//! The file is keyword-driven text; in BINARY files each array follows its header
//! line's newline as raw big-endian values, then a newline. One cursor
//! ([`Tokens`]) reads both: tokens for headers and ASCII values, [`Tokens::seek`] over
//! binary arrays. Errors name the line in ASCII files and the byte offset in binary ones.
//!
//! `read.rs` walks the keywords (the grid's points and cells), `attributes.rs` the data
//! arrays, `datasets.rs` the structured and polygonal datasets, `write.rs` writes.

mod attributes;
mod datasets;
mod read;
mod write;

pub(crate) use read::read;
pub(crate) use write::write;

/// Decodes VTK's `%XX` escapes in legacy names (`vtkDataWriter` writes spaces and
/// other special characters that way).
pub(super) fn decode_name(raw: &[u8]) -> String {
    let mut out = Vec::with_capacity(raw.len());
    let mut i = 0;
    while i < raw.len() {
        if raw[i] == b'%' && i + 2 < raw.len() {
            let h = std::str::from_utf8(&raw[i + 1..i + 3])
                .ok()
                .and_then(|s| u8::from_str_radix(s, 16).ok());
            if let Some(b) = h {
                out.push(b);
                i += 3;
                continue;
            }
        }
        out.push(raw[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Encodes a name for a legacy file as `vtkDataWriter` does: printable ASCII other
/// than space, `"` and `%` as is, every other byte as `%XX`.
pub(super) fn encode_name(out: &mut Vec<u8>, name: &str) {
    const HEX: &[u8; 16] = b"0123456789ABCDEF";
    for &b in name.as_bytes() {
        if b.is_ascii_graphic() && b != b'"' && b != b'%' {
            out.push(b);
        } else {
            out.extend_from_slice(&[b'%', HEX[(b >> 4) as usize], HEX[(b & 15) as usize]]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_through_percent_escapes() {
        let mut out = Vec::new();
        encode_name(&mut out, "far field 100%");
        assert_eq!(out, b"far%20field%20100%25");
        assert_eq!(decode_name(&out), "far field 100%");
        assert_eq!(decode_name(b"a%2"), "a%2");
    }
}
