//! The experiments' worlds (`--world fu2019|lab`): the staged experiments stand as designed in
//! the `lab` and where their paths are clear in the replica, every figure of the `lab` is what
//! it was before the worlds existed, the replica changes what the robots see and do, and the
//! arena's trial in the replica is the robustness suite's reference trial.

use alvs_host::experiments::evasion::{EvasionConfig, DEFAULT_DISTANCE_MM};
use alvs_host::experiments::stimuli::{self, StimuliConfig};
use alvs_host::experiments::swarm::{self, SwarmConfig};
use alvs_host::experiments::two_threats::{self, TwoThreatConfig};
use alvs_host::experiments::{arena, robustness, Report};
use alvs_sim::encounter::{self, Threat, ESCAPE_ROOM_MM};
use alvs_sim::stage::MIN_CLEARANCE_MM;
use alvs_sim::world::ROBOT_RADIUS_MM;
use alvs_sim::{BuiltinWorld, GainModel, Kind, Pose, World};
use serde_json::Value;

mod common;
use common::alvs;

/// FNV-1a, 64 bits, of a JSON value's compact text (keys sorted): a digest that is the same on
/// every platform and Rust release.
fn digest(v: &Value) -> u64 {
    serde_json::to_string(v)
        .unwrap()
        .bytes()
        .fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        })
}

/// A report's JSON without what may differ between runs or was added with the worlds: the
/// wall-clock times, the configuration echo, and the world and placement keys; and the
/// stimuli's `own` and `own_frames`, added later and computed from the fields' tracks and the
/// obstacles' columns that the digest holds.
fn results(mut v: Value) -> Value {
    fn strip(v: &mut Value) {
        match v {
            Value::Object(m) => {
                for k in [
                    "wall_clock_s",
                    "config",
                    "world",
                    "start",
                    "observer",
                    "own",
                    "own_frames",
                ] {
                    m.remove(k);
                }
                m.values_mut().for_each(strip);
            }
            Value::Array(a) => a.iter_mut().for_each(strip),
            _ => {}
        }
    }
    strip(&mut v);
    v
}

/// A robot's body at `(x, y)` clears every wall and obstacle of `world` by the stage's margin.
fn clear(world: &World, x: f64, y: f64) -> bool {
    world.static_distance(x, y) >= ROBOT_RADIUS_MM + MIN_CLEARANCE_MM - 1e-6
}

/// Every point 1 mm apart on the straight line from `a` to `b` is [`clear`].
fn clear_path(world: &World, a: (f64, f64), b: (f64, f64)) -> bool {
    let n = ((b.0 - a.0).hypot(b.1 - a.1).ceil() as usize).max(1);
    (0..=n).all(|i| {
        let t = i as f64 / n as f64;
        clear(world, a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
    })
}

/// The tested robot's escape room behind `start` is clear: paths every 1° over ±35° of
/// straight back, [`ESCAPE_ROOM_MM`] long.
fn escape_room_clear(world: &World, start: &Pose) -> bool {
    (-35..=35).all(|b| {
        let r = f64::from(180 + b).to_radians();
        let end = start.offset(ESCAPE_ROOM_MM * r.cos(), ESCAPE_ROOM_MM * r.sin());
        clear_path(world, (start.x_mm, start.y_mm), end)
    })
}

#[test]
fn the_staged_experiments_stand_as_designed_in_the_lab() {
    let lab = BuiltinWorld::Lab;
    for distance in [None, Some(60.0), Some(550.0)] {
        let (d, p) = EvasionConfig {
            world: lab,
            distance_mm: distance,
            ..EvasionConfig::default()
        }
        .placement();
        assert!(p.designed, "{p:?}");
        assert_eq!(p.pose, encounter::tested_start());
        assert_eq!(d, distance.unwrap_or(DEFAULT_DISTANCE_MM));
    }
    let p = TwoThreatConfig {
        world: lab,
        ..TwoThreatConfig::default()
    }
    .placement();
    assert!(p.designed && p.pose == encounter::tested_start(), "{p:?}");
    let p = StimuliConfig {
        world: lab,
        ..StimuliConfig::default()
    }
    .placement();
    let (x, y, h) = stimuli::OBSERVER;
    assert!(p.designed && p.pose == Pose::new(x, y, h), "{p:?}");
}

/// In the replica no place holds the evasion's nine paths at 500 mm clear of the cylinders
/// (the best comes within 5 mm of one): the obstacle starts at the longest distance that fits,
/// 450 mm. Every obstacle's path, the tested robot and its escape room are clear of every
/// wall and cylinder by the margin, checked point by point; so are the two threats' paths of
/// 50 runs and the stimuli's observer (its obstacles' paths: `stimuli.rs`'s own test).
#[test]
fn in_the_replica_every_staged_path_is_clear_of_walls_and_obstacles() {
    let fu = BuiltinWorld::Fu2019;
    let world = fu.world();
    let config = EvasionConfig {
        world: fu,
        ..EvasionConfig::default()
    };
    let (d, p) = config.placement();
    assert_eq!(d, 450.0);
    assert!(!p.designed);
    let start = p.pose;
    assert!(clear(&world, start.x_mm, start.y_mm));
    assert!(escape_room_clear(&world, &start), "{p:?}");
    for b in config.bearings() {
        let t = Threat {
            bearing_deg: b,
            distance_mm: d,
            speed_mm_s: 100.0,
        };
        let s = t.start_pose(&start);
        assert!(
            clear_path(&world, (s.x_mm, s.y_mm), (start.x_mm, start.y_mm)),
            "bearing {b}: {p:?}"
        );
    }
    // 500 mm does not fit, and asking for it is one line
    let at_500 = EvasionConfig {
        distance_mm: Some(500.0),
        ..config.clone()
    };
    let e = at_500.validate().unwrap_err().to_string();
    assert!(e.contains("does not fit in the fu2019 world"), "{e}");
    assert_eq!(e.lines().count(), 1);

    let two = TwoThreatConfig {
        world: fu,
        runs: 50,
        ..TwoThreatConfig::default()
    };
    let p = two.placement();
    let start = p.pose;
    assert!(escape_room_clear(&world, &start), "{p:?}");
    for r in 0..two.runs {
        let pair = two.pair(r);
        for t in [pair.fast, pair.slow] {
            let s = Threat::from(t).start_pose(&start);
            assert!(
                clear_path(&world, (s.x_mm, s.y_mm), (start.x_mm, start.y_mm)),
                "run {r}: {t:?} from {p:?}"
            );
        }
    }
    let p = StimuliConfig {
        world: fu,
        ..StimuliConfig::default()
    }
    .placement();
    assert!(!p.designed && p.clearance_mm >= MIN_CLEARANCE_MM, "{p:?}");
    assert!(clear(&world, p.pose.x_mm, p.pose.y_mm));
}

/// The replica's stimuli: the same answers as the lab's (approaching robots alert, a receding
/// one does not, each of a double approach gets its own field), seen differently.
#[test]
fn the_stimuli_in_the_replica_differ_from_the_lab_and_still_tell_approach_from_recession() {
    let run = |world| {
        let config = StimuliConfig {
            world,
            ..StimuliConfig::default()
        };
        stimuli::run(&config, 2).unwrap()
    };
    let (fu, lab) = (run(BuiltinWorld::Fu2019), run(BuiltinWorld::Lab));
    assert_ne!(results(fu.json()), results(lab.json()));
    let json = fu.json();
    assert_eq!(json["world"], "fu2019");
    assert_eq!(json["background"], "ribs");
    let table = fu.table();
    let scene = |n: &str| fu.scenes.iter().find(|s| s.name == n).unwrap();
    assert_eq!(scene("recede").alert_frames, 0, "{table}");
    assert!(
        scene("approach").first_alert_frame.is_some_and(|f| f < 120),
        "{table}"
    );
    assert_eq!(scene("double").localised, 2, "{table}");
}

/// Every `lab` figure is what it was before `--world` existed: digests of the results of
/// `cargo alvs stimuli`, `two-threats --runs 6`, `arena --minutes 0.5` and `swarm --minutes
/// 0.3 --leader --seed 3` as the binary of commit 23ea16c wrote them (their JSON without the
/// wall-clock times and the configuration echo). The last three were recorded again when the
/// default controller changed (issue 30: brisk takeoff turns, the floor line's covered foot),
/// and all four when the default was re-judged on the held-out seeds (the options that did
/// not earn their place off: `t_s` back to Table I's 7000 moves the stimuli's short mode);
/// the stimuli's once more for the blind arms at the side borders (`border_arms`, standing
/// robots only: the other three held), and the other three when the floor line came to
/// follow the floor's grey up each column (driving robots only: the stimuli's held); the
/// two threats' once more for the takeoff's jump (`jump_frames`, takeoffs from standing only);
/// the two threats' and the arena's when the floor line learned to ignore a floor's grain
/// (driving robots only; the stimuli's and the swarm's held); the stimuli's, the arena's and
/// the swarm's when the γ path's options came into the default (`short_uncut`, standing
/// robots; `gamma_turn`, every γ path; the two threats' held); the same three when
/// `q_grow_run` and `border_crossing` came into it (the two threats' held); and the
/// stimuli's when `short_young` did (a standing robot's short mode; the other three held).
/// The worlds' camera has since become the real clips' (a 0.3 % gain draw); these runs keep
/// the 2 % draw they were recorded with (`GainModel::Jitter`), so that they still hold the
/// lab's code path to its figures bit for bit.
#[test]
fn the_lab_is_bit_identical_to_before_the_worlds() {
    let lab = BuiltinWorld::Lab;
    let stimuli = stimuli::run(
        &StimuliConfig {
            world: lab,
            gain: GainModel::Jitter,
            ..StimuliConfig::default()
        },
        2,
    )
    .unwrap();
    let two = two_threats::run(
        &TwoThreatConfig {
            world: lab,
            gain: GainModel::Jitter,
            runs: 6,
            ..TwoThreatConfig::default()
        },
        2,
        &|_| {},
    )
    .unwrap();
    let arena = arena::run(
        &arena::ArenaConfig {
            world: lab,
            gain: GainModel::Jitter,
            minutes: 0.5,
            ..arena::ArenaConfig::default()
        },
        2,
        &|_| {},
    )
    .unwrap();
    let swarm = swarm::run(
        &SwarmConfig {
            world: lab,
            gain: GainModel::Jitter,
            minutes: 0.3,
            leader: true,
            seed: 3,
            ..SwarmConfig::default()
        },
        2,
        &|_| {},
    )
    .unwrap();
    assert_eq!(
        [
            digest(&results(stimuli.json())),
            digest(&results(two.json())),
            digest(&results(arena.json())),
            digest(&results(swarm.json())),
        ],
        [
            0xea9a_a047_61d8_9009,
            0x46ba_3acc_5d5d_9610,
            0xc615_8a07_7701_274f,
            0xbfe8_2b5a_f876_ee9a
        ]
    );
}

/// The arena's trial in the replica with its own walls is the robustness suite's reference
/// trial (`none`) of the same seed: the same robots, starts, noise and counting.
#[test]
fn the_arena_in_the_replica_is_the_robustness_suites_reference() {
    let seed = 11;
    let a = arena::run(
        &arena::ArenaConfig {
            minutes: 0.2,
            seed,
            controllers: vec![Kind::Lgmd2],
            ..arena::ArenaConfig::default()
        },
        1,
        &|_| {},
    )
    .unwrap();
    let r = alvs_host::experiments::sweep::run_all(
        &robustness::RobustnessConfig {
            seeds: vec![seed],
            perturbations: vec![robustness::Perturbation::None],
            controllers: vec![robustness::SuiteController::Lgmd2],
            minutes: 0.2,
            ..robustness::RobustnessConfig::default()
        },
        1,
        &|_| {},
    )
    .unwrap();
    let (at, rt) = (&a.trials[0], &r.trials[0].trial);
    assert_eq!(at.background, "ribs");
    assert_eq!(
        (at.encounters, at.collisions, at.start_poses.clone()),
        (rt.encounters, rt.collisions, rt.start_poses.clone())
    );
    assert_eq!(at.end_poses, rt.end_poses);
    // the starts are clear of the walls and of the cylinders
    let world = BuiltinWorld::Fu2019.world();
    for p in &at.start_poses {
        assert!(world.static_distance(p.x_mm, p.y_mm) >= arena::START_WALL_CLEARANCE_MM);
    }
}

#[test]
fn every_experiment_takes_world_and_refuses_an_unknown_one_in_one_line() {
    for cmd in ["stimuli", "evasion", "two-threats", "arena", "swarm"] {
        let out = alvs().args([cmd, "--help"]).output().unwrap();
        assert!(out.status.success(), "{cmd}");
        let help = String::from_utf8_lossy(&out.stdout);
        assert!(help.contains("--world") && help.contains("fu2019"), "{cmd}");
        let out = alvs().args([cmd, "--world", "moon"]).output().unwrap();
        assert!(!out.status.success(), "{cmd}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{cmd}: {err}");
        assert!(err.contains("moon"), "{cmd}: {err}");
    }
    let out = alvs()
        .args(["evasion", "--distance", "500", "--png", "/nonexistent"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("does not fit in the fu2019 world"), "{err}");
}

/// `cargo alvs tables`: per experiment a markdown table with a row per seed and the pooled
/// row, headed by the command that makes it; each row is the experiment's own run.
#[test]
fn tables_give_a_row_per_seed_under_the_command_that_makes_them() {
    use alvs_host::experiments::tables::{tables, Experiment, TablesConfig};
    let config = TablesConfig {
        world: BuiltinWorld::Lab,
        seeds: vec![1, 2],
        experiments: vec![Experiment::Swarm, Experiment::Arena],
        arena_minutes: 0.05,
        swarm_minutes: 0.05,
        firmware: false,
        gain: GainModel::Clips,
    };
    let text = tables(&config, 2, &|_| {}).unwrap();
    assert!(text.contains(
        "`cargo alvs tables --world lab --seed 1 --seed 2 --experiment swarm --swarm-minutes 0.05`"
    ));
    assert!(
        text.contains("--experiment arena --arena-minutes 0.05`"),
        "{text}"
    );
    let rows = |first: &str| text.lines().filter(|l| l.starts_with(first)).count();
    assert_eq!((rows("| 1 |"), rows("| 2 |")), (2, 2), "{text}");
    assert_eq!(
        (rows("| **all** |"), rows("| **pooled** |")),
        (1, 1),
        "{text}"
    );
    // the arena's row of seed 2 is the arena's own run
    let r = arena::run(
        &arena::ArenaConfig {
            world: BuiltinWorld::Lab,
            minutes: 0.05,
            seed: 2,
            ..arena::ArenaConfig::default()
        },
        2,
        &|_| {},
    )
    .unwrap();
    let alvs = &r.summaries[0];
    let success = alvs
        .success_rate
        .map_or("–".into(), |r| format!("{:.1} %", 100.0 * r));
    let cell = format!("| 2 | {success} ({}) |", alvs.encounters);
    assert!(text.contains(&cell), "{cell}: {text}");
    // --firmware: the authors' firmware beside the paper's model, in the arena's table only
    let fw = TablesConfig {
        seeds: vec![2],
        experiments: vec![Experiment::Arena],
        firmware: true,
        ..config.clone()
    };
    let text = tables(&fw, 2, &|_| {}).unwrap();
    assert!(text.contains("--arena-minutes 0.05 --firmware`"), "{text}");
    assert!(
        text.contains("| seed | ALVS | the paper's model | the authors' firmware | LGMD2 |"),
        "{text}"
    );
    assert!(text.contains(&cell), "the ALVS column is unchanged: {text}");
    // --camera-gain: every run with that camera, named in the command; on seed 12 the former
    // 2 % draw makes the translating robot alert (docs/world.md, "The camera's gain")
    let stimuli = |gain| {
        let c = TablesConfig {
            world: BuiltinWorld::Fu2019,
            seeds: vec![12],
            experiments: vec![Experiment::Stimuli],
            gain,
            ..config.clone()
        };
        tables(&c, 2, &|_| {}).unwrap()
    };
    let (clips, jitter) = (stimuli(GainModel::Clips), stimuli(GainModel::Jitter));
    assert!(clips.contains("--experiment stimuli`"), "{clips}");
    assert!(
        jitter.contains("--experiment stimuli --camera-gain jitter`"),
        "{jitter}"
    );
    assert!(clips.contains("| translate | 1 | 0/1 |"), "{clips}");
    assert!(jitter.contains("| translate | 1 | 1/1 |"), "{jitter}");
    let bad = TablesConfig {
        seeds: Vec::new(),
        ..config
    };
    assert!(tables(&bad, 1, &|_| {}).is_err());
}
