//! Reading recorded video: raw Y8 clips (99x72 frames, row-major, no header) and directories of
//! binary PGM (P5) frames. Every malformed input is a clear error, never a panic.

use std::path::{Path, PathBuf};

use alvs_tasks::frame::{check_dimensions, Frame};
use alvs_tasks::{HEIGHT, PIXELS, WIDTH};
use anyhow::{bail, Context, Result};

/// Loads a clip: a directory of `.pgm` frames (sorted by name) or a raw Y8 file of
/// `width` x `height` frames.
pub fn load(path: &Path, width: usize, height: usize) -> Result<Vec<Frame>> {
    check_dimensions(width, height).map_err(|e| anyhow::anyhow!("{e}"))?;
    if !path.exists() {
        bail!("{}: no such file or directory", path.display());
    }
    if path.is_dir() {
        load_pgm_dir(path)
    } else {
        let bytes =
            std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
        y8_frames(&bytes).with_context(|| format!("{}", path.display()))
    }
}

/// Splits raw Y8 bytes into frames.
pub fn y8_frames(bytes: &[u8]) -> Result<Vec<Frame>> {
    if bytes.is_empty() {
        bail!("empty clip: no frames");
    }
    if !bytes.len().is_multiple_of(PIXELS) {
        bail!(
            "size {} bytes is not a multiple of a {WIDTH}x{HEIGHT} frame ({PIXELS} bytes)",
            bytes.len()
        );
    }
    Ok(bytes
        .chunks_exact(PIXELS)
        .map(|c| {
            let mut f = [0u8; PIXELS];
            f.copy_from_slice(c);
            f
        })
        .collect())
}

fn load_pgm_dir(dir: &Path) -> Result<Vec<Frame>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("{}: cannot list", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("pgm")))
        .collect();
    files.sort();
    if files.is_empty() {
        bail!("{}: no .pgm frames in this directory", dir.display());
    }
    files
        .iter()
        .map(|p| {
            let bytes =
                std::fs::read(p).with_context(|| format!("{}: cannot read", p.display()))?;
            parse_pgm(&bytes).with_context(|| format!("{}", p.display()))
        })
        .collect()
}

/// Parses one binary PGM (P5, maxval ≤ 255) of exactly 99x72 pixels.
pub fn parse_pgm(bytes: &[u8]) -> Result<Frame> {
    let mut pos = 0;
    let mut fields = [0usize; 3];
    if bytes.get(..2) != Some(b"P5") {
        bail!("not a binary PGM (expected magic P5)");
    }
    pos += 2;
    for field in &mut fields {
        // skip whitespace and comments
        loop {
            match bytes.get(pos) {
                Some(b) if b.is_ascii_whitespace() => pos += 1,
                Some(b'#') => {
                    while bytes.get(pos).is_some_and(|&b| b != b'\n') {
                        pos += 1;
                    }
                }
                _ => break,
            }
        }
        let start = pos;
        while bytes.get(pos).is_some_and(u8::is_ascii_digit) {
            pos += 1;
        }
        *field = std::str::from_utf8(&bytes[start..pos])
            .ok()
            .and_then(|s| s.parse().ok())
            .context("bad PGM header")?;
    }
    let [w, h, maxval] = fields;
    if maxval == 0 || maxval > 255 {
        bail!("PGM maxval {maxval} unsupported (8-bit grey only)");
    }
    check_dimensions(w, h).map_err(|e| anyhow::anyhow!("{e}"))?;
    pos += 1; // the single whitespace after maxval
    let data = bytes.get(pos..).unwrap_or_default();
    if data.len() != PIXELS {
        bail!("PGM pixel data is {} bytes, expected {PIXELS}", data.len());
    }
    let mut f = [0u8; PIXELS];
    for (o, &v) in f.iter_mut().zip(data) {
        if usize::from(v) > maxval {
            bail!("PGM pixel value {v} exceeds maxval {maxval}");
        }
        // rescale to 0..=255, rounding to nearest
        *o = ((usize::from(v) * 255 + maxval / 2) / maxval) as u8;
    }
    Ok(f)
}

/// Encodes a frame as binary PGM (for tests and tools).
pub fn to_pgm(frame: &Frame) -> Vec<u8> {
    let mut v = format!("P5\n{WIDTH} {HEIGHT}\n255\n").into_bytes();
    v.extend_from_slice(frame);
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn y8_sizes_are_checked() {
        assert_eq!(y8_frames(&vec![7; 2 * PIXELS]).unwrap().len(), 2);
        let e = y8_frames(&vec![0; PIXELS + 3]).unwrap_err().to_string();
        assert!(e.contains("not a multiple"), "{e}");
        assert!(y8_frames(&[]).is_err());
    }

    #[test]
    fn pgm_round_trip_and_errors() {
        let mut f = [0u8; PIXELS];
        f[5] = 200;
        assert_eq!(parse_pgm(&to_pgm(&f)).unwrap(), f);
        let commented = [b"P5\n# made by hand\n99 72\n255\n".as_slice(), &f].concat();
        assert_eq!(parse_pgm(&commented).unwrap(), f);
        assert!(parse_pgm(b"P2\n99 72\n255\n").is_err());
        // a 4-bit PGM is rescaled to 8 bits; values above maxval are refused
        let mut g = [0u8; PIXELS];
        g[0] = 15;
        g[1] = 8;
        let four_bit = [b"P5\n99 72\n15\n".as_slice(), &g].concat();
        let h = parse_pgm(&four_bit).unwrap();
        assert_eq!((h[0], h[1], h[2]), (255, 136, 0));
        g[2] = 16;
        let over = [b"P5\n99 72\n15\n".as_slice(), &g].concat();
        assert!(format!("{:#}", parse_pgm(&over).unwrap_err()).contains("exceeds maxval"));
        let wrong = [b"P5\n100 72\n255\n".as_slice(), &[0; 7200]].concat();
        assert!(format!("{:#}", parse_pgm(&wrong).unwrap_err()).contains("99x72"));
        let short = [b"P5\n99 72\n255\n".as_slice(), &[0; 10]].concat();
        assert!(parse_pgm(&short).is_err());
    }

    #[test]
    fn other_dimensions_are_refused() {
        let e = load(Path::new("/nonexistent"), 160, 120)
            .unwrap_err()
            .to_string();
        assert!(e.contains("99x72"), "{e}");
    }
}
