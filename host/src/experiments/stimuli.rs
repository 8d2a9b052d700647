//! Experiment 1, `stimuli` (paper Sec. III-A, Fig. 3): the ALVS robot stands still, its
//! perception running, while obstacle robots move in front of it in five patterns —
//! translating, receding, approaching, two approaching, three approaching. Per scene: the
//! attention fields over time (their tracks and LPLC2 responses), alerts, and the network's
//! layers at the first alert and at the peak response.
//!
//! # Scenes
//!
//! The observer stands at [`OBSERVER`] facing +x in the `lab` (as designed); in another world
//! where the paths of every scene's obstacles fit with the most room ([`alvs_sim::stage`]). The
//! obstacles (ideal motors) are placed by bearing and distance from the observer's centre:
//!
//! | scene | obstacles |
//! |---|---|
//! | `translate` | one, 300 mm ahead, crossing from −30° to +30° at 100 mm/s (left to right) |
//! | `recede` | one, 100 mm ahead, driving straight away at 100 mm/s |
//! | `approach` | one, 500 mm ahead, driving at the observer at 100 mm/s, stopping 100 mm away |
//! | `double` | two at −20° and +20°, 500 mm, approaching as above |
//! | `triple` | three at −25°, 0° and +25°, 500 mm, approaching as above |
//!
//! The observer's view of each obstacle is known (the pinhole model), so the report says how
//! many of the obstacles an attention field sits on (`localised`, at the frame with most
//! fields: a field's column within the obstacle's silhouette, widened by [`LOCALISED_PX`]
//! columns on each side), and how many at once each have a field of their own (`own`: a
//! field sits on one obstacle only in a one-to-one matching, so one wide field over three
//! obstacles counts once; Fig. 3 (e)–(f): "a corresponding number of attention fields").

use std::path::{Path, PathBuf};

use alvs_tasks::model::fsm::Behaviour;
use alvs_tasks::{Frame, Params};
use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};

use super::sweep::{Shard, Sweep};
use super::{parallel, Report};
use crate::replay::{self, Pipeline};
use alvs_sim::canvas::Plot;
use alvs_sim::controller::{Approach, Stationary};
use alvs_sim::render::{column_of_bearing, CAMERA_FORWARD_MM};
use alvs_sim::stage::{Placement, Shape, Stage, Staged};
use alvs_sim::world::ROBOT_RADIUS_MM;
use alvs_sim::{
    BuiltinWorld, GyroParams, Kind, MotorParams, Pose, SensorNoise, Sim, World, FRAME_DT_S,
};

/// Observer's pose as designed (x mm, y mm, heading °): in the left part of the `lab` arena
/// facing the right wall 900 mm away, so every obstacle is seen against the wall texture.
pub const OBSERVER: (f64, f64, f64) = (300.0, 450.0, 0.0);
/// An attention field within an obstacle's silhouette widened by this many columns on each
/// side localises it.
pub const LOCALISED_PX: f32 = 3.0;
/// Distance from the observer's centre at which approaching obstacles stop, mm.
pub const STOP_MM: f64 = 100.0;

/// One obstacle's motion: start bearing (°, positive = right) and distance (mm) from the
/// observer, heading relative to the direction towards the observer (0 = straight at it),
/// speed (mm/s), frames it drives.
#[derive(Debug, Clone, Copy)]
struct Mover {
    bearing_deg: f64,
    distance_mm: f64,
    heading_off_deg: f64,
    speed_mm_s: f64,
    frames: u32,
}

/// A scene of the experiment.
#[derive(Debug, Clone)]
pub struct StimulusScene {
    /// Name (file names, JSON).
    pub name: &'static str,
    /// The obstacles approach the observer.
    pub looming: bool,
    movers: Vec<Mover>,
    /// Camera frames.
    pub frames: u32,
}

impl Mover {
    /// Adds it to `sim` (ideal motors and gyro, blind) by the observer at `me`.
    fn add_to(&self, sim: &mut Sim, me: &Pose) {
        let b = self.bearing_deg.to_radians();
        let (x, y) = me.offset(self.distance_mm * b.cos(), self.distance_mm * b.sin());
        let towards = (me.y_mm - y).atan2(me.x_mm - x).to_degrees();
        let mover = Approach {
            speed_mm_s: self.speed_mm_s as f32,
            frames_left: self.frames,
        };
        sim.add(
            Pose::new(x, y, towards + self.heading_off_deg),
            Box::new(mover),
            MotorParams::ideal(),
            GyroParams::ideal(),
            SensorNoise::default(),
        );
    }

    /// Its start and end in the observer's frame (forward, right), mm, and its heading there,
    /// degrees (0 = the observer's heading).
    fn start_in_frame(&self) -> ((f64, f64), f64) {
        let b = self.bearing_deg.to_radians();
        let (f, r) = (self.distance_mm * b.cos(), self.distance_mm * b.sin());
        let towards = (-r).atan2(-f).to_degrees();
        ((f, r), towards + self.heading_off_deg)
    }

    /// The path its body sweeps, in the observer's frame.
    fn path(&self) -> Shape {
        let ((f, r), heading) = self.start_in_frame();
        let length = self.speed_mm_s * f64::from(self.frames) * FRAME_DT_S;
        let h = heading.to_radians();
        Shape::Path {
            from: (f, r),
            to: (f + length * h.cos(), r + length * h.sin()),
        }
    }
}

/// An obstacle approaching from `bearing_deg`, 500 mm away, to [`STOP_MM`].
fn approacher(bearing_deg: f64) -> Mover {
    let (d, v) = (500.0, 100.0);
    Mover {
        bearing_deg,
        distance_mm: d,
        heading_off_deg: 0.0,
        speed_mm_s: v,
        frames: ((d - STOP_MM) / v * 30.0).round() as u32,
    }
}

/// The five scenes of Fig. 3.
pub fn scenes() -> Vec<StimulusScene> {
    let ahead = 300.0f64;
    let y0 = ahead * (-30f64).to_radians().tan();
    vec![
        StimulusScene {
            name: "translate",
            looming: false,
            movers: vec![Mover {
                bearing_deg: -30.0,
                distance_mm: ahead.hypot(y0),
                // heading +90° (towards the observer's right): the line of sight back to the
                // observer points at 150°
                heading_off_deg: -60.0,
                speed_mm_s: 100.0,
                frames: 105,
            }],
            frames: 120,
        },
        StimulusScene {
            name: "recede",
            looming: false,
            movers: vec![Mover {
                bearing_deg: 0.0,
                distance_mm: 100.0,
                heading_off_deg: 180.0,
                speed_mm_s: 100.0,
                frames: 90,
            }],
            frames: 105,
        },
        StimulusScene {
            name: "approach",
            looming: true,
            movers: vec![approacher(0.0)],
            frames: 135,
        },
        StimulusScene {
            name: "double",
            looming: true,
            movers: vec![approacher(-20.0), approacher(20.0)],
            frames: 135,
        },
        StimulusScene {
            name: "triple",
            looming: true,
            movers: vec![approacher(-25.0), approacher(0.0), approacher(25.0)],
            frames: 135,
        },
    ]
}

/// What to run.
#[derive(Debug, Clone)]
pub struct StimuliConfig {
    /// Seed of the camera noise.
    pub seed: u64,
    /// ALVS model parameters.
    pub params: Params,
    /// Motion parameters of the controllers (`--fsm NAME=VALUE`).
    pub fsm: alvs_tasks::model::fsm::FsmParams,
    /// The world.
    pub world: BuiltinWorld,
    /// Wall texture specification; `None`: the world's own walls.
    pub background: Option<String>,
    /// Camera exposure as a fraction of the 33 ms frame period (0 = instantaneous snapshots,
    /// the default; 1 = the whole period): motion during the exposure blurs the picture
    /// ([`alvs_sim::SensorNoise::exposure`]).
    pub exposure: f32,
    /// How the camera's gain moves from frame to frame (`--camera-gain`, [`alvs_sim::GainModel`]).
    pub gain: alvs_sim::GainModel,
}

impl Default for StimuliConfig {
    fn default() -> Self {
        StimuliConfig {
            seed: 1,
            params: Params::default(),
            fsm: alvs_tasks::model::fsm::FsmParams::default(),
            world: BuiltinWorld::Fu2019,
            background: None,
            exposure: 0.0,
            gain: alvs_sim::GainModel::default(),
        }
    }
}

impl StimuliConfig {
    /// The stage: the observer standing and every scene's obstacles' paths.
    pub fn stage() -> Stage {
        let mut shapes = vec![Shape::Path {
            from: (0.0, 0.0),
            to: (0.0, 0.0),
        }];
        shapes.extend(
            scenes()
                .iter()
                .flat_map(|s| s.movers.iter().map(Mover::path)),
        );
        Stage { shapes }
    }

    /// Where the observer stands in the world (whether it fits is
    /// [`StimuliConfig::validate`]'s).
    pub fn placement(&self) -> Placement {
        Self::stage().place(&self.world.world(), observer())
    }

    /// Checks the configuration, the background and that the stage fits (one error line);
    /// gives the world with its walls and where the observer stands.
    pub fn validate(&self) -> Result<Staged> {
        super::validate_setup(&[Kind::Alvs], &self.params)?;
        let what = "the stimuli's stage";
        self.placement()
            .staged(self.world, self.background.as_deref(), what)
    }

    /// The background the walls show.
    pub fn background(&self) -> &str {
        self.world.background(self.background.as_deref())
    }
}

/// An attention field's sample: `[frame, x, y, lplc2]`.
pub type TrackPoint = [u32; 4];

/// One attention field over its life.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Track {
    /// The field's id.
    pub id: u32,
    /// Its samples.
    pub points: Vec<TrackPoint>,
}

/// One scene's outcome.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneResult {
    /// Scene name.
    #[serde(deserialize_with = "scene_name")]
    pub name: super::sweep::StaticName,
    /// Obstacles.
    pub objects: usize,
    /// The obstacles approach.
    pub looming: bool,
    /// Frames.
    pub frames: u32,
    /// Frames with an alert.
    pub alert_frames: u32,
    /// First alert; `null` without one.
    pub first_alert_frame: Option<u32>,
    /// Frames in short mode (`ΣLPLC2 > T_s`).
    pub short_mode_frames: u32,
    /// Most attention fields at once.
    pub max_afs: usize,
    /// Largest `ΣLPLC2` and its frame.
    pub peak_lplc2_sum: u32,
    /// See `peak_lplc2_sum`.
    pub peak_frame: u32,
    /// Obstacles with an attention field on them, at the (last) frame with most fields.
    pub localised: usize,
    /// Most obstacles at once that each have an attention field of their own on them (a
    /// one-to-one matching of fields to obstacles, "on" as for `localised`).
    #[serde(default)]
    pub own: usize,
    /// Frames in which every obstacle in view has a field of its own (some in view).
    #[serde(default)]
    pub own_frames: u32,
    /// Every attention field's track.
    pub tracks: Vec<Track>,
    /// Each obstacle's image column per frame (`null` when out of view).
    pub object_columns: Vec<Vec<Option<f32>>>,
    /// The observer's camera frames, for the layer pictures; not in the JSON, so a merged
    /// run (`alvs merge`) has none and draws only the tracks.
    #[serde(skip)]
    observed: Vec<Frame>,
}

/// Reads a scene's name back as the program's own (see [`super::sweep::static_name`]).
fn scene_name<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<&'static str, D::Error> {
    let s = String::deserialize(d)?;
    scenes()
        .iter()
        .map(|sc| sc.name)
        .find(|n| *n == s)
        .ok_or_else(|| serde::de::Error::custom(format!("unknown scene {s:?}")))
}

/// Everything a run produced.
#[derive(Debug, Clone)]
pub struct StimuliReport {
    /// What ran.
    pub config: StimuliConfig,
    /// Where the observer stood.
    pub placement: Placement,
    /// One per scene.
    pub scenes: Vec<SceneResult>,
    /// Wall-clock seconds.
    pub wall_clock_s: f64,
}

/// Runs the five scenes on `jobs` threads (0 = all cores).
pub fn run(config: &StimuliConfig, jobs: usize) -> Result<StimuliReport> {
    super::sweep::run_all(config, jobs, &|_| {})
}

/// Trial `k` is scene `k` (translate, recede, approach, double, triple).
impl Sweep for StimuliConfig {
    const NAME: &'static str = "stimuli";
    type Trial = SceneResult;
    type Report = StimuliReport;

    fn trial_count(&self) -> usize {
        scenes().len()
    }

    fn run_slice(
        &self,
        jobs: usize,
        shard: Option<Shard>,
        _progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<(usize, SceneResult)>> {
        let staged = self.validate()?;
        let all = scenes();
        parallel::slice(all.len(), jobs, shard, |i| {
            run_scene(&all[i], self, &staged.world, staged.placement.pose)
        })?
        .into_iter()
        .map(|(i, r)| r.map(|r| (i, r)))
        .collect()
    }

    fn report(&self, scenes: Vec<SceneResult>, wall_clock_s: f64, _jobs: usize) -> StimuliReport {
        StimuliReport {
            config: self.clone(),
            placement: self.placement(),
            scenes,
            wall_clock_s,
        }
    }
}

fn observer() -> Pose {
    Pose::new(OBSERVER.0, OBSERVER.1, OBSERVER.2)
}

fn run_scene(
    scene: &StimulusScene,
    config: &StimuliConfig,
    world: &World,
    me: Pose,
) -> Result<SceneResult> {
    let mut sim = Sim::new(world, config.seed);
    // The observer must see (a blind scripted robot's frame is not rendered); its own copy of
    // the model runs beside the one recorded here, and its wheels stay still.
    let stand = Stationary(Kind::Alvs.make(config.params, config.fsm, 0));
    sim.add(
        me,
        Box::new(stand),
        MotorParams::ideal(),
        GyroParams::ideal(),
        config.gain.camera(config.exposure),
    );
    for m in &scene.movers {
        m.add_to(&mut sim, &me);
    }
    let mut pipe = Pipeline::new(config.params, config.fsm, Behaviour::Escape)?;
    let mut observed: Vec<Frame> = Vec::with_capacity(scene.frames as usize);
    let mut tracks: Vec<Track> = Vec::new();
    let mut object_columns = vec![Vec::new(); scene.movers.len()];
    let (mut alerts, mut shorts, mut first) = (0, 0, None);
    let (mut max_afs, mut peak, mut peak_frame, mut localised) = (0, 0, 0, 0);
    let (mut own, mut own_frames) = (0, 0);
    for f in 0..scene.frames {
        // columns of the obstacles as the frame about to be rendered shows them
        let cam = {
            let (x, y) = me.offset(CAMERA_FORWARD_MM, 0.0);
            Pose::new(x, y, me.heading_deg)
        };
        // (centre, left edge, right edge) columns of each obstacle's silhouette
        let silhouettes: Vec<Option<(f32, f32, f32)>> = sim.physics.poses()[1..]
            .iter()
            .map(|p| {
                let b = cam.bearing_to(p.x_mm, p.y_mm);
                let d = cam.distance_to(p).max(ROBOT_RADIUS_MM + 1.0);
                let half = (ROBOT_RADIUS_MM / d).asin().to_degrees();
                let col = |a: f64| column_of_bearing(a.clamp(-89.0, 89.0)) as f32;
                (b.abs() < 35.5).then(|| (col(b), col(b - half), col(b + half)))
            })
            .collect();
        let columns: Vec<Option<f32>> = silhouettes.iter().map(|s| s.map(|s| s.0)).collect();
        let mut frame: Option<Frame> = None;
        sim.step_with(|i, fr, _| {
            if i == 0 {
                frame = Some(*fr);
            }
        });
        let Some(frame) = frame else { continue };
        let (out, json) = pipe.step(&frame);
        observed.push(frame);
        for (k, c) in columns.iter().enumerate() {
            object_columns[k].push(c.map(|v| (v * 10.0).round() / 10.0));
        }
        alerts += u32::from(json.alert);
        shorts += u32::from(json.short_mode);
        if json.alert && first.is_none() {
            first = Some(f);
        }
        if json.lplc2_sum > peak {
            (peak, peak_frame) = (json.lplc2_sum, f);
        }
        for a in out.afs.iter() {
            let point = [f, u32::from(a.x), u32::from(a.y), a.lplc2];
            match tracks.iter_mut().find(|t| t.id == a.id) {
                Some(t) => t.points.push(point),
                None => tracks.push(Track {
                    id: a.id,
                    points: vec![point],
                }),
            }
        }
        let columns: Vec<f32> = out.afs.iter().map(|a| f32::from(a.x)).collect();
        let in_view: Vec<(f32, f32)> = silhouettes
            .iter()
            .flatten()
            .map(|&(_, l, r)| (l, r))
            .collect();
        let matched = own_fields(&in_view, &columns);
        own = own.max(matched);
        own_frames += u32::from(!in_view.is_empty() && matched == in_view.len());
        if out.afs.len() >= max_afs && !out.afs.is_empty() {
            max_afs = out.afs.len();
            localised = in_view
                .iter()
                .filter(|&&o| columns.iter().any(|&c| sits_on(o, c)))
                .count();
        }
    }
    Ok(SceneResult {
        name: scene.name,
        objects: scene.movers.len(),
        looming: scene.looming,
        frames: scene.frames,
        alert_frames: alerts,
        first_alert_frame: first,
        short_mode_frames: shorts,
        max_afs,
        peak_lplc2_sum: peak,
        peak_frame,
        localised,
        own,
        own_frames,
        tracks,
        object_columns,
        observed,
    })
}

impl Report for StimuliReport {
    /// `{"scenes":[{...}, ...]}`.
    fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "scenes": self.scenes,
            "seed": self.config.seed,
            "world": self.config.world.label(),
            "background": self.config.background(),
            "observer": self.placement.json(),
        })
    }

    /// One line per scene.
    fn table(&self) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        let _ = writeln!(
            out,
            "stimuli: standing ALVS robot, obstacle robots moving in front of it (world {}, background {}, seed {}, {:.1} s)",
            self.config.world.label(),
            self.config.background(),
            self.config.seed,
            self.wall_clock_s
        );
        let _ = writeln!(out, "observer {}", self.placement.describe());
        let _ = writeln!(
            out,
            "{:<10} {:>7} {:>7} {:>6} {:>6} {:>11} {:>6} {:>7} {:>9} {:>9} {:>9}",
            "scene",
            "objects",
            "looming",
            "frames",
            "alerts",
            "first alert",
            "short",
            "max AFs",
            "localised",
            "own (fr)",
            "peak sum"
        );
        for s in &self.scenes {
            let _ = writeln!(
                out,
                "{:<10} {:>7} {:>7} {:>6} {:>6} {:>11} {:>6} {:>7} {:>9} {:>9} {:>9}",
                s.name,
                s.objects,
                s.looming,
                s.frames,
                s.alert_frames,
                s.first_alert_frame.map_or("-".into(), |f| f.to_string()),
                s.short_mode_frames,
                s.max_afs,
                format!("{}/{}", s.localised, s.objects),
                format!("{}/{} ({})", s.own, s.objects, s.own_frames),
                s.peak_lplc2_sum
            );
        }
        out
    }

    /// Per scene: `<scene>_tracks.png` (each field's column over time with the obstacles'
    /// columns), `<scene>_trace.png` (LPLC2 per field) and `<scene>_layers_NNNN.png` (the
    /// layers at the first alert and the peak), in `dir`.
    fn write_pictures(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        let mut paths = Vec::new();
        for s in &self.scenes {
            let path = dir.join(format!("{}_tracks.png", s.name));
            tracks_plot(s)
                .render(900, 450)
                .save_png(&path)
                .with_context(|| format!("cannot write {}", path.display()))?;
            paths.push(path);
            if s.observed.is_empty() {
                // a merged run: the camera frames stayed with the shards
                continue;
            }
            replay::run(
                &s.observed,
                self.config.params,
                self.config.fsm,
                Behaviour::Escape,
                Some((dir, &[], s.name)),
                |_| Ok(()),
            )?;
        }
        Ok(paths)
    }
}

/// Column of every attention field and every obstacle over time.
/// Whether a field at `column` sits on the obstacle whose silhouette spans columns
/// `(left, right)`: within it, widened by [`LOCALISED_PX`] on each side.
fn sits_on((left, right): (f32, f32), column: f32) -> bool {
    (left - LOCALISED_PX..=right + LOCALISED_PX).contains(&column)
}

/// How many of the obstacles (`(left, right)` silhouette columns) can each have a field of
/// their own among the fields at `columns`: the largest one-to-one matching, a field matching
/// an obstacle whose silhouette widened by [`LOCALISED_PX`] holds its column
/// ([`crate::multi_target::one_to_one`]).
pub fn own_fields(obstacles: &[(f32, f32)], columns: &[f32]) -> usize {
    let on = |o: usize, f: usize| sits_on(obstacles[o], columns[f]);
    crate::multi_target::one_to_one(obstacles.len(), columns.len(), &on)
}

fn tracks_plot(s: &SceneResult) -> Plot {
    let n = s.frames as usize;
    let mut plot = Plot::new(&format!(
        "{}: attention-field columns (AFn) and obstacle columns (obj)",
        s.name
    ))
    .x_label("frame")
    .y_range(0.0, 98.0);
    for (k, cols) in s.object_columns.iter().enumerate() {
        let ys: Vec<f32> = cols.iter().map(|c| c.unwrap_or(f32::NAN)).collect();
        plot = plot.series(&format!("obj{}", k + 1), &ys);
    }
    for t in s.tracks.iter().take(8) {
        let mut ys = vec![f32::NAN; n];
        for p in &t.points {
            if let Some(y) = ys.get_mut(p[0] as usize) {
                *y = p[1] as f32;
            }
        }
        plot = plot.series(&format!("AF{}", t.id), &ys);
    }
    plot
}

#[cfg(test)]
mod tests {
    use super::*;
    use alvs_sim::stage::MIN_CLEARANCE_MM;

    /// One field over three obstacles localises all three but gives only one a field of its
    /// own; a field per obstacle gives each its own, whatever the order; a field between two
    /// obstacles' widened silhouettes goes to whichever needs it.
    #[test]
    fn each_obstacle_needs_a_field_of_its_own() {
        let three = [(10.0, 20.0), (40.0, 50.0), (70.0, 80.0)];
        assert_eq!(own_fields(&three, &[45.0]), 1);
        assert_eq!(own_fields(&three, &[75.0, 15.0, 45.0]), 3);
        assert_eq!(
            own_fields(&three, &[15.0, 16.0, 45.0]),
            2,
            "two on one obstacle"
        );
        assert_eq!(own_fields(&three, &[]), 0);
        assert_eq!(own_fields(&[], &[15.0]), 0);
        // 22 is on the first (widened to 23) only, 38 on the second only (from 37): with 22
        // taken by the first, the second still gets 38
        assert_eq!(own_fields(&three[..2], &[22.0, 38.0]), 2);
        // a field on both widened silhouettes moves over to free one for the other
        let touching = [(10.0, 20.0), (24.0, 30.0)];
        assert_eq!(own_fields(&touching, &[22.0, 12.0]), 2);
        assert_eq!(own_fields(&touching, &[22.0]), 1);
    }

    /// The stage holds every path the scenes' obstacles drive: simulated in the replica from
    /// where its observer stands, each obstacle's centre stays on its stage path and clear of
    /// every wall and cylinder by the stage's margin.
    #[test]
    fn every_obstacle_drives_its_stage_path_clear_of_the_replica() {
        let config = StimuliConfig::default();
        let (world, me) = (config.world.world(), config.placement().pose);
        for scene in scenes() {
            let mut sim = Sim::new(&world, 1);
            for m in &scene.movers {
                m.add_to(&mut sim, &me);
            }
            for _ in 0..scene.frames {
                sim.step();
                for (p, m) in sim.physics.poses().iter().zip(&scene.movers) {
                    let Shape::Path { from, to } = m.path() else {
                        unreachable!("a mover's path")
                    };
                    let (a, b) = (me.offset(from.0, from.1), me.offset(to.0, to.1));
                    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                    let t = (((p.x_mm - a.0) * dx + (p.y_mm - a.1) * dy) / (dx * dx + dy * dy))
                        .clamp(0.0, 1.0);
                    let off = (a.0 + t * dx - p.x_mm).hypot(a.1 + t * dy - p.y_mm);
                    assert!(off < 0.5, "{}: {off} mm off its path", scene.name);
                    let gap = world.static_distance(p.x_mm, p.y_mm) - ROBOT_RADIUS_MM;
                    assert!(gap >= MIN_CLEARANCE_MM - 1e-6, "{}: {gap} mm", scene.name);
                }
            }
        }
    }
}
