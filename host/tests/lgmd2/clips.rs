//! Both parameter sets on the looming clips of `data/clips`, with a per-clip table.

use super::*;

/// Writes to the process's stderr directly: the harness captures `println!`, and the table is
/// meant to be read in every CI log.
macro_rules! table {
    ($($arg:tt)*) => {{
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

struct ClipRun {
    name: String,
    looming: bool,
    frames: usize,
    outs: Vec<Lgmd2Output>,
}

impl ClipRun {
    fn collisions(&self) -> usize {
        self.outs.iter().filter(|o| o.collision).count()
    }
    fn first_collision(&self) -> Option<usize> {
        self.outs.iter().position(|o| o.collision)
    }
    fn peak_smp(&self) -> f32 {
        self.outs.iter().map(|o| o.smp).fold(0.0, f32::max)
    }
    /// Peak SMP from frame 5 on: without the start-up transient (the delayed inhibition starts
    /// from empty layers, so the first processed frames are barely inhibited).
    fn peak_smp_settled(&self) -> f32 {
        self.outs.iter().skip(5).map(|o| o.smp).fold(0.0, f32::max)
    }
    fn peak_sfa(&self) -> f32 {
        self.outs.iter().map(|o| o.sfa).fold(0.0, f32::max)
    }
    fn spikes(&self) -> u32 {
        self.outs.iter().map(|o| o.spikes).sum()
    }
    /// One character a frame: `C` collision, `s` spikes without collision, `.` silent.
    fn timeline(&self) -> String {
        self.outs
            .iter()
            .map(|o| match (o.collision, o.spikes) {
                (true, _) => 'C',
                (false, 0) => '.',
                _ => 's',
            })
            .collect()
    }
}

fn run_clips(params: &Lgmd2Params) -> Vec<ClipRun> {
    data::manifest()
        .expect("data/clips/manifest.csv")
        .into_iter()
        .map(|c| {
            let frames = clip::load(&data::clip_path(&c.name), 99, 72).expect("clip");
            assert_eq!(frames.len(), c.frames, "{}: frame count", c.name);
            let mut m = Lgmd2::new(params.clone());
            let outs = frames.iter().map(|f| m.step(f)).collect();
            ClipRun {
                name: c.name,
                looming: c.looming,
                frames: frames.len(),
                outs,
            }
        })
        .collect()
}

fn print_table(title: &str, runs: &[ClipRun]) {
    table!("\nLGMD2 {title}: C collision, s spikes without collision, . silent");
    table!(
        "{:<38} {:>4} {:>6} {:>5} {:>6} {:>8} {:>8} {:>8} {:>6}  timeline",
        "clip",
        "loom",
        "frames",
        "coll",
        "first",
        "peak SMP",
        "SMP t>=5",
        "peak SFA",
        "spikes"
    );
    for r in runs {
        let first = r
            .first_collision()
            .map_or("-".to_string(), |f| f.to_string());
        table!(
            "{:<38} {:>4} {:>6} {:>5} {:>6} {:>8.4} {:>8.4} {:>8.4} {:>6}  {}",
            r.name,
            if r.looming { "yes" } else { "no" },
            r.frames,
            r.collisions(),
            first,
            r.peak_smp(),
            r.peak_smp_settled(),
            r.peak_sfa(),
            r.spikes(),
            r.timeline()
        );
    }
}

/// The looming clips on which the Colias baseline (the default parameters) raises a collision
/// alert. The other looming clips do not trigger it with the faithful parameters, and the
/// model is not tuned to make them: the 7 synthetic `outdoor_*` clips (a dark square growing
/// only ~0.3 px a frame per edge at 99x72 over a scrolling textured background: SMP peaks at
/// 0.56–0.64 after the start-up frames, SFA stays below T_sp = 0.63, not one spike),
/// `test_white_approach` (LGMD2 is selective to
/// darker objects: a brightening edge is always out-inhibited, SMP stays 0.5), and the real
/// clips `real_bear_attack`, `real_bird_attack_2`, `real_bird_attack_2_slow`,
/// `real_helmet_attack`, which spike but are low-frame-rate footage repeated at 30 fps: the
/// near-duplicate frames are silent, and a silent frame ends the spike burst before it
/// reaches 4 spikes (module doc of `lgmd2`, interpretation 11).
const COLIAS_ALERTS_ON: [&str; 7] = [
    "test_black_approach",
    "real_UAV_outdoor_1",
    "real_UAV_outdoor_1_slow",
    "real_UAV_outdoor_2",
    "real_UAV_outdoor_black_rectangle",
    "real_bird_attack",
    "real_car_attack",
];

fn find<'a>(runs: &'a [ClipRun], name: &str) -> &'a ClipRun {
    runs.iter()
        .find(|r| r.name == name)
        .unwrap_or_else(|| panic!("{name} is not in manifest.csv"))
}

#[test]
fn clips_colias_baseline() {
    let runs = run_clips(&Lgmd2Params::colias());
    print_table("colias() (the default, the robot baseline)", &runs);
    let silent: Vec<String> = runs
        .iter()
        .filter(|r| r.looming && r.collisions() == 0)
        .map(|r| {
            format!(
                "{} (peak SMP {:.3}, {} spikes)",
                r.name,
                r.peak_smp(),
                r.spikes()
            )
        })
        .collect();
    table!("looming clips without a collision alert (reported, not asserted): {silent:#?}");
    for name in COLIAS_ALERTS_ON {
        let r = find(&runs, name);
        assert!(r.looming, "{name} is a looming clip");
        assert!(
            r.collisions() > 0,
            "{name}: no collision alert; {}",
            r.timeline()
        );
    }
    // selectivity to darker objects: an approaching white square gives no response at all
    let white = find(&runs, "test_white_approach");
    assert!(
        white.peak_smp() <= 0.5 + 1e-6,
        "white approach: peak SMP {}",
        white.peak_smp()
    );
}

#[test]
fn clips_reference() {
    let runs = run_clips(&Lgmd2Params::reference());
    print_table("reference() (the C# reference values)", &runs);
    // with T_sp = 0.78 and 8 spikes, only the high-contrast synthetic approach alerts
    assert!(find(&runs, "test_black_approach").collisions() > 0);
    let white = find(&runs, "test_white_approach");
    assert!(
        white.peak_smp() <= 0.5 + 1e-6,
        "white approach: peak SMP {}",
        white.peak_smp()
    );
}
