//! Where a log comes from: cargo-embed's files (one per tab,
//! `<elf>_<chip>_<unix ms>_channel<tab>.txt`), found from one of them or from their folder, or
//! text on standard input.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

/// A text to read and what to call it in messages.
#[derive(Clone, Debug)]
pub struct Source {
    pub name: String,
    pub text: String,
}

/// `(session, tab)` of a cargo-embed log file's name: everything before `_channel`, and the
/// tab's number.
fn session_of(path: &Path) -> Option<(String, u32)> {
    let name = path.file_name()?.to_str()?;
    let (session, rest) = name.rsplit_once("_channel")?;
    let tab = rest.strip_suffix(".txt")?.parse().ok()?;
    Some((session.to_owned(), tab))
}

/// The session's unix time in ms (the number before `_channel`), to find the newest.
fn started_ms(session: &str) -> u64 {
    session
        .rsplit('_')
        .next()
        .and_then(|t| t.parse().ok())
        .unwrap_or(0)
}

/// The files of one cargo-embed session, in tab order: `path` is one of them (its sibling tabs
/// come too), another text file (read alone), or a folder (its newest session).
pub fn locate(path: &Path) -> Result<Vec<PathBuf>> {
    let meta = std::fs::metadata(path).with_context(|| path.display().to_string())?;
    let (dir, session) = if meta.is_dir() {
        let sessions = tabs_in(path)?;
        let Some(newest) = sessions
            .iter()
            .map(|(_, (s, _))| s)
            .max_by_key(|s| (started_ms(s), s.as_str()))
        else {
            bail!(
                "{}: no cargo-embed log in this folder (files named …_channel<N>.txt)",
                path.display()
            );
        };
        (path.to_path_buf(), newest.clone())
    } else {
        match session_of(path) {
            Some((s, _)) => (
                path.parent()
                    .filter(|p| !p.as_os_str().is_empty())
                    .unwrap_or(Path::new("."))
                    .to_path_buf(),
                s,
            ),
            None => return Ok(vec![path.to_path_buf()]),
        }
    };
    let mut files: Vec<(u32, PathBuf)> = tabs_in(&dir)?
        .into_iter()
        .filter(|(_, (s, _))| *s == session)
        .map(|(p, (_, tab))| (tab, p))
        .collect();
    files.sort();
    Ok(files.into_iter().map(|(_, p)| p).collect())
}

/// The cargo-embed log files in `dir` with their session and tab.
fn tabs_in(dir: &Path) -> Result<Vec<(PathBuf, (String, u32))>> {
    let entries = std::fs::read_dir(dir).with_context(|| dir.display().to_string())?;
    Ok(entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter_map(|p| session_of(&p).map(|s| (p, s)))
        .collect())
}

/// Reads the files (bytes that are not UTF-8 become U+FFFD, and their lines do not parse).
pub fn read_files(files: &[PathBuf]) -> Result<Vec<Source>> {
    files
        .iter()
        .map(|p| {
            let bytes = std::fs::read(p).with_context(|| p.display().to_string())?;
            Ok(Source {
                name: p.display().to_string(),
                text: String::from_utf8_lossy(&bytes).into_owned(),
            })
        })
        .collect()
}

/// Reads standard input to its end.
pub fn read_stdin() -> Result<Source> {
    use std::io::Read;
    let mut bytes = Vec::new();
    std::io::stdin()
        .read_to_end(&mut bytes)
        .context("standard input")?;
    Ok(Source {
        name: "standard input".into(),
        text: String::from_utf8_lossy(&bytes).into_owned(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sessions_from_a_file_or_a_folder() {
        let dir = std::env::temp_dir().join(format!("alvs_log_source_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let old = "alvs-firmware_STM32F427VITx_1700000000000";
        let new = "alvs-firmware_STM32F427VITx_1800000000000";
        for name in [
            format!("{old}_channel0.txt"),
            format!("{old}_channel1.txt"),
            format!("{new}_channel1.txt"),
            format!("{new}_channel0.txt"),
            "notes.txt".into(),
        ] {
            std::fs::write(dir.join(name), "x").unwrap();
        }
        let names = |v: Vec<PathBuf>| -> Vec<String> {
            v.iter()
                .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
                .collect()
        };
        assert_eq!(
            names(locate(&dir).unwrap()),
            [format!("{new}_channel0.txt"), format!("{new}_channel1.txt")]
        );
        assert_eq!(
            names(locate(&dir.join(format!("{old}_channel1.txt"))).unwrap()),
            [format!("{old}_channel0.txt"), format!("{old}_channel1.txt")]
        );
        assert_eq!(
            names(locate(&dir.join("notes.txt")).unwrap()),
            ["notes.txt"]
        );
        let empty = dir.join("empty");
        std::fs::create_dir_all(&empty).unwrap();
        let e = locate(&empty).unwrap_err().to_string();
        assert!(e.ends_with("no cargo-embed log in this folder (files named …_channel<N>.txt)"));
        assert!(locate(&dir.join("missing")).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
