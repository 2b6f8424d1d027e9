//! Goniometric profiles: how a point light's intensity varies with direction, from an IES file
//! (`iesname`, see [`super::ies`]), a lat-long image (`mapname`, LuxRender's `goniometric`
//! light) or both multiplied, as LuxRender 1.x's spherical functions have them; and the slide
//! projector of LuxRender's `projection` light ([`Projector`]).
//!
//! ```text
//! iesname --SceneFiles--> ies::parse --+
//! mapname --SceneFiles--> RGB image ---+--> Goniometric::eval(light-space direction) -> Rgb
//!                                      +--> 256 × 128 luminance × sin θ grid -> sampling pdf
//! ```
//!
//! **Frames.** A light-space direction d (the light's transform at its statement) is at polar
//! angle θ from +z and azimuth φ = atan2(y, x). The map is looked up bilinearly at
//! (φ/2π, θ/π), row 0 at the top (θ = 0), the map repeating past its edges in both
//! directions (LuxRender's default `TEXTURE_REPEAT` wrap, for slides too). The IES profile's
//! nadir axis (vertical angle 0) is +z and its horizontal angle 0 is +x, unless `flipz`
//! (default false) turns the profile upside down, as LuxRender does (its IES rows are indexed
//! by θ/π).
//!
//! **Projection.** `projection` projects `mapname` (required) along the light's +z through a
//! pinhole with field of view `fov` (degrees, default 45) along the image's shorter side: the
//! screen window at unit distance is [−a, a] × [−1, 1] · tan(fov/2) for an image of aspect
//! a = width/height > 1, else [−1, 1] × [−1/a, 1/a] · tan(fov/2); the image's top row is toward
//! +y and its left column toward −x. The intensity toward a direction at angle θ from +z inside
//! the window is `map(s, t) / (A·cos³θ)` with LuxRender's A = 4·tan²(fov/2)/a, so a plane
//! facing the projector at distance d receives the even irradiance `map / (A·d²)`; outside the
//! window nothing.
//!
//! **Sampling.** Light subpaths leave in directions drawn from a piecewise-constant
//! distribution over 256 × 128 lat-long cells weighted by the profile's luminance at the cell
//! centre × sin θ, every cell at least 10⁻³ of the largest weight so that no direction the
//! profile lights is left out (the pdf is that distribution's; the profile itself is
//! evaluated exactly, so the estimate stays unbiased).

use super::ies::{self, IesProfile};
use super::latlong::{dir_to_st, st_to_dir};
use crate::fileio::SceneFiles;
use crate::lxs::ParamSet;
use crate::sampling::PiecewiseConstant2D;
use crate::spectrum::Rgb;
use crate::texture::image_io;
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;

const GRID_WIDTH: usize = 256;
const GRID_HEIGHT: usize = 128;

/// An RGB image (a lat-long map or a slide) with LuxRender's bilinear lookup: texel centres
/// at half-integer coordinates, and the image repeating in both directions past its edges
/// (LuxRender 1.x makes these maps with its default `TEXTURE_REPEAT` wrap, so a lookup
/// within half a texel of an edge blends in the opposite edge).
#[derive(Debug)]
struct LatLongMap {
    width: usize,
    height: usize,
    texels: Vec<Rgb>,
}

impl LatLongMap {
    fn texel(&self, x: usize, y: usize) -> Rgb {
        self.texels
            .get((y % self.height) * self.width + x % self.width)
            .copied()
            .unwrap_or(Rgb::BLACK)
    }

    /// Bilinear lookup at (s, t), row 0 at t = 0.
    fn lookup(&self, s: f32, t: f32) -> Rgb {
        let u = (s * self.width as f32 - 0.5).rem_euclid(self.width as f32);
        let v = (t * self.height as f32 - 0.5).rem_euclid(self.height as f32);
        let (x0, y0) = (u as usize, v as usize);
        let (fu, fv) = (u - x0 as f32, v - y0 as f32);
        let top = self.texel(x0, y0) * (1.0 - fu) + self.texel(x0 + 1, y0) * fu;
        let bottom = self.texel(x0, y0 + 1) * (1.0 - fu) + self.texel(x0 + 1, y0 + 1) * fu;
        top * (1.0 - fv) + bottom * fv
    }
}

/// The slide projector of LuxRender's `projection` light (see the module documentation).
#[derive(Debug)]
pub struct Projector {
    slide: LatLongMap,
    tan_half: f32,
    /// Screen window in units of tan(fov/2): x0, x1, y0, y1.
    window: [f32; 4],
    /// LuxRender's normalising area 4·tan²(fov/2)/aspect.
    area: f32,
}

impl Projector {
    /// A projector of the RGB image (width, height, texels) with field of view `fov_deg`.
    pub fn new(
        width: usize,
        height: usize,
        texels: Vec<Rgb>,
        fov_deg: f32,
    ) -> Result<Projector, String> {
        if width == 0 || height == 0 || texels.len() != width * height {
            return Err("the projected image is empty".into());
        }
        if !(fov_deg > 0.0 && fov_deg < 180.0) {
            return Err(format!(
                "fov must be between 0 and 180 degrees (got {fov_deg})"
            ));
        }
        let aspect = width as f32 / height as f32;
        let window = if aspect > 1.0 {
            [-aspect, aspect, -1.0, 1.0]
        } else {
            [-1.0, 1.0, -1.0 / aspect, 1.0 / aspect]
        };
        let tan_half = (fov_deg.to_radians() / 2.0).tan();
        Ok(Projector {
            slide: LatLongMap {
                width,
                height,
                texels,
            },
            tan_half,
            window,
            area: 4.0 * tan_half * tan_half / aspect,
        })
    }

    /// Intensity factor toward the unit light-space direction `d`.
    pub fn eval(&self, d: Vec3A) -> Rgb {
        if d.z <= 1e-6 {
            return Rgb::BLACK;
        }
        let (x, y) = (d.x / (d.z * self.tan_half), d.y / (d.z * self.tan_half));
        let [x0, x1, y0, y1] = self.window;
        if x < x0 || x >= x1 || y < y0 || y >= y1 {
            return Rgb::BLACK;
        }
        let s = (x - x0) / (x1 - x0);
        let t = (y - y0) / (y1 - y0);
        self.slide.lookup(s, 1.0 - t) / (self.area * d.z * d.z * d.z)
    }
}

/// A directional intensity profile with its sampling distribution.
#[derive(Debug)]
pub struct Goniometric {
    ies: Option<IesProfile>,
    flip_z: bool,
    map: Option<LatLongMap>,
    projector: Option<Projector>,
    dist: PiecewiseConstant2D,
    /// Solid-angle mean of the profile's luminance over the sphere.
    mean: f32,
}

fn luminance(c: Rgb) -> f32 {
    0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b
}

impl Goniometric {
    /// The profile a light's `iesname`, `mapname` and `flipz` describe (None without either
    /// file); files are read through the scene's files. Errors name the parameter at fault.
    pub fn from_params(
        params: &ParamSet,
        files: &SceneFiles,
    ) -> Result<Option<Goniometric>, (&'static str, String)> {
        let ies = match params.string("iesname").filter(|s| !s.is_empty()) {
            Some(name) => Some(load_ies(files, name).map_err(|m| ("iesname", m))?),
            None => None,
        };
        let map = match params.string("mapname").filter(|s| !s.is_empty()) {
            Some(name) => {
                let (width, height, texels) =
                    image_io::load_scene_rgb(files, name).map_err(|m| ("mapname", m))?;
                if width == 0 || height == 0 || texels.len() != width * height {
                    return Err(("mapname", format!("\"{name}\": empty image")));
                }
                Some(LatLongMap {
                    width,
                    height,
                    texels,
                })
            }
            None => None,
        };
        let flip_z = params.bool_or("flipz", false);
        if ies.is_none() && map.is_none() {
            return Ok(None);
        }
        Ok(Some(Goniometric::new(ies, map_parts(map), flip_z)))
    }

    /// A profile from an IES table and/or an RGB lat-long image (width, height, texels).
    pub fn new(
        ies: Option<IesProfile>,
        map: Option<(usize, usize, Vec<Rgb>)>,
        flip_z: bool,
    ) -> Goniometric {
        let map = map
            .filter(|(w, h, t)| *w > 0 && *h > 0 && t.len() == w * h)
            .map(|(width, height, texels)| LatLongMap {
                width,
                height,
                texels,
            });
        let mut g = Goniometric {
            ies,
            flip_z,
            map,
            projector: None,
            dist: PiecewiseConstant2D::new(&[1.0], 1, 1),
            mean: 0.0,
        };
        g.build_distribution();
        g
    }

    /// The profile of a slide projector.
    pub fn projection(projector: Projector) -> Goniometric {
        let mut g = Goniometric {
            ies: None,
            flip_z: false,
            map: None,
            projector: Some(projector),
            dist: PiecewiseConstant2D::new(&[1.0], 1, 1),
            mean: 0.0,
        };
        g.build_distribution();
        g
    }

    /// The profile of a `projection` light's `mapname` and `fov`.
    pub fn projection_from_params(
        params: &ParamSet,
        files: &SceneFiles,
    ) -> Result<Goniometric, (&'static str, String)> {
        let name = params.string("mapname").filter(|s| !s.is_empty()).ok_or((
            "mapname",
            "a projection light needs a \"mapname\"".to_string(),
        ))?;
        let (w, h, texels) = image_io::load_scene_rgb(files, name).map_err(|m| ("mapname", m))?;
        let fov = params.float_or("fov", 45.0);
        let projector = Projector::new(w, h, texels, fov).map_err(|m| ("fov", m))?;
        Ok(Goniometric::projection(projector))
    }

    fn build_distribution(&mut self) {
        let (w, h) = (GRID_WIDTH, GRID_HEIGHT);
        let mut weights = Vec::with_capacity(w * h);
        let mut total = 0.0f64;
        for j in 0..h {
            for i in 0..w {
                let (d, sin_t) =
                    st_to_dir((i as f32 + 0.5) / w as f32, (j as f32 + 0.5) / h as f32);
                let y = luminance(self.eval(d)).max(0.0);
                weights.push(y * sin_t);
                total += f64::from(y * sin_t);
            }
        }
        let cell = f64::from((PI / h as f32) * (2.0 * PI / w as f32));
        self.mean = (total * cell / (4.0 * std::f64::consts::PI)) as f32;
        self.dist = PiecewiseConstant2D::new(&weights, w, h);
    }

    /// The profile toward the unit light-space direction `d`.
    pub fn eval(&self, d: Vec3A) -> Rgb {
        let mut f = Rgb::WHITE;
        if let Some(m) = &self.map {
            let (s, t, _) = dir_to_st(d);
            f *= m.lookup(s, t);
        }
        if let Some(p) = &self.projector {
            f *= p.eval(d);
        }
        if let Some(p) = &self.ies {
            let z = if self.flip_z { -d.z } else { d.z };
            f *= p.candela([d.x, d.y, z]);
        }
        f
    }

    /// Solid-angle mean of the profile's luminance (its power relative to a uniform one).
    pub fn mean(&self) -> f32 {
        self.mean
    }

    /// A light-space direction drawn ∝ the profile, with its solid-angle pdf.
    pub fn sample(&self, u: Vec2) -> Option<(Vec3A, f32)> {
        let ([s, t], pdf_st) = self.dist.sample(u.x, u.y);
        let (d, sin_t) = st_to_dir(s, t);
        (sin_t > 0.0 && pdf_st > 0.0).then(|| (d, pdf_st / (2.0 * PI * PI * sin_t)))
    }

    /// Solid-angle density of [`Self::sample`] at the light-space direction `d` (unit).
    pub fn pdf(&self, d: Vec3A) -> f32 {
        let (s, t, sin_t) = dir_to_st(d);
        if sin_t <= 0.0 {
            return 0.0;
        }
        self.dist.pdf(s, t) / (2.0 * PI * PI * sin_t)
    }
}

fn map_parts(map: Option<LatLongMap>) -> Option<(usize, usize, Vec<Rgb>)> {
    map.map(|m| (m.width, m.height, m.texels))
}

/// Reads and parses the IES file `name` through the scene's files.
fn load_ies(files: &SceneFiles, name: &str) -> Result<IesProfile, String> {
    let (_, size) = files.open(name).map_err(|e| e.to_string())?;
    if size > ies::MAX_BYTES as u64 {
        return Err(format!(
            "\"{name}\": {size} bytes, more than an IES file may have ({})",
            ies::MAX_BYTES
        ));
    }
    let bytes = files.read(name).map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&bytes);
    ies::parse(&text).map_err(|m| format!("\"{name}\" {m}"))
}

#[cfg(test)]
mod tests;
