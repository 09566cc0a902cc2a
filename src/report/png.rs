//! SVG to PNG through resvg (usvg parses, tiny-skia rasterises, the `png` crate encodes):
//! the same renderer for every picture, so a PNG shows exactly what the SVG says.
//!
//! Text needs a font. The system's fonts are loaded (fontdb); the SVG asks for DejaVu
//! Sans, Liberation Sans, Arial or Helvetica, then the generic sans-serif, which is
//! pointed at the first of those installed, else at any installed family. With no font
//! at all the PNG is drawn without its text, and the notes say so.

use resvg::{tiny_skia, usvg};

/// Families tried, in order, for the generic sans-serif.
const PREFERRED: [&str; 4] = ["DejaVu Sans", "Liberation Sans", "Arial", "Helvetica"];

/// Why an SVG could not become a PNG.
#[derive(Debug, thiserror::Error)]
pub enum PngError {
    /// The SVG did not parse (a bug of the writer: the report always writes valid SVG).
    #[error("the report's SVG did not parse: {0}")]
    Parse(String),
    /// The picture has no area or is too large for memory.
    #[error("cannot make a {0} x {1} pixel image")]
    Size(u32, u32),
    /// Encoding failed.
    #[error("PNG encoding failed: {0}")]
    Encode(String),
}

/// A rasterised picture.
#[derive(Debug, Clone)]
pub struct Png {
    /// The PNG file's bytes.
    pub bytes: Vec<u8>,
    /// Things the caller should tell the user (e.g. no font found).
    pub notes: Vec<String>,
}

/// How the PNG is encoded.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PngOptions {
    /// Quantise to a palette of 256 colours (NeuQuant) and write an indexed PNG: about a
    /// third of the size of true colour, for pictures to commit or attach.
    pub palette: bool,
}

/// Rasterises `svg` at its own pixel size.
pub fn rasterise(svg: &str, options: &PngOptions) -> Result<Png, PngError> {
    let mut opt = usvg::Options::default();
    let mut notes = Vec::new();
    {
        let db = opt.fontdb_mut();
        db.load_system_fonts();
        let mut families: Vec<String> =
            db.faces().flat_map(|f| f.families.iter().map(|(n, _)| n.clone())).collect();
        families.sort();
        families.dedup();
        let chosen = PREFERRED
            .iter()
            .map(|s| s.to_string())
            .find(|p| families.contains(p))
            .or_else(|| families.first().cloned());
        match chosen {
            Some(f) => {
                db.set_sans_serif_family(f.clone());
                opt.font_family = f;
            }
            None => notes.push("no font is installed (fontconfig found none): the PNG is drawn without its text; the SVG has it".to_string()),
        }
    }
    let tree = usvg::Tree::from_str(svg, &opt).map_err(|e| PngError::Parse(e.to_string()))?;
    let size = tree.size().to_int_size();
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height())
        .ok_or(PngError::Size(size.width(), size.height()))?;
    resvg::render(&tree, tiny_skia::Transform::identity(), &mut pixmap.as_mut());
    let bytes = if options.palette { encode_indexed(&pixmap) } else { encode(&pixmap) }
        .map_err(|e| PngError::Encode(e.to_string()))?;
    Ok(Png { bytes, notes })
}

/// Encodes the pixmap with a palette of 256 colours that NeuQuant learns from it (its
/// sampling factor 1: every pixel is looked at, deterministic).
fn encode_indexed(pixmap: &tiny_skia::Pixmap) -> Result<Vec<u8>, png::EncodingError> {
    let mut rgba = Vec::with_capacity(pixmap.pixels().len() * 4);
    for p in pixmap.pixels() {
        let c = p.demultiply();
        rgba.extend_from_slice(&[c.red(), c.green(), c.blue(), c.alpha()]);
    }
    let nq = color_quant::NeuQuant::new(1, 256, &rgba);
    let indices: Vec<u8> = rgba.chunks_exact(4).map(|px| nq.index_of(px) as u8).collect();
    let map = nq.color_map_rgba();
    let rgb: Vec<u8> = map.chunks_exact(4).flat_map(|c| [c[0], c[1], c[2]]).collect();
    let alpha: Vec<u8> = map.chunks_exact(4).map(|c| c[3]).collect();
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, pixmap.width(), pixmap.height());
        enc.set_color(png::ColorType::Indexed);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_palette(rgb);
        if alpha.iter().any(|&a| a != 255) {
            enc.set_trns(alpha);
        }
        enc.set_compression(png::Compression::Best);
        enc.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
        let mut w = enc.write_header()?;
        w.write_image_data(&indices)?;
    }
    Ok(out)
}

/// Encodes the pixmap as 8-bit RGB (RGBA only where some pixel is not opaque: the report
/// paints a white background, so in practice never) with the strongest compression and
/// adaptive filters: about a third of tiny-skia's default RGBA encoding for these
/// pictures of thin lines on flat fills.
fn encode(pixmap: &tiny_skia::Pixmap) -> Result<Vec<u8>, png::EncodingError> {
    let opaque = pixmap.pixels().iter().all(|p| p.alpha() == 255);
    let mut data = Vec::with_capacity(pixmap.pixels().len() * if opaque { 3 } else { 4 });
    for p in pixmap.pixels() {
        let c = p.demultiply();
        data.extend_from_slice(&[c.red(), c.green(), c.blue()]);
        if !opaque {
            data.push(c.alpha());
        }
    }
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, pixmap.width(), pixmap.height());
        enc.set_color(if opaque { png::ColorType::Rgb } else { png::ColorType::Rgba });
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Best);
        enc.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
        let mut w = enc.write_header()?;
        w.write_image_data(&data)?;
    }
    Ok(out)
}
