//! The repository's own test data, `data` (see its README): the 23 looming clips with
//! `manifest.csv`, and the three outdoor photographs. Tests, examples and docs read them from
//! here; a missing or malformed file is an error naming it, never a silent skip.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

/// `data` of the repository this crate was built from.
pub fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data")
}

/// The folder of the `.y8` clips and their `manifest.csv`.
pub fn clips_dir() -> PathBuf {
    dir().join("clips")
}

/// A clip's file by name (without `.y8`).
pub fn clip_path(name: &str) -> PathBuf {
    clips_dir().join(format!("{name}.y8"))
}

/// The authors' record of their offline model's fields on the two multi-target clips
/// ([`crate::multi_target::read_authors`]).
pub fn authors_fields_path() -> PathBuf {
    dir().join("authors/multi_target_fields.csv")
}

/// The outdoor photograph `n` (1–3), usable as an arena wall texture.
pub fn photo_path(n: u8) -> PathBuf {
    dir().join(format!("photos/outdoor_{n}.jpg"))
}

/// One line of `manifest.csv`: what a clip shows and what a detector should do with it.
#[derive(Clone, Debug, PartialEq)]
pub struct ClipInfo {
    pub name: String,
    pub frames: usize,
    pub fps: u32,
    /// `basic`, `phases`, `multi` or `real`.
    pub category: String,
    /// The clip contains an approach a looming detector should alert on.
    pub looming: bool,
    /// In words: what the clip shows and what should happen.
    pub expected: String,
}

/// Reads `clips/manifest.csv` (header `name,frames,fps,category,looming,expected`).
pub fn manifest() -> Result<Vec<ClipInfo>> {
    let path = clips_dir().join("manifest.csv");
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("{}: cannot read", path.display()))?;
    parse_manifest(&text).with_context(|| format!("{}", path.display()))
}

/// Parses the manifest's text; every malformed line is an error with its line number.
pub fn parse_manifest(text: &str) -> Result<Vec<ClipInfo>> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    match lines.next() {
        Some((_, h)) if h.trim() == "name,frames,fps,category,looming,expected" => {}
        _ => bail!("the first line must be the header name,frames,fps,category,looming,expected"),
    }
    lines
        .map(|(i, line)| parse_line(line).with_context(|| format!("line {}: {line:?}", i + 1)))
        .collect()
}

fn parse_line(line: &str) -> Result<ClipInfo> {
    // the last column is free text and may hold commas
    let cols: Vec<&str> = line.splitn(6, ',').collect();
    let [name, frames, fps, category, looming, expected] = cols[..] else {
        bail!("expected 6 columns, found {}", cols.len());
    };
    let looming = match looming {
        "yes" => true,
        "no" => false,
        other => bail!("looming must be yes or no, not {other:?}"),
    };
    Ok(ClipInfo {
        name: name.to_owned(),
        frames: frames.parse().context("frames is not a whole number")?,
        fps: fps.parse().context("fps is not a whole number")?,
        category: category.to_owned(),
        looming,
        expected: expected.to_owned(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_is_read_column_by_column_with_commas_in_the_last() {
        let m = parse_manifest(
            "name,frames,fps,category,looming,expected\n\
             a,50,30,basic,yes,grows: detect, then stop\n\nb,1,25,real,no,x\n",
        )
        .unwrap();
        assert_eq!(m.len(), 2);
        assert_eq!(m[0].name, "a");
        assert_eq!((m[0].frames, m[0].fps, m[0].looming), (50, 30, true));
        assert_eq!(m[0].expected, "grows: detect, then stop");
        assert_eq!(
            (m[1].fps, m[1].looming, &*m[1].category),
            (25, false, "real")
        );
    }

    #[test]
    fn malformed_manifests_name_the_line() {
        let head = "name,frames,fps,category,looming,expected\n";
        for (body, msg) in [
            ("a,5,30,basic,maybe,x", "looming must be yes or no"),
            ("a,five,30,basic,yes,x", "frames is not a whole number"),
            ("a,5,30", "expected 6 columns"),
        ] {
            let e = format!(
                "{:#}",
                parse_manifest(&format!("{head}{body}")).unwrap_err()
            );
            assert!(e.contains("line 2") && e.contains(msg), "{e}");
        }
        let e = format!("{:#}", parse_manifest("a,5,30,basic,yes,x").unwrap_err());
        assert!(e.contains("header"), "{e}");
    }

    #[test]
    fn the_repository_holds_every_clip_of_its_manifest_and_the_photographs() {
        let m = manifest().unwrap();
        assert_eq!(m.len(), 23);
        for c in &m {
            let len = std::fs::metadata(clip_path(&c.name))
                .unwrap_or_else(|e| panic!("{}: {e}", c.name))
                .len();
            assert_eq!(len, (c.frames * alvs_tasks::PIXELS) as u64, "{}", c.name);
            assert_eq!(c.fps, 30, "{}", c.name);
        }
        for n in 1..=3 {
            let p = photo_path(n);
            assert!(p.is_file(), "{}", p.display());
        }
    }
}
