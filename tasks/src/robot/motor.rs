//! The bottom-board UART protocol: the bytes the motor task sends to the Colias basic unit.
//!
//! The sense board does not drive the motors itself: it writes the motor registers of the
//! bottom board (the "Colias basic unit", CBU) over a UART. Every protocol fact below comes from
//! the public C firmware of the Colias family (`coliasapi.c`, `visuomotor_LPLC2.c`) and from
//! `docs/hardware.md`; none was checked on a board, so each is a named constant here and nowhere
//! else.
//!
//! A frame is `head, address, data…, END`:
//!
//! ```text
//! 78 9A 2C 01 D4 FE 7F    write (no ack) at 0x9A: left power +300, right power −300, end
//! ```
//!
//! A data byte equal to the frame's head or to [`END`] would end or confuse the frame, so it is
//! sent as two bytes, the head and then `byte − ESCAPE_OFFSET`: with head `0x78`, data `0x78`
//! becomes `78 58` and data `0x7F` becomes `78 5F`. Every other byte, including the other head
//! values, is sent as it is.
//!
//! **The register address is never escaped, and an address that would need it is refused.**
//! The public firmware hands address and data to `SendFrametoCBU` as one buffer, whose source is
//! not published, so whether the address goes through the escape rule is unknown. None of the
//! registers any Colias firmware writes (0x12, 0x20–0x40, 0x99–0x9E) equals a head or `END`,
//! so both readings give the same bytes for every frame this module can build;
//! [`encode`] returns [`EncodeError::ReservedAddress`] instead of guessing.
//!
//! Units: the FSM speaks mm/s per wheel; the board takes a signed 16-bit "power" per wheel
//! (little-endian, positive = forward). [`power`] converts with [`POWER_PER_MM_S`], an estimate
//! to calibrate at bring-up.
//!
//! Writes use [`HEAD_WRITE`] (no acknowledgement), as the public firmware does for motion: the
//! motor task never waits on the UART. Lost bytes are tolerated because the powers are rewritten
//! every frame and [`MotorOutput`] resends the stop frames every frame while motors are off.

/// UART baud rate, 8N1. From public firmware (UART4 in older boards; the 2025 firmware uses
/// UART2 with an unpublished rate); verify at bring-up.
pub const BAUD: u32 = 38_400;

/// Head byte: write registers, no reply. From public firmware; verify at bring-up.
pub const HEAD_WRITE: u8 = 0x78;
/// Head byte: write registers, the board replies [`REPLY_OK`] / [`REPLY_ERROR`]. From public
/// firmware; verify at bring-up.
pub const HEAD_WRITE_ACK: u8 = 0x7C;
/// Head byte: read registers. From public firmware; verify at bring-up.
pub const HEAD_READ: u8 = 0x7D;
/// Last byte of every frame. From public firmware; verify at bring-up.
pub const END: u8 = 0x7F;
/// An escaped data byte is sent as `head, byte − ESCAPE_OFFSET`. From public firmware; verify
/// at bring-up.
pub const ESCAPE_OFFSET: u8 = 0x20;
/// Reply byte: the write was accepted. From public firmware; verify at bring-up.
pub const REPLY_OK: u8 = 0x7B;
/// Reply byte: the write was refused. From public firmware; verify at bring-up.
pub const REPLY_ERROR: u8 = 0x7A;

/// Motor control register (one byte): [`CONTROL_ENABLE`] turns the motor drivers on. From
/// public firmware; verify at bring-up.
pub const REG_CONTROL: u8 = 0x99;
/// Left wheel power, signed 16-bit little-endian (0x9A low, 0x9B high). From public firmware;
/// verify at bring-up.
pub const REG_POWER_LEFT: u8 = 0x9A;
/// Right wheel power, signed 16-bit little-endian (0x9C low, 0x9D high). From public firmware;
/// verify at bring-up.
pub const REG_POWER_RIGHT: u8 = 0x9C;
/// Power increments, one signed byte per wheel (0x9E left, 0x9F right); not used here. From
/// public firmware; verify at bring-up.
pub const REG_POWER_INC: u8 = 0x9E;
/// Value of [`REG_CONTROL`] that enables the motors (`CAPI_MotionEnable`). From public
/// firmware; verify at bring-up.
pub const CONTROL_ENABLE: u8 = 0x80;
/// Value of [`REG_CONTROL`] that disables the motors (`CAPI_MotionDisable`). From public
/// firmware; verify at bring-up.
pub const CONTROL_DISABLE: u8 = 0x00;

/// Board power per mm/s of wheel speed. **Estimate; calibrate at bring-up.**
///
/// From the public firmware's units: it wanders at `vrun = 5 × 0.5 = 2.5` speed units and sends
/// `power = 100 × speed` (`Motion_LR`), i.e. power 250, while the paper gives the wander speed
/// as ≈ 10 cm/s: 250 / 100 mm/s = 2.5. Its escape ceiling (4.5 units, power 450) then means
/// 180 mm/s, in line with the FSM's escape speeds.
pub const POWER_PER_MM_S: f32 = 2.5;

/// Largest power magnitude sent; commands beyond it saturate. From public firmware (an older
/// protocol comment gives the range ±1000; the 2025 API accepts the full 16 bits); verify at
/// bring-up. At [`POWER_PER_MM_S`] it is 400 mm/s, above the FSM's 300 mm/s wheel limit, so it
/// only binds if the scale or the FSM limits are wrong.
pub const MAX_POWER: i16 = 1000;

/// Data bytes one frame may carry (the largest write the public firmware makes is 5: control
/// and both powers).
pub const MAX_DATA: usize = 8;

/// Longest encoded frame: head, address, every data byte escaped, end.
pub const FRAME_CAP: usize = 2 + 2 * MAX_DATA + 1;

/// Most frames one call of this module returns (powers as two frames plus a control write).
pub const MAX_FRAMES: usize = 3;

/// One encoded frame, ready for the UART.
pub type MotorFrame = heapless::Vec<u8, FRAME_CAP>;

/// The frames one call returns, to be sent in order.
pub type MotorFrames = heapless::Vec<MotorFrame, MAX_FRAMES>;

/// The kind of a frame, given by its head byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Head {
    /// [`HEAD_WRITE`]: write without reply.
    Write,
    /// [`HEAD_WRITE_ACK`]: write, the board replies.
    WriteAck,
    /// [`HEAD_READ`]: read.
    Read,
}

impl Head {
    /// The head byte on the wire.
    pub const fn byte(self) -> u8 {
        match self {
            Head::Write => HEAD_WRITE,
            Head::WriteAck => HEAD_WRITE_ACK,
            Head::Read => HEAD_READ,
        }
    }

    /// The head a byte starts, if any.
    pub const fn from_byte(b: u8) -> Option<Head> {
        match b {
            HEAD_WRITE => Some(Head::Write),
            HEAD_WRITE_ACK => Some(Head::WriteAck),
            HEAD_READ => Some(Head::Read),
            _ => None,
        }
    }
}

/// The board's one-byte answer to a [`Head::WriteAck`] frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reply {
    /// [`REPLY_OK`].
    Ok,
    /// [`REPLY_ERROR`].
    Error,
}

impl Reply {
    /// The reply a byte means, if any.
    pub const fn from_byte(b: u8) -> Option<Reply> {
        match b {
            REPLY_OK => Some(Reply::Ok),
            REPLY_ERROR => Some(Reply::Error),
            _ => None,
        }
    }
}

/// A byte that may not appear unescaped inside a frame: a head or [`END`].
pub const fn is_reserved(b: u8) -> bool {
    Head::from_byte(b).is_some() || b == END
}

/// Why a frame cannot be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EncodeError {
    /// The address equals a head byte or [`END`]; whether the board expects it escaped is
    /// unknown (see the module docs), so it is not sent at all.
    ReservedAddress(u8),
    /// More than [`MAX_DATA`] data bytes.
    TooMuchData {
        /// Data bytes given.
        len: usize,
    },
}

impl core::fmt::Display for EncodeError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            EncodeError::ReservedAddress(a) => {
                write!(f, "register address {a:#04x} is a reserved byte")
            }
            EncodeError::TooMuchData { len } => {
                write!(f, "{len} data bytes, a frame carries at most {MAX_DATA}")
            }
        }
    }
}

impl core::error::Error for EncodeError {}

/// Encodes one frame: `head, address, escaped data, END`.
pub fn encode(head: Head, address: u8, data: &[u8]) -> Result<MotorFrame, EncodeError> {
    if is_reserved(address) {
        return Err(EncodeError::ReservedAddress(address));
    }
    if data.len() > MAX_DATA {
        return Err(EncodeError::TooMuchData { len: data.len() });
    }
    let h = head.byte();
    let mut out = MotorFrame::new();
    // FRAME_CAP covers the worst case, so no push below can fail; the results are still
    // checked rather than unwrapped.
    let mut push = |b: u8| {
        out.push(b)
            .map_err(|_| EncodeError::TooMuchData { len: data.len() })
    };
    push(h)?;
    push(address)?;
    for &b in data {
        if b == h || b == END {
            push(h)?;
            push(b - ESCAPE_OFFSET)?;
        } else {
            push(b)?;
        }
    }
    push(END)?;
    Ok(out)
}

/// A frame read back by [`decode`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Decoded {
    /// The frame's kind.
    pub head: Head,
    /// First register written or read.
    pub address: u8,
    /// Data bytes, unescaped.
    pub data: heapless::Vec<u8, MAX_DATA>,
}

/// Why bytes are not one well-formed frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DecodeError {
    /// No bytes at all.
    Empty,
    /// The first byte is not a head.
    UnknownHead(u8),
    /// The frame stops before its address.
    MissingAddress,
    /// The address is a head byte or [`END`] (never produced by [`encode`]).
    ReservedAddress(u8),
    /// The head byte at `at` inside the data is followed by a byte that does not unescape to
    /// the head or [`END`].
    BadEscape {
        /// Offset of the escape's head byte.
        at: usize,
    },
    /// The bytes run out before [`END`].
    MissingEnd,
    /// Bytes follow the [`END`] at `at − 1`.
    TrailingBytes {
        /// Offset of the first byte after the end.
        at: usize,
    },
    /// More than [`MAX_DATA`] data bytes.
    TooMuchData,
}

impl core::fmt::Display for DecodeError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            DecodeError::Empty => f.write_str("empty frame"),
            DecodeError::UnknownHead(b) => write!(f, "unknown head byte {b:#04x}"),
            DecodeError::MissingAddress => f.write_str("frame ends before its address"),
            DecodeError::ReservedAddress(a) => write!(f, "reserved byte {a:#04x} as address"),
            DecodeError::BadEscape { at } => write!(f, "invalid escape at byte {at}"),
            DecodeError::MissingEnd => f.write_str("frame has no end byte"),
            DecodeError::TrailingBytes { at } => write!(f, "bytes after the end, from {at}"),
            DecodeError::TooMuchData => write!(f, "more than {MAX_DATA} data bytes"),
        }
    }
}

impl core::error::Error for DecodeError {}

/// Decodes exactly one frame, the inverse of [`encode`]; anything else is an error. For tests
/// and the host-side simulator (the firmware only sends).
pub fn decode(bytes: &[u8]) -> Result<Decoded, DecodeError> {
    let (&h, rest) = bytes.split_first().ok_or(DecodeError::Empty)?;
    let head = Head::from_byte(h).ok_or(DecodeError::UnknownHead(h))?;
    let (&address, rest) = rest.split_first().ok_or(DecodeError::MissingAddress)?;
    if is_reserved(address) {
        return Err(DecodeError::ReservedAddress(address));
    }
    let mut data = heapless::Vec::new();
    let mut i = 0;
    while let Some(&b) = rest.get(i) {
        let at = i + 2;
        let byte = if b == END {
            return if i + 1 == rest.len() {
                Ok(Decoded {
                    head,
                    address,
                    data,
                })
            } else {
                Err(DecodeError::TrailingBytes { at: at + 1 })
            };
        } else if b == h {
            let next = *rest.get(i + 1).ok_or(DecodeError::MissingEnd)?;
            let v = next.wrapping_add(ESCAPE_OFFSET);
            if v != h && v != END {
                return Err(DecodeError::BadEscape { at });
            }
            i += 2;
            v
        } else {
            i += 1;
            b
        };
        data.push(byte).map_err(|_| DecodeError::TooMuchData)?;
    }
    Err(DecodeError::MissingEnd)
}

/// Wheel speed (mm/s, positive = forward) → board power: `round(mm_s · POWER_PER_MM_S)`,
/// saturated to ±[`MAX_POWER`]; NaN gives 0.
pub fn power(mm_s: f32) -> i16 {
    let p = mm_s * POWER_PER_MM_S;
    let max = f32::from(MAX_POWER);
    if p.is_nan() {
        0
    } else if p >= max {
        MAX_POWER
    } else if p <= -max {
        -MAX_POWER
    } else if p >= 0.0 {
        // |p| < 1000: the casts are exact after rounding half away from zero.
        (p + 0.5) as i16
    } else {
        (p - 0.5) as i16
    }
}

/// How the two wheel powers are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WheelLayout {
    /// One frame at [`REG_POWER_LEFT`] with 4 data bytes (left, then right, relying on the
    /// board's address auto-increment): what the public firmware does (`CAPI_MotionSet_LR`),
    /// and both wheels change together.
    OneWrite,
    /// One frame per wheel, at [`REG_POWER_LEFT`] and [`REG_POWER_RIGHT`], 2 data bytes each.
    PerWheel,
}

/// The layout [`wheel_frames`] uses. The public firmware only ever writes both powers in one
/// frame from 0x9A (or 0x99); 0x9C is defined there but never written alone. Verify at
/// bring-up; switch to [`WheelLayout::PerWheel`] if the board turns out not to auto-increment.
pub const WHEEL_LAYOUT: WheelLayout = WheelLayout::OneWrite;

fn push_frame(frames: &mut MotorFrames, address: u8, data: &[u8]) {
    // The addresses are this module's constants (never reserved) and the data at most 4
    // bytes, so encoding cannot fail; capacity is MAX_FRAMES, never exceeded by the callers.
    if let Ok(f) = encode(Head::Write, address, data) {
        let _ = frames.push(f);
    }
}

fn push_powers(frames: &mut MotorFrames, layout: WheelLayout, left: i16, right: i16) {
    let [l0, l1] = left.to_le_bytes();
    let [r0, r1] = right.to_le_bytes();
    match layout {
        WheelLayout::OneWrite => push_frame(frames, REG_POWER_LEFT, &[l0, l1, r0, r1]),
        WheelLayout::PerWheel => {
            push_frame(frames, REG_POWER_LEFT, &[l0, l1]);
            push_frame(frames, REG_POWER_RIGHT, &[r0, r1]);
        }
    }
}

/// The frames that set both wheel powers from speeds in mm/s ([`power`]), in [`WHEEL_LAYOUT`].
pub fn wheel_frames(left_mm_s: f32, right_mm_s: f32) -> MotorFrames {
    wheel_frames_with(WHEEL_LAYOUT, left_mm_s, right_mm_s)
}

/// [`wheel_frames`] in a given layout.
pub fn wheel_frames_with(layout: WheelLayout, left_mm_s: f32, right_mm_s: f32) -> MotorFrames {
    let mut frames = MotorFrames::new();
    push_powers(&mut frames, layout, power(left_mm_s), power(right_mm_s));
    frames
}

/// Turns the motors on without a jolt: both powers to 0 first (the registers may hold stale
/// values), then [`CONTROL_ENABLE`].
pub fn enable_sequence() -> MotorFrames {
    let mut frames = MotorFrames::new();
    push_powers(&mut frames, WHEEL_LAYOUT, 0, 0);
    push_frame(&mut frames, REG_CONTROL, &[CONTROL_ENABLE]);
    frames
}

/// Stops: both powers to 0, then [`CONTROL_DISABLE`]; either alone stops the robot, so one
/// lost frame does not keep it moving.
pub fn stop_frames() -> MotorFrames {
    let mut frames = MotorFrames::new();
    push_powers(&mut frames, WHEEL_LAYOUT, 0, 0);
    push_frame(&mut frames, REG_CONTROL, &[CONTROL_DISABLE]);
    frames
}

/// What the motor task sends each frame, given whether the safety policy allows motion.
///
/// Enabling sends the new powers, then [`CONTROL_ENABLE`]; while enabled, only the powers;
/// while disabled, [`stop_frames`] every frame (no acknowledgement exists, so a stop is
/// repeated rather than trusted).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MotorOutput {
    enabled: bool,
}

impl MotorOutput {
    /// Motors assumed disabled.
    pub const fn new() -> Self {
        MotorOutput { enabled: false }
    }

    /// Whether the last [`MotorOutput::update`] left the motors enabled.
    pub fn enabled(&self) -> bool {
        self.enabled
    }

    /// The frames for this period.
    pub fn update(&mut self, enable: bool, left_mm_s: f32, right_mm_s: f32) -> MotorFrames {
        let was = core::mem::replace(&mut self.enabled, enable);
        if !enable {
            return stop_frames();
        }
        let mut frames = wheel_frames(left_mm_s, right_mm_s);
        if !was {
            push_frame(&mut frames, REG_CONTROL, &[CONTROL_ENABLE]);
        }
        frames
    }
}

/// The bottom board's motor registers as written by decoded frames: a host-side model for
/// tests and the simulator. Writes auto-increment the address, as the public firmware assumes;
/// registers outside 0x99..=0x9F and read frames are ignored.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BoardModel {
    regs: [u8; 7],
}

impl BoardModel {
    /// All registers 0: motors disabled, powers 0.
    pub const fn new() -> Self {
        BoardModel { regs: [0; 7] }
    }

    /// Decodes one frame and applies it.
    pub fn apply(&mut self, frame: &[u8]) -> Result<Decoded, DecodeError> {
        let d = decode(frame)?;
        if d.head != Head::Read {
            for (k, &b) in d.data.iter().enumerate() {
                let a = usize::from(d.address) + k;
                if let Some(r) = a
                    .checked_sub(usize::from(REG_CONTROL))
                    .and_then(|i| self.regs.get_mut(i))
                {
                    *r = b;
                }
            }
        }
        Ok(d)
    }

    /// [`BoardModel::apply`] to each frame in order.
    pub fn apply_all(&mut self, frames: &MotorFrames) -> Result<(), DecodeError> {
        frames.iter().try_for_each(|f| self.apply(f).map(|_| ()))
    }

    fn reg(&self, a: u8) -> u8 {
        usize::from(a)
            .checked_sub(usize::from(REG_CONTROL))
            .and_then(|i| self.regs.get(i))
            .copied()
            .unwrap_or(0)
    }

    /// The control register holds [`CONTROL_ENABLE`].
    pub fn enabled(&self) -> bool {
        self.reg(REG_CONTROL) & CONTROL_ENABLE != 0
    }

    /// `(left, right)` power registers.
    pub fn powers(&self) -> (i16, i16) {
        let w = |a: u8| i16::from_le_bytes([self.reg(a), self.reg(a.wrapping_add(1))]);
        (w(REG_POWER_LEFT), w(REG_POWER_RIGHT))
    }

    /// The powers the wheels actually get: the registers when enabled, else 0.
    pub fn wheel_powers(&self) -> (i16, i16) {
        if self.enabled() {
            self.powers()
        } else {
            (0, 0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn bytes(f: &MotorFrame) -> &[u8] {
        f.as_slice()
    }

    #[test]
    fn constants_are_what_the_public_firmware_uses() {
        assert_eq!(
            (HEAD_WRITE, HEAD_WRITE_ACK, HEAD_READ, END),
            (0x78, 0x7C, 0x7D, 0x7F)
        );
        assert_eq!((ESCAPE_OFFSET, REPLY_OK, REPLY_ERROR), (0x20, 0x7B, 0x7A));
        assert_eq!(
            (REG_CONTROL, REG_POWER_LEFT, REG_POWER_RIGHT, REG_POWER_INC),
            (0x99, 0x9A, 0x9C, 0x9E)
        );
        assert_eq!((CONTROL_ENABLE, BAUD), (0x80, 38_400));
        // the escaped forms do not collide with reserved bytes
        for h in [HEAD_WRITE, HEAD_WRITE_ACK, HEAD_READ] {
            assert!(!is_reserved(h - ESCAPE_OFFSET));
            assert!(!is_reserved(END - ESCAPE_OFFSET));
        }
        assert_eq!(Reply::from_byte(0x7B), Some(Reply::Ok));
        assert_eq!(Reply::from_byte(0x7A), Some(Reply::Error));
        assert_eq!(Reply::from_byte(0x78), None);
    }

    #[test]
    fn plain_frames_are_head_address_data_end() {
        let f = encode(Head::Write, 0x99, &[0x80]).unwrap();
        assert_eq!(bytes(&f), &[0x78, 0x99, 0x80, 0x7F]);
        let f = encode(Head::WriteAck, 0x9E, &[0x05, 0xFB]).unwrap();
        assert_eq!(bytes(&f), &[0x7C, 0x9E, 0x05, 0xFB, 0x7F]);
        let f = encode(Head::Read, 0x20, &[]).unwrap();
        assert_eq!(bytes(&f), &[0x7D, 0x20, 0x7F]);
    }

    #[test]
    fn data_equal_to_the_head_or_end_is_escaped() {
        // head 0x78: 0x78 → 78 58, 0x7F → 78 5F; other heads pass as they are
        let f = encode(Head::Write, 0x9A, &[0x78, 0x7F, 0x7C, 0x7D, 0x58]).unwrap();
        assert_eq!(
            bytes(&f),
            &[0x78, 0x9A, 0x78, 0x58, 0x78, 0x5F, 0x7C, 0x7D, 0x58, 0x7F]
        );
        // head 0x7C escapes 0x7C (→ 7C 5C) but not 0x78
        let f = encode(Head::WriteAck, 0x9A, &[0x7C, 0x78, 0x7F]).unwrap();
        assert_eq!(bytes(&f), &[0x7C, 0x9A, 0x7C, 0x5C, 0x78, 0x7C, 0x5F, 0x7F]);
    }

    #[test]
    fn reserved_addresses_and_long_data_are_refused() {
        for a in [0x78, 0x7C, 0x7D, 0x7F] {
            assert_eq!(
                encode(Head::Write, a, &[1]),
                Err(EncodeError::ReservedAddress(a))
            );
        }
        assert_eq!(
            encode(Head::Write, 0x9A, &[0; MAX_DATA + 1]),
            Err(EncodeError::TooMuchData { len: MAX_DATA + 1 })
        );
        // the longest frame fits
        let f = encode(Head::Write, 0x9A, &[0x7F; MAX_DATA]).unwrap();
        assert_eq!(f.len(), FRAME_CAP);
    }

    #[test]
    fn decode_inverts_encode() {
        let d = decode(&[0x78, 0x9A, 0x78, 0x58, 0x01, 0x78, 0x5F, 0x7F]).unwrap();
        assert_eq!(d.head, Head::Write);
        assert_eq!(d.address, 0x9A);
        assert_eq!(d.data.as_slice(), &[0x78, 0x01, 0x7F]);
    }

    #[test]
    fn malformed_frames_are_rejected() {
        use DecodeError::*;
        assert_eq!(decode(&[]), Err(Empty));
        assert_eq!(decode(&[0x42, 0x9A, 0x7F]), Err(UnknownHead(0x42)));
        assert_eq!(decode(&[0x78]), Err(MissingAddress));
        assert_eq!(decode(&[0x78, 0x7F]), Err(ReservedAddress(0x7F)));
        assert_eq!(decode(&[0x78, 0x9A, 0x01]), Err(MissingEnd));
        assert_eq!(decode(&[0x78, 0x9A, 0x01, 0x78]), Err(MissingEnd));
        // 0x78 0x01 would unescape to 0x21: not an escape
        assert_eq!(
            decode(&[0x78, 0x9A, 0x00, 0x78, 0x01, 0x7F]),
            Err(BadEscape { at: 3 })
        );
        // escaping the head of *another* frame kind is not valid here
        assert_eq!(
            decode(&[0x78, 0x9A, 0x78, 0x5C, 0x7F]),
            Err(BadEscape { at: 2 })
        );
        assert_eq!(
            decode(&[0x78, 0x9A, 0x01, 0x7F, 0x00]),
            Err(TrailingBytes { at: 4 })
        );
        // head, address, MAX_DATA + 1 data bytes, end
        let mut long = [0x01u8; MAX_DATA + 4];
        long[0] = 0x78;
        long[1] = 0x9A;
        long[MAX_DATA + 3] = 0x7F;
        assert_eq!(decode(&long), Err(TooMuchData));
        assert!(decode(&long[..MAX_DATA + 3]).is_err());
    }

    #[test]
    fn power_scales_rounds_and_saturates() {
        assert_eq!(power(0.0), 0);
        assert_eq!(power(100.0), 250); // the public firmware's wander power
        assert_eq!(power(-100.0), -250);
        assert_eq!(power(0.2), 1); // 0.5 rounds away from zero
        assert_eq!(power(-0.2), -1);
        assert_eq!(power(0.1), 0);
        assert_eq!(power(399.9), 1000);
        assert_eq!(power(1e9), MAX_POWER);
        assert_eq!(power(-1e9), -MAX_POWER);
        assert_eq!(power(f32::INFINITY), MAX_POWER);
        assert_eq!(power(f32::NEG_INFINITY), -MAX_POWER);
        assert_eq!(power(f32::NAN), 0);
    }

    #[test]
    fn wheel_frames_are_byte_exact() {
        // 120 mm/s → 300 = 0x012C; −120 → −300 = 0xFED4
        let f = wheel_frames(120.0, -120.0);
        assert_eq!(f.len(), 1);
        assert_eq!(bytes(&f[0]), &[0x78, 0x9A, 0x2C, 0x01, 0xD4, 0xFE, 0x7F]);
        let f = wheel_frames_with(WheelLayout::PerWheel, 120.0, -120.0);
        assert_eq!(f.len(), 2);
        assert_eq!(bytes(&f[0]), &[0x78, 0x9A, 0x2C, 0x01, 0x7F]);
        assert_eq!(bytes(&f[1]), &[0x78, 0x9C, 0xD4, 0xFE, 0x7F]);
    }

    #[test]
    fn wheel_powers_with_reserved_low_bytes_are_escaped() {
        // 48 mm/s → 120 = 0x0078 (low byte = head); 50.8 mm/s → 127 = 0x007F (low byte = end)
        assert_eq!(power(48.0), 0x78);
        assert_eq!(power(50.8), 0x7F);
        let f = wheel_frames(48.0, 50.8);
        assert_eq!(
            bytes(&f[0]),
            &[0x78, 0x9A, 0x78, 0x58, 0x00, 0x78, 0x5F, 0x00, 0x7F]
        );
        // −52 mm/s → −130 = 0xFF7E: nothing to escape; −51.6 → −129 = 0xFF7F: low byte escaped
        assert_eq!(power(-51.6), -129);
        let f = wheel_frames(-52.0, -51.6);
        assert_eq!(
            bytes(&f[0]),
            &[0x78, 0x9A, 0x7E, 0xFF, 0x78, 0x5F, 0xFF, 0x7F]
        );
        // NaN is a stop, not garbage
        let f = wheel_frames(f32::NAN, 10_000.0);
        assert_eq!(bytes(&f[0]), &[0x78, 0x9A, 0x00, 0x00, 0xE8, 0x03, 0x7F]);
    }

    #[test]
    fn enable_and_stop_sequences_are_byte_exact() {
        let e = enable_sequence();
        assert_eq!(e.len(), 2);
        assert_eq!(bytes(&e[0]), &[0x78, 0x9A, 0, 0, 0, 0, 0x7F]);
        assert_eq!(bytes(&e[1]), &[0x78, 0x99, 0x80, 0x7F]);
        let s = stop_frames();
        assert_eq!(s.len(), 2);
        assert_eq!(bytes(&s[0]), &[0x78, 0x9A, 0, 0, 0, 0, 0x7F]);
        assert_eq!(bytes(&s[1]), &[0x78, 0x99, 0x00, 0x7F]);
    }

    #[test]
    fn motor_output_enables_once_and_repeats_stops() {
        let mut m = MotorOutput::new();
        let f = m.update(false, 100.0, 100.0);
        assert_eq!(f, stop_frames());
        assert_eq!(m.update(false, 100.0, 100.0), stop_frames());
        // enabling: the new powers first, then the enable
        let f = m.update(true, 100.0, 100.0);
        assert_eq!(f.len(), 2);
        assert_eq!(bytes(&f[0]), &[0x78, 0x9A, 0xFA, 0x00, 0xFA, 0x00, 0x7F]);
        assert_eq!(bytes(&f[1]), &[0x78, 0x99, 0x80, 0x7F]);
        assert!(m.enabled());
        // then powers only
        assert_eq!(m.update(true, 100.0, 100.0), wheel_frames(100.0, 100.0));
        assert_eq!(m.update(false, 100.0, 100.0), stop_frames());
        assert!(!m.enabled());
    }

    #[test]
    fn board_model_follows_the_frames() {
        let mut b = BoardModel::new();
        assert_eq!((b.enabled(), b.wheel_powers()), (false, (0, 0)));
        b.apply_all(&enable_sequence()).unwrap();
        assert!(b.enabled());
        b.apply_all(&wheel_frames(48.0, -51.6)).unwrap();
        assert_eq!(b.wheel_powers(), (120, -129));
        b.apply_all(&wheel_frames_with(WheelLayout::PerWheel, -4.0, 8.0))
            .unwrap();
        assert_eq!(b.wheel_powers(), (-10, 20));
        // the public firmware's combined write from the control register
        b.apply(&[0x78, 0x99, 0x81, 0x01, 0x00, 0x02, 0x00, 0x7F])
            .unwrap();
        assert_eq!((b.enabled(), b.powers()), (true, (1, 2)));
        // other registers and reads leave the motors alone
        b.apply(&[0x78, 0x12, 0x80, 0x7F]).unwrap();
        b.apply(&[0x7D, 0x99, 0x00, 0x7F]).unwrap();
        assert_eq!(b.powers(), (1, 2));
        b.apply_all(&stop_frames()).unwrap();
        assert_eq!(
            (b.enabled(), b.powers(), b.wheel_powers()),
            (false, (0, 0), (0, 0))
        );
        assert!(b.apply(&[0x78]).is_err());
    }

    proptest! {
        #[test]
        fn round_trip(h in 0usize..3, address in any::<u8>(),
                      data in prop::collection::vec(any::<u8>(), 0..=MAX_DATA)) {
            let head = [Head::Write, Head::WriteAck, Head::Read][h];
            match encode(head, address, &data) {
                Ok(f) => {
                    prop_assert!(!is_reserved(address));
                    // END only last; the head only first or as an escape prefix
                    prop_assert!(f[..f.len() - 1].iter().all(|&b| b != END));
                    let d = decode(&f).unwrap();
                    prop_assert_eq!(d.head, head);
                    prop_assert_eq!(d.address, address);
                    prop_assert_eq!(d.data.as_slice(), &data[..]);
                }
                Err(e) => prop_assert_eq!(e, EncodeError::ReservedAddress(address)),
            }
        }

        #[test]
        fn decode_never_panics(bytes in prop::collection::vec(
            prop::sample::select(&[0x78u8, 0x7C, 0x7D, 0x7F, 0x58, 0x5F, 0x5C, 0x9A, 0x00][..]),
            0..24,
        )) {
            if let Ok(d) = decode(&bytes) {
                // every accepted frame is canonical
                let again = encode(d.head, d.address, &d.data).unwrap();
                prop_assert_eq!(again.as_slice(), &bytes[..]);
            }
        }

        #[test]
        fn speeds_reach_the_board(l in any::<f32>(), r in any::<f32>()) {
            let mut b = BoardModel::new();
            b.apply_all(&enable_sequence()).unwrap();
            b.apply_all(&wheel_frames(l, r)).unwrap();
            prop_assert_eq!(b.wheel_powers(), (power(l), power(r)));
            prop_assert!(power(l).abs() <= MAX_POWER);
        }
    }
}
