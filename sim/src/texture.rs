//! The wall texture as precomputed look-up tables: a mip-map pyramid over the texture
//! coordinates `(u, v)` (mm along the walls, mm above the floor), built once per world.
//!
//! Level 0 has one texel per [`TEXEL_MM`]; each further level halves the resolution by 2x2 box
//! averaging (wrapping around the arena in `u`, so the texture has no seam at the corner where
//! `u` restarts). The renderer picks, per image column, the level whose texel matches the
//! pixel's footprint on the wall and blends the two nearest levels (trilinear filtering across
//! levels, linear along the wall, nearest in height). A texture point-sampled at 1 mm would
//! alias and shimmer as the robot moves, and shimmer is motion to a looming detector; the
//! pre-filtered levels keep distant walls calm, and the blending keeps a wall's sharpness from
//! jumping when the robot crosses the distance where the level changes.
//!
//! Storage is column-major (`data[u_index * rows + v_index]`) because the renderer walks each
//! image column down a wall column.

use super::rng::Rng;
use super::world::{GreyImage, WallTexture, World};

/// Texel size of the finest level, mm. The camera is never closer than 2 mm to a wall; at 70 mm
/// (a robot length) one pixel covers 1 mm of wall, so finer texels would rarely be seen.
pub const TEXEL_MM: f32 = 1.0;

/// Greys of the dark and light parts of the stripes and checkerboard.
pub const PATTERN_DARK: u8 = 40;
/// See [`PATTERN_DARK`].
pub const PATTERN_LIGHT: u8 = 215;

/// Most levels kept (the coarsest texel is then 2^11 mm).
const MAX_LEVELS: usize = 12;

/// One level of the pyramid.
#[derive(Debug, Clone)]
struct Level {
    /// Texels along the walls.
    cols: usize,
    /// Texels up the walls.
    rows: usize,
    /// Texels per mm.
    scale: f32,
    /// Column-major grey levels.
    data: Vec<u8>,
}

impl Level {
    fn column(&self, i: usize) -> &[u8] {
        &self.data[i * self.rows..(i + 1) * self.rows]
    }

    /// The two texel columns around `u` (mm, in `[0, perimeter)`) and the weight of the
    /// second; wraps around the arena.
    fn columns_at(&self, u_mm: f32) -> (&[u8], &[u8], f32) {
        let x = u_mm * self.scale - 0.5;
        let fl = x.floor();
        let w = x - fl;
        let i0 = if fl < 0.0 {
            self.cols - 1
        } else {
            (fl as usize).min(self.cols - 1)
        };
        let i1 = if i0 + 1 == self.cols { 0 } else { i0 + 1 };
        (self.column(i0), self.column(i1), w)
    }
}

/// The mip-map pyramid of a world's walls.
#[derive(Debug, Clone)]
pub struct WallMap {
    levels: Vec<Level>,
    perimeter_mm: f32,
    /// Mean grey of the whole texture (the coarsest level).
    mean: f32,
}

/// Samples one image column's strip of wall: fixed `u`, any height `v`.
#[derive(Debug, Clone, Copy)]
pub struct ColumnSampler<'a> {
    a0: &'a [u8],
    a1: &'a [u8],
    wa: f32,
    scale_a: f32,
    b0: &'a [u8],
    b1: &'a [u8],
    wb: f32,
    scale_b: f32,
    /// Weight of the coarser level.
    t: f32,
}

impl ColumnSampler<'_> {
    /// Fills `out` with `shade` times the greys from height `v_top_mm` (first element) down in
    /// steps of `dv_mm` per element; heights are clamped to the wall. Indices are stepped in
    /// 16.16 fixed point (the rounding drifts by less than 1/900 texel over a frame's height).
    #[inline]
    pub fn fill(&self, out: &mut [f32], v_top_mm: f32, dv_mm: f32, shade: f32) {
        const ONE: f32 = 65_536.0;
        let (na, nb) = (self.a0.len(), self.b0.len());
        let (a0, a1) = (self.a0, &self.a1[..na]);
        let (b0, b1) = (self.b0, &self.b1[..nb]);
        // Indices are clamped to 0..=n−1 in `usize`, so the compiler sees they are in bounds.
        let (la, lb) = (na.saturating_sub(1), nb.saturating_sub(1));
        let mut fa = (v_top_mm * self.scale_a * ONE) as i64;
        let mut fb = (v_top_mm * self.scale_b * ONE) as i64;
        let da = (dv_mm * self.scale_a * ONE) as i64;
        let db = (dv_mm * self.scale_b * ONE) as i64;
        let (wa, wb, t) = (self.wa, self.wb, self.t);
        for g in out {
            let ia = ((fa >> 16).max(0) as usize).min(la);
            let ib = ((fb >> 16).max(0) as usize).min(lb);
            let (p, q) = (f32::from(a0[ia]), f32::from(a1[ia]));
            let a = p + wa * (q - p);
            let (p, q) = (f32::from(b0[ib]), f32::from(b1[ib]));
            let b = p + wb * (q - p);
            *g = shade * (a + t * (b - a));
            fa -= da;
            fb -= db;
        }
    }

    /// Grey (0..=255, fractional) at height `v_mm` on the wall (clamped to the wall).
    #[inline(always)]
    pub fn at(&self, v_mm: f32) -> f32 {
        // Float-to-int casts saturate: a negative height reads row 0.
        let ia = ((v_mm * self.scale_a) as usize).min(self.a0.len() - 1);
        let ib = ((v_mm * self.scale_b) as usize).min(self.b0.len() - 1);
        let (p, q) = (f32::from(self.a0[ia]), f32::from(self.a1[ia]));
        let a = p + self.wa * (q - p);
        let (p, q) = (f32::from(self.b0[ib]), f32::from(self.b1[ib]));
        let b = p + self.wb * (q - p);
        a + self.t * (b - a)
    }
}

impl WallMap {
    /// Builds the pyramid of `world`'s walls (a few milliseconds for the default arena).
    pub fn new(world: &World) -> Self {
        let perimeter = world.arena.perimeter_mm().max(1.0);
        let height = world.wall_height_mm.max(1.0);
        let cols = (perimeter / f64::from(TEXEL_MM)).ceil() as usize;
        let rows = (height / f64::from(TEXEL_MM)).ceil() as usize;
        let data = level0(&world.texture, cols, rows, height);
        let mut levels = vec![Level {
            cols,
            rows,
            scale: 1.0 / TEXEL_MM,
            data,
        }];
        while levels.len() < MAX_LEVELS {
            let last = levels.last().expect("level 0 exists");
            if last.cols <= 1 && last.rows <= 1 {
                break;
            }
            let next = downsample(last);
            levels.push(next);
        }
        let coarsest = levels.last().expect("level 0 exists");
        let mean = coarsest.data.iter().map(|&g| f32::from(g)).sum::<f32>()
            / coarsest.data.len().max(1) as f32;
        WallMap {
            levels,
            perimeter_mm: perimeter as f32,
            mean,
        }
    }

    /// Number of levels.
    pub fn levels(&self) -> usize {
        self.levels.len()
    }

    /// Mean grey of the walls.
    pub fn mean(&self) -> f32 {
        self.mean
    }

    /// A sampler for the wall strip at `u_mm` seen with a pixel footprint of `footprint_mm`.
    #[inline]
    pub fn sampler(&self, u_mm: f32, footprint_mm: f32) -> ColumnSampler<'_> {
        let u = u_mm.rem_euclid(self.perimeter_mm);
        let lod = (footprint_mm / TEXEL_MM).max(1.0).log2();
        let top = self.levels.len() - 1;
        let a = (lod as usize).min(top);
        let b = (a + 1).min(top);
        let t = if a == b { 0.0 } else { lod - a as f32 };
        let (la, lb) = (&self.levels[a], &self.levels[b]);
        let (a0, a1, wa) = la.columns_at(u);
        let (b0, b1, wb) = lb.columns_at(u);
        ColumnSampler {
            a0,
            a1,
            wa,
            scale_a: la.scale,
            b0,
            b1,
            wb,
            scale_b: lb.scale,
            t,
        }
    }

    /// The finest level as a row-major grey picture (top row = top of the wall), for looking
    /// at a texture.
    pub fn unrolled(&self) -> GreyImage {
        let l = &self.levels[0];
        let mut px = vec![0u8; l.cols * l.rows];
        for i in 0..l.cols {
            for j in 0..l.rows {
                px[(l.rows - 1 - j) * l.cols + i] = l.data[i * l.rows + j];
            }
        }
        GreyImage::new(l.cols, l.rows, px).expect("sizes agree")
    }
}

/// The finest level: `cols` x `rows` texels over `perimeter` x `height` mm.
fn level0(tex: &WallTexture, cols: usize, rows: usize, height: f64) -> Vec<u8> {
    let mut data = vec![0u8; cols * rows];
    let texel = f64::from(TEXEL_MM);
    let (dark, light) = (f64::from(PATTERN_DARK), f64::from(PATTERN_LIGHT));
    match tex {
        WallTexture::Plain(g) => data.fill(*g),
        WallTexture::Stripes { period_mm } => {
            let p = period_mm.max(texel);
            supersample(
                cols,
                rows,
                |u, _| {
                    if (u / p).rem_euclid(1.0) < 0.5 {
                        dark
                    } else {
                        light
                    }
                },
                &mut data,
            );
        }
        WallTexture::Checker { size_mm } => {
            let s = size_mm.max(texel);
            supersample(
                cols,
                rows,
                |u, v| {
                    // u, v ≥ 0: truncation is the floor.
                    let k = (u / s) as u64 + (v / s) as u64;
                    if k.is_multiple_of(2) {
                        dark
                    } else {
                        light
                    }
                },
                &mut data,
            );
        }
        WallTexture::Ribs {
            period_mm,
            dark,
            light,
        } => {
            let p = period_mm.max(texel);
            let (dark, light) = (f64::from(*dark), f64::from(*light));
            supersample(
                cols,
                rows,
                |u, _| {
                    let c = (std::f64::consts::TAU * u / p).cos();
                    dark + (light - dark) * 0.5 * (1.0 - c)
                },
                &mut data,
            );
        }
        WallTexture::Clutter { seed } => clutter(*seed, cols, rows, texel, &mut data),
        WallTexture::Outdoor { seed } => outdoor(*seed, cols, rows, texel, &mut data),
        WallTexture::Image(img) => image_level0(img, cols, rows, height, &mut data),
    }
    data
}

/// Box-filtered sampling of an analytic pattern `f(u, v)` (mm): 4x4 sub-samples per texel.
fn supersample(cols: usize, rows: usize, f: impl Fn(f64, f64) -> f64, data: &mut [u8]) {
    let texel = f64::from(TEXEL_MM);
    for i in 0..cols {
        for j in 0..rows {
            let mut acc = 0.0;
            for a in 0..4 {
                for b in 0..4 {
                    let u = (i as f64 + (a as f64 + 0.5) / 4.0) * texel;
                    let v = (j as f64 + (b as f64 + 0.5) / 4.0) * texel;
                    acc += f(u, v);
                }
            }
            data[i * rows + j] = (acc / 16.0).round().clamp(0.0, 255.0) as u8;
        }
    }
}

/// A procedural outdoor scene (see [`WallTexture::Outdoor`]): the clutter of the same seed
/// (a "dead leaves" picture: occluding shapes of power-law sizes, which is what gives natural
/// photographs their 1/f spectrum and their sharp edges) below a horizon that wanders between
/// 55 % and 80 % of the wall height, a bright sky above it (grey 175–200, brightest at the
/// top), and dark vertical trunks and poles (6–30 mm wide, about one per 150 mm of wall)
/// reaching from the ground into the sky. Matched to the three outdoor photographs of
/// `data/photos` (sky above ground, means 113–146, RMS contrast 0.28–0.51, horizontal
/// amplitude spectra falling as f^−0.8 to f^−1.15). Wraps in `u`.
fn outdoor(seed: u64, cols: usize, rows: usize, texel: f64, data: &mut [u8]) {
    clutter(seed, cols, rows, texel, data);
    let mut rng = Rng::new(seed).fork(0x0d);
    let (perimeter, height) = (cols as f64 * texel, rows as f64 * texel);
    // Horizon: a few slow sinusoids around 2/3 of the height.
    let waves: Vec<(f64, f64, f64)> = (0..3)
        .map(|k| {
            let cycles = (1 + rng.below(4) + 3 * k) as f64;
            let k = cycles * std::f64::consts::TAU / perimeter;
            (
                k,
                rng.range(0.0, std::f64::consts::TAU),
                rng.range(5.0, 12.0),
            )
        })
        .collect();
    let trunks: Vec<(f64, f64, u8)> = (0..(perimeter / 150.0).ceil() as usize)
        .map(|_| {
            let w = (6f64.ln() + rng.uniform() * 5f64.ln()).exp();
            (rng.range(0.0, perimeter), w, rng.range(20.0, 80.0) as u8)
        })
        .collect();
    for i in 0..cols {
        let u = (i as f64 + 0.5) * texel;
        let wave: f64 = waves.iter().map(|(k, ph, a)| a * (k * u + ph).sin()).sum();
        let horizon = (0.675 * height + wave).clamp(0.55 * height, 0.8 * height);
        let trunk = trunks.iter().find(|(c, w, _)| {
            let d = (u - c).rem_euclid(perimeter);
            d.min(perimeter - d) <= w / 2.0
        });
        for j in 0..rows {
            let v = (j as f64 + 0.5) * texel;
            if v < horizon {
                continue;
            }
            data[i * rows + j] = match trunk {
                Some(&(_, _, g)) => g,
                None => (175.0 + 25.0 * (v - horizon) / (height - horizon).max(1.0)) as u8,
            };
        }
    }
}

/// Procedural clutter: a smooth mid-grey background with overlapping rectangles and ellipses,
/// large ones first, sizes log-uniform in 6..180 mm, greys uniform in 15..240. Wraps in `u`.
fn clutter(seed: u64, cols: usize, rows: usize, texel: f64, data: &mut [u8]) {
    let mut rng = Rng::new(seed).fork(0xc1);
    // Background: a few slow horizontal sinusoids around mid grey.
    let perimeter = cols as f64 * texel;
    let waves: Vec<(f64, f64, f64)> = (0..3)
        .map(|k| {
            let cycles = (2 + rng.below(6) + 4 * k) as f64;
            (
                cycles * std::f64::consts::TAU / perimeter,
                rng.range(0.0, std::f64::consts::TAU),
                rng.range(10.0, 25.0),
            )
        })
        .collect();
    for i in 0..cols {
        let u = (i as f64 + 0.5) * texel;
        let g: f64 = 120.0
            + waves
                .iter()
                .map(|(k, ph, a)| a * (k * u + ph).sin())
                .sum::<f64>();
        data[i * rows..(i + 1) * rows].fill(g.clamp(0.0, 255.0) as u8);
    }
    // Shapes: about one per 1500 mm² of wall, so most of the wall is covered 2–3 times.
    let area = cols as f64 * rows as f64 * texel * texel;
    let n = (area / 1500.0).ceil() as usize;
    let height = rows as f64 * texel;
    let mut shapes: Vec<(f64, f64, f64, f64, u8, bool)> = (0..n)
        .map(|_| {
            let w = (6f64.ln() + rng.uniform() * (180f64 / 6.0).ln()).exp();
            let h = (w * rng.range(0.3, 3.0)).min(2.0 * height);
            let cu = rng.range(0.0, perimeter);
            let cv = rng.range(-0.1 * height, 1.1 * height);
            let grey = rng.range(15.0, 240.0) as u8;
            let disc = rng.uniform() < 0.4;
            (cu, cv, w, h, grey, disc)
        })
        .collect();
    shapes.sort_by(|a, b| (b.2 * b.3).total_cmp(&(a.2 * a.3)));
    for (cu, cv, w, h, grey, disc) in shapes {
        let (i0, i1) = (
            ((cu - w / 2.0) / texel).floor() as i64,
            ((cu + w / 2.0) / texel).ceil() as i64,
        );
        let j0 = (((cv - h / 2.0) / texel).floor() as i64).max(0);
        let j1 = (((cv + h / 2.0) / texel).ceil() as i64).min(rows as i64);
        for i in i0..i1 {
            let col = i.rem_euclid(cols as i64) as usize;
            let du = ((i as f64 + 0.5) * texel - cu) / (w / 2.0);
            for j in j0..j1 {
                let dv = ((j as f64 + 0.5) * texel - cv) / (h / 2.0);
                let inside = if disc {
                    du * du + dv * dv <= 1.0
                } else {
                    du.abs() <= 1.0 && dv.abs() <= 1.0
                };
                if inside {
                    data[col * rows + j as usize] = grey;
                }
            }
        }
    }
}

/// The picture scaled to the wall height (aspect ratio kept) and repeated along the walls:
/// bilinear interpolation averaged over `k` x `k` sub-samples per texel (area averaging when the
/// picture is finer than the texels), done separably (rows, then columns).
fn image_level0(img: &GreyImage, cols: usize, rows: usize, height: f64, data: &mut [u8]) {
    let texel = f64::from(TEXEL_MM);
    let tile_mm = height * img.width as f64 / img.height as f64;
    let px_per_mm = img.height as f64 / height;
    let k = (px_per_mm * texel).ceil().clamp(1.0, 8.0) as usize;
    // Taps (source index, weight) of each destination sample along one axis: `pos(t)` maps a
    // destination coordinate (texels) to a source coordinate (pixels, centres at +0.5).
    let taps = |n: usize, src: usize, wrap: bool, pos: &dyn Fn(f64) -> f64| {
        (0..n)
            .map(|i| {
                let mut t = Vec::with_capacity(2 * k);
                for a in 0..k {
                    let x = pos(i as f64 + (a as f64 + 0.5) / k as f64) - 0.5;
                    let x = if wrap {
                        x
                    } else {
                        x.clamp(0.0, src as f64 - 1.0)
                    };
                    let x0 = x.floor();
                    let f = x - x0;
                    let idx = |d: i64| {
                        let i = x0 as i64 + d;
                        if wrap {
                            i.rem_euclid(src as i64) as usize
                        } else {
                            (i.max(0) as usize).min(src - 1)
                        }
                    };
                    t.push((idx(0), (1.0 - f) / k as f64));
                    t.push((idx(1), f / k as f64));
                }
                t
            })
            .collect::<Vec<_>>()
    };
    let (iw, ih) = (img.width as f64, img.height as f64);
    let col_taps = taps(cols, img.width, true, &|u| {
        (u * texel / tile_mm).rem_euclid(1.0) * iw
    });
    // Texel row 0 is the bottom of the wall, the picture's last row.
    let row_taps = taps(rows, img.height, false, &|v| {
        (1.0 - v * texel / height) * ih
    });
    // Pass 1: every picture row resampled along the wall.
    let mut wide = vec![0f32; img.height * cols];
    for (y, line) in img.pixels.chunks_exact(img.width).enumerate() {
        for (i, t) in col_taps.iter().enumerate() {
            wide[y * cols + i] = t.iter().map(|&(x, w)| f64::from(line[x]) * w).sum::<f64>() as f32;
        }
    }
    // Pass 2: up the wall.
    for i in 0..cols {
        for (j, t) in row_taps.iter().enumerate() {
            let g: f64 = t
                .iter()
                .map(|&(y, w)| f64::from(wide[y * cols + i]) * w)
                .sum();
            data[i * rows + j] = g.round().clamp(0.0, 255.0) as u8;
        }
    }
}

/// The next coarser level: 2x2 box average, wrapping in `u`, clamping in `v`.
fn downsample(l: &Level) -> Level {
    let cols = l.cols.div_ceil(2);
    let rows = l.rows.div_ceil(2);
    let mut data = vec![0u8; cols * rows];
    for i in 0..cols {
        let (c0, c1) = (2 * i % l.cols, (2 * i + 1) % l.cols);
        for j in 0..rows {
            let (r0, r1) = (2 * j, (2 * j + 1).min(l.rows - 1));
            let s = u32::from(l.data[c0 * l.rows + r0])
                + u32::from(l.data[c0 * l.rows + r1])
                + u32::from(l.data[c1 * l.rows + r0])
                + u32::from(l.data[c1 * l.rows + r1]);
            data[i * rows + j] = ((s + 2) / 4) as u8;
        }
    }
    Level {
        cols,
        rows,
        scale: l.scale / 2.0,
        data,
    }
}

/// Reads a `--background` specification (`plain[:GREY]`, `stripes[:PERIOD_MM]`,
/// `checker[:SIZE_MM]`, `clutter[:SEED]`, `outdoor[:SEED]` or a PNG/JPEG path); the error is
/// one line.
pub fn parse(spec: &str) -> anyhow::Result<WallTexture> {
    use anyhow::Context;
    let name = spec.split_once(':').map_or(spec, |(n, _)| n);
    let known = WallTexture::NAMES.contains(&name);
    if !known && !std::path::Path::new(spec).exists() {
        anyhow::bail!(
            "--background {spec}: neither plain[:GREY], stripes[:PERIOD_MM], checker[:SIZE_MM], \
             clutter[:SEED], outdoor[:SEED], ribs[:PERIOD_MM[:DARK:LIGHT]] nor an existing \
             PNG/JPEG file"
        );
    }
    WallTexture::from_spec(spec).with_context(|| format!("--background {spec}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::Arena;

    #[test]
    fn an_unknown_background_is_one_line_naming_every_form() {
        let err = parse("nonsense:3").unwrap_err().to_string();
        assert_eq!(err.lines().count(), 1, "{err}");
        for name in WallTexture::NAMES {
            assert!(err.contains(&format!("{name}[:")), "{name}: {err}");
        }
    }

    fn world(texture: WallTexture) -> World {
        World {
            arena: Arena::new(300.0, 200.0),
            wall_height_mm: 60.0,
            texture,
            ..World::default()
        }
    }

    #[test]
    fn stripes_average_to_mid_grey_in_coarse_levels() {
        let m = WallMap::new(&world(WallTexture::Stripes { period_mm: 20.0 }));
        let mid = (f32::from(PATTERN_DARK) + f32::from(PATTERN_LIGHT)) / 2.0;
        // Fine: full contrast.
        let s = m.sampler(5.0, 1.0);
        let s2 = m.sampler(15.0, 1.0);
        assert!((s.at(30.0) - f32::from(PATTERN_DARK)).abs() < 1.0);
        assert!((s2.at(30.0) - f32::from(PATTERN_LIGHT)).abs() < 1.0);
        // A 40 mm footprint (two periods) cuts the contrast; 160 mm averages it away.
        for u in [3.0, 8.0, 13.0, 17.0] {
            assert!((m.sampler(u, 40.0).at(30.0) - mid).abs() < 45.0);
            assert!((m.sampler(u, 160.0).at(30.0) - mid).abs() < 6.0);
        }
        assert!((m.mean() - mid).abs() < 3.0);
    }

    #[test]
    fn outdoor_has_a_bright_sky_over_textured_ground() {
        let w = World {
            texture: WallTexture::Outdoor { seed: 3 },
            ..World::default()
        };
        let img = WallMap::new(&w).unrolled();
        assert_eq!(img, WallMap::new(&w).unrolled(), "reproducible");
        let band = |r0: usize, r1: usize| -> (f64, f64) {
            let px: Vec<f64> = (r0 * img.width..r1 * img.width)
                .map(|i| f64::from(img.pixels[i]))
                .collect();
            let m = px.iter().sum::<f64>() / px.len() as f64;
            let sd = (px.iter().map(|g| (g - m) * (g - m)).sum::<f64>() / px.len() as f64).sqrt();
            (m, sd)
        };
        // top row = top of the wall: the top 15 % is sky (but for trunks), the bottom half ground
        let (sky, sky_sd) = band(0, img.height * 15 / 100);
        let (ground, ground_sd) = band(img.height / 2, img.height);
        assert!(sky > ground + 30.0, "sky {sky}, ground {ground}");
        assert!(sky_sd < ground_sd, "{sky_sd} {ground_sd}");
        // RMS contrast of the ground as in outdoor photographs (0.28–0.51)
        assert!(
            (0.25..0.6).contains(&(ground_sd / ground)),
            "{ground_sd} / {ground}"
        );
    }

    #[test]
    fn plain_is_plain_at_every_level_and_clutter_is_reproducible() {
        let m = WallMap::new(&world(WallTexture::Plain(77)));
        for fp in [0.5, 1.0, 3.0, 17.0, 1e6] {
            assert_eq!(m.sampler(123.0, fp).at(10.0), 77.0);
        }
        let a = WallMap::new(&world(WallTexture::Clutter { seed: 4 })).unrolled();
        let b = WallMap::new(&world(WallTexture::Clutter { seed: 4 })).unrolled();
        let c = WallMap::new(&world(WallTexture::Clutter { seed: 5 })).unrolled();
        assert_eq!(a, b);
        assert_ne!(a, c);
    }
}
