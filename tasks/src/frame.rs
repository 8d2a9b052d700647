//! Frame geometry and conventions shared by every stage.
//!
//! A frame is 72 rows x 99 columns of 8-bit luminance, row-major, top row first:
//! `x` = column 0..=98 from the robot's left to its right, `y` = row 0..=71 from top to bottom.
//! The model never flips: the camera driver delivers upright, unmirrored frames (the OV7670's
//! MVFP register does the vertical flip in the sensor, at no CPU cost; see `docs/model.md`).
//! A mirrored image would make the robot escape *towards* threats, so the bring-up checklist
//! checks the sign of the threat centroid first.

/// Columns of the robot's retina.
pub const WIDTH: usize = 99;
/// Rows of the robot's retina.
pub const HEIGHT: usize = 72;
/// Photoreceptors in one frame.
pub const PIXELS: usize = WIDTH * HEIGHT;
/// Horizontal centre of the visual field used by the visuomotor equations (paper: 49).
pub const CENTRE_X: f32 = 49.0;

/// One grey frame, row-major, `frame[y * WIDTH + x]`.
pub type Frame = [u8; PIXELS];

/// Why a buffer is not a frame the model can take.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameError {
    /// The buffer holds `got` bytes, a frame needs exactly [`PIXELS`].
    WrongSize {
        /// Bytes received.
        got: usize,
    },
    /// The source's frames are `width` x `height`; the model takes only 99 x 72.
    WrongDimensions {
        /// Columns of the source.
        width: usize,
        /// Rows of the source.
        height: usize,
    },
}

impl core::fmt::Display for FrameError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            FrameError::WrongSize { got } => {
                write!(f, "a frame is {PIXELS} bytes (99x72 Y8), got {got}")
            }
            FrameError::WrongDimensions { width, height } => write!(
                f,
                "the aLPLC2 network takes 99x72 frames (the Colias retina), not {width}x{height}"
            ),
        }
    }
}

/// Checks that a source of `width` x `height` frames can feed the model.
pub fn check_dimensions(width: usize, height: usize) -> Result<(), FrameError> {
    if width == WIDTH && height == HEIGHT {
        Ok(())
    } else {
        Err(FrameError::WrongDimensions { width, height })
    }
}

/// Borrows a byte slice as a frame, or says why it is not one.
pub fn as_frame(bytes: &[u8]) -> Result<&Frame, FrameError> {
    bytes
        .try_into()
        .map_err(|_| FrameError::WrongSize { got: bytes.len() })
}

/// Index of pixel (`x`, `y`).
#[inline(always)]
pub const fn idx(x: usize, y: usize) -> usize {
    y * WIDTH + x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dimensions_are_checked() {
        assert_eq!(check_dimensions(99, 72), Ok(()));
        assert_eq!(
            check_dimensions(100, 72),
            Err(FrameError::WrongDimensions {
                width: 100,
                height: 72
            })
        );
    }

    #[test]
    fn slices_of_wrong_size_are_rejected() {
        let buf = [0u8; PIXELS + 1];
        assert_eq!(as_frame(&buf[..PIXELS]).map(|f| f.len()), Ok(PIXELS));
        assert_eq!(
            as_frame(&buf),
            Err(FrameError::WrongSize { got: PIXELS + 1 })
        );
    }
}
