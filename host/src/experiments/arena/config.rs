//! What a run is: its configuration, checked and prepared, and the robots' start poses.

use super::*;

/// What to run.
#[derive(Debug, Clone)]
pub struct ArenaConfig {
    /// Robots in the arena (all running the trial's controller).
    pub robots: usize,
    /// Simulated minutes per trial.
    pub minutes: f64,
    /// The world; its walls show each background in turn, and the robots start clear of its
    /// walls and obstacles.
    pub world: BuiltinWorld,
    /// Wall textures, as [`WallTexture::from_spec`] reads them; one trial per background and
    /// controller. Empty: the world's own ([`BuiltinWorld::default_backgrounds`]: the replica's
    /// ribbed walls in `fu2019`, [`DEFAULT_BACKGROUNDS`] in the `lab`).
    pub backgrounds: Vec<String>,
    /// Controllers to compare.
    pub controllers: Vec<Kind>,
    /// Seed of everything random (start poses, noise, LGMD2's turns).
    pub seed: u64,
    /// ALVS model parameters (ALVS and swarm).
    pub params: Params,
    /// Motion parameters of the controllers (`--fsm NAME=VALUE`).
    pub fsm: alvs_tasks::model::fsm::FsmParams,
    /// Realistic sensors and motors ([`SensorNoise::typical`], default motor lag and noise,
    /// default gyro); `false` gives ideal ones.
    pub noise: bool,
    /// Camera exposure as a fraction of the 33 ms frame period (0 = instantaneous snapshots,
    /// the default): motion during the exposure blurs the picture
    /// ([`alvs_sim::SensorNoise::exposure`]).
    pub exposure: f32,
    /// How the camera's gain moves from frame to frame (`--camera-gain`, [`alvs_sim::GainModel`]).
    pub gain: alvs_sim::GainModel,
    /// Keep every robot's frame-by-frame trace ([`Trial::trace`]) for `--trace`.
    pub trace: bool,
}

impl Default for ArenaConfig {
    /// The paper's setting: 3 robots, 10 minutes, ALVS and LGMD2, seed 1, noise, in the
    /// recorded arena's replica with its own walls.
    fn default() -> Self {
        ArenaConfig {
            robots: 3,
            minutes: 10.0,
            world: BuiltinWorld::Fu2019,
            backgrounds: Vec::new(),
            controllers: vec![Kind::Alvs, Kind::Lgmd2],
            seed: 1,
            params: Params::default(),
            fsm: alvs_tasks::model::fsm::FsmParams::default(),
            noise: true,
            exposure: 0.0,
            gain: alvs_sim::GainModel::default(),
            trace: false,
        }
    }
}

impl ArenaConfig {
    /// Camera frames per trial.
    pub fn frames(&self) -> u64 {
        frames_in(self.minutes)
    }

    /// Checks the configuration (backgrounds readable, robots placeable, ...); the error is one
    /// line. [`run`] checks too; this is for failing before anything else starts.
    pub fn validate(&self) -> Result<()> {
        self.prepare().map(|_| ())
    }

    /// The backgrounds of a run without repeats, in their order: the configuration's, or the
    /// world's own.
    pub fn background_specs(&self) -> Vec<String> {
        let given: Vec<&str> = if self.backgrounds.is_empty() {
            self.world.default_backgrounds().to_vec()
        } else {
            self.backgrounds.iter().map(String::as_str).collect()
        };
        let mut v: Vec<String> = Vec::new();
        for b in given {
            if !v.iter().any(|s| s == b) {
                v.push(b.to_string());
            }
        }
        v
    }

    /// Checks the configuration and parses the backgrounds (one error line per problem).
    pub(super) fn prepare(&self) -> Result<Prepared> {
        ensure!(self.robots >= 1, "--robots must be at least 1");
        ensure!(
            self.minutes.is_finite() && self.minutes > 0.0,
            "--minutes must be a positive number of minutes, got {}",
            self.minutes
        );
        ensure!(
            self.minutes <= MAX_MINUTES,
            "--minutes must be at most {MAX_MINUTES}, got {}",
            self.minutes
        );
        ensure!(
            (0.0..=1.0).contains(&self.exposure),
            "--exposure must be a fraction of the frame period in 0..=1, got {}",
            self.exposure
        );
        crate::experiments::validate_setup(&self.controllers, &self.params)?;
        let backgrounds = self
            .background_specs()
            .into_iter()
            .map(|spec| {
                let t = alvs_sim::texture::parse(&spec)?;
                Ok((spec, t))
            })
            .collect::<Result<Vec<(String, WallTexture)>>>()?;
        let mut controllers: Vec<Kind> = Vec::new();
        for &k in &self.controllers {
            if !controllers.contains(&k) {
                controllers.push(k);
            }
        }
        if self.trace {
            // the trace is kept in memory until the run ends (trials run in parallel)
            let lines = self
                .frames()
                .saturating_mul(self.robots as u64)
                .saturating_mul((backgrounds.len() * controllers.len()) as u64);
            ensure!(
                lines <= MAX_TRACE_LINES,
                "--trace: {lines} lines (≈ {} MB) is more than the {MAX_TRACE_LINES} a run may \
                 trace; shorten --minutes or trace fewer robots, backgrounds or controllers",
                lines.saturating_mul(TRACE_LINE_BYTES) / 1_000_000
            );
        }
        let world = self.world.world();
        let starts = start_poses_among(&world.arena, &world.obstacles, self.robots, self.seed)?;
        let (motor, gyro, mut noise) = alvs_sim::robot_noise(self.noise);
        noise.exposure = self.exposure;
        if self.noise {
            self.gain.apply(&mut noise);
        }
        let controller_seeds = controller_seeds(self.seed, self.robots);
        Ok(Prepared {
            backgrounds,
            controllers,
            starts,
            controller_seeds,
            motor,
            gyro,
            noise,
            frames: self.frames(),
        })
    }
}

/// A checked configuration.
pub(super) struct Prepared {
    pub(super) backgrounds: Vec<(String, WallTexture)>,
    pub(super) controllers: Vec<Kind>,
    pub(super) starts: Vec<Pose>,
    pub(super) controller_seeds: Vec<u64>,
    pub(super) motor: MotorParams,
    pub(super) gyro: GyroParams,
    pub(super) noise: SensorNoise,
    pub(super) frames: u64,
}

/// The seeds of `robots` robots' controllers (LGMD2's random turns) in a run of `seed`: robot
/// `i` takes sub-stream `i` of the seed's controller stream.
pub fn controller_seeds(seed: u64, robots: usize) -> Vec<u64> {
    let root = Rng::new(seed).fork(CONTROLLER_STREAM);
    (0..robots as u64)
        .map(|i| root.fork(i).next_u64())
        .collect()
}

/// `robots` start poses in `arena` for `seed`: uniform positions at least
/// [`START_WALL_CLEARANCE_MM`] from the walls and [`START_SEPARATION_MM`] from each other,
/// uniform headings. Fails (one line) when that many robots do not fit.
pub fn start_poses(arena: &Arena, robots: usize, seed: u64) -> Result<Vec<Pose>> {
    start_poses_among(arena, &[], robots, seed)
}

/// [`start_poses`] in an arena with `obstacles`: a position is also at least
/// [`START_WALL_CLEARANCE_MM`] from every obstacle's surface (outside a robot–obstacle
/// encounter, which counts as one with the wall). Without obstacles the same poses as
/// [`start_poses`].
pub fn start_poses_among(
    arena: &Arena,
    obstacles: &[Obstacle],
    robots: usize,
    seed: u64,
) -> Result<Vec<Pose>> {
    let m = START_WALL_CLEARANCE_MM;
    let sep = START_SEPARATION_MM;
    let (w, h) = (arena.size_x_mm - 2.0 * m, arena.size_y_mm - 2.0 * m);
    let too_many = || {
        anyhow::anyhow!(
            "cannot place {robots} robots in the {} x {} mm arena ({sep} mm apart, {m} mm from \
             the walls); use fewer robots",
            arena.size_x_mm,
            arena.size_y_mm
        )
    };
    if w < 0.0 || h < 0.0 {
        return Err(too_many());
    }
    // Discs of diameter `sep` around the centres fit in the free rectangle grown by sep/2; no
    // packing is denser than the hexagonal one.
    let disc = std::f64::consts::PI * sep * sep / 4.0;
    let most = 0.9069 * (w + sep) * (h + sep) / disc;
    if robots as f64 > most {
        return Err(too_many());
    }
    let root = Rng::new(seed).fork(START_STREAM);
    for attempt in 0..20 {
        let mut rng = root.fork(attempt);
        let mut poses: Vec<Pose> = Vec::with_capacity(robots);
        'robot: while poses.len() < robots {
            for _ in 0..2000 {
                let (x, y) = (m + w * rng.uniform(), m + h * rng.uniform());
                let heading = rng.range(-180.0, 180.0);
                let p = Pose::new(x, y, heading);
                let clear = obstacles.iter().all(|o| o.surface_distance(x, y) >= m);
                if clear && poses.iter().all(|q| q.distance_to(&p) >= sep) {
                    poses.push(p);
                    continue 'robot;
                }
            }
            break;
        }
        if poses.len() == robots {
            return Ok(poses);
        }
    }
    Err(too_many())
}
