//! Writing a figure like every other output file of the project: drawn into memory, encoded as
//! PNG, then written atomically by `preflight::save` (a temporary file beside it, synced, renamed
//! over it), so a kill or a full disk leaves the previous figure whole, never a truncated one that
//! looks whole; a symbolic link of that name is replaced, not written through; an error names the
//! file.

use anyhow::{Context, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::io::{self, Write};
use std::path::Path;

/// Draws a figure of `size` [px] with `draw` into an RGB buffer (every pixel black to start
/// with, as plotters' own file backend) and writes it as the PNG file `path`, atomically (see the
/// module). Errors, of the drawing or of the write, name `path`.
pub fn figure(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<BitMapBackend, Shift>) -> Result<()>,
) -> Result<()> {
    let mut rgb = vec![0; 3 * size.0 as usize * size.1 as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        draw(&root).with_context(|| format!("drawing {}", path.display()))?;
        root.present()
            .with_context(|| format!("drawing {}", path.display()))?;
    }
    // `atomically` names the file in most of its errors, but not all: one in removing a stale
    // temporary file (as when the folder is a file) names that temporary file instead
    preflight::save::atomically(path, |w| encode(w, &rgb, size))
        .with_context(|| format!("writing {}", path.display()))
}

/// Encodes the 8-bit RGB pixels `rgb` (row by row, `size` = (width, height) [px]) as PNG into
/// `w`, with the compression and filters of plotters' own file backend (through the `image`
/// crate). An error of `w` comes back as it was, of the same kind.
fn encode(w: impl Write, rgb: &[u8], size: (u32, u32)) -> io::Result<()> {
    let as_io = |e: png::EncodingError| match e {
        png::EncodingError::IoError(e) => e,
        e => io::Error::other(e),
    };
    let mut encoder = png::Encoder::new(w, size.0, size.1);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Default);
    encoder.set_filter(png::FilterType::Sub);
    encoder.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
    let mut writer = encoder.write_header().map_err(as_io)?;
    writer.write_image_data(rgb).map_err(as_io)?;
    writer.finish().map_err(as_io)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("compare-plot-file-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// A picture whose PNG does not compress to almost nothing: pseudo-random pixels.
    fn picture(root: &DrawingArea<BitMapBackend, Shift>) -> Result<()> {
        let mut x: u32 = 12345;
        for i in 0..200 {
            for j in 0..150 {
                x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                let [r, g, b, _] = x.to_le_bytes();
                root.draw_pixel((i, j), &RGBColor(r, g, b))?;
            }
        }
        Ok(())
    }

    /// A write that fails on the way (a full disk: the encoder's writer fails after 2 KiB) is an
    /// error of the same kind, so `atomically` keeps the previous file whole, leaves no temporary
    /// file and names the file.
    #[test]
    fn a_write_failing_half_way_keeps_the_previous_figure() {
        struct Full<W>(W, usize);
        impl<W: Write> Write for Full<W> {
            fn write(&mut self, b: &[u8]) -> io::Result<usize> {
                if self.1 == 0 {
                    return Err(io::Error::new(
                        io::ErrorKind::StorageFull,
                        "no space left on device",
                    ));
                }
                let n = self.0.write(&b[..b.len().min(self.1)])?;
                self.1 -= n;
                Ok(n)
            }
            fn flush(&mut self) -> io::Result<()> {
                self.0.flush()
            }
        }
        let dir = scratch("full");
        let path = dir.join("fig.png");
        figure(&path, (200, 150), picture).unwrap();
        let before = std::fs::read(&path).unwrap();
        assert!(before.len() > 4096, "{} bytes", before.len());
        let size = (200, 150);
        let mut rgb = vec![0; 3 * 200 * 150];
        picture(&BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area()).unwrap();
        let e = preflight::save::atomically(&path, |w| encode(Full(w, 2048), &rgb, size)).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::StorageFull);
        assert!(e.to_string().contains(&path.display().to_string()), "{e}");
        assert!(
            std::fs::read(&path).unwrap() == before,
            "the previous figure changed"
        );
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "a temporary file left"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The file decodes to the very pixels drawn, at the size drawn.
    #[test]
    fn the_file_holds_the_pixels_drawn() {
        let dir = scratch("pixels");
        let path = dir.join("fig.png");
        figure(&path, (200, 150), picture).unwrap();
        let mut rgb = vec![0; 3 * 200 * 150];
        picture(&BitMapBackend::with_buffer(&mut rgb, (200, 150)).into_drawing_area()).unwrap();
        let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
        let mut reader = png::Decoder::new(file).read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!(
            (info.width, info.height, info.color_type),
            (200, 150, png::ColorType::Rgb)
        );
        assert!(buf == rgb, "the pixels differ");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// An error while drawing names the file, and nothing is written.
    #[test]
    fn a_drawing_error_names_the_file() {
        let dir = scratch("draw");
        let path = dir.join("fig.png");
        let e = figure(&path, (20, 10), |_| Err(anyhow::anyhow!("no data"))).unwrap_err();
        let e = format!("{e:#}");
        assert!(
            e.contains(&path.display().to_string()) && e.contains("no data"),
            "{e}"
        );
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
