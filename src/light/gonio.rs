//! Goniometric profiles: how a point light's intensity varies with direction, from an IES file
//! (`iesname`, see [`super::ies`]), a lat-long image (`mapname`, LuxRender's `goniometric`
//! light) or both multiplied, as LuxRender 1.x's spherical functions have them.
//!
//! ```text
//! iesname --SceneFiles--> ies::parse --+
//! mapname --SceneFiles--> RGB image ---+--> Goniometric::eval(light-space direction) -> Rgb
//!                                      +--> 256 × 128 luminance × sin θ grid -> sampling pdf
//! ```
//!
//! **Frames.** A light-space direction d (the light's transform at its statement) is at polar
//! angle θ from +z and azimuth φ = atan2(y, x). The map is looked up bilinearly at
//! (φ/2π, θ/π), row 0 at the top (θ = 0). The IES profile's nadir axis (vertical angle 0) is
//! +z and its horizontal angle 0 is +x, unless `flipz` (default false) turns the profile upside
//! down, as LuxRender does (its IES rows are indexed by θ/π).
//!
//! **Sampling.** Light subpaths leave in directions drawn from a piecewise-constant
//! distribution over 256 × 128 lat-long cells weighted by the profile's luminance at the cell
//! centre × sin θ (the pdf is that distribution's; the profile itself is evaluated exactly).

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

/// An RGB lat-long image with bilinear lookup.
#[derive(Debug)]
struct LatLongMap {
    width: usize,
    height: usize,
    texels: Vec<Rgb>,
}

impl LatLongMap {
    fn texel(&self, x: usize, y: usize) -> Rgb {
        self.texels
            .get(y.min(self.height - 1) * self.width + x % self.width)
            .copied()
            .unwrap_or(Rgb::BLACK)
    }

    fn lookup(&self, s: f32, t: f32) -> Rgb {
        let u = (s * self.width as f32 - 0.5).rem_euclid(self.width as f32);
        let v = (t * self.height as f32 - 0.5).clamp(0.0, (self.height - 1) as f32);
        let (x0, y0) = (u as usize, v as usize);
        let (fu, fv) = (u - x0 as f32, v - y0 as f32);
        let top = self.texel(x0, y0) * (1.0 - fu) + self.texel(x0 + 1, y0) * fu;
        let bottom = self.texel(x0, y0 + 1) * (1.0 - fu) + self.texel(x0 + 1, y0 + 1) * fu;
        top * (1.0 - fv) + bottom * fv
    }
}

/// A directional intensity profile with its sampling distribution.
#[derive(Debug)]
pub struct Goniometric {
    ies: Option<IesProfile>,
    flip_z: bool,
    map: Option<LatLongMap>,
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
            dist: PiecewiseConstant2D::new(&[1.0], 1, 1),
            mean: 0.0,
        };
        g.build_distribution();
        g
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
            f = f * m.lookup(s, t);
        }
        if let Some(p) = &self.ies {
            let z = if self.flip_z { -d.z } else { d.z };
            f = f * p.candela([d.x, d.y, z]);
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
