//! Replay: the exact `alvs-tasks` perception and motor-control code run on recorded frames,
//! one JSON object per frame, and the pictures a researcher looks at.

use alvs_tasks::model::param_table::off0;
use std::path::{Path, PathBuf};

use alvs_tasks::model::closed_loop::movers::Movers;
use alvs_tasks::model::fsm::{Behaviour, Fsm, FsmParams, HeadingEstimator, Odometry};
use alvs_tasks::model::hrc::{motion_map, Direction};
use alvs_tasks::{Frame, Network, Params, Perception, HEIGHT, PIXELS, WIDTH};
use anyhow::{Context, Result};
use serde::Serialize;

use alvs_sim::canvas::{colour_cycle, grey_map, Canvas, Plot, BLACK, WHITE};

/// Camera frame interval (30 fps).
pub const DT_S: f32 = 1.0 / 30.0;

/// One attention field in the JSON output.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct AfJson {
    /// Centroid column.
    pub x: u8,
    /// Centroid row.
    pub y: u8,
    /// `LPLC2_k`.
    pub lplc2: u32,
}

/// One frame of replay output (the documented JSON line).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FrameJson {
    /// Frame index.
    pub frame: u32,
    /// Attention fields standing after the frame.
    pub afs: Vec<AfJson>,
    /// `ΣLPLC2`.
    pub lplc2_sum: u32,
    /// `S`.
    pub strength: f32,
    /// `X̄`, null without threat.
    pub threat_x: Option<f32>,
    /// The frame triggers an escape.
    pub alert: bool,
    /// Short-mode escape.
    pub short_mode: bool,
    /// FSM state after the frame.
    pub state: &'static str,
}

/// The perception and motor-control tasks as the firmware runs them, minus the hardware: the
/// heading comes from odometry of the FSM's own wheel commands (the robot turns freely).
pub struct Pipeline {
    /// Perception task state.
    pub net: Network,
    /// Motor-control task state.
    pub fsm: Fsm,
    odometry: Odometry,
    /// The swarm's look beside the network (`Params::look_change`), as the arena's swarm
    /// robots run it; `None` for the escape.
    movers: Option<Movers>,
    /// The FSM commanded both wheels to stand for this frame.
    standing: bool,
}

impl Pipeline {
    /// A fresh pipeline: the model with `params`, the FSM with `fp` and `behaviour`.
    pub fn new(params: Params, fp: FsmParams, behaviour: Behaviour) -> Result<Self> {
        let net = Network::new(params).map_err(|e| anyhow::anyhow!("{e}"))?;
        Ok(Pipeline {
            net,
            fsm: Fsm::new(fp, behaviour),
            odometry: Odometry::new(fp.motion.track_mm, 0.0),
            movers: (behaviour == Behaviour::Swarm).then(Movers::new),
            standing: false,
        })
    }

    /// One frame through perception and motor control.
    pub fn step(&mut self, frame: &Frame) -> (Perception, FrameJson) {
        let mut out = self.net.step(frame);
        if let Some(m) = &mut self.movers {
            out.vm.sighting = m.step(
                frame,
                self.standing,
                off0(self.net.params().swarm.look_change),
            );
        }
        let cmd = self.fsm.step(&out.vm, self.odometry.heading_deg());
        self.standing = cmd.stands();
        self.odometry.update(cmd.left_mm_s, cmd.right_mm_s, DT_S);
        let json = FrameJson {
            frame: out.frame,
            afs: out
                .afs
                .iter()
                .map(|a| AfJson {
                    x: a.x,
                    y: a.y,
                    lplc2: a.lplc2,
                })
                .collect(),
            lplc2_sum: out.vm.lplc2_sum,
            strength: out.vm.strength,
            threat_x: out.vm.threat_x,
            alert: out.vm.alert,
            short_mode: out.vm.short_mode,
            state: cmd.state.name(),
        };
        (out, json)
    }
}

/// Scale of the layer pictures (99x72 → 297x216).
const SCALE: usize = 3;

/// The layers of the paper's Fig. 3 for the current frame: input, `L̂_ON`, `L̂_OFF`, saliency
/// `L̂_t` with attention fields, and the four rectified local-motion maps `LM_r,l,d,u`.
pub fn layer_sheet(frame: &Frame, net: &Network, out: &Perception) -> Canvas {
    let maps = net.maps();
    let w = net.weights();
    let to_i32 = |f: &dyn Fn(usize) -> u32| -> Vec<i32> {
        (0..PIXELS)
            .map(|i| f(i).min(i32::MAX as u32) as i32)
            .collect()
    };
    let input: Vec<i32> = frame.iter().map(|&v| i32::from(v)).collect();
    let on = to_i32(&|i| (w.on_q8 * u32::from(maps.on(i))) >> 8);
    let off = to_i32(&|i| (w.off_q8 * u32::from(maps.off(i))) >> 8);
    let sal = to_i32(&|i| w.saliency(maps.on(i), maps.off(i)));
    let mut tiles: Vec<(String, Canvas)> = vec![
        (
            format!("input t={}", out.frame),
            grey_map(&input, WIDTH, HEIGHT, SCALE),
        ),
        ("L_ON".into(), grey_map(&on, WIDTH, HEIGHT, SCALE)),
        ("L_OFF".into(), grey_map(&off, WIDTH, HEIGHT, SCALE)),
    ];
    let mut s = grey_map(&sal, WIDTH, HEIGHT, SCALE);
    let r = i32::from(net.params().table1.r_af);
    for (k, a) in out.afs.iter().enumerate() {
        let c = colour_cycle(k);
        let (x, y) = (i32::from(a.x), i32::from(a.y));
        let sc = SCALE as i32;
        let (x0, y0) = ((x - r).max(0), (y - r).max(0));
        let (x1, y1) = (
            (x + r).min(WIDTH as i32 - 1),
            (y + r).min(HEIGHT as i32 - 1),
        );
        s.rect_outline(x0 * sc, y0 * sc, (x1 - x0 + 1) * sc, (y1 - y0 + 1) * sc, c);
        s.cross(x * sc + 1, y * sc + 1, 6, c);
        s.text(x * sc + 5, y * sc + 4, &format!("{}", a.lplc2), c, 1);
    }
    tiles.push(("saliency + AFs".into(), s));
    let mut lm = [0u32; PIXELS];
    for d in Direction::ALL {
        motion_map(&maps, net.lm_scale(), d, &mut lm);
        let v = to_i32(&|i| lm[i]);
        tiles.push((
            format!("LM_{}", d.letter()),
            grey_map(&v, WIDTH, HEIGHT, SCALE),
        ));
    }
    let (tw, th) = (WIDTH * SCALE, HEIGHT * SCALE);
    let label_h = 14;
    let cols = 4;
    let rows = tiles.len().div_ceil(cols);
    let mut sheet = Canvas::new(cols * (tw + 4) + 4, rows * (th + label_h + 4) + 4, WHITE);
    for (k, (label, tile)) in tiles.iter().enumerate() {
        let (cx, cy) = (
            (k % cols) * (tw + 4) + 4,
            (k / cols) * (th + label_h + 4) + 4,
        );
        sheet.text(cx as i32, cy as i32 + 2, label, BLACK, 1);
        sheet.blit(tile, cx as i32, (cy + label_h) as i32);
    }
    sheet
}

/// LPLC2 of every attention field over time, with `ΣLPLC2`, `T_s` and the alert frames.
pub fn trace_plot(records: &[(FrameJson, Vec<(u32, u32)>)], t_s: u32, title: &str) -> Canvas {
    let n = records.len();
    let mut ids: Vec<u32> = records
        .iter()
        .flat_map(|(_, a)| a.iter().map(|p| p.0))
        .collect();
    ids.sort_unstable();
    ids.dedup();
    // the fields with the largest peaks, at most six lines
    ids.sort_by_key(|id| {
        std::cmp::Reverse(
            records
                .iter()
                .flat_map(|(_, a)| a.iter().filter(|p| p.0 == *id).map(|p| p.1))
                .max()
                .unwrap_or(0),
        )
    });
    ids.truncate(6);
    let mut plot = Plot::new(title).x_label("frame");
    let sum: Vec<f32> = records.iter().map(|(j, _)| j.lplc2_sum as f32).collect();
    plot = plot.series("sum LPLC2", &sum);
    for id in &ids {
        let ys: Vec<f32> = records
            .iter()
            .map(|(_, a)| {
                a.iter()
                    .find(|p| p.0 == *id)
                    .map_or(f32::NAN, |p| p.1 as f32)
            })
            .collect();
        plot = plot.series(&format!("AF{id}"), &ys);
    }
    plot = plot.series("T_s", &vec![t_s as f32; n]);
    let alerts: Vec<usize> = records
        .iter()
        .enumerate()
        .filter(|(_, (j, _))| j.alert)
        .map(|(i, _)| i)
        .collect();
    plot.markers("alert", &alerts).render(900, 420)
}

/// Which frames get a layer sheet: the ones asked for, else the first alert and the peak.
pub fn chosen_frames(asked: &[u32], records: &[FrameJson]) -> Vec<u32> {
    if !asked.is_empty() {
        return asked.to_vec();
    }
    let mut v = Vec::new();
    if let Some(a) = records.iter().find(|r| r.alert) {
        v.push(a.frame);
    }
    if let Some(p) = records.iter().max_by_key(|r| r.lplc2_sum) {
        if p.lplc2_sum > 0 && !v.contains(&p.frame) {
            v.push(p.frame);
        }
    }
    if v.is_empty() {
        v.push((records.len() / 2) as u32);
    }
    v
}

/// Runs a clip, calling `emit` for each frame's JSON; writes pictures into `png` if given.
pub fn run(
    frames: &[Frame],
    params: Params,
    fsm: FsmParams,
    behaviour: Behaviour,
    png: Option<(&Path, &[u32], &str)>,
    mut emit: impl FnMut(&FrameJson) -> Result<()>,
) -> Result<Vec<FrameJson>> {
    let mut pipe = Pipeline::new(params, fsm, behaviour)?;
    let mut records = Vec::with_capacity(frames.len());
    for f in frames {
        let (out, json) = pipe.step(f);
        emit(&json)?;
        let fields = out.afs.iter().map(|a| (a.id, a.lplc2)).collect();
        records.push((json, fields));
    }
    if let Some((dir, asked, name)) = png {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create", dir.display()))?;
        let jsons: Vec<FrameJson> = records.iter().map(|r| r.0.clone()).collect();
        let wanted = chosen_frames(asked, &jsons);
        // a second pass re-creates the network state at the chosen frames (deterministic)
        let mut pipe = Pipeline::new(params, fsm, behaviour)?;
        for (i, f) in frames.iter().enumerate() {
            let (out, _) = pipe.step(f);
            if wanted.contains(&(i as u32)) {
                let path: PathBuf = dir.join(format!("{name}_layers_{i:04}.png"));
                layer_sheet(f, &pipe.net, &out)
                    .save_png(&path)
                    .with_context(|| format!("{}: cannot write", path.display()))?;
            }
        }
        let path = dir.join(format!("{name}_trace.png"));
        trace_plot(
            &records,
            params.table1.t_s,
            &format!("{name}: LPLC2 per attention field"),
        )
        .save_png(&path)
        .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    Ok(records.into_iter().map(|r| r.0).collect())
}
