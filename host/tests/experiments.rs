//! The paper's experiments 1, 2, 3 and 5 (`alvs stimuli`, `evasion`, `two-threats`, `swarm`)
//! on short runs: their headline results as assertions with margins, determinism by seed
//! whatever the number of threads, the documented JSON, and a command line that helps and
//! fails cleanly. (Experiment 4, `arena`, is `arena_experiment.rs`.)

use alvs_host::experiments::evasion::{self, EvasionConfig};
use alvs_host::experiments::stimuli::{self, StimuliConfig};
use alvs_host::experiments::swarm::{self, SwarmConfig};
use alvs_host::experiments::two_threats::{self, TwoThreatConfig};
use alvs_host::experiments::Report;
use alvs_sim::encounter::Side;
use alvs_sim::{BuiltinWorld, Kind};
use alvs_tasks::model::fsm::{Escape, FsmParams, State, Swarm};
use alvs_tasks::Params;
use core::num::NonZeroU32;

mod common;
use alvs_tasks::model::params::Efference;
use common::{alvs, read_json, succeed};

/// The one trial of a swarm run with a single controller (on 2 threads).
fn one_swarm_trial(config: SwarmConfig) -> swarm::SwarmTrial {
    let mut r = swarm::run(&config, 2, &|_| {}).expect("a valid configuration");
    assert_eq!(r.trials.len(), 1, "one controller");
    r.trials.remove(0)
}

fn alvs_only() -> Vec<Kind> {
    vec![Kind::Alvs]
}

/// Paper Fig. 4d: "regardless of the approach angle, [ALVS] consistently selected the correct
/// escape direction". Every bearing alerts and turns away from the obstacle's side (dead
/// ahead: turns round). The JSON has the shape the issue asks for.
#[test]
fn alvs_escapes_to_the_correct_side_from_all_nine_bearings() {
    let config = EvasionConfig {
        controllers: alvs_only(),
        world: BuiltinWorld::Lab,
        ..EvasionConfig::default()
    };
    let r = evasion::run(&config, 2, &|_| {}).expect("a valid configuration");
    let a = &r.controllers[0];
    let table = r.table();
    assert_eq!(a.angles, 9);
    assert_eq!(a.alerted, 9, "{table}");
    assert_eq!(a.correct_side, 9, "{table}");
    let bearings: Vec<f64> = a.per_angle.iter().map(|o| o.angle_deg).collect();
    assert_eq!(bearings.first(), Some(&-35.0));
    assert_eq!(bearings.last(), Some(&35.0));
    assert_eq!(bearings[4], 0.0);
    for o in &a.per_angle {
        // a real escape turn, not a twitch: a long takeoff turns ~180° minus the bearing, a
        // γ path ends 180° from the threat too
        assert!(o.escape_turn_deg.abs() > 90.0, "{table}");
        if o.angle_deg > 0.0 {
            assert_eq!(o.side, Side::Left, "{table}");
        }
    }
    let json = r.json();
    assert_eq!(json["alvs"]["angles"], 9);
    assert_eq!(json["alvs"]["correct_side"], 9);
    // the takeoff backs out of the obstacle's path while it turns, and the escape saccade
    // keeps the escape from turning back into it: at most 1 of 9 collides (seed 1: 0; without
    // the moving takeoff 2, without the saccade 6, the paper's model 9; docs/experiments.md),
    // the goal
    assert!(
        json["alvs"]["collisions"].as_u64().is_some_and(|c| c <= 1),
        "{table}"
    );
}

/// `Params::border_arms`: in the recorded arena's replica the obstacles from ±35° aim at the
/// tested robot's centre, 19 mm behind its camera, so their centres stay outside the 70° view
/// and only their inner halves expand in it. Without the blind arms counted, one of them opens
/// the gate too late and collides (tuning seed 1: −35°, alerted by `q_grow_run`'s run of
/// growth 42 mm away; before it, never); with them every bearing alerts and turns away, and no
/// trial collides.
#[test]
fn an_obstacle_half_out_of_view_is_escaped_in_the_replica() {
    let run = |border_arms: bool| {
        let mut params = Params::ALVS;
        params.mechanisms.border_arms = border_arms;
        let config = EvasionConfig {
            controllers: alvs_only(),
            params,
            ..EvasionConfig::default()
        };
        evasion::run(&config, 2, &|_| {}).expect("a valid configuration")
    };
    let (with, without) = (run(true), run(false));
    let (w, wo) = (&with.controllers[0], &without.controllers[0]);
    assert_eq!(w.alerted, 9, "{}", with.table());
    assert_eq!(w.correct_side, 9, "{}", with.table());
    assert_eq!(w.collisions, 0, "{}", with.table());
    let hit: Vec<f64> = wo
        .per_angle
        .iter()
        .filter(|o| o.collided)
        .map(|o| o.angle_deg)
        .collect();
    assert_eq!(hit, [-35.0], "{}", without.table());
}

/// An obstacle first seen close at the edge of the view: on seed 3 (the lab) the obstacle at
/// −35° starts 100 mm away, its field cut by the view's border. The default counts a cut
/// field whole for `T_s` (`short_uncut`; and `short_young` sees it alert in its field's first
/// frames) and backs off along the γ path. Table I's 7000 on the
/// shown part alone starts a long takeoff, which with the paper's turn (4/s, 360°/s) turns in
/// place while the obstacle comes on and collides; the default's brisk takeoff gets away from
/// it too (docs/ablation.md). (With the 2 % camera gain before the clips' camera, the same
/// happened from 500 mm, where the draw held the alert back until the obstacle was close;
/// with the clips' camera every obstacle from 500 mm alerts in time for a long takeoff.)
#[test]
fn an_obstacle_first_seen_close_starts_the_gamma_path() {
    let run = |short_uncut: &str, fsm: FsmParams| {
        let mut params = alvs_tasks::Params::default();
        params.set("short_uncut", short_uncut).unwrap();
        // the table-one runs test the cut field alone; `short_young` is the next test's
        params.set("short_young", short_uncut).unwrap();
        let config = EvasionConfig {
            controllers: alvs_only(),
            seed: 3,
            params,
            fsm,
            world: BuiltinWorld::Lab,
            distance_mm: Some(100.0),
            ..EvasionConfig::default()
        };
        evasion::run(&config, 2, &|_| {}).expect("a valid configuration")
    };
    let papers_turn = FsmParams {
        escape: Escape {
            takeoff_gain: 1.0,
            takeoff_yaw_deg_s: 360.0,
            gamma_turn: false,
            ..FsmParams::ALVS.escape
        },
        ..FsmParams::ALVS
    };
    let (default, table_one) = (run("1", FsmParams::ALVS), run("0", papers_turn));
    let brisk_table_one = run("0", FsmParams::ALVS);
    assert!(
        brisk_table_one.controllers[0].collisions <= 1,
        "{}",
        brisk_table_one.table()
    );
    let (d, t) = (&default.controllers[0], &table_one.controllers[0]);
    assert_eq!(d.correct_side, 9, "{}", default.table());
    assert!(d.collisions <= 1, "{}", default.table());
    // the edge bearing: the γ path, against Table I's long takeoff that collides, or with the
    // brisk turn gets away
    let edge = |r: &evasion::EvasionReport| r.controllers[0].per_angle[0].clone();
    let (de, te, be) = (edge(&default), edge(&table_one), edge(&brisk_table_one));
    assert_eq!(de.angle_deg, -35.0);
    assert_eq!(
        de.reaction,
        Some(State::ShortTakeoff.name()),
        "{}",
        default.table()
    );
    assert!(de.correct_side && !de.collided, "{}", default.table());
    let long = Some(State::LongTakeoff.name());
    assert!(te.reaction == long && te.collided, "{}", table_one.table());
    assert!(
        be.reaction == long && !be.collided,
        "{}",
        brisk_table_one.table()
    );
    assert!(d.collisions < t.collisions, "{}", table_one.table());
}

/// The default's evasion on seed 1 with the obstacle starting 100 mm away, with parameters set
/// (`(name, value)`, in order).
fn from_100_mm(set: &[(&str, &str)]) -> evasion::ControllerEvasion {
    from_100_mm_before(None, set)
}

/// [`from_100_mm`] in front of a photograph from `data/photos/` instead of the ribs.
fn from_100_mm_before(photo: Option<&str>, set: &[(&str, &str)]) -> evasion::ControllerEvasion {
    evasion_before(photo, Some(100.0), set)
}

/// The default's evasion on seed 1 in front of `photo` (or the ribs), the obstacle starting
/// `distance_mm` away (or at the stage's default distance), with parameters set.
fn evasion_before(
    photo: Option<&str>,
    distance_mm: Option<f64>,
    set: &[(&str, &str)],
) -> evasion::ControllerEvasion {
    evasion_on(1, photo, distance_mm, set)
}

/// [`evasion_before`] on `seed`.
fn evasion_on(
    seed: u64,
    photo: Option<&str>,
    distance_mm: Option<f64>,
    set: &[(&str, &str)],
) -> evasion::ControllerEvasion {
    let mut params = alvs_tasks::Params::default();
    for (name, value) in set {
        params.set(name, value).unwrap();
    }
    let background =
        photo.map(|name| format!("{}/../data/photos/{name}", env!("CARGO_MANIFEST_DIR")));
    let config = EvasionConfig {
        controllers: alvs_only(),
        seed,
        distance_mm,
        background,
        params,
        ..EvasionConfig::default()
    };
    let r = evasion::run(&config, 2, &|_| {}).expect("a valid configuration");
    r.controllers[0].clone()
}

/// An obstacle already 100 mm away when the robot starts looking approaches steadily: its drive
/// grows some 10 % a frame, never the +50 % step of `q_grow_pct`, once the warm-up has passed
/// its onset. On seed 1 the default without `q_grow_run` (and without `border_crossing`, whose
/// own test follows) alerts on it at +17.5° only after 0.67 s, too late: its long takeoff
/// turns the wrong way and is hit; with `q_grow_run` = 3 (growth on 3 frames in a row, the
/// default) every bearing alerts, on the correct side, mostly with the γ path, and nothing
/// collides (docs/notes/2026-11-28-edge-history.md).
#[test]
fn a_run_of_growth_lets_an_obstacle_first_seen_close_alert() {
    let run = |value| from_100_mm(&[("border_crossing", "0"), ("q_grow_run", value)]);
    let (before, after) = (run("0"), run("3"));
    let late = |r: &evasion::ControllerEvasion| {
        r.per_angle
            .iter()
            .filter(|o| o.first_alert_s.is_none_or(|s| s > 0.5))
            .count()
    };
    assert!(late(&before) >= 1, "{before:?}");
    assert!(
        before.correct_side < 9 && before.collisions >= 1,
        "{before:?}"
    );
    assert_eq!(late(&after), 0, "{after:?}");
    assert_eq!(
        (after.alerted, after.correct_side, after.collisions),
        (9, 9, 0),
        "{after:?}"
    );
    assert!(after.gamma_paths() >= Some(6), "{after:?}");
}

/// An obstacle first seen 100 mm away at ±17.5° already runs off a side border, and on a
/// photographed wall the attention centroid rides its top edge, 18–35 columns from the border:
/// the half-side rule leaves that side uncut, its outer quadrants stay dark, and the default
/// without `border_crossing` (and without `q_grow_run`) never alerts and is hit, at both
/// bearings on seed 2 (a tuning seed; held out in
/// docs/notes/2026-11-28-first-seen-close-on-textured-walls.md). With `border_crossing` (the
/// default) that side is cut, the mirror opens the gate, and every bearing alerts on the
/// correct side; the other seven trials do not change.
#[test]
fn a_field_whose_square_crosses_the_border_counts_its_blind_side() {
    let run = |value| {
        evasion_on(
            2,
            Some("outdoor_2.jpg"),
            Some(100.0),
            &[("q_grow_run", "0"), ("border_crossing", value)],
        )
    };
    let (before, after) = (run("0"), run("1"));
    assert_eq!((before.alerted, before.collisions), (7, 2), "{before:?}");
    assert_eq!(
        (after.alerted, after.correct_side, after.collisions),
        (9, 9, 0),
        "{after:?}"
    );
    for (b, a) in before.per_angle.iter().zip(&after.per_angle) {
        if b.angle_deg.abs() == 17.5 {
            assert!(b.first_alert_s.is_none() && b.collided, "{before:?}");
        } else {
            assert_eq!(b, a);
        }
    }
}

/// An obstacle first seen 100 mm away in front of a photograph alerts at ±35° under `T_s`
/// even counted whole (the photograph's texture halves the response) and starts a long
/// takeoff. Its field was born 4 frames before (−35°), or in the warm-up and alerts in the
/// second frame after it (+35°): with `short_young` an alert in a field's first `d` frames
/// that could alert starts the γ path; the other bearings do not change. From 450 mm the
/// fields alert long after their birth, and nothing changes at all (seed 1, a tuning seed;
/// held out in docs/notes/2026-11-28-first-seen-close-on-textured-walls.md).
#[test]
fn an_alert_in_a_young_field_starts_the_gamma_path() {
    let run = |value| from_100_mm_before(Some("outdoor_1.jpg"), &[("short_young", value)]);
    let (before, after) = (run("0"), run("1"));
    let short = Some(State::ShortTakeoff.name());
    for (b, a) in before.per_angle.iter().zip(&after.per_angle) {
        if b.angle_deg.abs() == 35.0 {
            assert_ne!(b.reaction, short, "{before:?}");
            assert_eq!(a.reaction, short, "{after:?}");
            assert!(a.correct_side && !a.collided, "{after:?}");
        } else {
            assert_eq!(b, a);
        }
    }
    let from_afar =
        |value| evasion_before(Some("outdoor_1.jpg"), None, &[("short_young", value)]).per_angle;
    assert_eq!(from_afar("0"), from_afar("1"));
}

/// An obstacle first seen 100 mm away at the view's edge (±35°) is half outside the picture:
/// its field's response stays under `T_s`, and counted as shown it starts a long takeoff. With
/// `short_uncut` (the default) the short mode counts the cut field at its whole width, so both edge bearings
/// start the γ path as the central ones do; the sides and collisions do not change (seed 1, a
/// tuning seed; held out in docs/notes/2026-11-28-the-gamma-path.md).
#[test]
fn a_field_cut_by_the_border_counts_whole_for_the_short_mode() {
    let run = |value| from_100_mm(&[("short_young", "0"), ("short_uncut", value)]);
    let (before, after) = (run("0"), run("1"));
    let short = Some(State::ShortTakeoff.name());
    let edges = |r: &evasion::ControllerEvasion| -> Vec<bool> {
        r.per_angle
            .iter()
            .filter(|o| o.angle_deg.abs() > 30.0)
            .map(|o| o.reaction == short)
            .collect()
    };
    assert_eq!(edges(&before), [false, false], "{before:?}");
    assert_eq!(edges(&after), [true, true], "{after:?}");
    assert!(after.gamma_paths() > before.gamma_paths(), "{after:?}");
    assert_eq!(
        (after.correct_side, after.collisions),
        (before.correct_side, before.collisions)
    );
}

/// With the camera's exposure blur (`--exposure`, an OV7670 exposing for most of the frame
/// period) the evasion still goes to the correct side from every bearing, and the blur reaches
/// the tested robot's camera: the runs differ from the snapshot camera's.
#[test]
fn a_blurred_camera_still_escapes_to_the_correct_side() {
    let run = |exposure: f32| {
        let config = EvasionConfig {
            controllers: alvs_only(),
            exposure,
            world: BuiltinWorld::Lab,
            ..EvasionConfig::default()
        };
        evasion::run(&config, 2, &|_| {}).expect("a valid configuration")
    };
    let (sharp, blurred) = (run(0.0), run(0.75));
    let b = &blurred.controllers[0];
    assert_eq!(b.correct_side, 9, "{}", blurred.table());
    let turns = |r: &evasion::EvasionReport| -> Vec<f64> {
        r.controllers[0]
            .per_angle
            .iter()
            .map(|o| o.escape_turn_deg)
            .collect()
    };
    assert_ne!(turns(&sharp), turns(&blurred));
}

/// The evasion holds the tested robot still until its first alert. Its FSM is told the wheels
/// did not move, so the blocked way (efference copy of forward travel) does not read "commanding
/// travel, view unchanged" as a wall and turn it round before the obstacle comes.
#[test]
fn a_held_robot_with_the_blocked_way_still_escapes_to_the_correct_side() {
    let mut params = alvs_tasks::Params::default();
    params.set("blocked_change", "6").unwrap();
    let config = EvasionConfig {
        controllers: alvs_only(),
        params,
        world: BuiltinWorld::Lab,
        ..EvasionConfig::default()
    };
    let r = evasion::run(&config, 2, &|_| {}).expect("a valid configuration");
    assert_eq!(r.controllers[0].correct_side, 9, "{}", r.table());
}

/// Paper Fig. 4c,d: the direction-blind LGMD2 escape "result[s] in a higher likelihood of
/// collisions". On plain walls (a lab arena) ALVS's directed turn clears the obstacle from
/// most bearings while LGMD2's random turn does not. (On the textured default walls both
/// collide: docs/experiments.md, *Evasion*.)
#[test]
fn on_plain_walls_alvs_collides_less_than_lgmd2() {
    let config = EvasionConfig {
        controllers: vec![Kind::Alvs, Kind::Lgmd2],
        background: Some("plain:200".into()),
        world: BuiltinWorld::Lab,
        ..EvasionConfig::default()
    };
    let r = evasion::run(&config, 2, &|_| {}).expect("a valid configuration");
    let (alvs, lgmd2) = (&r.controllers[0], &r.controllers[1]);
    let table = r.table();
    assert_eq!(alvs.correct_side, 9, "{table}");
    // the goal, ≤ 1 of 9 (measured 0; 1 without the moving takeoff)
    assert!(alvs.collisions <= 1, "{table}");
    assert!(lgmd2.collisions >= alvs.collisions + 3, "{table}");
}

/// Paper Fig. 4b: ALVS takes the faster of two simultaneous threats for the more imminent one
/// and evades away from it. LGMD2, which has no direction, serves as the chance level.
#[test]
fn the_faster_of_two_threats_wins() {
    let config = TwoThreatConfig {
        runs: 8,
        controllers: vec![Kind::Alvs, Kind::Lgmd2],
        world: BuiltinWorld::Lab,
        ..TwoThreatConfig::default()
    };
    let r = two_threats::run(&config, 2, &|_| {}).expect("a valid configuration");
    let (alvs, lgmd2) = (&r.controllers[0], &r.controllers[1]);
    let table = r.table();
    assert_eq!(alvs.runs, 8);
    assert!(alvs.away_from_faster >= 7, "{table}");
    assert!(alvs.away_from_faster > lgmd2.away_from_faster, "{table}");
    for o in &alvs.per_run {
        // the geometry: opposite sides, the faster really faster
        assert!(o.threats.fast.bearing_deg * o.threats.slow.bearing_deg < 0.0);
        assert!(o.threats.fast.speed_mm_s > o.threats.slow.speed_mm_s);
    }
    assert_eq!(
        r.json()["alvs"]["fraction"].as_f64(),
        Some(alvs.away_from_faster as f64 / 8.0)
    );
}

/// A short mode is a threat close by: with `gamma_turn` the γ path turns with the long
/// takeoff's gain (at the paper's yaw limit, so its retreat keeps its speed) and gets out of a
/// fast robot's way that the slow turn leaves it facing. Two threats on the tuning seeds 2 and 5
/// with the default's perception, whose `short_uncut` starts more γ paths
/// (docs/notes/2026-11-28-the-gamma-path.md): 8 collisions of 100 → 2 (with the 2 % camera
/// gain before the clips' camera, 5 → 1), every run still away from the faster.
#[test]
fn a_brisk_gamma_path_gets_away_from_the_faster_of_two_threats() {
    let collisions = |gamma_turn: bool| -> usize {
        [2, 5]
            .into_iter()
            .map(|seed| {
                let mut fsm = FsmParams::default();
                fsm.escape.gamma_turn = gamma_turn;
                let config = TwoThreatConfig {
                    runs: 50,
                    controllers: alvs_only(),
                    seed,
                    fsm,
                    ..TwoThreatConfig::default()
                };
                let r = two_threats::run(&config, 2, &|_| {}).expect("a valid configuration");
                let alvs = &r.controllers[0];
                assert_eq!(alvs.away_from_faster, 50, "{}", r.table());
                alvs.collisions
            })
            .sum()
    };
    let (slow, brisk) = (collisions(false), collisions(true));
    assert_eq!((slow, brisk), (8, 2));
}

/// Evasion and two-threats are pure functions of their configuration: the same numbers on one
/// thread or two, twice; another seed changes the noise.
#[test]
fn encounters_are_deterministic_by_seed_whatever_the_threads() {
    let config = TwoThreatConfig {
        runs: 3,
        world: BuiltinWorld::Lab,
        ..TwoThreatConfig::default()
    };
    let a = two_threats::run(&config, 1, &|_| {}).unwrap().json();
    let b = two_threats::run(&config, 2, &|_| {}).unwrap().json();
    assert_eq!(a, b);
    let other = TwoThreatConfig {
        seed: 2,
        ..config.clone()
    };
    let c = two_threats::run(&other, 2, &|_| {}).unwrap().json();
    assert_ne!(a["alvs"]["per_run"], c["alvs"]["per_run"]);
}

/// Paper Fig. 3: approaching robots alert the standing robot and get an attention field each
/// (two at once for the double approach); a receding robot does not alert.
#[test]
fn stimuli_tell_approach_from_recession_and_count_the_objects() {
    let r = stimuli::run(
        &StimuliConfig {
            world: BuiltinWorld::Lab,
            ..StimuliConfig::default()
        },
        2,
    )
    .expect("a valid configuration");
    let table = r.table();
    let scene = |n: &str| r.scenes.iter().find(|s| s.name == n).expect(n);
    assert_eq!(r.scenes.len(), 5);
    assert_eq!(scene("recede").alert_frames, 0, "{table}");
    for n in ["approach", "double", "triple"] {
        assert!(scene(n).alert_frames > 0, "{n}: {table}");
        assert!(scene(n).localised >= 1, "{n}: {table}");
    }
    let double = scene("double");
    assert!(double.max_afs >= 2, "{table}");
    assert_eq!(double.localised, 2, "{table}");
    // the approach alerts before the obstacle stops (frame 120), i.e. before contact
    assert!(scene("approach").first_alert_frame.is_some_and(|f| f < 120));
    let json = r.json();
    assert_eq!(json["scenes"].as_array().map(Vec::len), Some(5));
}

/// Swarm mode spins and never escapes; escape mode never spins; spreads are distances.
#[test]
fn swarm_robots_spin_and_escaping_robots_do_not() {
    let config = SwarmConfig {
        minutes: 0.25,
        world: BuiltinWorld::Lab,
        ..SwarmConfig::default()
    };
    let r = swarm::run(&config, 2, &|_| {}).expect("a valid configuration");
    let (sw, esc) = (&r.trials[0], &r.trials[1]);
    assert_eq!((sw.controller, esc.controller), ("swarm", "alvs"));
    assert!(sw.state_fraction.get("spin").copied().unwrap_or(0.0) > 0.0);
    assert!(!sw.state_fraction.contains_key("escape"));
    assert!(!esc.state_fraction.contains_key("spin"));
    for t in &r.trials {
        assert_eq!(t.spread_mm.len(), 16); // t = 0 and once per second for 15 s
        assert_eq!(t.spread_mm[0], t.spread_start_mm);
        assert!(t.spread_mm.iter().all(|s| (0.0..1500.0).contains(s)));
        // six robots keep at least a body apart (centre distances)
        assert!(t.nearest_mm.iter().all(|n| *n >= 40.0));
    }
    // both start from the same poses
    assert_eq!(sw.trails[0][0], esc.trails[0][0]);
    let (a, b) = (swarm::spread(&[(0.0, 0.0), (6.0, 8.0)]), (5.0, 10.0));
    assert_eq!(a, b);
}

/// Paper Fig. 7, the default swarm (`FsmParams::look_every`, `Params::look_change`): robots
/// that stop to look for moving objects and head for them gather where the others spin;
/// without the looks (spin on approach, and on the floor line's obstacle close ahead) the
/// group keeps its spread.
#[test]
fn a_swarm_that_looks_for_movers_gathers_over_five_minutes() {
    let run = |look_every: Option<NonZeroU32>| {
        let config = SwarmConfig {
            controllers: vec![Kind::Swarm],
            fsm: FsmParams {
                swarm: Swarm {
                    look_every,
                    ..FsmParams::default().swarm
                },
                ..FsmParams::default()
            },
            world: BuiltinWorld::Lab,
            ..SwarmConfig::default()
        };
        let t = one_swarm_trial(config);
        (
            t.spread_start_mm,
            t.spread_last_minute_mm,
            t.nearest_last_minute_mm,
            t.state_fraction.get("look").copied().unwrap_or(0.0),
            t.robot_collisions_per_minute,
        )
    };
    let (start, end, nearest, look, collisions) = run(FsmParams::default().swarm.look_every);
    assert!(end < 0.5 * start, "the default: {start} → {end} mm");
    assert!(
        nearest < 100.0,
        "the default's nearest neighbour: {nearest} mm"
    );
    assert!(look > 0.1, "it looked {look} of the time");
    // the spin on the floor line's obstacle: they gather without bumping into each other
    assert!(
        collisions < 1.0,
        "{collisions} robot–robot collisions a minute"
    );
    let (start, end, ..) = run(None);
    assert!(end > 0.8 * start, "without looks: {start} → {end} mm");
}

/// `leader`: one more robot spins in place among the others, who start where they would
/// without it; their distance to it is measured, and it is in the trails (last) but not in the
/// group's figures.
#[test]
fn a_swarm_leader_spins_in_place_beside_the_same_group() {
    let run = |leader: bool, robots: usize| {
        let config = SwarmConfig {
            controllers: vec![Kind::Swarm],
            minutes: 0.2,
            robots,
            leader,
            seed: 2,
            world: BuiltinWorld::Lab,
            ..SwarmConfig::default()
        };
        one_swarm_trial(config)
    };
    for robots in [6, 20] {
        let (with, without) = (run(true, robots), run(false, robots));
        assert_eq!(with.trails.len(), robots + 1);
        assert_eq!(without.trails.len(), robots);
        let start =
            |t: &swarm::SwarmTrial| t.trails[..robots].iter().map(|p| p[0]).collect::<Vec<_>>();
        assert_eq!(start(&with), start(&without));
        assert_eq!(
            (with.spread_mm[0], with.nearest_mm[0]),
            (without.spread_mm[0], without.nearest_mm[0])
        );
        // the leader turns on the spot
        let l = &with.trails[robots];
        let moved = l
            .iter()
            .map(|p| (p[0] - l[0][0]).hypot(p[1] - l[0][1]))
            .fold(0.0, f64::max);
        assert!(moved < 10.0, "the leader moved {moved} mm");
        // the others' mean distance to it, once per second from the start
        assert_eq!(with.leader_mm.len(), with.spread_mm.len());
        let d0 = with.trails[..robots]
            .iter()
            .map(|t| (t[0][0] - l[0][0]).hypot(t[0][1] - l[0][1]))
            .sum::<f64>()
            / robots as f64;
        assert!(
            (with.leader_mm[0] - d0).abs() < 0.1,
            "{} against {d0}",
            with.leader_mm[0]
        );
        assert!(without.leader_last_minute_mm.is_none() && without.leader_mm.is_empty());
        assert!(!with.state_fraction.contains_key("scripted"));
    }
}

/// The paper's swarm (`--model paper`) never looks, nor do escaping robots; the default's
/// swarm robots do.
#[test]
fn only_the_default_swarm_looks() {
    let looked = |kind: Kind, params: Params, fsm: FsmParams| {
        let config = SwarmConfig {
            controllers: vec![kind],
            minutes: 0.5,
            params,
            fsm,
            world: BuiltinWorld::Lab,
            ..SwarmConfig::default()
        };
        let t = one_swarm_trial(config);
        t.state_fraction.get("look").copied().unwrap_or(0.0)
    };
    assert_eq!(looked(Kind::Swarm, Params::PAPER, FsmParams::PAPER), 0.0);
    assert!(looked(Kind::Swarm, Params::default(), FsmParams::default()) > 0.1);
    // the escape never looks, whatever its parameters
    assert_eq!(
        looked(Kind::Alvs, Params::default(), FsmParams::default()),
        0.0
    );
}

/// Spin on approach alone, without looks: six robots draw together only while they spin on
/// their own flow. Each spin turns a robot half round, away from what it saw; near others it
/// stops and turns again and again, alone it runs on, so the group gathers. With a full turn
/// per spin (360°/s) it does not. The gathering needs the robots to see their own forward flow
/// and nothing else while they drive (`Params::band_row` and `floor_row` 0, the default of an
/// earlier round): with the default's band and floor line they wander on and the spread stays
/// (330 → 343 mm, docs/experiments.md, "Swarm").
#[test]
fn a_spinning_swarm_clusters_over_five_minutes() {
    let spin = |deg_s: f32| {
        let config = SwarmConfig {
            controllers: vec![Kind::Swarm],
            params: Params {
                efference: Efference {
                    band_row: None,
                    floor_row: None,
                    ..Params::default().efference
                },
                ..Params::default()
            },
            fsm: FsmParams {
                swarm: Swarm {
                    spin_deg_s: deg_s,
                    look_every: None,
                    ..FsmParams::default().swarm
                },
                ..FsmParams::default()
            },
            world: BuiltinWorld::Lab,
            ..SwarmConfig::default()
        };
        let t = one_swarm_trial(config);
        (t.spread_start_mm, t.spread_last_minute_mm)
    };
    let (start, end) = spin(FsmParams::default().swarm.spin_deg_s);
    assert!(end < 0.6 * start, "the default: {start} → {end} mm");
    let (start, end) = spin(360.0);
    assert!(
        end > 0.9 * start,
        "a full turn per spin: {start} → {end} mm"
    );
}

#[test]
fn cli_runs_an_experiment_and_writes_json_and_pictures() {
    let dir = std::env::temp_dir().join(format!("alvs-exp-cli-{}", std::process::id()));
    let json = dir.join("ev.json");
    std::fs::create_dir_all(&dir).unwrap();
    let trace = dir.join("ev.csv");
    let out = succeed(
        alvs()
            .args(["evasion", "--world", "lab", "--controller", "alvs"])
            .args(["--jobs", "2", "--json"])
            .arg(&json)
            .arg("--png")
            .arg(&dir)
            .arg("--trace")
            .arg(&trace)
            .args(["--fsm", "settle_frames=2"]),
    );
    let v = read_json(&json);
    assert_eq!(v["alvs"]["angles"], 9);
    assert!(dir.join("evasion.png").exists());
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("correct side"), "{stdout}");
    assert!(
        stdout.contains(&format!("trace in {}", trace.display())),
        "{stdout}"
    );
    // the trace: a header, then every frame of the 9 trials; the tested robot stands until its
    // first alert and the obstacle closes in at 100 mm/s
    let csv = std::fs::read_to_string(&trace).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("controller,bearing_deg,frame,t_s,x_mm,y_mm,heading_deg,state,alert,short_mode,response,threat_x,fields,distance_mm")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(rows.iter().all(|r| r.len() == 14 && r[0] == "alvs"));
    let first: Vec<&Vec<&str>> = rows.iter().filter(|r| r[2] == "0").collect();
    assert_eq!(first.len(), 9);
    let d = |r: &Vec<&str>| r[13].parse::<f64>().unwrap();
    assert!((d(first[0]) - 496.7).abs() < 0.2, "{:?}", first[0]);
    let alerts = rows.iter().filter(|r| r[8] == "1");
    assert!(alerts.clone().count() >= 9);
    // every alert has a threat column; a field's alert has a response (the floor line's,
    // at ΣLPLC2 0, none)
    assert!(alerts.clone().all(|r| !r[11].is_empty()));
    assert!(alerts.clone().any(|r| r[10].parse::<u32>().unwrap() > 0));
    // bad values of --fsm fail with one line naming the parameter
    let out = alvs()
        .args(["evasion", "--fsm", "settle_frames=-1"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("settle_frames"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cli_helps_and_fails_cleanly() {
    for cmd in ["stimuli", "evasion", "two-threats", "swarm"] {
        let out = alvs().args([cmd, "--help"]).output().unwrap();
        assert!(out.status.success(), "{cmd}");
        assert!(
            ["--seed", "--exposure", "--camera-gain"]
                .iter()
                .all(|f| String::from_utf8_lossy(&out.stdout).contains(f)),
            "{cmd}"
        );
    }
    for args in [
        &["evasion", "--background", "nonsense:3"][..],
        &["two-threats", "--fast", "50", "--slow", "100"],
        &["swarm", "--robots", "1"],
        &["evasion", "--speed", "-3"],
        &["stimuli", "--jobs", "0"],
        &["swarm", "--exposure", "1.5"],
        &["evasion", "--exposure", "-1"],
        &["stimuli", "--camera-gain", "auto"],
    ] {
        let out = alvs().args(args).output().unwrap();
        assert!(!out.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("alvs: error:"), "{args:?}: {err}");
    }
}

#[test]
fn an_unwritable_output_fails_before_the_run() {
    let dir = std::env::temp_dir().join(format!("alvs-unwritable-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let fails = |args: &[&str], png: &std::path::Path, what: &str| {
        let out = alvs().args(args).arg("--png").arg(png).output().unwrap();
        assert!(!out.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(what), "{args:?}: {err}");
    };
    for (args, picture) in [
        (["evasion", "--trace"], "evasion.png"),
        (["two-threats", "--json"], "two_threats.png"),
        (["stimuli", "--json"], "approach_tracks.png"),
    ] {
        let args = [args[0], args[1], "/nonexistent/dir/out"];
        fails(&args, &dir, "cannot write /nonexistent/dir/out");
        // nothing ran: no picture was drawn
        assert!(!dir.join(picture).exists(), "{args:?}");
    }
    // a pictures folder that cannot be made (under a file) fails first too
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    fails(&["evasion"], &file.join("png"), "cannot create");
    // a run refused for its arguments leaves an earlier JSON file as it was
    let json = dir.join("earlier.json");
    std::fs::write(&json, "{\"kept\":1}\n").unwrap();
    let json_arg = json.to_str().unwrap();
    fails(
        &["stimuli", "--background", "bogus", "--json", json_arg],
        &dir,
        "bogus",
    );
    fails(
        &["swarm", "--jobs", "0", "--json", json_arg],
        &dir,
        "--jobs",
    );
    assert_eq!(std::fs::read_to_string(&json).unwrap(), "{\"kept\":1}\n");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Experiment 4 on two simulated minutes (the issue's "a 2-minute arena's counts are
/// consistent"): every count is an episode count of the documented kind, the per-kind counts
/// add up, each collision is a recorded event inside the trial, and the robots meet something.
#[test]
fn a_two_minute_arena_has_consistent_counts() {
    use alvs_host::experiments::arena::{self, ArenaConfig};
    let config = ArenaConfig {
        minutes: 2.0,
        backgrounds: vec!["clutter:1".into()],
        controllers: alvs_only(),
        seed: 5,
        world: BuiltinWorld::Lab,
        ..ArenaConfig::default()
    };
    let r = arena::run(&config, 1, &|_| {}).expect("a valid configuration");
    let t = &r.trials[0];
    let table = r.table();
    assert_eq!(t.frames, 3600);
    assert!(t.encounters >= 5, "{table}");
    for k in [&t.robot_robot, &t.robot_wall] {
        assert!(k.collided_encounters <= k.encounters, "{table}");
        assert!(k.collisions >= k.collided_encounters, "{table}");
    }
    assert_eq!(
        t.encounters,
        t.robot_robot.encounters + t.robot_wall.encounters
    );
    assert_eq!(
        t.collided_encounters,
        t.robot_robot.collided_encounters + t.robot_wall.collided_encounters
    );
    let successes = t.encounters - t.collided_encounters;
    assert_eq!(
        t.success_rate,
        Some(successes as f64 / t.encounters as f64),
        "{table}"
    );
    assert_eq!(t.collision_events.len() as u64, t.collisions);
    let wall_events = t
        .collision_events
        .iter()
        .filter(|e| e.other_robot.is_none())
        .count() as u64;
    assert_eq!(wall_events, t.robot_wall.collisions);
    assert!(t
        .collision_events
        .iter()
        .all(|e| (0.0..=120.0).contains(&e.time_s) && e.other_robot.is_none_or(|o| o > e.robot)));
    let frames: u64 = t.state_frames.values().sum();
    assert_eq!(frames, 3 * 3600);
}
