//! Pieces shared by the parsers of the firmware's RTT lines (the telemetry record, the 1 Hz
//! summary, the boot self-test's `bench:` lines): canonical decimals, `key=value` tokens, and
//! the error of the lines that have no error type of their own. Integer-only, never a panic:
//! the host reads whatever a probe saved.

use core::fmt;

/// A canonical unsigned decimal: digits only, no sign, no leading zero, no overflow.
pub fn canonical_u32(s: &str) -> Option<u32> {
    if s.is_empty() || (s.len() > 1 && s.starts_with('0')) {
        return None;
    }
    s.bytes().try_fold(0u32, |acc, c| {
        if !c.is_ascii_digit() {
            return None;
        }
        acc.checked_mul(10)?.checked_add(u32::from(c - b'0'))
    })
}

/// The next token's value if the token is `key` followed by the value (e.g. `key = "sum="`).
pub fn tagged<'a>(tokens: &mut impl Iterator<Item = &'a str>, key: &str) -> Option<&'a str> {
    tokens.next()?.strip_prefix(key)
}

/// The line without its terminator (`"\n"` or `"\r\n"`, optional).
pub fn bare(s: &str) -> &str {
    s.strip_suffix("\r\n")
        .or_else(|| s.strip_suffix('\n'))
        .unwrap_or(s)
}

/// Why a line is not the summary or `bench:` line it was read as.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineError {
    /// The line does not start as that kind of line does.
    OtherLine,
    /// The named field is absent, out of order or misspelt.
    Missing(&'static str),
    /// The named field's value is not a canonical decimal of the expected shape.
    BadNumber(&'static str),
    /// The named value disagrees with the others (a total that is not the sum of its parts).
    Inconsistent(&'static str),
    /// Something follows the last field.
    TrailingData,
}

impl fmt::Display for LineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            LineError::OtherLine => f.write_str("another kind of line"),
            LineError::Missing(field) => write!(f, "missing field `{field}`"),
            LineError::BadNumber(field) => write!(f, "malformed number in `{field}`"),
            LineError::Inconsistent(field) => write!(f, "`{field}` disagrees with the rest"),
            LineError::TrailingData => f.write_str("unexpected data after the last field"),
        }
    }
}

impl core::error::Error for LineError {}

/// The next token as a canonical decimal, `field` naming it in the error.
pub fn number<'a>(
    tokens: &mut impl Iterator<Item = &'a str>,
    field: &'static str,
) -> Result<u32, LineError> {
    let t = tokens.next().ok_or(LineError::Missing(field))?;
    canonical_u32(t).ok_or(LineError::BadNumber(field))
}

/// The next token, which must be exactly `word` (`field` names it in the error).
pub fn word<'a>(
    tokens: &mut impl Iterator<Item = &'a str>,
    word: &str,
    field: &'static str,
) -> Result<(), LineError> {
    match tokens.next() {
        Some(t) if t == word => Ok(()),
        _ => Err(LineError::Missing(field)),
    }
}

/// The end of the line: no token left.
pub fn end<'a>(tokens: &mut impl Iterator<Item = &'a str>) -> Result<(), LineError> {
    match tokens.next() {
        None => Ok(()),
        Some(_) => Err(LineError::TrailingData),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn canonical_decimals_only() {
        assert_eq!(canonical_u32("0"), Some(0));
        assert_eq!(canonical_u32("4294967295"), Some(u32::MAX));
        for bad in ["", "00", "01", "+1", "-1", "1.0", " 1", "4294967296", "1a"] {
            assert_eq!(canonical_u32(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn tokens() {
        let mut t = "sum=4 cyc=5 x".split(' ');
        assert_eq!(tagged(&mut t, "sum="), Some("4"));
        assert_eq!(tagged(&mut t, "sum="), None, "cyc= is not sum=");
        assert_eq!(word(&mut t, "x", "x"), Ok(()));
        assert_eq!(end(&mut t), Ok(()));
        let mut t = "7 y".split(' ');
        assert_eq!(number(&mut t, "n"), Ok(7));
        assert_eq!(end(&mut t), Err(LineError::TrailingData));
        assert_eq!(bare("a\r\n"), "a");
        assert_eq!(bare("a\n"), "a");
        assert_eq!(bare("a"), "a");
    }
}
