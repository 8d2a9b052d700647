//! The ablation (`cargo alvs ablation`, issue 30 item 1): each part is the experiment's own run
//! with the variant's model — the arena paired with the robustness suite's trial of the same
//! seed, evasion and two threats as their commands run them, the clips as `replay` runs them —
//! and a split run merges into the whole one.

use alvs_host::experiments::ablation::{
    AblationConfig, AblationReport, Measured, Part, Variant, CLOSE_MM, MECHANISMS,
};
use alvs_host::experiments::evasion::{self, EvasionConfig};
use alvs_host::experiments::robustness::{Perturbation, RobustnessConfig, SuiteController};
use alvs_host::experiments::sweep::{self, Shard, Sweep};
use alvs_host::experiments::two_threats::{self, TwoThreatConfig};
use alvs_host::experiments::Report;
use alvs_sim::Kind;
use alvs_tasks::model::fsm::{Escape, FsmParams};
use alvs_tasks::Params;

mod common;
use common::{alvs, succeed, tmp};

fn index(name: &str) -> usize {
    MECHANISMS.iter().position(|m| m.name == name).unwrap()
}

/// One seed, the default and the default without its escape saccade, short runs.
fn small() -> AblationConfig {
    AblationConfig {
        seeds: vec![11],
        variants: vec![Variant::Alvs, Variant::Without(index("escape-saccade"))],
        walls: vec![None],
        close_walls: vec![None],
        minutes: 0.2,
        two_threat_runs: 3,
        clips: false,
        ..AblationConfig::default()
    }
}

fn cell<'a>(r: &'a AblationReport, part: &Part, variant: usize) -> &'a Measured {
    let p = r.config.parts().iter().position(|x| x == part).unwrap();
    &r.cells[p][variant].pooled
}

#[test]
fn each_part_is_the_experiments_own_run_with_the_variants_model() {
    let config = small();
    let r = sweep::run_all(&config, 2, &|_| {}).unwrap();

    // the arena: the robustness suite's unperturbed trial of the same seed, exactly
    let suite = sweep::run_all(
        &RobustnessConfig {
            seeds: vec![11],
            perturbations: vec![Perturbation::None],
            controllers: vec![SuiteController::Alvs],
            minutes: 0.2,
            ..RobustnessConfig::default()
        },
        1,
        &|_| {},
    )
    .unwrap();
    let t = &suite.trials[0].trial;
    let arena = Part::Arena {
        perturbation: Perturbation::None,
    };
    match cell(&r, &arena, 0) {
        Measured::Arena {
            encounters,
            collided,
            speed_mm_s,
            at_wall,
            ..
        } => {
            assert_eq!(*encounters, t.encounters);
            assert_eq!(*collided, t.collided_encounters);
            assert_eq!(*speed_mm_s, t.mean_speed_mm_s);
            assert_eq!(*at_wall, t.wall_contact_fraction);
        }
        m => panic!("not an arena record: {m:?}"),
    }

    // evasion and two threats: the commands' runs, the variant's model
    let without = FsmParams {
        escape: Escape {
            escape_saccade: false,
            ..FsmParams::ALVS.escape
        },
        ..FsmParams::ALVS
    };
    for (v, fsm) in [(0, FsmParams::ALVS), (1, without)] {
        // from the stage's longest distance, and from 100 mm: the obstacle first seen close
        for from_mm in [None, Some(CLOSE_MM)] {
            let e = evasion::run(
                &EvasionConfig {
                    seed: 11,
                    controllers: vec![Kind::Alvs],
                    params: Params::ALVS,
                    fsm,
                    distance_mm: from_mm,
                    ..EvasionConfig::default()
                },
                1,
                &|_| {},
            )
            .unwrap();
            let c = &e.controllers[0];
            let part = Part::Evasion {
                wall: None,
                from_mm,
            };
            assert_eq!(
                cell(&r, &part, v),
                &Measured::Evasion {
                    angles: 9,
                    correct: c.correct_side,
                    collisions: c.collisions,
                    gamma: c.gamma_paths().unwrap(),
                }
            );
        }
        let two = two_threats::run(
            &TwoThreatConfig {
                seed: 11,
                runs: 3,
                controllers: vec![Kind::Alvs],
                params: Params::ALVS,
                fsm,
                ..TwoThreatConfig::default()
            },
            1,
            &|_| {},
        )
        .unwrap();
        let c = &two.controllers[0];
        assert_eq!(
            cell(&r, &Part::TwoThreats, v),
            &Measured::TwoThreats {
                runs: 3,
                away: c.away_from_faster,
                collisions: c.collisions,
            }
        );
    }
    // and the table says which is the reference of which
    let table = r.table();
    assert!(table.contains("alvs-escape-saccade"), "{table}");
}

#[test]
fn the_clips_show_what_a_mechanism_does_to_the_first_alerts() {
    // the warm-up holds back the alerts of the first frames: without it some clip alerts
    // earlier, none later, and every looming clip is still detected
    let config = AblationConfig {
        seeds: vec![11],
        variants: vec![Variant::Alvs, Variant::Without(index("warmup"))],
        perturbations: vec![],
        walls: vec![],
        close_walls: vec![],
        two_threat_runs: 0,
        clips: true,
        ..AblationConfig::default()
    };
    assert_eq!(config.parts(), vec![Part::Clips]);
    let r = sweep::run_all(&config, 2, &|_| {}).unwrap();
    let (Measured::Clips(with), Measured::Clips(without)) =
        (cell(&r, &Part::Clips, 0), cell(&r, &Part::Clips, 1))
    else {
        panic!("not clip records");
    };
    assert_eq!(with.len(), without.len());
    let mut earlier = 0;
    for (a, b) in with.iter().zip(without) {
        assert_eq!(a.name, b.name);
        if a.looming {
            assert!(a.alerts > 0 && b.alerts > 0, "{} not detected", a.name);
            assert!(b.first_alert <= a.first_alert, "{}", a.name);
            earlier += usize::from(b.first_alert < a.first_alert);
        }
        // the warm-up lasts 4 frames: it moves no alert past frame 4
        if b.first_alert < a.first_alert {
            assert!(
                b.first_alert.unwrap() < 4,
                "{}: {:?}",
                a.name,
                b.first_alert
            );
        }
    }
    assert!(earlier > 0);
}

#[test]
fn merged_ablation_shards_are_the_unsharded_run() {
    let config = AblationConfig {
        minutes: 0.1,
        two_threat_runs: 2,
        ..small()
    };
    let strip = |mut v: serde_json::Value| {
        v.as_object_mut().unwrap().remove("wall_clock_s");
        v
    };
    let whole = strip(sweep::run_all(&config, 2, &|_| {}).unwrap().json());
    let dir = tmp("sweep-ablation");
    let files: Vec<_> = (1..=3)
        .map(|index| {
            let v = sweep::run_shard(&config, &[], Shard { index, count: 3 }, 1, &|_| {}).unwrap();
            let path = dir.join(format!("{index}.json"));
            std::fs::write(&path, serde_json::to_string(&v).unwrap()).unwrap();
            sweep::read(&path).unwrap()
        })
        .collect();
    // arena, evasion, evasion from 100 mm, two threats
    assert_eq!(config.trial_count(), 2 * 4);
    assert_eq!(strip(sweep::merge(&config, &files).unwrap().json()), whole);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cli_refuses_an_unknown_variant_in_one_line() {
    let out = alvs()
        .args(["ablation", "--variant", "alvs-wings"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("unknown variant") && err.contains("floor"),
        "{err}"
    );
    let help = succeed(alvs().args(["ablation", "--help"]));
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(
        help.contains("--variant") && help.contains("--wall") && help.contains("--close-wall"),
        "{help}"
    );
}
