//! `alvs multi-target`'s ground truth and records: the squares its scripts draw are where the
//! clips are dark, the authors' record reads whole (and a bad line is an error naming it), and
//! a field counts as an object's own only in a one-to-one matching.

use alvs_host::multi_target as mt;
use alvs_host::replay::{AfJson, FrameJson};
use alvs_host::{clip, data};

mod common;
use common::{alvs, fails_in_one_line, read_json, succeed, tmp};

fn frames(name: &str) -> Vec<alvs_tasks::Frame> {
    clip::load(&data::clip_path(name), 99, 72).expect("clip")
}

#[test]
fn the_scripts_squares_are_where_the_clips_are_dark() {
    for c in mt::clips() {
        let fr = frames(c.name);
        assert_eq!(fr.len(), 120, "{}", c.name);
        let px = |t: u32, x: f32, y: f32| fr[t as usize][y as usize * 99 + x as usize];
        for s in &c.squares {
            // black inside once it covers a pixel, until it vanishes
            for t in s.appear + 3..s.vanish {
                let (x0, x1, y0, y1) = s.at(t).unwrap();
                let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
                assert!(px(t, cx, cy) < 10, "{} {s:?} frame {t}", c.name);
                if t >= s.appear + 45 {
                    // full size: 24.75 x 24 pixels; its inner corners are black too
                    for (x, y) in [(x0 + 2.0, y0 + 2.0), (x1 - 2.0, y1 - 2.0)] {
                        assert!(px(t, x, y) < 10, "{} {s:?} frame {t} ({x}, {y})", c.name);
                    }
                }
            }
            // the photograph shows through before it appears and after it vanishes
            let (cx, cy) = (s.centre.0 * 99.0 / 320.0, s.centre.1 * 72.0 / 240.0);
            for t in [s.appear, s.vanish] {
                assert!(px(t, cx, cy) > 40, "{} {s:?} frame {t}", c.name);
            }
            assert_eq!(s.at(s.appear), None, "side 0 at its first frame");
        }
    }
}

#[test]
fn the_authors_record_reads_whole() {
    let path = data::authors_fields_path();
    let three = mt::read_authors(&path, "outdoor_3_black_expand_multi_3").unwrap();
    let six = mt::read_authors(&path, "outdoor_3_black_expand_multi_6").unwrap();
    assert_eq!((three.len(), six.len()), (23, 18));
    // their multi_3 record has no drop frames; multi_6's has, up to 6 fields at once
    assert_eq!(mt::authors_alive(&three, 120), None);
    let alive = mt::authors_alive(&six, 120).unwrap();
    assert_eq!(alive.iter().max(), Some(&6));
    // each object of multi_6 got a field of theirs within 7 frames of its onset
    let c = &mt::clips()[1];
    for (s, first) in c.squares.iter().zip(mt::authors_first_field(c, &six)) {
        let f = first.expect("a field on every object");
        assert!((s.appear..=s.appear + 7).contains(&f), "{s:?}: {f}");
    }
}

#[test]
fn a_bad_line_in_the_authors_record_is_an_error_naming_it() {
    let dir = std::env::temp_dir().join(format!("alvs-mt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("fields.csv");
    let clip = "outdoor_3_black_expand_multi_6";
    for (text, says) in [
        (
            format!("clip,field,born,died,x,y\n{clip},1,2,13,86,120\n{clip},2,x,14,1,1\n"),
            ":3: not a whole number",
        ),
        (
            format!("clip,field,born,died,x,y\n{clip},1,2\n"),
            ":2: expected 6",
        ),
        ("field,born\n".to_string(), "line 1 must be the header"),
    ] {
        std::fs::write(&path, text).unwrap();
        let e = mt::read_authors(&path, clip).unwrap_err().to_string();
        assert!(e.contains(says), "{e}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
    let e = mt::read_authors(&dir.join("none.csv"), clip).unwrap_err();
    assert!(e.to_string().contains("cannot read"));
}

fn frame(t: u32, afs: &[(u8, u8)]) -> FrameJson {
    FrameJson {
        frame: t,
        afs: afs
            .iter()
            .map(|&(x, y)| AfJson { x, y, lplc2: 0 })
            .collect(),
        lplc2_sum: 0,
        strength: 0.5,
        threat_x: None,
        alert: false,
        short_mode: false,
        state: "wander",
    }
}

#[test]
fn an_object_has_a_field_of_its_own_only_one_to_one() {
    let c = &mt::clips()[0]; // squares at (74, 18), (25, 36) and (59, 54) in retina pixels
                             // frame 80: all three drawn; one field each
    let each = frame(80, &[(74, 18), (25, 36), (59, 54)]);
    // one field between the lower two sits on neither; two fields on the first object
    let shared = frame(81, &[(74, 18), (73, 20), (42, 45)]);
    let s = mt::summarise(c, &[each, shared]);
    assert_eq!((s.own_all_frames, s.object_frames, s.max_fields), (1, 2, 3));
    assert_eq!(s.first_field, vec![Some(80), Some(80), Some(80)]);
    // nothing drawn yet: the frame is not counted
    let s = mt::summarise(c, &[frame(10, &[(74, 18)])]);
    assert_eq!((s.own_all_frames, s.object_frames), (0, 0));
    assert_eq!(s.first_field, vec![None, None, None]);
    // the matching: one field on two objects serves one of them
    let on = |_o: usize, _f: usize| true;
    assert_eq!(mt::one_to_one(2, 1, &on), 1);
    let diag = |o: usize, f: usize| o == f;
    assert_eq!(mt::one_to_one(3, 3, &diag), 3);
    // augmenting: field 0 could serve either, field 1 only object 0
    let aug = |o: usize, f: usize| f == 0 || o == 0;
    assert_eq!(mt::one_to_one(2, 2, &aug), 2);
}

#[test]
fn the_command_compares_both_models_with_the_authors_and_draws() {
    let d = tmp("multi-target");
    let out = succeed(
        alvs()
            .arg("multi-target")
            .arg("--clips")
            .arg(data::clips_dir())
            .arg("--authors")
            .arg(data::authors_fields_path())
            .arg("--png")
            .arg(d.join("png"))
            .arg("--json")
            .arg(d.join("mt.json")),
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let json = read_json(&d.join("mt.json"));
    let clips = json.as_array().unwrap();
    assert_eq!(clips.len(), 2);
    for (c, want) in clips.iter().zip(mt::clips()) {
        let name = c["clip"]["name"].as_str().unwrap();
        assert_eq!(name, want.name);
        let models: Vec<&str> = c["models"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m[0].as_str().unwrap())
            .collect();
        assert_eq!(models, ["paper", "alvs"]);
        for m in c["models"].as_array().unwrap() {
            let s = &m[1];
            assert_eq!(s["fields"].as_array().unwrap().len(), 120);
            // a field sits on an object only while it is drawn
            for (first, sq) in s["first_field"]
                .as_array()
                .unwrap()
                .iter()
                .zip(&want.squares)
            {
                if let Some(f) = first.as_u64() {
                    assert!(
                        (sq.appear as u64..sq.vanish as u64).contains(&f),
                        "{name}: {f}"
                    );
                }
            }
        }
        for model in ["paper", "alvs", "authors"] {
            assert!(
                text.lines()
                    .any(|l| l.starts_with(name) && l.contains(model)),
                "{text}"
            );
        }
        assert!(d.join("png").join(format!("{name}_fields.png")).exists());
    }
}

#[test]
fn bad_input_to_the_command_is_one_clear_line() {
    let d = tmp("multi-target-bad");
    std::fs::write(d.join("authors.csv"), "clip,field,born,died,x,y\nx,y\n").unwrap();
    let cases = [
        (
            vec!["--clips".to_string(), d.display().to_string()],
            "no such file",
        ),
        (
            vec![
                "--clips".to_string(),
                data::clips_dir().display().to_string(),
                "--authors".to_string(),
                d.join("authors.csv").display().to_string(),
            ],
            "authors.csv:2: expected 6",
        ),
        (
            vec!["--param".to_string(), "bogus=1".to_string()],
            "unknown parameter",
        ),
    ];
    for (args, expect) in cases {
        let png = d.join("png");
        fails_in_one_line(
            alvs().arg("multi-target").args(&args).arg("--png").arg(png),
            expect,
        );
    }
}
