//! What a run gives: per-trial counts and poses, and the per-controller pooled summary.

use super::*;

/// Counts of one kind of contact in a trial or an aggregate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TallyStats {
    /// Encounter episodes.
    pub encounters: u64,
    /// Collision episodes.
    pub collisions: u64,
    /// Encounters in which a collision happened.
    pub collided_encounters: u64,
    /// Encounters without a collision / encounters; `null` without encounters.
    pub success_rate: Option<f64>,
    /// Collisions per simulated minute, whole arena.
    pub collisions_per_minute: f64,
}

impl TallyStats {
    pub(super) fn new(t: &Tally, minutes: f64) -> Self {
        TallyStats {
            encounters: t.encounters,
            collisions: t.collisions,
            collided_encounters: t.collided_encounters,
            success_rate: t.success_rate(),
            collisions_per_minute: t.collisions as f64 / minutes,
        }
    }

    pub(super) fn tally(&self) -> Tally {
        Tally {
            encounters: self.encounters,
            collisions: self.collisions,
            collided_encounters: self.collided_encounters,
        }
    }
}

/// A pose for JSON.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PoseJson {
    /// mm.
    pub x_mm: f64,
    /// mm.
    pub y_mm: f64,
    /// Degrees, positive = clockwise seen from above.
    pub heading_deg: f64,
}

impl From<Pose> for PoseJson {
    fn from(p: Pose) -> Self {
        PoseJson {
            x_mm: p.x_mm,
            y_mm: p.y_mm,
            heading_deg: p.heading_deg,
        }
    }
}

/// A collision, where and when it began.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CollisionMark {
    /// Simulated time, s.
    pub time_s: f64,
    /// The robot (the lower index of a pair).
    pub robot: usize,
    /// The other robot; `null` for the wall.
    pub other_robot: Option<usize>,
    /// Midway between the two centres, or the robot's centre for the wall, mm.
    pub x_mm: f64,
    /// See `x_mm`.
    pub y_mm: f64,
}

/// The outcome of one trial.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Trial {
    /// "alvs", "lgmd2" or "swarm".
    #[serde(deserialize_with = "sweep::static_name")]
    pub controller: sweep::StaticName,
    /// The background specification.
    pub background: String,
    /// Seed of the run.
    pub seed: u64,
    /// Robots in the arena.
    pub robots: usize,
    /// Camera frames simulated (per robot).
    pub frames: u64,
    /// Simulated minutes.
    pub minutes: f64,
    /// Success rate over all encounters (robot–robot and robot–wall); `null` without any.
    pub success_rate: Option<f64>,
    /// All encounters.
    pub encounters: u64,
    /// All collisions.
    pub collisions: u64,
    /// All encounters with a collision.
    pub collided_encounters: u64,
    /// All collisions per simulated minute.
    pub collisions_per_minute: f64,
    /// Between robots.
    pub robot_robot: TallyStats,
    /// Between robots and the wall.
    pub robot_wall: TallyStats,
    /// Physical wall contacts (centre within one radius of a wall).
    pub wall_touches: u64,
    /// Fraction of robot-frames spent pressed against a wall or obstacle (body within
    /// [`WALL_CONTACT_SLACK_MM`] of it): time a robot is stuck rather than exploring.
    pub wall_contact_fraction: f64,
    /// Mean speed of the robots over the trial, mm/s (distance from frame to frame).
    pub mean_speed_mm_s: f64,
    /// Short takeoffs the robots started (ALVS; 0 for LGMD2).
    pub short_takeoffs: u64,
    /// … of them started inside an encounter (a wall within 105 mm or a robot within 126 mm,
    /// centre distances): around a real threat.
    pub short_takeoffs_in_encounter: u64,
    /// Fraction of robot-frames spent in each controller state (sums to 1).
    pub state_fraction: BTreeMap<String, f64>,
    /// Robot-frames spent in each controller state (summed over robots).
    pub state_frames: BTreeMap<String, u64>,
    /// Wall-clock time of the trial, s (the only number that changes between runs).
    pub wall_clock_s: f64,
    /// Where the robots started (the same in every trial of a run).
    pub start_poses: Vec<PoseJson>,
    /// Where they ended.
    pub end_poses: Vec<PoseJson>,
    /// Every collision.
    pub collision_events: Vec<CollisionMark>,
    /// Each robot's positions (x, y) mm, five per simulated second, rounded to 0.1 mm.
    pub trails: Vec<Vec<[f64; 2]>>,
    /// With [`ArenaConfig::trace`]: one CSV line per robot and camera frame, frame-major
    /// (the columns of [`trace_header`] after `controller,background,`); empty otherwise. Not
    /// in the JSON.
    #[serde(skip)]
    pub trace: Vec<String>,
}

/// One controller over all backgrounds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ControllerSummary {
    /// "alvs", "lgmd2" or "swarm".
    pub controller: &'static str,
    /// Trials pooled (one per background).
    pub trials: usize,
    /// Simulated minutes pooled.
    pub minutes: f64,
    /// Success rate over all encounters; `null` without any.
    pub success_rate: Option<f64>,
    /// All encounters.
    pub encounters: u64,
    /// All collisions.
    pub collisions: u64,
    /// All encounters with a collision.
    pub collided_encounters: u64,
    /// All collisions per simulated minute (per arena).
    pub collisions_per_minute: f64,
    /// Between robots.
    pub robot_robot: TallyStats,
    /// Between robots and the wall.
    pub robot_wall: TallyStats,
    /// Physical wall contacts.
    pub wall_touches: u64,
    /// Fraction of robot-frames pressed against a wall.
    pub wall_contact_fraction: f64,
    /// Mean speed of the robots, mm/s.
    pub mean_speed_mm_s: f64,
    /// Short takeoffs started, all trials.
    pub short_takeoffs: u64,
    /// … of them inside an encounter.
    pub short_takeoffs_in_encounter: u64,
    /// Fraction of robot-frames in each controller state.
    pub state_fraction: BTreeMap<String, f64>,
    /// Success rate per background.
    pub success_rate_by_background: BTreeMap<String, Option<f64>>,
    /// The paper's success rate (Sec. III-C), for reference.
    pub paper_success_rate: Option<f64>,
    /// Wall-clock seconds of its trials, summed.
    pub wall_clock_s: f64,
}

/// Everything a run produced.
#[derive(Debug, Clone)]
pub struct ArenaReport {
    /// What ran.
    pub config: ArenaConfig,
    /// Trials, controller-major in the order of the configuration.
    pub trials: Vec<Trial>,
    /// One per controller, in the order of the configuration.
    pub summaries: Vec<ControllerSummary>,
    /// Wall-clock seconds of the whole run.
    pub wall_clock_s: f64,
    /// Worker threads used.
    pub jobs: usize,
}

/// Pools the trials of one controller.
pub(crate) fn summarise(controller: &'static str, trials: &[&Trial]) -> ControllerSummary {
    let minutes: f64 = trials.iter().map(|t| t.minutes).sum();
    let (mut rr, mut rw) = (Tally::default(), Tally::default());
    let mut state_frames: BTreeMap<String, u64> = BTreeMap::new();
    for t in trials {
        rr = rr.plus(&t.robot_robot.tally());
        rw = rw.plus(&t.robot_wall.tally());
        for (s, n) in &t.state_frames {
            *state_frames.entry(s.clone()).or_insert(0) += n;
        }
    }
    let robot_frames: u64 = state_frames.values().sum();
    let total = rr.plus(&rw);
    let per_min = |n: u64| {
        if minutes > 0.0 {
            n as f64 / minutes
        } else {
            0.0
        }
    };
    ControllerSummary {
        controller,
        trials: trials.len(),
        minutes,
        success_rate: total.success_rate(),
        encounters: total.encounters,
        collisions: total.collisions,
        collided_encounters: total.collided_encounters,
        collisions_per_minute: per_min(total.collisions),
        robot_robot: TallyStats {
            collisions_per_minute: per_min(rr.collisions),
            ..TallyStats::new(&rr, 1.0)
        },
        robot_wall: TallyStats {
            collisions_per_minute: per_min(rw.collisions),
            ..TallyStats::new(&rw, 1.0)
        },
        wall_touches: trials.iter().map(|t| t.wall_touches).sum(),
        // every trial has as many robot-frames, so plain means pool them
        wall_contact_fraction: mean(trials.iter().map(|t| t.wall_contact_fraction)),
        mean_speed_mm_s: mean(trials.iter().map(|t| t.mean_speed_mm_s)),
        short_takeoffs: trials.iter().map(|t| t.short_takeoffs).sum(),
        short_takeoffs_in_encounter: trials.iter().map(|t| t.short_takeoffs_in_encounter).sum(),
        state_fraction: state_frames
            .iter()
            .map(|(s, &n)| (s.clone(), n as f64 / robot_frames.max(1) as f64))
            .collect(),
        success_rate_by_background: trials
            .iter()
            .map(|t| (t.background.clone(), t.success_rate))
            .collect(),
        paper_success_rate: paper_success_rate(controller),
        wall_clock_s: trials.iter().map(|t| t.wall_clock_s).sum(),
    }
}

pub(crate) fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let (n, sum) = v.fold((0usize, 0.0), |(n, s), x| (n + 1, s + x));
    if n == 0 {
        0.0
    } else {
        sum / n as f64
    }
}
