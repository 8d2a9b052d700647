//! The extraction from a clone of the recordings' repository to the committed JSON: the
//! arena (calibration and geometry, `arena.json`) and one track per run (`<run>.json`).

use std::path::Path;

use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::calibration::{find_floor, Calibration, FloorQuad, Homography};
use super::geometry::{self, ObstacleSeen};
use super::runs::{self, RunSpec, SnapshotFile, RUNS, SOURCE_COMMIT, SOURCE_REPO};
use super::snapshot::{find_marker, path_pixels, Rgb8, SNAPSHOT_SIZE};
use super::track::{Extractor, Track};
use super::{ArenaGeometry, Obstacle};
use alvs_sim::world::{ROBOT_DIAMETER_MM, ROBOT_HEIGHT_MM};

/// The camera's height above the floor, mm: assumed (see docs/recordings.md; plausible range
/// 1000-2500 mm). It only enters through the small correction of things above the floor.
pub const CAMERA_HEIGHT_MM: f64 = 1500.0;
/// The tracked white disc is the robot's top.
pub const ROBOT_TOP_MM: f64 = ROBOT_HEIGHT_MM;

/// A file the data came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SourceFile {
    /// Path in the source repository.
    pub path: String,
    pub sha256: String,
}

/// Where the data came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    pub repo: String,
    pub commit: String,
    /// The command that wrote the file.
    pub command: String,
    pub files: Vec<SourceFile>,
}

/// One run's committed data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunFile {
    pub run: String,
    /// Nominal forward speed, cm/s, and duration, s (from the folder's name).
    pub speed_cm_s: f64,
    pub duration_s: f64,
    /// Tracker frame rate (estimate, low and high bound), frames/s.
    pub tracker_fps: (f64, f64, f64),
    /// The floor as found in this run's first snapshot (a moved camera would show here).
    pub floor_quad: FloorQuad,
    pub calibration: Calibration,
    /// Snapshots whose robot marker was not found.
    pub missing_markers: usize,
    pub track: Track,
    pub provenance: Provenance,
}

/// The robot's top disc diameter, px: pixels within 45 px of the marker that are white
/// (luma > 180), the marker's own colours, or path inside the marker, as an equal-area
/// circle. Path and other white things nearby make it a little large at times, hence the
/// median over all snapshots.
fn disc_px(img: &Rgb8) -> Option<f64> {
    let m = find_marker(img)?;
    let mut n = 0usize;
    for y in (m.y - 45.0) as i64..=(m.y + 45.0) as i64 {
        for x in (m.x - 45.0) as i64..=(m.x + 45.0) as i64 {
            let r2 = (x as f64 - m.x).powi(2) + (y as f64 - m.y).powi(2);
            let Some(p) = img.get(x, y) else { continue };
            let marker = p == super::snapshot::MARKER_BLUE || p == super::snapshot::MARKER_RED;
            let inner_path = p == super::snapshot::PATH_GREEN && r2 <= m.radius * m.radius;
            if r2 <= 45.0 * 45.0
                && (marker
                    || inner_path
                    || super::snapshot::luma(p) > 180.0 && p != super::snapshot::PATH_GREEN)
            {
                n += 1;
            }
        }
    }
    Some(2.0 * (n as f64 / std::f64::consts::PI).sqrt())
}

fn sha256(path: &Path) -> Result<String> {
    let bytes = std::fs::read(path).with_context(|| format!("{}", path.display()))?;
    Ok(Sha256::digest(&bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect())
}

/// Everything `recordings extract` writes.
pub struct Extracted {
    pub arena: ArenaGeometry,
    pub runs: Vec<RunFile>,
}

/// Reads every run's snapshots under `repo` and computes the arena and the tracks. `tick` is
/// called once per snapshot read (twice per snapshot: calibration pass, then tracks).
pub fn extract_all(repo: &Path, command: &str, mut tick: impl FnMut(&str)) -> Result<Extracted> {
    let lists: Vec<(RunSpec, Vec<SnapshotFile>)> = RUNS
        .iter()
        .map(|r| Ok((*r, runs::list_snapshots(repo, r)?)))
        .collect::<Result<_>>()?;
    // Pass 1: the floor per run (first snapshot) and the robot's disc on every snapshot.
    let mut quads = Vec::new();
    let mut discs = Vec::new();
    let mut first_imgs = Vec::new();
    for (run, files) in &lists {
        for (i, f) in files.iter().enumerate() {
            let img = Rgb8::load_snapshot(&f.path)?;
            if i == 0 {
                let q = find_floor(&img).with_context(|| format!("{}", f.path.display()))?;
                quads.push(q);
            }
            discs.extend(disc_px(&img));
            if i == 0 && first_imgs.is_empty() {
                first_imgs.push((img, f.clone()));
            }
            tick(run.name);
        }
    }
    if discs.is_empty() {
        bail!("no robot marker in any snapshot");
    }
    discs.sort_by(f64::total_cmp);
    let disc_median = discs[discs.len() / 2];
    let (disc_q1, disc_q3) = (discs[discs.len() / 4], discs[3 * discs.len() / 4]);
    let top_shrink = (CAMERA_HEIGHT_MM - ROBOT_TOP_MM) / CAMERA_HEIGHT_MM;
    // The disc is seen at the robot's top, magnified by 1 / top_shrink against the floor.
    let px_per_mm = disc_median * top_shrink / ROBOT_DIAMETER_MM;
    // The arena from the first run's floor; the other runs' floors are checked against it.
    let q0 = quads[0];
    let s = q0.sides_px();
    let size_mm = (
        (s[0] + s[2]) / 2.0 / px_per_mm,
        (s[1] + s[3]) / 2.0 / px_per_mm,
    );
    let max_shift_px = quads
        .iter()
        .flat_map(|q| q.corners.iter().zip(q0.corners.iter()))
        .map(|(a, b)| ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt())
        .fold(0.0, f64::max);
    let nadir = (SNAPSHOT_SIZE.0 as f64 / 2.0, SNAPSHOT_SIZE.1 as f64 / 2.0);
    let calibration_of = |q: &FloorQuad| -> Result<Calibration> {
        let to = [
            (0.0, 0.0),
            (size_mm.0, 0.0),
            (size_mm.0, size_mm.1),
            (0.0, size_mm.1),
        ];
        Ok(Calibration {
            homography: Homography::from_points(q.corners, to)?,
            nadir_px: nadir,
            top_shrink,
        })
    };
    let (img0, file0) = &first_imgs[0];
    let cal0 = calibration_of(&q0)?;
    let arena = measure_arena(
        img0,
        file0,
        &q0,
        &cal0,
        px_per_mm,
        size_mm,
        (disc_q1, disc_median, disc_q3),
        max_shift_px,
        command,
    )?;
    // Pass 2: the tracks.
    let mut out = Vec::new();
    for ((run, files), quad) in lists.iter().zip(&quads) {
        let cal = calibration_of(quad)?;
        let frames: Vec<u64> = files.iter().map(|f| f.frame).collect();
        let fps = runs::tracker_fps(run, &frames);
        let mut ex = Extractor::new(|x, y| cal.top_mm(x, y), px_per_mm);
        let mut provenance = Vec::new();
        let mut missing = 0;
        for f in files {
            let img = Rgb8::load_snapshot(&f.path)?;
            let path = path_pixels(&img);
            let marker = find_marker(&img);
            missing += usize::from(marker.is_none());
            ex.push(
                f.frame,
                f.frame as f64 / fps.0,
                path.mask,
                marker.map(|m| (m.x, m.y, m.radius)),
                marker.map(|m| cal.top_mm(m.x, m.y)),
                path.ambiguous,
            );
            provenance.push(SourceFile {
                path: f.source.clone(),
                sha256: sha256(&f.path)?,
            });
            tick(run.name);
        }
        out.push(RunFile {
            run: run.name.into(),
            speed_cm_s: run.speed_cm_s,
            duration_s: run.duration_s,
            tracker_fps: fps,
            floor_quad: *quad,
            calibration: cal,
            missing_markers: missing,
            track: ex.finish(),
            provenance: Provenance {
                repo: SOURCE_REPO.into(),
                commit: SOURCE_COMMIT.into(),
                command: command.into(),
                files: provenance,
            },
        });
    }
    Ok(Extracted { arena, runs: out })
}

/// The arena's figures from one snapshot (the first run's first: the least path drawn).
#[allow(clippy::too_many_arguments)]
fn measure_arena(
    img: &Rgb8,
    file: &SnapshotFile,
    quad: &FloorQuad,
    cal: &Calibration,
    px_per_mm: f64,
    size_mm: (f64, f64),
    disc_px: (f64, f64, f64),
    max_shift_px: f64,
    command: &str,
) -> Result<ArenaGeometry> {
    let nadir = cal.nadir_px;
    let floor_luma = geometry::floor_luma(img, quad);
    let (wall_luma, band_px, edge_dist_px, profile) = geometry::wall_band(img, quad, nadir);
    let k_wall = band_px / edge_dist_px;
    let height = |k: f64| k * CAMERA_HEIGHT_MM / (1.0 + k);
    let rib_px = geometry::period_px(&profile);
    let marker = find_marker(img).map(|m| (m.x, m.y, 60.0));
    // 4 mm in from the floor's edge: the walls' bright foot must not join the obstacles
    // along a side into one blob.
    let inside = |x: f64, y: f64| {
        let (u, v) = cal.floor_mm(x, y);
        (4.0..size_mm.0 - 4.0).contains(&u) && (4.0..size_mm.1 - 4.0).contains(&v)
    };
    let blobs: Vec<ObstacleSeen> = geometry::find_obstacles(img, nadir, inside, marker);
    // A blob much wider than the robot is a corner's or a wall foot's reflection merged with
    // obstacles: not one obstacle, skipped (and counted).
    let (seen, merged): (Vec<ObstacleSeen>, Vec<ObstacleSeen>) = blobs
        .into_iter()
        .partition(|o| (30.0..70.0).contains(&(o.diameter_px / px_per_mm)));
    let mut diam: Vec<f64> = seen.iter().map(|o| o.diameter_px).collect();
    diam.sort_by(f64::total_cmp);
    let med = |v: &[f64]| v.get(v.len() / 2).copied().unwrap_or(f64::NAN);
    let obstacle_diameter_mm = med(&diam) / px_per_mm;
    let mut obstacles: Vec<Obstacle> = seen
        .iter()
        .map(|o| {
            let (mut x, mut y) = cal.floor_mm(o.base_px.0, o.base_px.1);
            if o.k.is_none() {
                // At a wall: the rolls stand against it (every picture shows them touching),
                // and only their side is seen over the floor, so the distance to the nearest
                // wall is set to the radius rather than taken from the side's extent.
                (x, y) = against_wall((x, y), o.diameter_px / px_per_mm / 2.0, size_mm);
            }
            Obstacle {
                x_mm: x,
                y_mm: y,
                diameter_mm: o.diameter_px / px_per_mm,
                k: None,
                top_px: None,
                base_px: o.base_px,
                seen_as: "side".into(),
            }
        })
        .collect();
    // The tops: each obstacle's nearest hole (within 60 px of where its top should be) fixes
    // its k = h / (H - h): the top is seen (1 + k) times as far from the nadir as the base.
    let holes = geometry::find_holes(img, marker);
    let nadir_mm = cal.floor_mm(nadir.0, nadir.1);
    let dist = |a: (f64, f64), b: (f64, f64)| ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt();
    let mut used = vec![false; holes.len()];
    for o in &mut obstacles {
        let base = (o.x_mm, o.y_mm);
        let best = holes
            .iter()
            .enumerate()
            .filter(|(i, _)| !used[*i])
            .map(|(i, &hp)| (i, hp, cal.floor_mm(hp.0, hp.1)))
            .filter(|&(_, _, hm)| dist(hm, base) < 60.0 / px_per_mm)
            .min_by(|a, b| dist(a.2, base).total_cmp(&dist(b.2, base)));
        if let Some((i, hp, hm)) = best {
            used[i] = true;
            o.top_px = Some(hp);
            o.k = Some(dist(hm, nadir_mm) / dist(base, nadir_mm).max(1.0) - 1.0);
        }
    }
    // Near the nadir the top's shift is a few px, all noise: k from obstacles 300 px out.
    let mut ks: Vec<f64> = obstacles
        .iter()
        .filter(|o| dist(o.base_px, nadir) > 300.0)
        .filter_map(|o| o.k)
        .collect();
    ks.sort_by(f64::total_cmp);
    let obstacle_k = (ks.len() >= 3).then(|| med(&ks));
    // Holes with no obstacle side on the floor (the corners, and where a wall's bright foot
    // swallowed the side): the base is the top brought back toward the nadir by 1 + k, the
    // diameter the others' median, and an obstacle at a wall is set against it.
    if let Some(k) = obstacle_k {
        for (i, &hp) in holes.iter().enumerate() {
            if used[i] {
                continue;
            }
            let base_px = (
                nadir.0 + (hp.0 - nadir.0) / (1.0 + k),
                nadir.1 + (hp.1 - nadir.1) / (1.0 + k),
            );
            let (x, y) = cal.floor_mm(base_px.0, base_px.1);
            let r = obstacle_diameter_mm / 2.0;
            // Only holes over or beside the floor (not the room outside the arena).
            if x < -r || y < -r || x > size_mm.0 + r || y > size_mm.1 + r {
                continue;
            }
            let (x, y) = against_wall((x, y), r, size_mm);
            obstacles.push(Obstacle {
                x_mm: x,
                y_mm: y,
                diameter_mm: obstacle_diameter_mm,
                k: None,
                top_px: Some(hp),
                base_px,
                seen_as: "top".into(),
            });
        }
    }
    obstacles.sort_by(|a, b| {
        (a.y_mm > size_mm.1 / 2.0, a.x_mm)
            .partial_cmp(&(b.y_mm > size_mm.1 / 2.0, b.x_mm))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    Ok(ArenaGeometry {
        size_x_mm: size_mm.0,
        size_y_mm: size_mm.1,
        px_per_mm,
        robot_disc_px: disc_px,
        camera_height_mm: CAMERA_HEIGHT_MM,
        floor_corners_px: quad.corners,
        camera_shift_px: max_shift_px,
        obstacles,
        skipped_blobs: merged.len(),
        obstacle_diameter_mm,
        obstacle_k,
        obstacle_height_mm: obstacle_k.map(height),
        holes_unused: holes.len() - used.iter().filter(|&&u| u).count(),
        wall_band_px: band_px,
        wall_k: k_wall,
        wall_height_mm: height(k_wall),
        floor_luma,
        wall_luma,
        wall_to_floor: wall_luma / floor_luma,
        rib_period_mm: rib_px.map(|p| p / px_per_mm),
        provenance: Provenance {
            repo: SOURCE_REPO.into(),
            commit: SOURCE_COMMIT.into(),
            command: command.into(),
            files: vec![SourceFile {
                path: file.source.clone(),
                sha256: sha256(&file.path)?,
            }],
        },
    })
}

/// `p` moved to touch the nearest wall when it is within a radius and a half of it (a roll
/// standing against the wall); farther ones stay where they are.
fn against_wall(p: (f64, f64), r: f64, size: (f64, f64)) -> (f64, f64) {
    let (mut x, mut y) = p;
    let gaps = [x, size.0 - x, y, size.1 - y];
    let nearest = (0..4)
        .min_by(|&a, &b| gaps[a].total_cmp(&gaps[b]))
        .unwrap_or(0);
    if gaps[nearest] > 2.5 * r {
        return p;
    }
    match nearest {
        0 => x = r,
        1 => x = size.0 - r,
        2 => y = r,
        _ => y = size.1 - r,
    }
    (x, y)
}
