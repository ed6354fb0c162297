//! A heightfield from a 16-bit grayscale PNG, read with the png crate: sample `(i, j)` is the
//! pixel in column `i` of row `rows - 1 - j` (the image's top row is the grid's far edge, +y),
//! its height `value * height_scale` metres.

use super::{LevelError, MAX_HEIGHTFIELD_CELLS};
use crate::contact::HeightGrid;

/// Reads a PNG's bytes into a grid of heights (m): `height_scale` metres per unit.
pub fn read_heightmap_png(
    bytes: &[u8],
    file: &str,
    height_scale: f64,
) -> Result<HeightGrid, LevelError> {
    let bad = |m: String| LevelError::new(file, m);
    let mut decoder =
        png::Decoder::new_with_limits(std::io::Cursor::new(bytes), png::Limits { bytes: 64 << 20 });
    decoder.set_transformations(png::Transformations::IDENTITY);
    let mut reader = decoder
        .read_info()
        .map_err(|e| bad(format!("not a readable PNG: {e}")))?;
    let info = reader.info();
    let (w, h) = (info.width, info.height);
    if info.color_type != png::ColorType::Grayscale || info.bit_depth != png::BitDepth::Sixteen {
        return Err(bad(format!(
            "expected a 16-bit grayscale PNG, got {:?} at {} bits",
            info.color_type, info.bit_depth as u8
        )));
    }
    if w < 2 || h < 2 {
        return Err(bad(format!(
            "expected at least 2 x 2 pixels, got {w} x {h}"
        )));
    }
    let cells = u64::from(w - 1) * u64::from(h - 1);
    if cells > MAX_HEIGHTFIELD_CELLS {
        return Err(bad(format!(
            "{w} x {h} pixels is {cells} cells, more than the {MAX_HEIGHTFIELD_CELLS} a heightfield may have"
        )));
    }
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| bad("the image is too large to decode".into()))?;
    let mut buf = vec![0; size];
    let frame = reader
        .next_frame(&mut buf)
        .map_err(|e| bad(format!("not a readable PNG: {e}")))?;
    let stride = frame.line_size;
    let mut heights = Vec::with_capacity(w as usize * h as usize);
    for j in 0..h as usize {
        let row = &buf[(h as usize - 1 - j) * stride..][..2 * w as usize];
        heights.extend(
            row.chunks_exact(2)
                .map(|b| f64::from(u16::from_be_bytes([b[0], b[1]])) * height_scale),
        );
    }
    Ok(HeightGrid {
        columns: w,
        rows: h,
        heights,
    })
}

/// A 16-bit grayscale PNG of `columns x rows` samples, `value(i, j)` at grid column `i`, row
/// `j` (the inverse of [`read_heightmap_png`]'s layout): for tests, generators and fuzz seeds.
pub fn write_heightmap_png(columns: u32, rows: u32, value: impl Fn(u32, u32) -> u16) -> Vec<u8> {
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, columns, rows);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Sixteen);
    let mut data = Vec::with_capacity(2 * columns as usize * rows as usize);
    for r in 0..rows {
        let j = rows - 1 - r;
        for i in 0..columns {
            data.extend_from_slice(&value(i, j).to_be_bytes());
        }
    }
    let mut writer = enc
        .write_header()
        .expect("a PNG header for a non-empty image writes to memory");
    writer
        .write_image_data(&data)
        .expect("the data has exactly the header's size");
    drop(writer);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_round_trip_with_the_top_row_at_the_far_edge() {
        let png = write_heightmap_png(3, 2, |i, j| (10 * j + i) as u16);
        let g = read_heightmap_png(&png, "h.png", 0.5).unwrap();
        assert_eq!((g.columns, g.rows), (3, 2));
        assert_eq!(g.heights, vec![0.0, 0.5, 1.0, 5.0, 5.5, 6.0]);
    }

    #[test]
    fn an_eight_bit_image_is_refused_naming_what_it_is() {
        let mut out = Vec::new();
        let mut enc = png::Encoder::new(&mut out, 2, 2);
        enc.set_color(png::ColorType::Grayscale);
        enc.set_depth(png::BitDepth::Eight);
        enc.write_header()
            .unwrap()
            .write_image_data(&[0; 4])
            .unwrap();
        let e = read_heightmap_png(&out, "h8.png", 1.0).unwrap_err();
        assert_eq!(
            e.to_string(),
            "h8.png: expected a 16-bit grayscale PNG, got Grayscale at 8 bits"
        );
        let e = read_heightmap_png(b"not a png", "x.png", 1.0).unwrap_err();
        assert!(
            e.to_string().starts_with("x.png: not a readable PNG"),
            "{e}"
        );
    }
}
