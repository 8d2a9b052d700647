//! Experiment 4 (`alvs arena`) on short runs: its counts are consistent, it is deterministic by
//! seed whatever the number of threads, ALVS and LGMD2 start from the same poses, the JSON has
//! the documented keys, and the command line helps and fails cleanly.

use std::sync::OnceLock;

use alvs_host::experiments::arena::{
    run, start_poses, trace_header, ArenaConfig, ArenaReport, TallyStats, START_SEPARATION_MM,
    START_WALL_CLEARANCE_MM,
};
use alvs_host::experiments::Report;
use alvs_sim::contacts::{ROBOT_ENCOUNTER_DISTANCE_MM, WALL_ENCOUNTER_DISTANCE_MM};
use alvs_sim::{BuiltinWorld, Kind, World};
use serde_json::Value;

mod common;
use common::{alvs, fails_in_one_line, read_json, succeed, tmp};

/// 0.5 simulated minutes: 900 camera frames per robot.
fn short_config() -> ArenaConfig {
    ArenaConfig {
        robots: 3,
        minutes: 0.5,
        backgrounds: vec!["clutter:1".into()],
        controllers: vec![Kind::Alvs, Kind::Lgmd2],
        seed: 7,
        world: BuiltinWorld::Lab,
        ..ArenaConfig::default()
    }
}

/// The short run on two threads, shared by the tests.
fn short_run() -> &'static ArenaReport {
    static REPORT: OnceLock<ArenaReport> = OnceLock::new();
    REPORT.get_or_init(|| run(&short_config(), 2, &|_| {}).expect("a valid configuration"))
}

/// The report's JSON without the wall-clock times (the only numbers allowed to vary).
fn numbers(report: &ArenaReport) -> Value {
    fn strip(v: &mut Value) {
        match v {
            Value::Object(m) => {
                m.remove("wall_clock_s");
                m.values_mut().for_each(strip);
            }
            Value::Array(a) => a.iter_mut().for_each(strip),
            _ => {}
        }
    }
    let mut v = report.json();
    strip(&mut v);
    v
}

fn check_tally(what: &str, t: &TallyStats, minutes: f64) {
    assert!(t.collided_encounters <= t.encounters, "{what}: {t:?}");
    assert!(t.collisions >= t.collided_encounters, "{what}: {t:?}");
    match t.success_rate {
        None => assert_eq!(t.encounters, 0, "{what}: {t:?}"),
        Some(r) => {
            assert!((0.0..=1.0).contains(&r), "{what}: {t:?}");
            let expect = (t.encounters - t.collided_encounters) as f64 / t.encounters as f64;
            assert!((r - expect).abs() < 1e-12, "{what}: {t:?}");
        }
    }
    assert!(
        (t.collisions_per_minute - t.collisions as f64 / minutes).abs() < 1e-9,
        "{what}: {t:?}"
    );
}

#[test]
fn counts_are_consistent() {
    let report = short_run();
    assert_eq!(report.trials.len(), 2);
    assert_eq!(report.summaries.len(), 2);
    for t in &report.trials {
        let what = format!("{} on {}", t.controller, t.background);
        assert_eq!(t.frames, 900, "{what}");
        assert!((t.minutes - 0.5).abs() < 1e-9, "{what}");
        check_tally(&format!("{what} robot-robot"), &t.robot_robot, t.minutes);
        check_tally(&format!("{what} robot-wall"), &t.robot_wall, t.minutes);
        let total = TallyStats {
            encounters: t.encounters,
            collisions: t.collisions,
            collided_encounters: t.collided_encounters,
            success_rate: t.success_rate,
            collisions_per_minute: t.collisions_per_minute,
        };
        check_tally(&format!("{what} total"), &total, t.minutes);
        assert_eq!(
            t.encounters,
            t.robot_robot.encounters + t.robot_wall.encounters
        );
        assert_eq!(
            t.collisions,
            t.robot_robot.collisions + t.robot_wall.collisions
        );
        assert_eq!(t.collision_events.len() as u64, t.collisions, "{what}");
        let sum: f64 = t.state_fraction.values().sum();
        assert!(
            (sum - 1.0).abs() < 1e-9,
            "{what}: state fractions sum to {sum}"
        );
        assert_eq!(
            t.state_frames.values().sum::<u64>(),
            t.frames * t.robots as u64,
            "{what}"
        );
        assert!(t.state_fraction.contains_key("wander"), "{what}");
        assert!((0.0..=1.0).contains(&t.wall_contact_fraction), "{what}");
        assert!(
            (0.0..400.0).contains(&t.mean_speed_mm_s),
            "{what}: {}",
            t.mean_speed_mm_s
        );
        assert_eq!(t.trails.len(), 3);
        assert!(t.trails.iter().all(|tr| tr.len() == 151), "{what}");
        assert!(t.short_takeoffs_in_encounter <= t.short_takeoffs, "{what}");
        if t.controller == "lgmd2" {
            assert_eq!(t.short_takeoffs, 0, "LGMD2 has no short mode");
        }
        assert!(t.wall_clock_s > 0.0);
    }
    for s in &report.summaries {
        let mine: Vec<_> = report
            .trials
            .iter()
            .filter(|t| t.controller == s.controller)
            .collect();
        assert_eq!(s.trials, mine.len());
        assert_eq!(s.encounters, mine.iter().map(|t| t.encounters).sum::<u64>());
        check_tally(
            &format!("{} robot-robot", s.controller),
            &s.robot_robot,
            s.minutes,
        );
        check_tally(
            &format!("{} robot-wall", s.controller),
            &s.robot_wall,
            s.minutes,
        );
        let sum: f64 = s.state_fraction.values().sum();
        assert!((sum - 1.0).abs() < 1e-9);
        assert_eq!(
            (s.short_takeoffs, s.short_takeoffs_in_encounter),
            (
                mine.iter().map(|t| t.short_takeoffs).sum::<u64>(),
                mine.iter()
                    .map(|t| t.short_takeoffs_in_encounter)
                    .sum::<u64>()
            )
        );
    }
    assert!(
        report.trials.iter().any(|t| t.encounters > 0),
        "robots meet the walls within half a minute"
    );
}

#[test]
fn deterministic_by_seed_whatever_the_threads() {
    let one_thread = run(&short_config(), 1, &|_| {}).unwrap();
    assert_eq!(numbers(short_run()), numbers(&one_thread));
    assert_eq!(one_thread.jobs, 1);
    assert_eq!(short_run().jobs, 2);

    let tiny = |seed| {
        let c = ArenaConfig {
            minutes: 0.05,
            seed,
            ..short_config()
        };
        numbers(&run(&c, 2, &|_| {}).unwrap())
    };
    assert_eq!(tiny(3), tiny(3));
    assert_ne!(
        tiny(3)["trials"],
        tiny(4)["trials"],
        "another seed, another run"
    );
}

#[test]
fn trace_follows_every_robot_frame_by_frame() {
    assert!(short_run().trials.iter().all(|t| t.trace.is_empty()));
    let c = ArenaConfig {
        minutes: 0.2,
        trace: true,
        // the paper's FSM, whose γ paths exercise the short-takeoff counts below (the
        // default's escape saccade starts few)
        fsm: alvs_tasks::model::fsm::FsmParams::PAPER,
        ..short_config()
    };
    let report = run(&c, 2, &|_| {}).unwrap();
    let header: Vec<String> = trace_header().split(',').map(String::from).collect();
    let col = |name: &str| header.iter().position(|h| h == name).unwrap() - 2;
    let arena = World::default().arena;
    for t in &report.trials {
        assert_eq!(
            t.trace.len() as u64,
            t.frames * t.robots as u64,
            "{}",
            t.controller
        );
        let rows: Vec<Vec<&str>> = t.trace.iter().map(|l| l.split(',').collect()).collect();
        // the states add up to the trial's time per state
        let mut states = std::collections::BTreeMap::new();
        // short takeoffs started, and those started inside an encounter
        let (mut last, mut starts, mut near) = (vec![String::new(); t.robots], 0u64, 0u64);
        // starts whose distances lie within the trace's rounding of a limit
        let mut borderline = 0u64;
        // frame-major: one line per robot, in order, for every frame
        for (frame, lines) in rows.chunks(t.robots).enumerate() {
            let num = |r: &[&str], name: &str| r[col(name)].parse::<f64>().unwrap();
            let xy: Vec<(f64, f64)> = lines
                .iter()
                .map(|r| (num(r, "x_mm"), num(r, "y_mm")))
                .collect();
            for (i, r) in lines.iter().enumerate() {
                assert_eq!(r.len(), header.len() - 2, "{r:?}");
                assert_eq!(r[col("robot")], i.to_string(), "{r:?}");
                assert_eq!(r[col("frame")], frame.to_string(), "{r:?}");
                assert_eq!(
                    r[col("t_s")],
                    format!("{:.4}", (frame + 1) as f64 / 30.0),
                    "{r:?}"
                );
                *states.entry(r[col("state")].to_string()).or_insert(0u64) += 1;
                let f = |name: &str| num(r, name);
                let wall = arena.wall_distance(f("x_mm"), f("y_mm"));
                if r[col("state")] == "short_takeoff" && last[i] != "short_takeoff" {
                    starts += 1;
                    let robots: Vec<f64> = xy
                        .iter()
                        .enumerate()
                        .filter(|&(j, _)| j != i)
                        .map(|(_, q)| (q.0 - xy[i].0).hypot(q.1 - xy[i].1))
                        .collect();
                    let robot_near = robots.iter().any(|&d| d < ROBOT_ENCOUNTER_DISTANCE_MM);
                    if robot_near || wall < WALL_ENCOUNTER_DISTANCE_MM {
                        near += 1;
                    }
                    let close = |d: f64, limit: f64| (d - limit).abs() < 0.2;
                    if close(wall, WALL_ENCOUNTER_DISTANCE_MM)
                        || robots
                            .iter()
                            .any(|&d| close(d, ROBOT_ENCOUNTER_DISTANCE_MM))
                    {
                        borderline += 1;
                    }
                }
                last[i] = r[col("state")].to_string();
                assert!((f("wall_mm") - wall).abs() <= 0.11, "{r:?}");
                // the nearest other robot of the same frame (positions rounded to 0.1 mm)
                let nearest = xy
                    .iter()
                    .enumerate()
                    .filter(|&(j, _)| j != i)
                    .map(|(_, q)| (q.0 - xy[i].0).hypot(q.1 - xy[i].1))
                    .fold(f64::INFINITY, f64::min);
                assert!((f("nearest_robot_mm") - nearest).abs() <= 0.2, "{r:?}");
                if t.controller == "alvs" {
                    // a field's response is an alert; an alert at ΣLPLC2 0 is the floor
                    // line's obstacle, which speaks only while the robot drives
                    let alert = r[col("alert")] == "1";
                    assert!(alert || f("response") == 0.0, "{r:?}");
                }
            }
        }
        assert_eq!(states, t.state_frames, "{}", t.controller);
        assert_eq!(t.short_takeoffs, starts, "{}", t.controller);
        assert!(
            t.short_takeoffs_in_encounter.abs_diff(near) <= borderline,
            "{}: {} against {near}",
            t.controller,
            t.short_takeoffs_in_encounter
        );
        if t.controller == "alvs" {
            assert!(starts > 0, "ALVS starts short takeoffs in these 12 s");
        }
        // the last frame's lines hold the end poses
        let last = &rows[rows.len() - t.robots..];
        for (r, end) in last.iter().zip(&t.end_poses) {
            assert_eq!(r[col("x_mm")], format!("{:.1}", end.x_mm));
            assert_eq!(r[col("y_mm")], format!("{:.1}", end.y_mm));
        }
    }
    let path = tmp("trace").join("trace.csv");
    report.write_trace(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(trace_header().as_str()));
    assert_eq!(
        lines.count(),
        report.trials.iter().map(|t| t.trace.len()).sum::<usize>()
    );
    assert!(text.contains("\nlgmd2,clutter:1,2,"));
}

#[test]
fn trace_quotes_a_background_path_and_leaves_a_lone_robot_without_neighbour() {
    let d = tmp("quoted");
    let wall = d.join("wall, \"grey\".png");
    alvs_sim::canvas::Canvas::new(64, 32, [128, 128, 128])
        .save_png(&wall)
        .unwrap();
    let c = ArenaConfig {
        robots: 1,
        minutes: 0.02,
        backgrounds: vec![wall.display().to_string()],
        controllers: vec![Kind::Lgmd2],
        trace: true,
        ..short_config()
    };
    let report = run(&c, 1, &|_| {}).unwrap();
    let path = d.join("trace.csv");
    report.write_trace(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let quoted = format!("\"{}\"", wall.display().to_string().replace('"', "\"\""));
    let first = text.lines().nth(1).unwrap();
    assert!(
        first.starts_with(&format!("lgmd2,{quoted},0,0,")),
        "{first}"
    );
    // no other robot: the last column is empty
    assert!(first.ends_with(','), "{first}");
    assert_eq!(text.lines().count(), 1 + 36);
}

#[test]
fn controllers_start_from_the_same_poses() {
    let report = short_run();
    let (a, l) = (&report.trials[0], &report.trials[1]);
    assert_eq!((a.controller, l.controller), ("alvs", "lgmd2"));
    assert_eq!(a.start_poses, l.start_poses);
    assert_eq!(a.trails[0][0], l.trails[0][0]);
    assert_ne!(a.end_poses, l.end_poses, "the controllers differ");
}

#[test]
fn start_poses_keep_their_distances() {
    let arena = World::default().arena;
    for seed in 0..50 {
        let poses = start_poses(&arena, 6, seed).unwrap();
        assert_eq!(poses, start_poses(&arena, 6, seed).unwrap());
        for (i, p) in poses.iter().enumerate() {
            assert!(arena.wall_distance(p.x_mm, p.y_mm) >= START_WALL_CLEARANCE_MM);
            for q in &poses[..i] {
                assert!(p.distance_to(q) >= START_SEPARATION_MM);
            }
        }
    }
    assert_ne!(
        start_poses(&arena, 3, 1).unwrap(),
        start_poses(&arena, 3, 2).unwrap()
    );
    let err = start_poses(&arena, 500, 1).unwrap_err().to_string();
    assert!(err.contains("cannot place 500 robots"), "{err}");
}

#[test]
fn json_has_the_documented_keys() {
    let v = short_run().json();
    let top: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
    assert_eq!(top.len(), 6, "{top:?}");
    for key in ["alvs", "lgmd2", "trials", "model", "fsm", "world"] {
        assert!(top.contains(&key), "{top:?}");
    }
    assert_eq!(v["model"], "alvs", "the default perception preset");
    assert_eq!(v["fsm"], "alvs", "the default motion preset");
    assert_eq!(v["world"], "lab");
    for c in ["alvs", "lgmd2"] {
        let s = &v[c];
        for key in [
            "success_rate",
            "encounters",
            "collisions",
            "collided_encounters",
            "short_takeoffs",
            "short_takeoffs_in_encounter",
        ] {
            assert!(s.get(key).is_some(), "{c} lacks {key}: {s}");
        }
        for part in ["robot_robot", "robot_wall"] {
            for key in [
                "encounters",
                "collisions",
                "success_rate",
                "collisions_per_minute",
            ] {
                assert!(s[part].get(key).is_some(), "{c}.{part} lacks {key}");
            }
        }
        assert!(s["state_fraction"].is_object());
        assert!(s["encounters"].is_u64());
        assert!(s["success_rate"].is_f64() || s["success_rate"].is_null());
    }
    assert!((v["alvs"]["paper_success_rate"].as_f64().unwrap() - 0.961).abs() < 1e-12);
    assert!((v["lgmd2"]["paper_success_rate"].as_f64().unwrap() - 0.937).abs() < 1e-12);
    let trials = v["trials"].as_array().unwrap();
    assert_eq!(trials.len(), 2);
    for t in trials {
        for key in [
            "controller",
            "background",
            "success_rate",
            "encounters",
            "collisions",
            "robot_robot",
            "robot_wall",
            "wall_touches",
            "short_takeoffs",
            "short_takeoffs_in_encounter",
            "state_fraction",
            "wall_clock_s",
            "start_poses",
            "trails",
        ] {
            assert!(t.get(key).is_some(), "a trial lacks {key}");
        }
    }
}

#[test]
fn cli_model_paper_runs_the_papers_perception_and_motion() {
    let d = tmp("paper");
    let run = |extra: &[&str]| {
        let json = d.join("arena.json");
        succeed(
            alvs()
                .args(["arena", "--minutes", "0.02", "--controller", "alvs"])
                .args(["--background", "plain:128", "--model", "paper", "--json"])
                .arg(&json)
                .arg("--png")
                .arg(d.join("png"))
                .args(extra),
        );
        let v = read_json(&json);
        (v["model"].clone(), v["fsm"].clone())
    };
    assert_eq!(run(&[]), ("paper".into(), "paper".into()));
    assert_eq!(
        run(&[
            "--fsm",
            "escape_saccade=1",
            "--fsm",
            "takeoff_drive=0.5",
            "--fsm",
            "takeoff_gain=3",
            "--fsm",
            "takeoff_yaw_deg_s=inf",
            "--fsm",
            "jump_frames=6",
            "--fsm",
            "gamma_turn=1",
            "--fsm",
            "look_every=45"
        ]),
        ("paper".into(), "alvs".into()),
        "the default's FSM is the paper's with the escape saccade, the moving takeoff, brisk \
         turns, the takeoff's jump, the γ path's turn and the swarm's looks"
    );
    assert_eq!(
        run(&["--fsm", "settle_frames=2"]),
        ("paper".into(), "custom".into())
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn cli_model_firmware_runs_the_authors_firmware() {
    let d = tmp("firmware");
    let json = d.join("arena.json");
    succeed(
        alvs()
            .args(["arena", "--minutes", "0.02", "--controller", "alvs"])
            .args(["--background", "plain:128", "--model", "firmware", "--json"])
            .arg(&json)
            .arg("--png")
            .arg(d.join("png")),
    );
    let v = read_json(&json);
    assert_eq!(
        (&v["model"], &v["fsm"]),
        (&"firmware".into(), &"firmware".into())
    );
    // the demo's scenes under it (every command shares the one `--model` choice)
    succeed(
        alvs()
            .args(["demo", "--model", "firmware", "--png"])
            .arg(d.join("demo")),
    );
    let bad = alvs()
        .args(["arena", "--model", "firmwar"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(err.contains("firmware"), "the choices are listed: {err}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn cli_writes_table_json_and_pictures() {
    let d = tmp("run");
    let json = d.join("arena.json");
    let out = alvs()
        .args(["arena", "--minutes", "0.05", "--background", "stripes:40"])
        .args(["--seed", "3", "--jobs", "2", "--json"])
        .arg(&json)
        .arg("--png")
        .arg(d.join("png"))
        .arg("--trace")
        .arg(d.join("trace.csv"))
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.is_empty(),
        "no progress bar off a terminal: {stderr}"
    );
    assert!(
        stdout.contains("96.1 %") && stdout.contains("93.7 %"),
        "{stdout}"
    );
    assert!(
        stdout.contains("alvs") && stdout.contains("lgmd2"),
        "{stdout}"
    );
    let v = read_json(&json);
    assert!(v["alvs"]["encounters"].is_u64() && v["lgmd2"]["collisions"].is_u64());
    assert_eq!(v["trials"][0]["background"], "stripes:40");
    for png in ["alvs_stripes-40.png", "lgmd2_stripes-40.png", "summary.png"] {
        let bytes = std::fs::read(d.join("png").join(png)).unwrap();
        assert!(bytes.starts_with(b"\x89PNG"), "{png}");
    }
    // 2 trials x 3 robots x 90 frames, after the header
    let trace = std::fs::read_to_string(d.join("trace.csv")).unwrap();
    assert_eq!(trace.lines().next(), Some(trace_header().as_str()));
    assert_eq!(trace.lines().count(), 1 + 2 * 3 * 90);
}

#[test]
fn cli_helps() {
    let out = alvs().args(["arena", "--help"]).output().unwrap();
    assert!(out.status.success());
    let help = String::from_utf8_lossy(&out.stdout);
    for flag in [
        "--minutes",
        "--robots",
        "--background",
        "--controller",
        "--seed",
        "--jobs",
        "--json",
        "--png",
        "--param",
        "encounter",
    ] {
        assert!(help.contains(flag), "--help lacks {flag}: {help}");
    }
}

#[test]
fn bad_arguments_are_one_clear_line_and_a_failure() {
    let d = tmp("bad");
    let cases: [(&[&str], &str); 13] = [
        (&["--background", "nosuch"], "nosuch"),
        (&["--background", "checker:-3"], "positive"),
        (&["--robots", "0"], "at least 1"),
        (&["--robots", "200"], "cannot place 200 robots"),
        (&["--minutes", "-1"], "positive"),
        (&["--minutes", "soon"], "soon"),
        (&["--controller", "fly"], "possible values"),
        (&["--jobs", "0"], "at least 1"),
        (&["--param", "bogus=1"], "unknown parameter"),
        (&["--exposure", "1.5"], "0..=1"),
        (&["--exposure", "-0.1"], "0..=1"),
        // refused before anything runs, not after a 10-minute run
        (&["--trace", "/nonexistent/dir/trace.csv"], "cannot write"),
        (&["--minutes", "2000", "--trace", "t.csv"], "--trace"),
    ];
    for (args, expect) in cases {
        fails_in_one_line(alvs().arg("arena").args(args).arg("--png").arg(&d), expect);
    }
}
