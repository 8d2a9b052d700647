//! The machinery behind [`crate::Params`] and [`crate::model::fsm::FsmParams`]: one declaration
//! per parameter (group, name, type, allowed values, documentation) generates the nested
//! structs, the list of names, the ranges, the checks and the setter by name
//! ([`param_groups!`]). `no_std`, no heap; the firmware only uses the presets.
//!
//! A parameter is named `group.field` (`efference.derotate`); its field name alone
//! (`derotate`) is accepted too, the spelling of the flat lists before the groups (field names
//! are unique across the groups).

use core::num::{NonZeroU16, NonZeroU32, NonZeroU8};

/// The values a parameter may take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Range {
    /// A whole number in `min..=max` (a switch: `0..=1`; a mechanism that 0 turns off: `0..=max`).
    Int(i64, i64),
    /// A real number in `[min, max]`, finite unless `max` is infinite (then `inf` is allowed
    /// too); `max = f32::MAX`: any finite number from `min`.
    Real(f32, f32),
}

impl core::fmt::Display for Range {
    /// What the range allows, as a refusal says it: "a whole number in 0..=255", "a finite
    /// number in [1, 16]", "a finite number ≥ 0", "a number ≥ 0, or inf".
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            Range::Int(min, max) => write!(f, "a whole number in {min}..={max}"),
            Range::Real(min, f32::MAX) => write!(f, "a finite number ≥ {min}"),
            Range::Real(min, f32::INFINITY) => write!(f, "a number ≥ {min}, or inf"),
            Range::Real(min, max) => write!(f, "a finite number in [{min}, {max}]"),
        }
    }
}

/// Why a text was refused for a parameter of some [`Range`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// Not a number of the parameter's kind (nor one of its words: `true`, `none`, ...).
    NotANumber,
    /// A number outside the range.
    OutOfRange,
}

/// A parameter's type: read from text within a [`Range`], checked against it.
pub trait Value: Copy {
    /// The other spellings it accepts, for the refusals ("" for a plain number).
    const WORDS: &'static str;
    /// The value of `text` (already trimmed).
    fn parse(text: &str, range: Range) -> Result<Self, Refusal>;
    /// Whether the value lies in `range`.
    fn within(self, range: Range) -> bool;
}

/// A whole number from text: a whole number (with an optional sign) outside the range, however
/// many digits it has, is out of range; anything else that does not parse is not a number.
fn whole(text: &str, range: Range) -> Result<i64, Refusal> {
    let Range::Int(min, max) = range else {
        return Err(Refusal::NotANumber);
    };
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    let x: i64 = match text.parse() {
        Ok(x) => x,
        Err(_) if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) => {
            return Err(Refusal::OutOfRange)
        }
        Err(_) => return Err(Refusal::NotANumber),
    };
    if (min..=max).contains(&x) {
        Ok(x)
    } else {
        Err(Refusal::OutOfRange)
    }
}

fn int_within(x: i64, range: Range) -> bool {
    matches!(range, Range::Int(min, max) if (min..=max).contains(&x))
}

/// `none` or `off`: a mechanism turned off.
fn is_off(text: &str) -> bool {
    text.eq_ignore_ascii_case("none") || text.eq_ignore_ascii_case("off")
}

macro_rules! whole_value {
    ($($t:ty),*) => {$(
        impl Value for $t {
            const WORDS: &'static str = "";
            fn parse(text: &str, range: Range) -> Result<Self, Refusal> {
                <$t>::try_from(whole(text, range)?).map_err(|_| Refusal::OutOfRange)
            }
            fn within(self, range: Range) -> bool {
                int_within(self.into(), range)
            }
        }
    )*};
}
whole_value!(u8, u16, u32);

macro_rules! off_value {
    ($($nz:ty: $t:ty),*) => {$(
        /// 0, `none` or `off`: the mechanism is off (`None`).
        impl Value for Option<$nz> {
            const WORDS: &'static str = " (0, none or off: off)";
            fn parse(text: &str, range: Range) -> Result<Self, Refusal> {
                if is_off(text) {
                    return Ok(None);
                }
                let x = whole(text, range)?;
                if x == 0 {
                    Ok(None)
                } else {
                    <$t>::try_from(x)
                        .ok()
                        .and_then(<$nz>::new)
                        .map(Some)
                        .ok_or(Refusal::OutOfRange)
                }
            }
            fn within(self, range: Range) -> bool {
                int_within(self.map_or(0, |x| i64::from(x.get())), range)
            }
        }
    )*};
}
off_value!(NonZeroU8: u8, NonZeroU16: u16, NonZeroU32: u32);

/// A count that may be absent: `none` or `off` is `None`, 0 a count like any other.
impl Value for Option<u32> {
    const WORDS: &'static str = " or none";
    fn parse(text: &str, range: Range) -> Result<Self, Refusal> {
        if is_off(text) {
            return Ok(None);
        }
        u32::parse(text, range).map(Some)
    }
    fn within(self, range: Range) -> bool {
        self.is_none_or(|x| x.within(range))
    }
}

/// A switch: `1`, `true` or `on`; `0`, `false` or `off` (its range is `0..=1`).
impl Value for bool {
    const WORDS: &'static str = " (or true/false)";
    fn parse(text: &str, range: Range) -> Result<Self, Refusal> {
        for (words, value) in [(["true", "on"], true), (["false", "off"], false)] {
            if words.iter().any(|w| text.eq_ignore_ascii_case(w)) {
                return Ok(value);
            }
        }
        Ok(whole(text, range)? != 0)
    }
    fn within(self, _: Range) -> bool {
        true
    }
}

/// A real number: refused when it does not parse or lies outside the range.
impl Value for f32 {
    const WORDS: &'static str = "";
    fn parse(text: &str, range: Range) -> Result<Self, Refusal> {
        let x: f32 = text.parse().map_err(|_| Refusal::NotANumber)?;
        if x.within(range) {
            Ok(x)
        } else {
            Err(Refusal::OutOfRange)
        }
    }
    fn within(self, range: Range) -> bool {
        match range {
            Range::Real(min, max) => {
                (self.is_finite() || (max == f32::INFINITY && self == max))
                    && self >= min
                    && self <= max
            }
            Range::Int(..) => false,
        }
    }
}

/// Declares a parameter struct made of groups, and its table: each field once, with its type
/// and its [`Range`].
///
/// ```text
/// param_groups! {
///     /// docs
///     pub struct Params {
///         /// docs of the group
///         table1: TableOne {
///             /// docs of the field
///             w: f32 = Range::Real(0.0, 4.0),
///             ...
///         },
///         ...
///     }
/// }
/// ```
///
/// generates the structs and, on the outer one, `NAMES` (`group.field`), `FIELDS` (the field
/// names alone, same order), `RANGES`, `WORDS` (each type's other spellings), `position(name)`
/// (either spelling), `parse_field(name, text)` (by the name in `NAMES`) and
/// `out_of_range()` (the first field outside its range).
macro_rules! param_groups {
    (
        $(#[$sm:meta])*
        $vis:vis struct $Params:ident {
            $(
                $(#[$gm:meta])*
                $group:ident : $Group:ident {
                    $(
                        $(#[$fm:meta])*
                        $field:ident : $ty:ty = $range:expr
                    ),* $(,)?
                }
            ),* $(,)?
        }
    ) => {
        $(#[$sm])*
        #[derive(Debug, Clone, Copy, PartialEq)]
        $vis struct $Params {
            $(
                $(#[$gm])*
                pub $group: $Group,
            )*
        }

        $(
            $(#[$gm])*
            #[derive(Debug, Clone, Copy, PartialEq)]
            pub struct $Group {
                $(
                    $(#[$fm])*
                    pub $field: $ty,
                )*
            }
        )*

        impl $Params {
            /// Every parameter's name, `group.field`, in declaration order.
            pub const NAMES: &'static [&'static str] =
                &[$($(concat!(stringify!($group), ".", stringify!($field)),)*)*];
            /// Every parameter's field name alone (also accepted by `set`), same order.
            pub const FIELDS: &'static [&'static str] = &[$($(stringify!($field),)*)*];
            /// The values each parameter of `NAMES` may take, same order.
            pub const RANGES: &'static [$crate::model::param_table::Range] = &[$($($range,)*)*];
            /// The other spellings each parameter accepts (a switch's `true`, an option's
            /// `none`), for the refusals, same order.
            pub const WORDS: &'static [&'static str] =
                &[$($(<$ty as $crate::model::param_table::Value>::WORDS,)*)*];

            /// Where `name`, `group.field` or the field name alone, is in `NAMES`.
            pub fn position(name: &str) -> Option<usize> {
                Self::NAMES
                    .iter()
                    .position(|n| *n == name)
                    .or_else(|| Self::FIELDS.iter().position(|n| *n == name))
            }

            /// Sets the parameter `name` (as in `NAMES`) from `text`, without the checks
            /// across parameters.
            fn parse_field(
                &mut self,
                name: &str,
                text: &str,
            ) -> Result<(), $crate::model::param_table::Refusal> {
                $($(
                    if name == concat!(stringify!($group), ".", stringify!($field)) {
                        self.$group.$field =
                            <$ty as $crate::model::param_table::Value>::parse(text, $range)?;
                        return Ok(());
                    }
                )*)*
                Err($crate::model::param_table::Refusal::NotANumber)
            }

            /// The name (as in `NAMES`) and range of the first parameter outside its range.
            fn out_of_range(&self) -> Option<(&'static str, $crate::model::param_table::Range)> {
                $($(
                    if !$crate::model::param_table::Value::within(self.$group.$field, $range) {
                        return Some((
                            concat!(stringify!($group), ".", stringify!($field)),
                            $range,
                        ));
                    }
                )*)*
                None
            }
        }
    };
}
pub(crate) use param_groups;

/// A mechanism that 0 turns off, as the number the code that runs it tests (0: off).
pub trait OffZero: Copy {
    /// The number's type.
    type Number;
    /// The value, 0 for `None`.
    fn off0(self) -> Self::Number;
}

impl OffZero for Option<NonZeroU8> {
    type Number = u8;
    fn off0(self) -> u8 {
        self.map_or(0, NonZeroU8::get)
    }
}

impl OffZero for Option<NonZeroU16> {
    type Number = u16;
    fn off0(self) -> u16 {
        self.map_or(0, NonZeroU16::get)
    }
}

impl OffZero for Option<NonZeroU32> {
    type Number = u32;
    fn off0(self) -> u32 {
        self.map_or(0, NonZeroU32::get)
    }
}

/// `x`'s value, 0 when the mechanism is off (`None`).
pub fn off0<T: OffZero>(x: T) -> T::Number {
    x.off0()
}

/// Writes `names` separated by ", ".
pub(crate) fn write_list(f: &mut core::fmt::Formatter<'_>, names: &[&str]) -> core::fmt::Result {
    for (i, n) in names.iter().enumerate() {
        if i > 0 {
            f.write_str(", ")?;
        }
        f.write_str(n)?;
    }
    Ok(())
}
