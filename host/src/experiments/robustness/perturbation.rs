//! The perturbations: each one thing a real lab or robot changes, by a magnitude with a
//! physical source (docs/robustness.md gives the reasoning at length).

use serde::{Deserialize, Serialize};

use alvs_sim::{
    CameraMount, FloorPattern, GainModel, HeadingSource, LightGradient, MotorParams, SensorNoise,
    SimOptions,
};

/// The textured floor: a grain of 5–80 mm, 10 % RMS. A choice, not a measurement: the grain
/// and speckle of a laminate, lino or plywood floor, whose grey visibly varies by some 10 % over
/// a few cm; enough to cross the floor line's 12-grey-level tolerance on the replica's dark
/// floor (grey 60–80) now and then, as a real patterned floor would.
pub const FLOOR_TEXTURE: FloorPattern = FloorPattern {
    contrast: 0.10,
    finest_mm: 5.0,
    coarsest_mm: 80.0,
    seed: 0,
};

/// The shaded floor: patches 10–40 cm across, 10 % RMS (±20 % at two standard deviations:
/// issue 29's probe of a floor shaded by ±10–20 %): boards of a slightly different grey, wear,
/// stains, reflections of the lamps.
pub const FLOOR_SHADE: FloorPattern = FloorPattern {
    contrast: 0.10,
    finest_mm: 100.0,
    coarsest_mm: 400.0,
    seed: 0,
};

/// Change of the camera's height, mm: the board's camera height is not published
/// (docs/hardware.md); the simulator's 20 mm puts the lens on the sense board a few mm below the
/// top of the 28 mm body, and ±5 mm spans where on that stack it can sit. The floor
/// line's distance scales with it (row 52: 85 mm ahead at 20 mm high, 106 at 25, 64 at 15).
pub const CAMERA_HEIGHT_CHANGE_MM: f64 = 5.0;

/// Change of the camera's pitch, degrees: the body rests on its two wheels and front and rear
/// skids; 1.5 mm of difference between the skids (wear, a hair, the module soldered slightly
/// askew) over the 42 mm body tilts it by 2°, which moves the horizon by `f · tan 2°` = 2.4 rows.
pub const PITCH_CHANGE_DEG: f64 = 2.0;

/// The lighting gradient: a lamp 2 m above one end of the 1.3 m arena lights it `cos³`-wise,
/// 1.7 times as brightly at that end as at the far one (`(1 + (1.31/2)²)^{3/2}`); ±25 % about
/// the middle is that to first order.
pub const LIGHTING: LightGradient = LightGradient { amplitude: 0.25 };

/// Motor asymmetry: the right wheel 5 % slower for the same power. The Colias basic unit drives
/// its micro gear motors open loop (a power per wheel, docs/hardware.md, no encoders), and the
/// datasheets of such motors commonly allow ±10 % on the no-load speed between units; 5 % is a
/// pair well inside that. Open loop it turns a straight run into a circle of 0.94 m radius.
pub const MOTOR_ASYMMETRY: f64 = 0.05;

/// Chance that a frame after a processed one is lost: 5 % (1.5 a second), three times the
/// worst rate the virtual board measured for the firmware today (0.5 a second on the grating
/// clip at 1 % blanking, docs/firmware.md) and a third of what the hand-off at VSYNC lost before
/// the row backlog (≤ 4.5 a second).
pub const FRAME_LOSS: f64 = 0.05;

/// The steady camera: no frame-to-frame gain change. The simulator's camera draws a global gain
/// of 0.3 % standard deviation every frame (`SensorNoise::typical`, [`GainModel::Clips`]), what
/// the recorded real clips' cameras measure (docs/world.md). An OV7670 whose automatic exposure
/// and gain are switched off (`COM8`'s AEC and AGC bits) under steady light has none; this row
/// shows how much each controller's figures rest on that draw.
pub const STEADY_GAIN: GainModel = GainModel::Steady;

/// The documented automatic exposure ([`alvs_sim::Aec::OV7670`]) in place of the draw: the
/// exposure holds while the view's mean grey stays in the sensor's stable region and steps by
/// 1/16 a frame when it leaves it, as the firmware's `COM8` 0x8F (AEC and AGC on) runs it.
pub const AEC_GAIN: GainModel = GainModel::Aec;

/// The worlds' camera before the real clips' cameras were measured: a global gain of 2 %
/// standard deviation every frame ([`alvs_sim::aec::JITTER_GAIN_SIGMA`]), a plausible figure for
/// automatic gain and lamp flicker that no recording measures, seven times the clips' figure.
pub const JITTER_GAIN: GainModel = GainModel::Jitter;

/// One perturbation of the world, the camera, the motors or the firmware's loop.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Perturbation {
    /// Nothing changed: the reference every other row is read against.
    None,
    /// A grain on the floor, 5–80 mm, 10 % RMS ([`FLOOR_TEXTURE`]).
    FloorTexture,
    /// Patches of shade on the floor, 10–40 cm, 10 % RMS ([`FLOOR_SHADE`]).
    FloorShade,
    /// The camera 5 mm higher ([`CAMERA_HEIGHT_CHANGE_MM`]).
    CameraHigh,
    /// The camera 5 mm lower.
    CameraLow,
    /// The camera pitched 2° up ([`PITCH_CHANGE_DEG`]).
    PitchUp,
    /// The camera pitched 2° down.
    PitchDown,
    /// The light falls by ±25 % along the arena ([`LIGHTING`]).
    Lighting,
    /// The right wheel 5 % slower ([`MOTOR_ASYMMETRY`]).
    MotorAsymmetry,
    /// The firmware's odometry heading in place of the gyro ([`HeadingSource::Odometry`]).
    Odometry,
    /// 5 % of the frames after a processed one lost ([`FRAME_LOSS`]).
    DroppedFrames,
    /// The camera's gain fixed: no per-frame gain draw ([`STEADY_GAIN`]).
    CameraSteady,
    /// The sensor's documented automatic exposure in place of the per-frame draw ([`AEC_GAIN`]).
    CameraAec,
    /// A per-frame gain draw of 2 % in place of 0.3 % ([`JITTER_GAIN`]).
    CameraJitter,
}

impl Perturbation {
    /// Every perturbation, the reference first.
    pub const ALL: [Perturbation; 14] = [
        Perturbation::None,
        Perturbation::FloorTexture,
        Perturbation::FloorShade,
        Perturbation::CameraHigh,
        Perturbation::CameraLow,
        Perturbation::PitchUp,
        Perturbation::PitchDown,
        Perturbation::Lighting,
        Perturbation::MotorAsymmetry,
        Perturbation::Odometry,
        Perturbation::DroppedFrames,
        Perturbation::CameraSteady,
        Perturbation::CameraAec,
        Perturbation::CameraJitter,
    ];

    /// Its name on the command line, in tables and in JSON.
    pub const fn name(self) -> &'static str {
        match self {
            Perturbation::None => "none",
            Perturbation::FloorTexture => "floor-texture",
            Perturbation::FloorShade => "floor-shade",
            Perturbation::CameraHigh => "camera-high",
            Perturbation::CameraLow => "camera-low",
            Perturbation::PitchUp => "pitch-up",
            Perturbation::PitchDown => "pitch-down",
            Perturbation::Lighting => "lighting",
            Perturbation::MotorAsymmetry => "motor-asymmetry",
            Perturbation::Odometry => "odometry",
            Perturbation::DroppedFrames => "dropped-frames",
            Perturbation::CameraSteady => "camera-steady",
            Perturbation::CameraAec => "camera-aec",
            Perturbation::CameraJitter => "camera-jitter",
        }
    }

    /// What it changes, by how much, in a few words.
    pub const fn what(self) -> &'static str {
        match self {
            Perturbation::None => "nothing (the reference)",
            Perturbation::FloorTexture => "floor grain 5-80 mm, 10 % RMS",
            Perturbation::FloorShade => "floor shade patches 10-40 cm, 10 % RMS",
            Perturbation::CameraHigh => "camera 25 mm high (+5)",
            Perturbation::CameraLow => "camera 15 mm high (-5)",
            Perturbation::PitchUp => "camera pitched 2 deg up",
            Perturbation::PitchDown => "camera pitched 2 deg down",
            Perturbation::Lighting => "light +-25 % along the arena",
            Perturbation::MotorAsymmetry => "right wheel 5 % slower",
            Perturbation::Odometry => "odometry heading, not the gyro",
            Perturbation::DroppedFrames => "5 % of frames lost",
            Perturbation::CameraSteady => "camera gain fixed (no 0.3 % draw)",
            Perturbation::CameraAec => "OV7670 auto exposure (no 0.3 % draw)",
            Perturbation::CameraJitter => "camera gain drawn at 2 %, not 0.3 %",
        }
    }

    /// The perturbation named `name` (one-line error naming them all).
    pub fn from_name(name: &str) -> anyhow::Result<Perturbation> {
        Perturbation::ALL
            .into_iter()
            .find(|p| p.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = Perturbation::ALL.iter().map(|p| p.name()).collect();
                anyhow::anyhow!(
                    "no perturbation {name:?}; the perturbations are {}",
                    names.join(", ")
                )
            })
    }

    /// Applies it to a robot's motors, its camera's noise and the loop's options; `seed` (the
    /// trial's) seeds the floor patterns, so each seed meets another floor.
    pub fn apply(
        self,
        seed: u64,
        motor: &mut MotorParams,
        noise: &mut SensorNoise,
        options: &mut SimOptions,
    ) {
        let mount = CameraMount::default();
        let render = &mut options.render;
        match self {
            Perturbation::None => {}
            Perturbation::FloorTexture => {
                render.floor_pattern = Some(FloorPattern {
                    seed,
                    ..FLOOR_TEXTURE
                });
            }
            Perturbation::FloorShade => {
                render.floor_pattern = Some(FloorPattern {
                    seed,
                    ..FLOOR_SHADE
                });
            }
            Perturbation::CameraHigh => {
                render.mount.height_mm = mount.height_mm + CAMERA_HEIGHT_CHANGE_MM;
            }
            Perturbation::CameraLow => {
                render.mount.height_mm = mount.height_mm - CAMERA_HEIGHT_CHANGE_MM;
            }
            Perturbation::PitchUp => render.mount.pitch_deg = PITCH_CHANGE_DEG,
            Perturbation::PitchDown => render.mount.pitch_deg = -PITCH_CHANGE_DEG,
            Perturbation::Lighting => render.lighting = Some(LIGHTING),
            Perturbation::MotorAsymmetry => motor.asymmetry = MOTOR_ASYMMETRY,
            Perturbation::Odometry => options.heading = HeadingSource::Odometry,
            Perturbation::DroppedFrames => options.frame_loss = Some(FRAME_LOSS),
            Perturbation::CameraSteady => STEADY_GAIN.apply(noise),
            Perturbation::CameraAec => AEC_GAIN.apply(noise),
            Perturbation::CameraJitter => JITTER_GAIN.apply(noise),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_an_unknown_one_lists_them_all() {
        for p in Perturbation::ALL {
            assert_eq!(Perturbation::from_name(p.name()).unwrap(), p);
            let json = serde_json::to_string(&p).unwrap();
            assert_eq!(json, format!("\"{}\"", p.name()));
        }
        let e = Perturbation::from_name("fog").unwrap_err().to_string();
        assert_eq!(e.lines().count(), 1);
        assert!(
            Perturbation::ALL.iter().all(|p| e.contains(p.name())),
            "{e}"
        );
    }

    /// Every perturbation changes something, each something else, and the reference nothing;
    /// every resulting render option is valid.
    #[test]
    fn each_perturbation_changes_one_thing() {
        let plain = (
            MotorParams::default(),
            SensorNoise::typical(),
            SimOptions::default(),
        );
        let mut seen = Vec::new();
        for p in Perturbation::ALL {
            let (mut motor, mut noise, mut options) = plain;
            p.apply(7, &mut motor, &mut noise, &mut options);
            options.render.check().unwrap();
            let changed = (motor, noise, options);
            assert_eq!(changed == plain, p == Perturbation::None, "{p:?}");
            assert!(!seen.contains(&changed), "{p:?} repeats another");
            seen.push(changed);
        }
    }
}
