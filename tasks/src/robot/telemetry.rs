//! The per-frame telemetry record: one text line per camera frame on RTT channel 1.
//!
//! The same line is read by a person in an RTT terminal and parsed back by the host, so it is
//! plain ASCII with `key=value` fields, for example
//!
//! ```text
//! F 1234 st=escape S=0.731 X=65.0 sum=4000 cyc=123456 af=20,30,1000;80,40,3000
//! ```
//!
//! frame 1234, FSM state `escape`, escape strength S = 0.731, threat centroid X̄ = 65.0 px,
//! ΣLPLC2 = 4000, 123456 CPU cycles for the frame, and two attention fields centred at
//! (20, 30) and (80, 40) with LPLC2 responses 1000 and 3000.
//!
//! The real-valued signals are stored quantised (S in thousandths, X̄ in tenths of a pixel) and
//! rendered from those integers, so the firmware never formats a float (smaller binary) and
//! `parse_line(to_line(r)) == r` exactly. Grammar (single spaces, fixed field order):
//!
//! ```text
//! line     = "F " u32 " st=" state " S=" milli " X=" tenths " sum=" u32 " cyc=" u32
//!            " af=" afs [ "\r" ] "\n"
//! state    = "wander" | "long_takeoff" | "escape" | "short_takeoff" | "spin" | "look"
//! milli    = uint "." DIGIT DIGIT DIGIT          ; value <= 1.000
//! tenths   = "-" | uint "." DIGIT                ; value <= 98.0, "-" = no threat
//! afs      = "-" | af *5( ";" af )               ; at most MAX_AFS = 6 fields
//! af       = uint "," uint "," u32               ; column < 99, row < 72
//! uint     = "0" | NONZERO *DIGIT                ; canonical decimal, no sign
//! ```
//!
//! The parser accepts exactly the lines [`Record::write_line`] produces for valid records
//! (the line terminator is optional), so every accepted line re-renders byte for byte.

use crate::frame::{HEIGHT, WIDTH};
use crate::model::fsm::State;
use crate::model::MAX_AFS;
use crate::robot::line;
use core::fmt::{self, Write};

/// Largest threat centroid in tenths of a pixel: the last column, `WIDTH - 1` = 98.0.
pub const MAX_X_TENTHS: u16 = (WIDTH as u16 - 1) * 10;

/// Largest strength in thousandths: S = 1.000.
pub const MAX_STRENGTH_MILLI: u16 = 1000;

/// Every FSM state, to size [`LINE_CAP`] from the longest name.
const STATES: [State; 7] = State::ALL;

const fn longest_state_name() -> usize {
    let mut max = 0;
    let mut i = 0;
    while i < STATES.len() {
        let n = STATES[i].name().len();
        if n > max {
            max = n;
        }
        i += 1;
    }
    max
}

/// Longest line [`Record::write_line`] can produce for *any* field values (even ones the
/// parser rejects), trailing `'\n'` included, so [`Record::to_line`] can never truncate:
///
/// | part | bytes |
/// |---|---|
/// | `"F "` + u32 | 2 + 10 |
/// | `" st="` + longest state (`short_takeoff`) | 4 + 13 |
/// | `" S="` + u16 milli (`65.535`) | 3 + 6 |
/// | `" X="` + u16 tenths (`6553.5`) | 3 + 6 |
/// | `" sum="` + u32, `" cyc="` + u32 | 2 × (5 + 10) |
/// | `" af="` + 6 × `255,255,4294967295` + 5 `;` | 4 + 6 × 18 + 5 |
/// | `'\n'` | 1 |
///
/// = 195 bytes with `MAX_AFS` = 6; a valid record's line is shorter (at most 180).
pub const LINE_CAP: usize = 2
    + 10
    + 4
    + longest_state_name()
    + 3
    + 6
    + 3
    + 6
    + 2 * (5 + 10)
    + 4
    + MAX_AFS * (3 + 1 + 3 + 1 + 10)
    + (MAX_AFS - 1)
    + 1;

/// One attention field as reported per frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AfTelemetry {
    /// Centroid column, 0..=98 (left to right).
    pub x: u8,
    /// Centroid row, 0..=71 (top to bottom).
    pub y: u8,
    /// The field's LPLC2 response.
    pub lplc2: u32,
}

/// Everything the firmware reports about one camera frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Record {
    /// Frame counter since boot.
    pub frame: u32,
    /// The attention fields existing in this frame, in the network's order.
    pub afs: heapless::Vec<AfTelemetry, MAX_AFS>,
    /// `ΣLPLC2_k` over the fields.
    pub lplc2_sum: u32,
    /// Escape strength S ∈ [0, 1] in thousandths (see [`quantize_strength`]).
    pub strength_milli: u16,
    /// Threat centroid X̄ ∈ [0, 98] in tenths of a pixel, `None` without threat
    /// (see [`quantize_x`]).
    pub threat_x_tenths: Option<u16>,
    /// FSM state after this frame.
    pub state: State,
    /// CPU cycles spent on this frame (DWT cycle counter).
    pub cycles: u32,
}

/// Quantises the escape strength to thousandths, rounding to nearest.
///
/// Clamps to [0, 1]; a non-finite value gives 0 rather than a panic or garbage, since a
/// telemetry line must never take the firmware down.
pub fn quantize_strength(s: f32) -> u16 {
    if !s.is_finite() {
        return 0;
    }
    // In [0.5, 1000.5]: the saturating cast rounds half up.
    (s.clamp(0.0, 1.0) * 1000.0 + 0.5) as u16
}

/// Quantises the threat centroid to tenths of a pixel, rounding to nearest.
///
/// Clamps to [0, 98]; `None` and non-finite values give `None` (no usable threat direction).
pub fn quantize_x(x: Option<f32>) -> Option<u16> {
    let max = f32::from(MAX_X_TENTHS) / 10.0;
    x.filter(|v| v.is_finite())
        .map(|v| (v.clamp(0.0, max) * 10.0 + 0.5) as u16)
}

impl Record {
    /// The record of one frame: the perception task's output, the FSM state the motor task
    /// chose for it, and the cycles the frame took.
    pub fn from_perception(
        p: &crate::model::network::Perception,
        state: State,
        cycles: u32,
    ) -> Record {
        Record {
            frame: p.frame,
            afs: p
                .afs
                .iter()
                .map(|a| AfTelemetry {
                    x: a.x,
                    y: a.y,
                    lplc2: a.lplc2,
                })
                .collect(),
            lplc2_sum: p.vm.lplc2_sum,
            strength_milli: quantize_strength(p.vm.strength),
            threat_x_tenths: quantize_x(p.vm.threat_x),
            state,
            cycles,
        }
    }

    /// Escape strength S as `f32` (from [`Record::strength_milli`]).
    pub fn strength(&self) -> f32 {
        f32::from(self.strength_milli) / 1000.0
    }

    /// Threat centroid X̄ in pixels as `f32` (from [`Record::threat_x_tenths`]).
    pub fn threat_x(&self) -> Option<f32> {
        self.threat_x_tenths.map(|t| f32::from(t) / 10.0)
    }

    /// The frame alerted: the visuomotor pathway has a threat centroid X̄ exactly when a field
    /// is stimulated or the floor line sees an obstacle ahead
    /// ([`crate::model::visuomotor::Visuomotor::alert`]), so the line carries the alert in
    /// its `X=` field.
    pub fn alert(&self) -> bool {
        self.threat_x_tenths.is_some()
    }

    /// Writes the line, with its trailing `'\n'`, using integer formatting only.
    ///
    /// Out-of-range quantised values are written as they are (e.g. `S=2.500`), so a bug
    /// upstream stays visible; [`Record::parse_line`] then rejects the line.
    pub fn write_line<W: Write>(&self, w: &mut W) -> fmt::Result {
        let s = self.strength_milli;
        write!(
            w,
            "F {} st={} S={}.{:03} X=",
            self.frame,
            self.state.name(),
            s / 1000,
            s % 1000
        )?;
        match self.threat_x_tenths {
            None => w.write_char('-')?,
            Some(t) => write!(w, "{}.{}", t / 10, t % 10)?,
        }
        write!(w, " sum={} cyc={} af=", self.lplc2_sum, self.cycles)?;
        if self.afs.is_empty() {
            w.write_char('-')?;
        }
        for (i, af) in self.afs.iter().enumerate() {
            if i > 0 {
                w.write_char(';')?;
            }
            write!(w, "{},{},{}", af.x, af.y, af.lplc2)?;
        }
        w.write_char('\n')
    }

    /// The line, with its trailing `'\n'`, in a fixed buffer; never truncated (see
    /// [`LINE_CAP`]).
    pub fn to_line(&self) -> heapless::String<LINE_CAP> {
        let mut line = heapless::String::new();
        // Cannot fail: LINE_CAP bounds every record's line (tested).
        let _ = self.write_line(&mut line);
        line
    }

    /// Parses one line produced by [`Record::write_line`]; a trailing `"\n"` or `"\r\n"` is
    /// optional. Anything else, including non-canonical numbers and out-of-range values, is
    /// an error: the host must not silently accept a corrupted RTT stream. Never panics.
    pub fn parse_line(s: &str) -> Result<Record, ParseError> {
        let mut tokens = line::bare(s).split(' ');
        if tokens.next() != Some("F") {
            return Err(ParseError::NotARecord);
        }
        let frame = tokens
            .next()
            .ok_or(ParseError::MissingField(Field::Frame))?;
        let frame = parse_u32(frame, Field::Frame)?;
        let state = tagged(&mut tokens, "st=", Field::State)?;
        let state = State::from_name(state).ok_or(ParseError::UnknownState)?;
        let strength_milli = parse_fixed(
            tagged(&mut tokens, "S=", Field::Strength)?,
            3,
            Field::Strength,
        )?;
        if strength_milli > u32::from(MAX_STRENGTH_MILLI) {
            return Err(ParseError::OutOfRange(Field::Strength));
        }
        let threat_x_tenths = match tagged(&mut tokens, "X=", Field::ThreatX)? {
            "-" => None,
            x => {
                let t = parse_fixed(x, 1, Field::ThreatX)?;
                if t > u32::from(MAX_X_TENTHS) {
                    return Err(ParseError::OutOfRange(Field::ThreatX));
                }
                Some(t as u16)
            }
        };
        let lplc2_sum = parse_u32(tagged(&mut tokens, "sum=", Field::Sum)?, Field::Sum)?;
        let cycles = parse_u32(tagged(&mut tokens, "cyc=", Field::Cycles)?, Field::Cycles)?;
        let afs = parse_afs(tagged(&mut tokens, "af=", Field::Afs)?)?;
        if tokens.next().is_some() {
            return Err(ParseError::TrailingData);
        }
        Ok(Record {
            frame,
            afs,
            lplc2_sum,
            strength_milli: strength_milli as u16,
            threat_x_tenths,
            state,
            cycles,
        })
    }
}

/// A field of the line, named in [`ParseError`]s.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Field {
    /// `F <frame>`.
    Frame,
    /// `st=`.
    State,
    /// `S=`.
    Strength,
    /// `X=`.
    ThreatX,
    /// `sum=`.
    Sum,
    /// `cyc=`.
    Cycles,
    /// `af=`.
    Afs,
    /// Column of an `af=` entry.
    AfX,
    /// Row of an `af=` entry.
    AfY,
    /// LPLC2 response of an `af=` entry.
    AfLplc2,
}

impl Field {
    /// The field's name as written in the line.
    pub const fn name(self) -> &'static str {
        match self {
            Field::Frame => "F",
            Field::State => "st",
            Field::Strength => "S",
            Field::ThreatX => "X",
            Field::Sum => "sum",
            Field::Cycles => "cyc",
            Field::Afs => "af",
            Field::AfX => "af column",
            Field::AfY => "af row",
            Field::AfLplc2 => "af lplc2",
        }
    }
}

/// Why a line is not a telemetry record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParseError {
    /// The line does not start with `"F "`: some other output on the channel (boot banner,
    /// summary), which the host may skip.
    NotARecord,
    /// The field is absent, out of order, or its `key=` is misspelt.
    MissingField(Field),
    /// The value is not a canonical unsigned decimal of the expected shape, or overflows.
    BadNumber(Field),
    /// The value is well formed but outside its range (S > 1, X̄ > 98, field off the retina).
    OutOfRange(Field),
    /// `st=` names no FSM state.
    UnknownState,
    /// More than [`MAX_AFS`] attention fields.
    TooManyFields,
    /// Something follows the `af=` field.
    TrailingData,
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            ParseError::NotARecord => f.write_str("not a telemetry record (no leading \"F \")"),
            ParseError::MissingField(field) => write!(f, "missing field `{}`", field.name()),
            ParseError::BadNumber(field) => write!(f, "malformed number in `{}`", field.name()),
            ParseError::OutOfRange(field) => write!(f, "`{}` out of range", field.name()),
            ParseError::UnknownState => f.write_str("unknown FSM state in `st`"),
            ParseError::TooManyFields => {
                write!(f, "more than {MAX_AFS} attention fields in `af`")
            }
            ParseError::TrailingData => f.write_str("unexpected data after `af`"),
        }
    }
}

impl core::error::Error for ParseError {}

/// The next token with its `key=` removed.
fn tagged<'a>(
    tokens: &mut impl Iterator<Item = &'a str>,
    key: &str,
    field: Field,
) -> Result<&'a str, ParseError> {
    line::tagged(tokens, key).ok_or(ParseError::MissingField(field))
}

/// A canonical unsigned decimal: digits only, no leading zero, no overflow.
fn parse_u32(s: &str, field: Field) -> Result<u32, ParseError> {
    line::canonical_u32(s).ok_or(ParseError::BadNumber(field))
}

/// A fixed-point `int.frac` with exactly `digits` fractional digits, as an integer in units
/// of `10^-digits`.
fn parse_fixed(s: &str, digits: usize, field: Field) -> Result<u32, ParseError> {
    let bad = ParseError::BadNumber(field);
    let (int, frac) = s.split_once('.').ok_or(bad)?;
    if frac.len() != digits || !frac.bytes().all(|c| c.is_ascii_digit()) {
        return Err(bad);
    }
    let frac = frac
        .bytes()
        .fold(0u32, |acc, c| acc * 10 + u32::from(c - b'0'));
    let scale = 10u32.checked_pow(digits as u32).ok_or(bad)?;
    parse_u32(int, field)?
        .checked_mul(scale)
        .and_then(|v| v.checked_add(frac))
        .ok_or(bad)
}

/// The `af=` value: `-` or up to [`MAX_AFS`] `x,y,lplc2` entries separated by `;`.
fn parse_afs(s: &str) -> Result<heapless::Vec<AfTelemetry, MAX_AFS>, ParseError> {
    let mut afs = heapless::Vec::new();
    if s == "-" {
        return Ok(afs);
    }
    for entry in s.split(';') {
        let mut parts = entry.splitn(3, ',');
        let mut next = |field| {
            parts
                .next()
                .ok_or(ParseError::MissingField(field))
                .and_then(|p| parse_u32(p, field))
        };
        let x = next(Field::AfX)?;
        let y = next(Field::AfY)?;
        let lplc2 = next(Field::AfLplc2)?;
        let x = u8::try_from(x)
            .ok()
            .filter(|&x| usize::from(x) < WIDTH)
            .ok_or(ParseError::OutOfRange(Field::AfX))?;
        let y = u8::try_from(y)
            .ok()
            .filter(|&y| usize::from(y) < HEIGHT)
            .ok_or(ParseError::OutOfRange(Field::AfY))?;
        afs.push(AfTelemetry { x, y, lplc2 })
            .map_err(|_| ParseError::TooManyFields)?;
    }
    Ok(afs)
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use proptest::prelude::*;
    use std::string::String;
    use std::vec::Vec;

    const EXAMPLE: &str =
        "F 1234 st=escape S=0.731 X=65.0 sum=4000 cyc=123456 af=20,30,1000;80,40,3000\n";

    fn example() -> Record {
        Record {
            frame: 1234,
            afs: heapless::Vec::from_slice(&[
                AfTelemetry {
                    x: 20,
                    y: 30,
                    lplc2: 1000,
                },
                AfTelemetry {
                    x: 80,
                    y: 40,
                    lplc2: 3000,
                },
            ])
            .unwrap(),
            lplc2_sum: 4000,
            strength_milli: 731,
            threat_x_tenths: Some(650),
            state: State::Escape,
            cycles: 123456,
        }
    }

    /// Fails to compile when a state is added, so `STATES` (and `LINE_CAP`) stay complete.
    #[allow(dead_code)]
    fn states_complete(s: State) {
        match s {
            State::Wander
            | State::LongTakeoff
            | State::Escape
            | State::ShortTakeoff
            | State::Spin
            | State::Look
            | State::Stop => {}
        }
    }

    fn parse(s: &str) -> Result<Record, ParseError> {
        Record::parse_line(s)
    }

    #[test]
    fn example_record_to_line() {
        assert_eq!(example().to_line().as_str(), EXAMPLE);
    }

    #[test]
    fn example_line_to_record() {
        assert_eq!(parse(EXAMPLE), Ok(example()));
        let bare = EXAMPLE.trim_end();
        assert_eq!(parse(bare), Ok(example()));
        let crlf = std::format!("{bare}\r\n");
        assert_eq!(parse(&crlf), Ok(example()));
    }

    #[test]
    fn no_threat_no_fields() {
        let r = Record {
            frame: 0,
            afs: heapless::Vec::new(),
            lplc2_sum: 0,
            strength_milli: 500,
            threat_x_tenths: None,
            state: State::Wander,
            cycles: 7,
        };
        let line = "F 0 st=wander S=0.500 X=- sum=0 cyc=7 af=-\n";
        assert_eq!(r.to_line().as_str(), line);
        assert_eq!(parse(line), Ok(r));
    }

    #[test]
    fn extremes_render() {
        let mut r = example();
        r.strength_milli = 1000;
        r.threat_x_tenths = Some(0);
        assert!(r.to_line().contains(" S=1.000 X=0.0 "));
        r.strength_milli = 5;
        r.threat_x_tenths = Some(980);
        assert!(r.to_line().contains(" S=0.005 X=98.0 "));
    }

    #[test]
    fn worst_case_line_fits() {
        let af = AfTelemetry {
            x: u8::MAX,
            y: u8::MAX,
            lplc2: u32::MAX,
        };
        let mut r = Record {
            frame: u32::MAX,
            afs: heapless::Vec::from_slice(&[af; MAX_AFS]).unwrap(),
            lplc2_sum: u32::MAX,
            strength_milli: u16::MAX,
            threat_x_tenths: Some(u16::MAX),
            state: State::ShortTakeoff,
            cycles: u32::MAX,
        };
        let mut big = heapless::String::<512>::new();
        r.write_line(&mut big).unwrap();
        assert_eq!(big.len(), LINE_CAP);
        assert_eq!(LINE_CAP, 195);
        assert_eq!(r.to_line(), big.as_str());
        for state in STATES {
            r.state = state;
            let mut s = heapless::String::<LINE_CAP>::new();
            assert!(r.write_line(&mut s).is_ok());
        }

        // The longest line the parser accepts.
        let af = AfTelemetry {
            x: 98,
            y: 71,
            lplc2: u32::MAX,
        };
        let r = Record {
            afs: heapless::Vec::from_slice(&[af; MAX_AFS]).unwrap(),
            strength_milli: 1000,
            threat_x_tenths: Some(980),
            state: State::ShortTakeoff,
            ..r
        };
        let line = r.to_line();
        assert_eq!(line.len(), 180);
        assert_eq!(parse(&line), Ok(r));
    }

    #[test]
    fn quantize() {
        assert_eq!(quantize_strength(0.7314), 731);
        assert_eq!(quantize_strength(0.7315), 732);
        assert_eq!(quantize_strength(1.0), 1000);
        assert_eq!(quantize_strength(1.5), 1000);
        assert_eq!(quantize_strength(-0.2), 0);
        assert_eq!(quantize_strength(f32::NAN), 0);
        assert_eq!(quantize_strength(f32::INFINITY), 0);
        assert_eq!(quantize_strength(f32::NEG_INFINITY), 0);
        assert_eq!(quantize_x(None), None);
        assert_eq!(quantize_x(Some(65.04)), Some(650));
        assert_eq!(quantize_x(Some(65.06)), Some(651));
        assert_eq!(quantize_x(Some(98.0)), Some(980));
        assert_eq!(quantize_x(Some(150.0)), Some(980));
        assert_eq!(quantize_x(Some(-3.0)), Some(0));
        assert_eq!(quantize_x(Some(f32::NAN)), None);
        assert_eq!(quantize_x(Some(f32::INFINITY)), None);
    }

    #[test]
    fn accessors_invert_quantizers() {
        for q in 0..=MAX_STRENGTH_MILLI {
            let r = Record {
                strength_milli: q,
                ..example()
            };
            assert_eq!(quantize_strength(r.strength()), q);
        }
        for q in 0..=MAX_X_TENTHS {
            let r = Record {
                threat_x_tenths: Some(q),
                ..example()
            };
            assert_eq!(quantize_x(r.threat_x()), Some(q));
        }
        let r = Record {
            threat_x_tenths: None,
            ..example()
        };
        assert_eq!(r.threat_x(), None);
        assert!((example().strength() - 0.731).abs() < 1e-6);
    }

    #[test]
    fn each_parse_error() {
        use Field::*;
        use ParseError::*;
        let cases: &[(&str, ParseError)] = &[
            ("", NotARecord),
            ("hello", NotARecord),
            ("F1234 st=escape", NotARecord),
            ("F", MissingField(Frame)),
            ("F 1", MissingField(State)),
            ("F 1 S=0.500", MissingField(State)),
            ("F 1 st=wander", MissingField(Strength)),
            ("F 1 st=wander S=0.500", MissingField(ThreatX)),
            ("F 1 st=wander S=0.500 X=-", MissingField(Sum)),
            ("F 1 st=wander S=0.500 X=- sum=0", MissingField(Cycles)),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=0", MissingField(Afs)),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=0 af=1", MissingField(AfY)),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=0 af=1,2", MissingField(AfLplc2)),
            ("F x st=wander S=0.500 X=- sum=0 cyc=0 af=-", BadNumber(Frame)),
            ("F 01 st=wander S=0.500 X=- sum=0 cyc=0 af=-", BadNumber(Frame)),
            ("F -1 st=wander S=0.500 X=- sum=0 cyc=0 af=-", BadNumber(Frame)),
            ("F 4294967296 st=wander S=0.500 X=- sum=0 cyc=0 af=-", BadNumber(Frame)),
            ("F  1 st=wander S=0.500 X=- sum=0 cyc=0 af=-", BadNumber(Frame)),
            ("F 1 st=wander S=0.5 X=- sum=0 cyc=0 af=-", BadNumber(Strength)),
            ("F 1 st=wander S=.500 X=- sum=0 cyc=0 af=-", BadNumber(Strength)),
            ("F 1 st=wander S=1 X=- sum=0 cyc=0 af=-", BadNumber(Strength)),
            ("F 1 st=wander S=0.5e0 X=- sum=0 cyc=0 af=-", BadNumber(Strength)),
            ("F 1 st=wander S=0.500 X=65 sum=0 cyc=0 af=-", BadNumber(ThreatX)),
            ("F 1 st=wander S=0.500 X=65.00 sum=0 cyc=0 af=-", BadNumber(ThreatX)),
            ("F 1 st=wander S=0.500 X= sum=0 cyc=0 af=-", BadNumber(ThreatX)),
            ("F 1 st=wander S=0.500 X=- sum=+1 cyc=0 af=-", BadNumber(Sum)),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=1.0 af=-", BadNumber(Cycles)),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=0 af=", BadNumber(AfX)),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=0 af=1,2,3;", BadNumber(AfX)),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=0 af=1,,3", BadNumber(AfY)),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=0 af=1,2,3,4", BadNumber(AfLplc2)),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=0 af=-\r", BadNumber(AfX)),
            ("F 1 st=wander S=1.001 X=- sum=0 cyc=0 af=-", OutOfRange(Strength)),
            ("F 1 st=wander S=2.000 X=- sum=0 cyc=0 af=-", OutOfRange(Strength)),
            ("F 1 st=wander S=0.500 X=98.1 sum=0 cyc=0 af=-", OutOfRange(ThreatX)),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=0 af=99,0,1", OutOfRange(AfX)),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=0 af=300,0,1", OutOfRange(AfX)),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=0 af=0,72,1", OutOfRange(AfY)),
            ("F 1 st=fly S=0.500 X=- sum=0 cyc=0 af=-", UnknownState),
            ("F 1 st=Wander S=0.500 X=- sum=0 cyc=0 af=-", UnknownState),
            (
                "F 1 st=wander S=0.500 X=- sum=0 cyc=0 af=0,0,1;0,0,1;0,0,1;0,0,1;0,0,1;0,0,1;0,0,1",
                TooManyFields,
            ),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=0 af=- x=1", TrailingData),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=0 af=- ", TrailingData),
            ("F 1 st=wander S=0.500 X=- sum=0 cyc=0 af=-\n\n", BadNumber(AfX)),
        ];
        for (line, err) in cases {
            assert_eq!(parse(line), Err(*err), "{line:?}");
            // Every error has a message.
            let mut msg = heapless::String::<128>::new();
            write!(msg, "{err}").unwrap();
            assert!(!msg.is_empty());
        }
        // Six fields is the limit, not an error.
        let six = "F 1 st=wander S=0.500 X=- sum=6 cyc=0 af=0,0,1;0,0,1;0,0,1;0,0,1;0,0,1;0,0,1";
        assert_eq!(parse(six).map(|r| r.afs.len()), Ok(MAX_AFS));
    }

    fn arb_af() -> impl Strategy<Value = AfTelemetry> {
        (0..WIDTH as u8, 0..HEIGHT as u8, any::<u32>()).prop_map(|(x, y, lplc2)| AfTelemetry {
            x,
            y,
            lplc2,
        })
    }

    fn arb_record() -> impl Strategy<Value = Record> {
        (
            any::<u32>(),
            prop::collection::vec(arb_af(), 0..=MAX_AFS),
            any::<u32>(),
            0..=MAX_STRENGTH_MILLI,
            prop::option::of(0..=MAX_X_TENTHS),
            prop::sample::select(&STATES[..]),
            any::<u32>(),
        )
            .prop_map(
                |(frame, afs, lplc2_sum, strength_milli, threat_x_tenths, state, cycles)| Record {
                    frame,
                    afs: heapless::Vec::from_slice(&afs).unwrap(),
                    lplc2_sum,
                    strength_milli,
                    threat_x_tenths,
                    state,
                    cycles,
                },
            )
    }

    /// If a line parses, it is exactly the line of the record it parses to.
    fn check_canonical(s: &str) {
        if let Ok(r) = parse(s) {
            let bare = s
                .strip_suffix("\r\n")
                .or_else(|| s.strip_suffix('\n'))
                .unwrap_or(s);
            assert_eq!(r.to_line().as_str().strip_suffix('\n'), Some(bare));
        }
    }

    proptest! {
        #[test]
        fn round_trip(r in arb_record()) {
            let line = r.to_line();
            prop_assert!(line.len() <= LINE_CAP);
            prop_assert!(line.ends_with('\n'));
            prop_assert_eq!(parse(&line), Ok(r.clone()));
            let crlf = std::format!("{}\r\n", line.trim_end());
            prop_assert_eq!(parse(&crlf), Ok(r));
        }

        #[test]
        fn quantized_round_trip(s in any::<f32>(), x in prop::option::of(any::<f32>())) {
            let r = Record {
                strength_milli: quantize_strength(s),
                threat_x_tenths: quantize_x(x),
                ..example()
            };
            prop_assert_eq!(parse(&r.to_line()), Ok(r));
        }

        #[test]
        fn parse_never_panics(s in any::<String>()) {
            check_canonical(&s);
        }

        #[test]
        fn parse_never_panics_near_grammar(s in "[F0-9 .,;=a-z_X\\-\r\n]{0,120}") {
            check_canonical(&s);
        }

        #[test]
        fn parse_never_panics_on_mutations(
            r in arb_record(),
            edits in prop::collection::vec(
                (any::<prop::sample::Index>(), 0u8..3, prop::sample::select(
                    &b"F0123456789 .,;=-_aefstwXSrc\r\n\xce"[..]
                )),
                1..4,
            ),
        ) {
            let mut bytes: Vec<u8> = r.to_line().as_bytes().to_vec();
            for (at, op, c) in edits {
                let i = at.index(bytes.len() + 1);
                match op {
                    0 => bytes.insert(i, c),
                    1 if i < bytes.len() => { bytes.remove(i); }
                    _ if i < bytes.len() => bytes[i] = c,
                    _ => {}
                }
            }
            // Invalid UTF-8 never reaches the parser (the host decodes first).
            if let Ok(s) = core::str::from_utf8(&bytes) {
                check_canonical(s);
            }
        }
    }

    #[test]
    fn the_alert_is_the_threat_centroid() {
        use crate::model::visuomotor::Visuomotor;
        let p = crate::model::params::Params::default();
        for fields in [&[][..], &[(20u8, 0u32)], &[(20, 1000), (80, 3000)]] {
            let vm = Visuomotor::from_fields(fields.iter().copied(), &p);
            assert_eq!(vm.alert, vm.threat_x.is_some(), "{fields:?}");
            let mut ahead = vm;
            ahead.ahead(40, &p);
            assert!(ahead.alert && ahead.threat_x.is_some());
        }
        let mut r = example();
        assert!(r.alert());
        r.threat_x_tenths = None;
        assert!(!r.alert());
    }

    #[test]
    fn a_perception_becomes_a_record_and_a_line() {
        use crate::model::network::{AfReport, Perception};
        use crate::model::visuomotor::Visuomotor;
        let mut p = Perception {
            frame: 42,
            ..Perception::default()
        };
        let _ = p.afs.push(AfReport {
            x: 20,
            y: 30,
            lplc2: 1000,
            ..AfReport::default()
        });
        let _ = p.afs.push(AfReport {
            x: 80,
            y: 40,
            lplc2: 3000,
            ..AfReport::default()
        });
        p.vm = Visuomotor::from_fields(
            p.afs.iter().map(|a| (a.x, a.lplc2)),
            &crate::model::params::Params::default(),
        );
        let r = Record::from_perception(&p, State::LongTakeoff, 123_456);
        assert_eq!(
            r.to_line().as_str(),
            "F 42 st=long_takeoff S=0.731 X=65.0 sum=4000 cyc=123456 af=20,30,1000;80,40,3000\n"
        );
    }
}
