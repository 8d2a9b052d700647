//! Fig. 3 (e)–(f) on recorded video: how many attention fields stand over time on the authors'
//! two multi-target clips, and whether each object gets a field of its own, beside the fields
//! the authors' own offline model kept on the same clips.
//!
//! The clips (`data/clips/outdoor_3_black_expand_multi_{3,6}.y8`) were drawn by a script, so
//! where and when each object is, is known exactly: a black square grows from its centre by
//! 2 source pixels a frame up to 80 (`max_square_size`), holds that size, and vanishes, over a
//! photograph scrolling by one source pixel a frame (`Ryannnice/SupplementaryMaterialsAttentionLPLC2`,
//! `synthetic_vedios/Vedio_generator_python/black_multi_{3,6}.py`; the later assignments of
//! `time_appear_object_k` in `black_multi_3.py` are the ones that take effect). The
//! authors' record of their offline model's fields on the same clips is
//! `data/authors/multi_target_fields.csv` (see `data/README.md`).

use std::path::Path;

use anyhow::{bail, Context, Result};
use serde::Serialize;

use crate::replay::FrameJson;
use alvs_tasks::{HEIGHT, WIDTH};

/// Width and height of the clips' 320 x 240 source, pixels.
const SOURCE: (f32, f32) = (320.0, 240.0);
/// Growth of a square's side per frame and its largest side, source pixels.
const GROWTH: f32 = 2.0;
const MAX_SIDE: f32 = 80.0;
/// A field whose centroid lies within an object's square widened by this many pixels on each
/// side sits on it (as `stimuli`' `LOCALISED_PX`).
pub const ON_OBJECT_PX: f32 = 3.0;

/// Source pixels (x, y) on the 99 x 72 retina: the clips were scaled down whole.
fn retina((x, y): (f32, f32)) -> (f32, f32) {
    (
        x * (WIDTH as f32 / SOURCE.0),
        y * (HEIGHT as f32 / SOURCE.1),
    )
}

/// One drawn object: a square growing from `centre`, present in frames `appear..vanish`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Square {
    /// Centre in source pixels (x, y).
    pub centre: (f32, f32),
    /// First frame it is drawn in (its side is 0 there).
    pub appear: u32,
    /// First frame it is no longer drawn in.
    pub vanish: u32,
}

impl Square {
    /// The square in retina pixels at `frame`, `(x0, x1, y0, y1)` inclusive of its edges, or
    /// `None` when it is not drawn or still has no area.
    pub fn at(&self, frame: u32) -> Option<(f32, f32, f32, f32)> {
        if !(self.appear..self.vanish).contains(&frame) {
            return None;
        }
        let side = (GROWTH * (frame - self.appear) as f32).min(MAX_SIDE);
        if side == 0.0 {
            return None;
        }
        let (cx, cy) = retina(self.centre);
        let (hx, hy) = retina((side / 2.0, side / 2.0));
        Some((cx - hx, cx + hx, cy - hy, cy + hy))
    }

    /// Whether a field at `(x, y)` (retina pixels) sits on the square at `frame`.
    pub fn holds(&self, frame: u32, x: f32, y: f32) -> bool {
        let w = ON_OBJECT_PX;
        self.at(frame).is_some_and(|(x0, x1, y0, y1)| {
            (x0 - w..=x1 + w).contains(&x) && (y0 - w..=y1 + w).contains(&y)
        })
    }
}

/// One of the two multi-target clips and its objects.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MultiClip {
    /// File stem in `data/clips`.
    pub name: &'static str,
    /// Its objects, in the script's order.
    pub squares: Vec<Square>,
}

/// The two multi-target clips as their scripts draw them (320 x 240, 120 frames).
pub fn clips() -> Vec<MultiClip> {
    let sq = |centre: (f32, f32), appear: u32| Square {
        centre,
        appear,
        vanish: appear + 50,
    };
    // the scripts' centres: (W·3/4, H/4), (W/4, H/2), (W·3/5, H·3/4), and for multi_6 their
    // mirror images (W/4, H/4), (W·3/4, H/2), (W·2/5, H·3/4)
    let (a, b, c) = ((240.0, 60.0), (80.0, 120.0), (192.0, 180.0));
    let (d, e, f) = ((80.0, 60.0), (240.0, 120.0), (128.0, 180.0));
    vec![
        MultiClip {
            name: "outdoor_3_black_expand_multi_3",
            squares: vec![sq(a, 35), sq(b, 45), sq(c, 55)],
        },
        MultiClip {
            name: "outdoor_3_black_expand_multi_6",
            squares: vec![
                sq(a, 5),
                sq(b, 15),
                sq(c, 25),
                sq(d, 45),
                sq(e, 55),
                sq(f, 65),
            ],
        },
    ]
}

/// One field of the authors' offline model, as their output files record it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AuthorsField {
    /// Their field number.
    pub field: u32,
    /// Frame it was born in.
    pub born: u32,
    /// Frame it was dropped in (120: alive at the end); `None` where the record has none.
    pub died: Option<u32>,
    /// Where it was born, source pixels; their multi-field fields do not move.
    pub at: (f32, f32),
}

/// The authors' fields of `clip` from `path` (`clip,field,born,died,x,y`, a header line first).
/// A malformed line is an error naming the line; nothing is skipped.
pub fn read_authors(path: &Path, clip: &str) -> Result<Vec<AuthorsField>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read", path.display()))?;
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, "clip,field,born,died,x,y")) => {}
        _ => bail!(
            "{}: line 1 must be the header clip,field,born,died,x,y",
            path.display()
        ),
    }
    let mut out = Vec::new();
    for (i, line) in lines {
        let bad = |what: &str| anyhow::anyhow!("{}:{}: {what}: {line:?}", path.display(), i + 1);
        let cells: Vec<&str> = line.split(',').collect();
        let [name, field, born, died, x, y] = cells[..] else {
            return Err(bad("expected 6 comma-separated cells"));
        };
        if name != clip {
            continue;
        }
        let num = |s: &str| s.parse::<u32>().map_err(|_| bad("not a whole number"));
        out.push(AuthorsField {
            field: num(field)?,
            born: num(born)?,
            died: if died.is_empty() {
                None
            } else {
                Some(num(died)?)
            },
            at: (num(x)? as f32, num(y)? as f32),
        });
    }
    Ok(out)
}

/// How many of the authors' fields stand in each of `frames` frames, or `None` when their
/// record lacks the frame some field was dropped in.
pub fn authors_alive(fields: &[AuthorsField], frames: usize) -> Option<Vec<usize>> {
    let mut n = vec![0; frames];
    for f in fields {
        let died = f.died? as usize;
        for c in n.iter_mut().take(died.min(frames)).skip(f.born as usize) {
            *c += 1;
        }
    }
    Some(n)
}

/// What one model's fields did on one clip.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// Fields standing after each frame.
    pub fields: Vec<usize>,
    /// Most fields at once.
    pub max_fields: usize,
    /// Frames with at least one object drawn in which every drawn object had a field of its
    /// own (one-to-one).
    pub own_all_frames: usize,
    /// Frames with at least one object drawn.
    pub object_frames: usize,
    /// Per object: the first frame a field sat on it, `None` if none ever did.
    pub first_field: Vec<Option<u32>>,
    /// Frames in which the model alerted.
    pub alert_frames: usize,
}

/// The summary of a model's per-frame output on `clip`.
pub fn summarise(clip: &MultiClip, records: &[FrameJson]) -> Summary {
    let n = clip.squares.len();
    let mut first_field = vec![None; n];
    let (mut own_all_frames, mut object_frames) = (0, 0);
    for r in records {
        let xy: Vec<(f32, f32)> = r
            .afs
            .iter()
            .map(|a| (f32::from(a.x), f32::from(a.y)))
            .collect();
        let drawn: Vec<usize> = (0..n)
            .filter(|&k| clip.squares[k].at(r.frame).is_some())
            .collect();
        for &k in &drawn {
            if first_field[k].is_none()
                && xy
                    .iter()
                    .any(|&(x, y)| clip.squares[k].holds(r.frame, x, y))
            {
                first_field[k] = Some(r.frame);
            }
        }
        if !drawn.is_empty() {
            object_frames += 1;
            let on = |o: usize, f: usize| clip.squares[drawn[o]].holds(r.frame, xy[f].0, xy[f].1);
            if one_to_one(drawn.len(), xy.len(), &on) == drawn.len() {
                own_all_frames += 1;
            }
        }
    }
    let fields: Vec<usize> = records.iter().map(|r| r.afs.len()).collect();
    Summary {
        max_fields: fields.iter().copied().max().unwrap_or(0),
        fields,
        own_all_frames,
        object_frames,
        first_field,
        alert_frames: records.iter().filter(|r| r.alert).count(),
    }
}

/// Per object, the first frame one of the authors' fields was born on it (their fields stay
/// where they are born).
pub fn authors_first_field(clip: &MultiClip, fields: &[AuthorsField]) -> Vec<Option<u32>> {
    clip.squares
        .iter()
        .map(|s| {
            fields
                .iter()
                .filter(|f| {
                    let (x, y) = retina(f.at);
                    s.holds(f.born, x, y)
                })
                .map(|f| f.born)
                .min()
        })
        .collect()
}

/// The largest one-to-one matching of `objects` objects to `fields` fields, where `on(o, f)`
/// says field `f` sits on object `o` (augmenting paths; a handful of each).
pub fn one_to_one(objects: usize, fields: usize, on: &dyn Fn(usize, usize) -> bool) -> usize {
    // owner[f]: the object field f is matched to
    let mut owner: Vec<Option<usize>> = vec![None; fields];
    fn augment(
        o: usize,
        seen: &mut [bool],
        owner: &mut [Option<usize>],
        on: &dyn Fn(usize, usize) -> bool,
    ) -> bool {
        for f in 0..owner.len() {
            if on(o, f) && !seen[f] {
                seen[f] = true;
                if owner[f].is_none_or(|p| augment(p, seen, owner, on)) {
                    owner[f] = Some(o);
                    return true;
                }
            }
        }
        false
    }
    (0..objects)
        .filter(|&o| augment(o, &mut vec![false; fields], &mut owner, on))
        .count()
}

/// The number of objects drawn in each of `frames` frames.
pub fn objects_drawn(clip: &MultiClip, frames: usize) -> Vec<usize> {
    (0..frames as u32)
        .map(|t| clip.squares.iter().filter(|s| s.at(t).is_some()).count())
        .collect()
}

/// The frame to draw the layers at: the middle of the first longest run of frames with the
/// most objects drawn.
pub fn busiest_frame(clip: &MultiClip, frames: usize) -> u32 {
    let n = objects_drawn(clip, frames);
    let most = n.iter().copied().max().unwrap_or(0);
    let start = n.iter().position(|&k| k == most).unwrap_or(0);
    let len = n[start..].iter().take_while(|&&k| k == most).count();
    (start + len / 2) as u32
}

/// Fields standing over time per model (and the authors' where their record allows), with
/// the number of objects drawn; markers where an object appears.
pub fn fields_plot(
    clip: &MultiClip,
    runs: &[(&str, &Summary)],
    authors: Option<&[usize]>,
) -> alvs_sim::canvas::Canvas {
    let frames = runs.first().map_or(0, |r| r.1.fields.len());
    let as_f32 = |v: &[usize]| v.iter().map(|&k| k as f32).collect::<Vec<f32>>();
    let mut plot = alvs_sim::canvas::Plot::new(&format!("{}: attention fields", clip.name))
        .x_label("frame")
        .series("objects drawn", &as_f32(&objects_drawn(clip, frames)));
    for (name, s) in runs {
        plot = plot.series(&format!("fields, {name}"), &as_f32(&s.fields));
    }
    if let Some(a) = authors {
        plot = plot.series("fields, the authors' offline model", &as_f32(a));
    }
    let onsets: Vec<usize> = clip.squares.iter().map(|s| s.appear as usize).collect();
    let most = runs
        .iter()
        .map(|r| r.1.max_fields)
        .chain(authors.into_iter().flatten().copied())
        .chain([clip.squares.len()])
        .max()
        .unwrap_or(1);
    plot.markers("an object appears", &onsets)
        .y_range(0.0, most as f32 + 0.5)
        .render(1000, 500)
}
