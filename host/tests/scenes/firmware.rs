//! The authors' firmware's perception (`Params::FIRMWARE`, docs/model.md "The authors'
//! firmware"): one attention field, its output the 4-frame mean above `T_LPLC2`.

use super::*;
use alvs_host::scenes::{demo_scenes, Scene, Square};
use alvs_tasks::model::param_table::off0;
use alvs_tasks::model::params::FirmwareVariant;

/// The demo's three squares approaching at once (paper Fig. 3's triple approach): the paper's
/// model opens a field on each, the firmware's never has more than one alive, nor does the
/// paper's model given the firmware's one field.
#[test]
fn the_firmware_keeps_one_attention_field() {
    let scene = demo_scenes()
        .into_iter()
        .find(|s| s.name == "triple_approach")
        .unwrap();
    let most = |p: Params| {
        let mut net = Network::new(p).unwrap();
        scene
            .frames()
            .iter()
            .map(|f| {
                let out = net.step(f);
                out.afs.len().max(net.fields().len())
            })
            .max()
            .unwrap()
    };
    assert_eq!(most(Params::PAPER), 3);
    assert!(most(Params::FIRMWARE) <= 1);
    let one = Params {
        firmware: FirmwareVariant {
            max_fields: 1,
            ..Params::PAPER.firmware
        },
        ..Params::PAPER
    };
    assert_eq!(most(one), 1);
    // the one field still sees a threat
    let mut net = Network::new(one).unwrap();
    let alerts = scene
        .frames()
        .iter()
        .filter(|f| net.step(f).alert())
        .count();
    assert!(alerts > 0, "{alerts}");
}

/// A dark square growing 2 px a frame: the firmware's field survives its first frame only if
/// its gate opens (three quadrants of `T_cardinal` = 50,000), and alerts once the mean of its
/// last 4 responses exceeds `T_LPLC2` = 150,000, passing on that mean: two frames after the
/// field opened, where the paper's model alerts on the frame its gate opens.
#[test]
fn the_firmware_alerts_on_its_four_frame_mean() {
    let scene = Scene {
        name: "fast_dark_square",
        looming: true,
        squares: vec![Square {
            x: 49.0,
            y: 36.0,
            half: 4.0,
            grow: 2.0,
            vx: 0.0,
            grey: 0,
        }],
        frames: 16,
    };
    let p = Params::FIRMWARE;
    let mut net = Network::new(p).unwrap();
    let outs: Vec<Perception> = scene.frames().iter().map(|f| net.step(f)).collect();
    let opened = outs.iter().position(|o| !o.afs.is_empty()).unwrap();
    let first = outs.iter().position(Perception::alert).unwrap();
    assert_eq!(first, opened + 2, "{opened} {first}");
    // before: a field whose gate opened, not yet stimulated
    let f = &outs[opened].afs[0];
    let excited = f
        .quadrants
        .iter()
        .filter(|&&q| q > p.choices.q_floor)
        .count();
    assert!(excited >= 3 && f.lplc2 == 0, "{f:?}");
    // at the alert: the field passes on its mean, above T_LPLC2, and that is ΣLPLC2
    let a = &outs[first];
    assert!(a.afs[0].lplc2 > off0(p.firmware.t_lplc2), "{a:?}");
    assert_eq!(a.vm.lplc2_sum, a.afs[0].lplc2);
    // the mean of 4 responses, three of them this field's (the frame before its birth counts 0)
    let responses: u32 = (opened..=first)
        .map(|i| outs[i].afs[0].quadrants.iter().sum::<u32>())
        .sum();
    assert_eq!(a.afs[0].lplc2, responses / 4);
    // the paper's model, from the same frames
    let mut paper = Network::new(Params::PAPER).unwrap();
    let first_paper = scene
        .frames()
        .iter()
        .position(|f| paper.step(f).alert())
        .unwrap();
    assert!(first_paper < first, "{first_paper} {first}");
}
