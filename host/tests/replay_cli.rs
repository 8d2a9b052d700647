//! `alvs replay` end to end: one JSON object per frame, pictures, and one clear error line with
//! a non-zero exit for bad input.

use alvs_host::clip::to_pgm;
use alvs_host::scenes::demo_scenes;

mod common;
use common::{alvs, fails_in_one_line, succeed, tmp};

#[test]
fn replay_prints_one_json_object_per_frame_and_draws() {
    let d = tmp("json");
    let scene = &demo_scenes()[0];
    let frames = scene.frames();
    let clip = d.join("approach.y8");
    std::fs::write(&clip, frames.concat()).unwrap();
    let out = succeed(
        alvs()
            .arg("replay")
            .arg(&clip)
            .arg("--png")
            .arg(d.join("png")),
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), frames.len());
    for (i, v) in lines.iter().enumerate() {
        assert_eq!(v["frame"], i as u64);
        for key in [
            "afs",
            "lplc2_sum",
            "strength",
            "threat_x",
            "alert",
            "short_mode",
            "state",
        ] {
            assert!(v.get(key).is_some(), "frame {i} lacks {key}: {v}");
        }
        let state = v["state"].as_str().unwrap();
        assert!(
            ["wander", "long_takeoff", "escape", "short_takeoff"].contains(&state),
            "{state}"
        );
    }
    assert_eq!(lines[0]["alert"], false, "the first frame primes");
    assert!(
        lines.iter().any(|v| v["alert"] == true),
        "an approaching square alerts"
    );
    assert!(
        lines.iter().any(|v| v["state"] != "wander"),
        "and the FSM leaves wander"
    );
    let pngs: Vec<_> = std::fs::read_dir(d.join("png"))
        .unwrap()
        .flatten()
        .collect();
    assert!(pngs
        .iter()
        .any(|e| e.file_name().to_string_lossy().ends_with("_trace.png")));
    assert!(pngs
        .iter()
        .any(|e| e.file_name().to_string_lossy().contains("_layers_")));
}

#[test]
fn a_directory_of_pgm_frames_gives_the_same_output() {
    let d = tmp("pgm");
    let frames = demo_scenes()[1].frames();
    std::fs::write(d.join("clip.y8"), frames.concat()).unwrap();
    let pgm = d.join("frames");
    std::fs::create_dir_all(&pgm).unwrap();
    for (i, f) in frames.iter().enumerate() {
        std::fs::write(pgm.join(format!("f{i:04}.pgm")), to_pgm(f)).unwrap();
    }
    let a = alvs()
        .arg("replay")
        .arg(d.join("clip.y8"))
        .output()
        .unwrap();
    let b = alvs().arg("replay").arg(&pgm).output().unwrap();
    assert!(a.status.success() && b.status.success());
    assert_eq!(a.stdout, b.stdout);
}

#[test]
fn bad_input_is_one_clear_line_and_a_failure() {
    let d = tmp("bad");
    std::fs::write(d.join("short.y8"), [0u8; 7000]).unwrap();
    std::fs::write(d.join("bad.pgm"), b"P6\n99 72\n255\n").unwrap();
    let ok = d.join("ok.y8");
    std::fs::write(&ok, vec![0u8; 7128 * 2]).unwrap();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![d.join("missing.y8").display().to_string()],
            "no such file",
        ),
        (
            vec![d.join("short.y8").display().to_string()],
            "not a multiple",
        ),
        (vec![d.display().to_string()], "P5"),
        (
            vec![ok.display().to_string(), "--width".into(), "160".into()],
            "99x72",
        ),
        (
            vec![ok.display().to_string(), "--param".into(), "bogus=1".into()],
            "unknown parameter",
        ),
        (
            vec![ok.display().to_string(), "--param".into(), "t_a".into()],
            "NAME=VALUE",
        ),
    ];
    for (args, expect) in cases {
        fails_in_one_line(alvs().arg("replay").args(&args), expect);
    }
}

#[test]
fn a_reader_that_stops_early_ends_the_replay_quietly() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    let d = tmp("pipe");
    // long enough that the output outgrows the pipe buffer after the reader has gone
    let frames: Vec<_> = (0..40).flat_map(|_| demo_scenes()[0].frames()).collect();
    std::fs::write(d.join("long.y8"), frames.concat()).unwrap();
    let mut child = alvs()
        .arg("replay")
        .arg(d.join("long.y8"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    assert!(first.starts_with("{\"frame\":0"), "{first}");
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && !err.contains("panicked"),
        "{:?} {err}",
        out.status
    );
}

/// `--mode swarm`: the replay runs the swarm's look beside the network, as the arena's swarm
/// robots do. A robot that stops to look at a scene where something moves sets off towards it
/// at the look's end; in a still scene it turns to look elsewhere.
#[test]
fn a_swarm_replay_looks_and_sets_off_towards_what_moves() {
    use alvs_host::replay::Pipeline;
    use alvs_tasks::model::closed_loop::movers::Sighting;
    use alvs_tasks::model::fsm::{Behaviour, FsmParams, State};
    use alvs_tasks::{Params, PIXELS, WIDTH};
    let run = |moving: bool| {
        let mut pipe =
            Pipeline::new(Params::default(), FsmParams::default(), Behaviour::Swarm).unwrap();
        let (mut states, mut seen) = (Vec::new(), Vec::new());
        for i in 0..70usize {
            let mut f = [120u8; PIXELS];
            // a small dark object near the horizon, drifting right a column every two frames
            let x0 = if moving { 60 + i / 2 } else { 70 };
            for y in 33..38 {
                for x in x0..x0 + 4 {
                    f[y * WIDTH + x] = 40;
                }
            }
            let (out, _) = pipe.step(&f);
            states.push(pipe.fsm.state());
            seen.push(out.vm.sighting);
        }
        (states, seen)
    };
    // 45 frames of wandering, then the look: 10 frames to settle and 12 to watch
    let (moving, seen) = run(true);
    assert_eq!(moving[43], State::Wander);
    assert!(
        moving[44..66].iter().all(|&s| s == State::Look),
        "{moving:?}"
    );
    // the look ends on frame 66 and finds the object (columns 87–96 by then) on the right
    assert!(seen[..66].iter().all(Option::is_none));
    let Some(Sighting::Mover { x }) = seen[66] else {
        panic!("{:?}", seen[66]);
    };
    assert!((80..=96).contains(&x), "{x}");
    assert_eq!(moving[66], State::Wander, "set off towards the mover");
    let (still, seen) = run(false);
    assert_eq!(seen[66], Some(Sighting::Nothing));
    assert_eq!(still[66], State::Look, "turning to look elsewhere");
}
