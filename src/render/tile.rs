//! Tiles of the film buffer and the rendering of one tile into its own small film (the tile
//! plus the filter's reach, clipped to the buffer), and into a depth buffer of the same
//! region when the Film asks for a Z output (each camera ray's first hit, found by one more
//! intersection of the primary ray; nothing is traced for depth otherwise).
//!
//! A tile samples its own pixels and, on the sides where it touches the buffer's edge, the
//! pixels of the sample extent's margin beyond it (`super::extent`): every pixel of the
//! extent is sampled by exactly one tile, so border pixels get their full filter footprint
//! and the tile reports every sample it drew.
//!
//! Under a sampling map (noise-aware sampling) each pixel takes the map's count of samples
//! for the pass instead of `pixelsamples` (`crate::sampler::map`), at the next indices of its
//! own sequence (`super::counts`); the tile reports the samples it took.

use super::counts::SampleCounts;
use super::extent::SampleExtent;
use super::setup::{RenderSetup, Renderable};
use crate::film::FilmParams;
use crate::film::{BufferType, Film, OutlierRejector, VarianceBuffer, ZBuffer};
use crate::integrator::{SampleOut, Splat};
use crate::sampler::map::{PassKey, SamplingMap};
use crate::spectrum::rgb_to_xyz;

pub const TILE_SIZE: u32 = 32;

/// A tile: pixels [x0, x1) × [y0, y1) of the buffer, and the buffer region [fx0, fx1) ×
/// [fy0, fy1) its film covers (wider by the filter radius).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    pub x0: u32,
    pub x1: u32,
    pub y0: u32,
    pub y1: u32,
    pub fx0: u32,
    pub fy0: u32,
    pub fx1: u32,
    pub fy1: u32,
}

/// The tiles of a `w` × `h` buffer in row-major order (film regions are set per render).
pub fn tiles(w: u32, h: u32) -> Vec<Tile> {
    let mut v = Vec::new();
    let mut y = 0;
    while y < h {
        let mut x = 0;
        while x < w {
            let (x1, y1) = ((x + TILE_SIZE).min(w), (y + TILE_SIZE).min(h));
            v.push(Tile {
                x0: x,
                x1,
                y0: y,
                y1,
                fx0: x,
                fy0: y,
                fx1: x1,
                fy1: y1,
            });
            x += TILE_SIZE;
        }
        y += TILE_SIZE;
    }
    v
}

/// What a tile discarded: contributions that were NaN/Inf/negative, and finite ones that the
/// film's `outlierrejection_k` test rejected.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Discarded {
    pub invalid: u64,
    pub outliers: u64,
}

/// What a tile rendered: its film (the tile plus the filter's reach), the tile with its film
/// region, what was discarded, the contributions its samples made at other film positions
/// (to be added to the session film's light buffer in tile order), and the depths of its
/// film region when the Film asks for a Z buffer.
pub struct TileOut {
    pub film: Film,
    /// Camera samples taken.
    pub samples: u64,
    pub tile: Tile,
    pub discarded: Discarded,
    pub splats: Vec<Splat>,
    pub depth: Option<ZBuffer>,
}

/// What every tile of one pass shares: the pass, samples per pixel, job seed and stream, the
/// film's buffer layout, the sample extent and the sampling map (noise-aware sampling), if
/// any.
#[derive(Clone, Copy)]
pub struct PassCtx<'a> {
    /// The first pass of the sweep.
    pub pass: u64,
    /// Passes in the sweep (1 under a map: see `super::pass`).
    pub passes: u32,
    pub spp: u32,
    pub seed: u64,
    pub stream: u64,
    pub buffers: &'a [BufferType],
    pub extent: SampleExtent,
    pub map: Option<&'a SamplingMap>,
    /// Each pixel's next sample index, once a map has been used (`super::counts`).
    pub counts: Option<&'a SampleCounts>,
    /// Whether tiles record depths (the session keeps a Z buffer).
    pub depth: bool,
    /// Whether tile films keep luminance spread sums (a noise-aware sampler's session).
    pub variance: bool,
}

impl PassCtx<'_> {
    /// Samples of raster pixel (`px`, `py`) in this pass; `bx`, `by` is the buffer pixel
    /// whose map count it takes (itself, or for a margin pixel the nearest buffer pixel).
    fn pixel_plan(&self, bx: u32, by: u32, px: i32, py: i32) -> u32 {
        match self.map {
            None => self.spp.saturating_mul(self.passes),
            Some(m) => m.pixel_samples(
                self.spp,
                bx,
                by,
                PassKey {
                    seed: self.seed,
                    stream: self.stream,
                    // Margin pixels left of or above the image wrap, as their sample keys do.
                    px: px as u32,
                    py: py as u32,
                    pass: self.pass,
                },
            ),
        }
    }

    /// Samples of raster pixel (`px`, `py`) in this pass, its margin pixels taking the
    /// nearest buffer pixel's count (as the tiles draw them).
    pub fn plan_at(&self, fp: &FilmParams, px: i32, py: i32) -> u32 {
        let bx = clamp_to(px, fp.x_pixel_start, fp.x_pixel_count);
        let by = clamp_to(py, fp.y_pixel_start, fp.y_pixel_count);
        self.pixel_plan(bx, by, px, py)
    }

    /// The samples this pass plans for tile `t` (the pixels it samples, margins included):
    /// its work, for scheduling.
    pub fn tile_samples(&self, fp: &FilmParams, t: &Tile) -> u64 {
        let (bw, bh) = (fp.x_pixel_count, fp.y_pixel_count);
        let [px0, px1, py0, py1] =
            sampled_pixels(t, self.extent, fp.x_pixel_start, fp.y_pixel_start, bw, bh);
        let mut n = 0;
        for py in py0..py1 {
            for px in px0..px1 {
                n += u64::from(self.plan_at(fp, px, py));
            }
        }
        n
    }

    /// The sample index of raster pixel (`px`, `py`)'s `k`-th sample in this sweep: the next
    /// of its own sequence under counts, else `pass × spp + k` (the sweep's later passes'
    /// samples follow on: k runs to passes × spp).
    fn sample_index(&self, px: i32, py: i32, k: u32) -> u64 {
        match self.counts.and_then(|c| c.next(px, py)) {
            Some(next) => next + u64::from(k),
            None => self.pass * u64::from(self.spp) + u64::from(k),
        }
    }
}

/// Renders tile `t` for the pass `ctx` into a film of the session's buffer layout (the
/// samples' own contributions go to buffer 0): `spp` samples per pixel, or the map's count.
pub fn render_tile(scene: &Renderable, t: &Tile, ctx: &PassCtx) -> TileOut {
    let (seed, stream, buffers) = (ctx.seed, ctx.stream, ctx.buffers);
    let mut samples = 0u64;
    let (setup, world) = (&scene.setup, &scene.world);
    let fp = &setup.film_params;
    let (bw, bh) = (fp.x_pixel_count, fp.y_pixel_count);
    let r = setup.filter.radius();
    let (rx, ry) = (
        r.x.ceil().max(0.0) as u32 + 1,
        r.y.ceil().max(0.0) as u32 + 1,
    );
    let mut t = *t;
    t.fx0 = t.x0.saturating_sub(rx);
    t.fy0 = t.y0.saturating_sub(ry);
    t.fx1 = (t.x1 + rx).min(bw);
    t.fy1 = (t.y1 + ry).min(bh);
    let (fw, fh) = (t.fx1 - t.fx0, t.fy1 - t.fy0);
    let mut film = Film::with_buffers(fw, fh, world.groups().to_vec(), buffers.to_vec())
        .unwrap_or_else(|_| Film::new(fw, fh, world.groups().to_vec()));
    if ctx.variance {
        // A tile film has the size of its new buffer: the call cannot be refused.
        let _ = film.set_variance(Some(VarianceBuffer::new(fw, fh)));
    }
    let mut depth = ctx
        .depth
        .then(|| ZBuffer::new(t.fx1 - t.fx0, t.fy1 - t.fy0));
    // Offset from full-image raster coordinates to this tile film's coordinates.
    let ox = i64::from(fp.x_pixel_start) + i64::from(t.fx0);
    let oy = i64::from(fp.y_pixel_start) + i64::from(t.fy0);
    let ngroups = world.groups().len();
    let mut out = SampleOut::new(ngroups);
    let mut splats = Vec::new();
    let mut discarded = Discarded::default();
    let mut outliers = outlier_rejector(setup, &t);
    let [px0, px1, py0, py1] =
        sampled_pixels(&t, ctx.extent, fp.x_pixel_start, fp.y_pixel_start, bw, bh);
    for py in py0..py1 {
        for px in px0..px1 {
            let bx = clamp_to(px, fp.x_pixel_start, bw);
            let by = clamp_to(py, fp.y_pixel_start, bh);
            let n = ctx.pixel_plan(bx, by, px, py);
            samples += u64::from(n);
            for k in 0..n {
                let index = ctx.sample_index(px, py, k);
                let mut st = setup.sampler.start_at(seed, stream, px, py, index);
                let cs = st.camera_sample();
                let Some((ray, w)) = setup.camera.generate_ray(&cs) else {
                    continue;
                };
                if w.is_nan() || w <= 0.0 {
                    continue;
                }
                if let Some(z) = depth.as_mut() {
                    if let Some(hit) = world.intersect(&ray) {
                        let d = setup.camera.hit_depth(&ray, hit.t);
                        setup.filter.footprint(cs.p_film, |x, y| {
                            let (lx, ly) = (i64::from(x) - ox, i64::from(y) - oy);
                            if lx >= 0 && ly >= 0 {
                                z.add(lx as u32, ly as u32, d, 1.0);
                            }
                        });
                    }
                }
                setup
                    .integrator
                    .sample(world, &setup.camera, ray, &mut st, &mut out);
                let alpha = out.alpha;
                if !out.splats.is_empty() {
                    splats.extend(out.splats.drain(..).map(|mut sp| {
                        sp.l *= w;
                        sp
                    }));
                }
                // With premultiplyalpha the film holds colours already multiplied by alpha.
                let scale = if fp.premultiply_alpha { w * alpha } else { w };
                for (g, c) in out.l.iter().enumerate() {
                    let xyz = rgb_to_xyz(*c * scale);
                    if !xyz.iter().all(|v| v.is_finite()) || xyz[1] < 0.0 {
                        discarded.invalid += 1;
                        continue;
                    }
                    if let Some(o) = outliers.as_mut() {
                        if !o.accept(cs.p_film.x, cs.p_film.y, xyz[1]) {
                            discarded.outliers += 1;
                            continue;
                        }
                    }
                    setup.filter.splat(cs.p_film, |x, y, fw| {
                        let (lx, ly) = (i64::from(x) - ox, i64::from(y) - oy);
                        if lx >= 0 && ly >= 0 {
                            film.add_splat(g, lx as u32, ly as u32, xyz, alpha, fw);
                            film.add_variance(lx as u32, ly as u32, xyz[1], fw);
                        }
                    });
                }
            }
        }
    }
    TileOut {
        film,
        samples,
        tile: t,
        discarded,
        splats,
        depth,
    }
}

/// The raster pixels `[x0, x1, y0, y1]` (half-open) tile `t` samples: its own, widened to the
/// extent's edge on each side where the tile touches the buffer's (buffer pixel (0, 0) is
/// raster pixel (`xs`, `ys`), the buffer `w` × `h`).
fn sampled_pixels(t: &Tile, e: SampleExtent, xs: u32, ys: u32, w: u32, h: u32) -> [i32; 4] {
    let axis = |a: u32, b: u32, start: u32, len: u32, lo: i32, hi: i32| {
        let r = |v: u32| i32::try_from(i64::from(start) + i64::from(v)).unwrap_or(i32::MAX);
        let from = if a == 0 { lo.min(r(a)) } else { r(a) };
        let to = if b >= len { hi.max(r(b)) } else { r(b) };
        (from, to)
    };
    let (x0, x1) = axis(t.x0, t.x1, xs, w, e.x0, e.x1);
    let (y0, y1) = axis(t.y0, t.y1, ys, h, e.y0, e.y1);
    [x0, x1, y0, y1]
}

/// The buffer index on an axis nearest to raster pixel `p` (buffer pixel 0 at raster
/// `start`, `len` pixels).
fn clamp_to(p: i32, start: u32, len: u32) -> u32 {
    let i = i64::from(p) - i64::from(start);
    i.clamp(0, i64::from(len.max(1)) - 1) as u32
}

/// The film's `outlierrejection_k` test over this tile's film region, when enabled. Each tile
/// keeps its own record of outliers, so the result does not depend on the thread count.
fn outlier_rejector(setup: &RenderSetup, t: &Tile) -> Option<OutlierRejector> {
    let fp = &setup.film_params;
    let r = setup.filter.radius();
    OutlierRejector::new(
        fp.outlier_rejection_k,
        t.fx1 - t.fx0,
        t.fy1 - t.fy0,
        [fp.x_pixel_start + t.fx0, fp.y_pixel_start + t.fy0],
        [r.x, r.y],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_the_buffer_once() {
        let (w, h) = (70, 33);
        let mut seen = vec![0u8; (w * h) as usize];
        for t in tiles(w, h) {
            for y in t.y0..t.y1 {
                for x in t.x0..t.x1 {
                    seen[(y * w + x) as usize] += 1;
                }
            }
        }
        assert!(seen.iter().all(|&c| c == 1));
    }

    /// With the sample extent's margin, the tiles' sampled pixels cover the extent once.
    #[test]
    fn sampled_pixels_cover_the_extent_once() {
        let (w, h, xs, ys) = (70u32, 33u32, 5u32, 2u32);
        let e = SampleExtent {
            x0: 3,
            x1: 78,
            y0: 0,
            y1: 36,
            image_pixels: u64::from(w * h),
        };
        let (ew, eh) = ((e.x1 - e.x0) as usize, (e.y1 - e.y0) as usize);
        let mut seen = vec![0u8; ew * eh];
        for t in tiles(w, h) {
            let [x0, x1, y0, y1] = sampled_pixels(&t, e, xs, ys, w, h);
            for y in y0..y1 {
                for x in x0..x1 {
                    let i = (y - e.y0) as usize * ew + (x - e.x0) as usize;
                    seen[i] += 1;
                }
            }
        }
        assert!(seen.iter().all(|&c| c == 1), "{seen:?}");
        assert_eq!(clamp_to(1, 5, 70), 0);
        assert_eq!(clamp_to(80, 5, 70), 69);
        assert_eq!(clamp_to(-4, 5, 70), 0);
    }
}
