//! The OV7670's automatic exposure and gain (AEC/AGC), as its documentation describes it, and
//! the camera's choices of frame-to-frame gain ([`GainModel`]).
//!
//! The sensor's average-based AEC/AGC compares the mean luminance of each frame (`YAVG`, the
//! full window by default: `COM4`/`COM17`) with a *stable operating region* (`AEW` 0x24, `AEB`
//! 0x25) and a wider *control zone* (`VPT` 0x26): inside the stable region it does not adjust
//! at all; inside the control zone it moves the exposure by 1/16 a step; outside it, it doubles
//! or halves it (OmniVision, OV9650 Implementation Guide 1.1, "AEC Convergence Limits"; the
//! OV7675 datasheet 2.0, 4.4.6, "Inside Stable Operating Region, the AEC/AGC does not adjust
//! exposure time and gain anymore"). The firmware leaves those registers at their reset values
//! (`AEW` 0x75, `AEB` 0x63, `VPT` 0xD4, OV7670 datasheet 1.4, register table) and keeps AEC and
//! AGC on (`COM8` 0x8F, `src/camera/ov7670.rs`).
//!
//! What is modelled: one step per frame, applied to the next frame, on the mean of the clipped
//! picture. The region's centre is the mean of the camera's first frame: the simulated greys
//! are what a camera that has settled shows (docs/world.md), so the stable region is placed
//! around the first view, with its reset-value width relative to its centre. Not modelled:
//! exposure and gain as separate controls (both scale the picture), the gain's quantisation,
//! banding.

/// The average-based AEC/AGC: its stable region and control zone, relative to the region's
/// centre, and its step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aec {
    /// Half width of the stable operating region over its centre.
    pub stable: f32,
    /// The exposure's change per frame inside the control zone, relative.
    pub step: f32,
    /// The control zone's lower and upper limits over the stable region's centre; beyond
    /// them the exposure doubles or halves.
    pub zone: (f32, f32),
}

/// `AEW` 0x75 (117), `AEB` 0x63 (99): the stable region's centre 108.
const AEW: f32 = 117.0;
const AEB: f32 = 99.0;
/// `VPT` 0xD4: the control zone `{0xD, 0}` = 208 to `{0x4, 0}` = 64.
const VPT_HIGH: f32 = 208.0;
const VPT_LOW: f32 = 64.0;

impl Aec {
    /// The OV7670 at its reset values: the stable region ±8.3 % (`(AEW − AEB)/(AEW + AEB)`),
    /// steps of 1/16, the control zone 0.59–1.93 of the region's centre.
    pub const OV7670: Aec = Aec {
        stable: (AEW - AEB) / (AEW + AEB),
        step: 1.0 / 16.0,
        zone: (VPT_LOW * 2.0 / (AEW + AEB), VPT_HIGH * 2.0 / (AEW + AEB)),
    };

    /// The exposure's factor for the next frame, given this frame's mean `mean` and the stable
    /// region's centre `centre` (both grey levels).
    pub fn next(&self, mean: f32, centre: f32) -> f32 {
        if !(centre > 0.0 && mean.is_finite()) {
            return 1.0;
        }
        let q = mean / centre;
        if q > self.zone.1 {
            0.5
        } else if q < self.zone.0 {
            2.0
        } else if q > 1.0 + self.stable {
            1.0 - self.step
        } else if q < 1.0 - self.stable {
            1.0 + self.step
        } else {
            1.0
        }
    }
}

/// How a camera's global gain moves from frame to frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GainModel {
    /// A random gain of [`JITTER_GAIN_SIGMA`] drawn every frame, independently: the worlds'
    /// camera until the real clips' cameras were measured, a plausible figure no recording
    /// measures, and not what the sensor's documented AEC does in a steady view.
    Jitter,
    /// No frame-to-frame change: AEC and AGC off (`COM8` bits 0 and 2 cleared once the
    /// exposure has settled) under steady light.
    Steady,
    /// The documented AEC/AGC ([`Aec::OV7670`]): the gain holds while the view's mean stays in
    /// the stable region and steps by 1/16 a frame when it leaves it.
    Aec,
    /// A random gain of [`CLIPS_GAIN_SIGMA`] drawn every frame, independently: what the
    /// cameras of the recorded real clips (`data/clips/real_*`, other cameras than the OV7670)
    /// measure from frame to frame. The worlds' camera
    /// ([`SensorNoise::typical`](crate::SensorNoise::typical)).
    #[default]
    Clips,
}

/// [`GainModel::Jitter`]'s standard deviation, 2 %: a plausible figure for automatic gain and
/// lamp flicker that no recording measures.
pub const JITTER_GAIN_SIGMA: f32 = 0.02;

/// The frame-to-frame gain of the recorded real clips' cameras, standard deviation: 0.08–0.34 %
/// in 8 of the 10 `real_*` clips, median 0.29 % (the least-squares gain over the pixels that
/// barely change; `docs/notes/2026-11-28-camera-gain.md`, "What the recorded clips say").
pub const CLIPS_GAIN_SIGMA: f32 = 0.003;

impl GainModel {
    /// Every model, in the order the command line lists them.
    pub const ALL: [GainModel; 4] = [
        GainModel::Clips,
        GainModel::Jitter,
        GainModel::Steady,
        GainModel::Aec,
    ];

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            GainModel::Jitter => "jitter",
            GainModel::Steady => "steady",
            GainModel::Aec => "aec",
            GainModel::Clips => "clips",
        }
    }

    /// The typical camera ([`SensorNoise::typical`](crate::SensorNoise::typical)) with
    /// `exposure` and this model's gain: what an experiment's `--exposure` and `--camera-gain`
    /// give its tested robot.
    pub fn camera(self, exposure: f32) -> crate::SensorNoise {
        let mut noise = crate::SensorNoise {
            exposure,
            ..crate::SensorNoise::typical()
        };
        self.apply(&mut noise);
        noise
    }

    /// `noise` with this model's gain settings (its pixel noise, exposure and shake kept).
    pub fn apply(self, noise: &mut crate::SensorNoise) {
        let (sigma, aec) = match self {
            GainModel::Jitter => (JITTER_GAIN_SIGMA, None),
            GainModel::Steady => (0.0, None),
            GainModel::Aec => (0.0, Some(Aec::OV7670)),
            GainModel::Clips => (CLIPS_GAIN_SIGMA, None),
        };
        noise.gain_sigma = sigma;
        noise.aec = aec;
    }
}

impl core::fmt::Display for GainModel {
    /// [`GainModel::name`], as the command line's defaults print it.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

impl core::str::FromStr for GainModel {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        GainModel::ALL
            .into_iter()
            .find(|m| m.name() == s.trim())
            .ok_or_else(|| {
                format!("{s:?} is not a camera gain model: clips, jitter, steady or aec")
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reset_values_give_the_documented_region_and_zone() {
        let a = Aec::OV7670;
        assert!((a.stable - 18.0 / 216.0).abs() < 1e-6);
        assert!((a.zone.0 - 64.0 / 108.0).abs() < 1e-6);
        assert!((a.zone.1 - 208.0 / 108.0).abs() < 1e-6);
    }

    #[test]
    fn inside_the_stable_region_the_exposure_holds() {
        let a = Aec::OV7670;
        for m in [100.0, 108.0, 92.0, 95.0] {
            assert_eq!(a.next(m, 100.0), 1.0, "mean {m}");
        }
    }

    #[test]
    fn outside_it_the_exposure_steps_toward_it() {
        let a = Aec::OV7670;
        assert_eq!(a.next(80.0, 100.0), 1.0 + 1.0 / 16.0);
        assert_eq!(a.next(120.0, 100.0), 1.0 - 1.0 / 16.0);
        assert_eq!(a.next(50.0, 100.0), 2.0);
        assert_eq!(a.next(200.0, 100.0), 0.5);
        // no centre yet, or a broken mean: no change
        assert_eq!(a.next(50.0, 0.0), 1.0);
        assert_eq!(a.next(f32::NAN, 100.0), 1.0);
    }

    /// The worlds' camera is the measured one: the typical camera draws the clips' gain, and
    /// `jitter` keeps its own, larger figure.
    #[test]
    fn the_worlds_camera_draws_the_clips_gain() {
        assert_eq!(GainModel::default(), GainModel::Clips);
        assert_eq!(crate::SensorNoise::typical().gain_sigma, CLIPS_GAIN_SIGMA);
        assert_eq!(GainModel::Clips.camera(0.0), crate::SensorNoise::typical());
        assert!(GainModel::Jitter.camera(0.0).gain_sigma > 5.0 * CLIPS_GAIN_SIGMA);
    }

    #[test]
    fn the_names_parse_back() {
        for m in GainModel::ALL {
            assert_eq!(m.name().parse::<GainModel>(), Ok(m));
        }
        assert!("auto".parse::<GainModel>().is_err());
    }
}
