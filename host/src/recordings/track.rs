//! A robot's track as the recordings give it: straight runs (segments) of the drawn path, each
//! with the snapshot it first appeared in, and the robot's position at each snapshot. Real
//! snapshots and simulated trails go through the same [`Extractor`], so their statistics come
//! out of one code path.

use serde::{Deserialize, Serialize};

use super::segments::{self, PxSegment};
use super::snapshot::Mask;

/// Segments shorter than this are not straight runs (turn marks, wiggles), mm.
pub const MIN_SEGMENT_MM: f64 = 25.0;
/// The tracker's path line width, px (measured: 3 px across on every snapshot).
pub const LINE_WIDTH_PX: f64 = 3.0;

/// A straight run of the path, floor mm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    pub a: (f64, f64),
    pub b: (f64, f64),
    /// Index of the snapshot it first appears in (drawn between snapshots `k-1` and `k`).
    pub snapshot: usize,
}

impl Segment {
    pub fn length_mm(&self) -> f64 {
        ((self.b.0 - self.a.0).powi(2) + (self.b.1 - self.a.1).powi(2)).sqrt()
    }
}

/// One snapshot: when, where the robot was, and what the extraction did with its pixels.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SnapshotFix {
    /// Camera frame number (the file name), or the simulated frame.
    pub frame: u64,
    /// Time since the recording started, s.
    pub t_s: f64,
    /// The robot's centre, floor mm; `None` when its marker was not found.
    pub robot_mm: Option<(f64, f64)>,
    /// Path pixels in the snapshot.
    pub path_px: usize,
    /// Path pixels new since the previous snapshot.
    pub new_px: usize,
    /// New pixels that lay under the previous snapshot's marker (older path it had hidden,
    /// indistinguishable from new), skipped.
    pub hidden_px: usize,
    /// New pixels no segment took.
    pub leftover_px: usize,
    /// Green-looking pixels that were not the path's exact colour, skipped.
    pub ambiguous_px: usize,
    /// Pixels of the previous snapshot's path missing from this one (should be 0 for a
    /// cumulative drawing; the robot's marker covers some).
    pub vanished_px: usize,
}

/// A whole track.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Track {
    pub snapshots: Vec<SnapshotFix>,
    pub segments: Vec<Segment>,
}

/// Streams snapshots (all path pixels so far, and the robot marker) into segments.
pub struct Extractor<F: Fn(f64, f64) -> (f64, f64)> {
    to_mm: F,
    min_len_px: f64,
    prev: Option<Mask>,
    prev_marker: Option<(f64, f64, f64)>,
    track: Track,
}

impl<F: Fn(f64, f64) -> (f64, f64)> Extractor<F> {
    /// `to_mm` maps a path pixel to floor mm; `px_per_mm` is the drawing's scale (sets the
    /// minimum segment length in px).
    pub fn new(to_mm: F, px_per_mm: f64) -> Self {
        Extractor {
            to_mm,
            min_len_px: MIN_SEGMENT_MM * px_per_mm,
            prev: None,
            prev_marker: None,
            track: Track {
                snapshots: vec![],
                segments: vec![],
            },
        }
    }

    /// Adds the next snapshot: its path mask, the marker (centre and radius, px) and where the
    /// robot's centre is on the floor.
    pub fn push(
        &mut self,
        frame: u64,
        t_s: f64,
        mask: Mask,
        marker_px: Option<(f64, f64, f64)>,
        robot_mm: Option<(f64, f64)>,
        ambiguous_px: usize,
    ) {
        let k = self.track.snapshots.len();
        let (mut new, mut hidden, mut vanished) = (Vec::new(), 0, 0);
        for (i, &on) in mask.bits.iter().enumerate() {
            let old = self.prev.as_ref().is_some_and(|p| p.bits[i]);
            let (x, y) = ((i % mask.width) as i32, (i / mask.width) as i32);
            if old && !on {
                vanished += 1;
            }
            if !on || old {
                continue;
            }
            let under_marker = self.prev_marker.is_some_and(|(mx, my, r)| {
                (x as f64 - mx).powi(2) + (y as f64 - my).powi(2) <= (r + 4.0).powi(2)
            });
            if under_marker {
                hidden += 1;
            } else {
                new.push((x, y));
            }
        }
        let found = segments::extract(&new, &mask, self.min_len_px);
        for PxSegment { a, b, .. } in found.segments {
            self.track.segments.push(Segment {
                a: (self.to_mm)(a.0, a.1),
                b: (self.to_mm)(b.0, b.1),
                snapshot: k,
            });
        }
        self.track.snapshots.push(SnapshotFix {
            frame,
            t_s,
            robot_mm,
            path_px: mask.count(),
            new_px: new.len(),
            hidden_px: hidden,
            leftover_px: found.leftover,
            ambiguous_px,
            vanished_px: vanished,
        });
        self.prev = Some(mask);
        self.prev_marker = marker_px;
    }

    pub fn finish(self) -> Track {
        self.track
    }
}

/// How a simulated trail is drawn to look like a recording.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Drawing {
    /// Arena inner size, mm.
    pub arena_mm: (f64, f64),
    /// The recordings' scale, px per floor mm.
    pub px_per_mm: f64,
    /// Time between snapshots, s.
    pub snapshot_every_s: f64,
    /// The marker's radius, px (the path under the previous marker is skipped, as in the
    /// recordings).
    pub marker_radius_px: f64,
}

/// A simulated trail (t s, x mm, y mm; arena frame, time increasing) drawn as the tracker
/// draws a path (3 px wide, at the recordings' scale), snapshot every
/// `drawing.snapshot_every_s`, and run through the same segment extraction as the recordings.
pub fn track_from_trail(trail: &[(f64, f64, f64)], drawing: &Drawing) -> Track {
    let k = drawing.px_per_mm;
    let (w, h) = (
        (drawing.arena_mm.0 * k).ceil() as usize + 1,
        (drawing.arena_mm.1 * k).ceil() as usize + 1,
    );
    let mut ex = Extractor::new(move |x, y| (x / k, y / k), k);
    let Some(&(t_start, ..)) = trail.first() else {
        return ex.finish();
    };
    let mut mask = Mask::new(w, h);
    let every = drawing.snapshot_every_s.max(1e-3);
    let mut next_snap = t_start + every;
    let mut last = (trail[0].1, trail[0].2);
    let mut frame = 0;
    let r = drawing.marker_radius_px;
    for &(t, x, y) in trail {
        // The snapshot shows the path up to the last point before it, the robot there.
        while t > next_snap {
            frame += 1;
            let marker = Some((last.0 * k, last.1 * k, r));
            ex.push(
                frame,
                next_snap - t_start,
                mask.clone(),
                marker,
                Some(last),
                0,
            );
            next_snap += every;
        }
        mask.thick_line((last.0 * k, last.1 * k), (x * k, y * k), LINE_WIDTH_PX);
        last = (x, y);
    }
    let t_end = trail[trail.len() - 1].0;
    if t_end > next_snap - every {
        let marker = Some((last.0 * k, last.1 * k, r));
        ex.push(frame + 1, t_end - t_start, mask, marker, Some(last), 0);
    }
    ex.finish()
}
