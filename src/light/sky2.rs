//! `sky2` light: the daylight sky of Hosek & Wilkie ("An Analytic Model for Full Spectral
//! Sky-Dome Radiance", SIGGRAPH 2012) as LuxRender 1.x's `sky2` plugin has it, as an
//! environment light.
//!
//! **Model.** For a light-space direction ω (z is up) at zenith angle θ and angle γ from the sun
//! (`sundir`, light space, default (0, 0, 1)), each colour channel's radiance is
//!
//! ```text
//! L = (1 + A·e^(B / (cos θ + 0.01))) · (C + D·e^(E·γ) + F·cos²γ + G·χ(I, γ) + H·√cos θ) · R
//! χ(I, γ) = (1 + cos²γ) / (1 + I² − 2·I·cos γ)^1.5
//! ```
//!
//! with cos θ clamped at 0 (below the horizon the sky keeps its horizon's zenith terms, as in
//! LuxRender). The nine parameters A..I and the scale R come from the tables of
//! [`super::sky2_data`]: each is a quintic Bézier in the normalised solar elevation
//! (elevation / 90°)^(1/3) (control-point weights 1, 5, 10, 10, 5, 1), interpolated linearly
//! between the two tabulated turbidities around `turbidity` (clamped to 1..10) and between the
//! ground albedos 0 and 1. LuxRender 1.x fixes the ground albedo at 0 (it has no parameter for
//! it); so does luxfarm. A sun below the horizon is taken at elevation 0 (LuxRender's power
//! of a negative elevation is undefined).
//!
//! **Colour and units.** LuxRender 1.x evaluates the same model on the spectral tables (11
//! bands, 320–720 nm); luxfarm uses the authors' RGB fit of those spectra (linear sRGB, the
//! tables' values × 683 lm/W giving cd/m²), converted to film XYZ with the sRGB (D65) matrix
//! and from there to luxfarm's illuminant RGB. LuxCore's `sky2` uses the same RGB tables
//! (× 683), which is what `tests/render_sky2.rs` compares against. `gain` (default 1, as
//! LuxRender's code has it; exporters write 0.005 or so) scales the result.
//!
//! **Rendering.** The radiance is evaluated analytically for every escaping ray. Directions
//! are importance sampled with a piecewise-constant distribution over a 256 × 128 lat-long grid
//! (s = φ/2π, t = θ/π as the infinite light has it) weighted by the luminance at each cell's
//! centre × sin θ; the pdf is that distribution's, so the estimate is unbiased.
//!
//! Parameters: `sundir`, `turbidity` (2), `gain` (1), `nsamples` (1).

use super::latlong::{self, st_to_dir};
use super::sky2_data as data;
use super::{LightCommon, LightSample};
use crate::geometry::Interaction;
use crate::lxs::ParamSet;
use crate::sampling::PiecewiseConstant2D;
use crate::spectrum::xyz::LUMENS_PER_WATT;
use crate::spectrum::{xyz_to_rgb, Rgb};
use glam::{Mat4, Vec2, Vec3A};
use std::f32::consts::{FRAC_PI_2, PI};

/// Grid cells in φ and θ of the sampling distribution.
pub const GRID_WIDTH: usize = 256;
pub const GRID_HEIGHT: usize = 128;

/// Linear sRGB (D65) to CIE XYZ, IEC 61966-2-1.
const SRGB_TO_XYZ: [[f32; 3]; 3] = [
    [0.4124, 0.3576, 0.1805],
    [0.2126, 0.7152, 0.0722],
    [0.0193, 0.1192, 0.9505],
];

/// The Bernstein weights of a quintic Bézier at `x` ∈ [0, 1].
fn bezier_weights(x: f32) -> [f32; data::CONTROL_POINTS] {
    const BINOMIAL: [f32; 6] = [1.0, 5.0, 10.0, 10.0, 5.0, 1.0];
    std::array::from_fn(|k| BINOMIAL[k] * (1.0 - x).powi(5 - k as i32) * x.powi(k as i32))
}

/// The two tabulated turbidity indices around `t` and the weight of the upper one.
fn turbidity_bracket(t: f32) -> (usize, usize, f32) {
    let low = (t - 1.0).clamp(0.0, 9.0).floor() as usize;
    let high = (low + 1).min(data::TURBIDITIES - 1);
    (low, high, (t - high as f32).clamp(0.0, 1.0))
}

/// Interpolates one table entry (`pick` reads a control point's value for an albedo and a
/// turbidity index) over the elevation curve, the turbidity and the albedo.
fn interpolate(
    pick: impl Fn(usize, usize, usize) -> f32,
    bez: &[f32; 6],
    turbidity: f32,
    albedo: f32,
) -> f32 {
    let (lo, hi, tw) = turbidity_bracket(turbidity);
    let curve = |a: usize, t: usize| (0..6).map(|k| bez[k] * pick(a, t, k)).sum::<f32>();
    let at = |a: usize| curve(a, lo) * (1.0 - tw) + curve(a, hi) * tw;
    let aw = albedo.clamp(0.0, 1.0);
    at(0) * (1.0 - aw) + at(1) * aw
}

/// The Hosek–Wilkie sky's radiance distribution in light space.
#[derive(Clone, Debug)]
pub struct Sky2Model {
    /// Unit direction toward the sun.
    pub sun: Vec3A,
    /// Parameters A..I per colour channel.
    params: [[f32; data::PARAMS]; 3],
    /// Radiance scale R per colour channel, × 683 lm/W.
    scale: [f32; 3],
}

impl Sky2Model {
    /// The model for a sun toward `sun` (light space), `turbidity` and ground `albedo`.
    pub fn new(sun: Vec3A, turbidity: f32, albedo: f32) -> Sky2Model {
        let sun = sun.normalize_or(Vec3A::Z);
        let elevation = (FRAC_PI_2 - sun.z.clamp(-1.0, 1.0).acos()).max(0.0);
        let bez = bezier_weights((elevation / FRAC_PI_2).clamp(0.0, 1.0).cbrt());
        let params = std::array::from_fn(|c| {
            std::array::from_fn(|i| {
                let pick = |a: usize, t: usize, k: usize| data::COEFFS[c][a][t][k][i];
                interpolate(pick, &bez, turbidity, albedo)
            })
        });
        let scale = std::array::from_fn(|c| {
            let pick = |a: usize, t: usize, k: usize| data::RADIANCE[c][a][t][k];
            interpolate(pick, &bez, turbidity, albedo) * LUMENS_PER_WATT as f32
        });
        Sky2Model { sun, params, scale }
    }

    /// Linear sRGB radiance (cd/m² scale) toward the unit light-space direction `w`.
    pub fn srgb(&self, w: Vec3A) -> [f32; 3] {
        let cos_g = w.dot(self.sun).clamp(-1.0, 1.0);
        let gamma = cos_g.acos();
        let cos_t = w.z.max(0.0);
        std::array::from_fn(|c| {
            let [a, b, cc, d, e, f, g, h, i] = self.params[c];
            let mie = (1.0 + cos_g * cos_g) / (1.0 + i * i - 2.0 * i * cos_g).max(1e-6).powf(1.5);
            let dist = (1.0 + a * (b / (cos_t + 0.01)).exp())
                * (cc + d * (e * gamma).exp() + f * cos_g * cos_g + g * mie + h * cos_t.sqrt());
            let v = dist * self.scale[c];
            if v.is_finite() {
                v.max(0.0)
            } else {
                0.0
            }
        })
    }

    /// Film XYZ of the radiance toward `w` (unit, light space).
    pub fn xyz(&self, w: Vec3A) -> [f32; 3] {
        let rgb = self.srgb(w);
        SRGB_TO_XYZ.map(|row| row[0] * rgb[0] + row[1] * rgb[1] + row[2] * rgb[2])
    }
}

#[derive(Debug)]
pub struct Sky2Light {
    pub common: LightCommon,
    pub model: Sky2Model,
    gain: f32,
    l2w: Mat4,
    w2l: Mat4,
    dist: PiecewiseConstant2D,
    /// Solid-angle mean of the luminance over the sphere (× gain).
    mean_y: f32,
    pub world_radius: f32,
    /// Windows it is sampled through (`PortalShape`), see [`super::portal`].
    pub portals: Option<super::portal::Portals>,
}

impl Sky2Light {
    pub fn new(params: &ParamSet, l2w: Mat4, common: LightCommon) -> Result<Sky2Light, String> {
        let gain = params.float_or("gain", 1.0);
        let turbidity = params.float_or("turbidity", 2.0);
        let sundir = Vec3A::from_array(params.vector("sundir").unwrap_or([0.0, 0.0, 1.0]));
        let sun = sundir
            .try_normalize()
            .ok_or_else(|| "sky2: sundir must be a non-zero vector".to_string())?;
        if !(gain >= 0.0 && gain.is_finite() && turbidity.is_finite()) {
            return Err("sky2: gain must be non-negative and finite, turbidity finite".into());
        }
        if !(1.0..=10.0).contains(&turbidity) {
            tracing::warn!("sky2: turbidity {turbidity} is outside the model's 1..10; clamped");
        }
        if sun.z < 0.0 {
            tracing::warn!("sky2: the sun is below the horizon; the sky is taken at sunset");
        }
        Ok(Sky2Light::from_model(
            Sky2Model::new(sun, turbidity, 0.0),
            gain,
            l2w,
            common,
        ))
    }

    /// The light of `model` × `gain`, with its sampling distribution.
    pub fn from_model(model: Sky2Model, gain: f32, l2w: Mat4, common: LightCommon) -> Sky2Light {
        let (w, h) = (GRID_WIDTH, GRID_HEIGHT);
        let mut weights = Vec::with_capacity(w * h);
        let mut total = 0.0f64;
        for j in 0..h {
            for i in 0..w {
                let (d, sin_t) =
                    st_to_dir((i as f32 + 0.5) / w as f32, (j as f32 + 0.5) / h as f32);
                let y = (model.xyz(d)[1] * gain).max(0.0);
                weights.push(y * sin_t);
                total += f64::from(y * sin_t);
            }
        }
        let cell = (PI / h as f32) * (2.0 * PI / w as f32);
        let mean_y = (total * f64::from(cell) / (4.0 * std::f64::consts::PI)) as f32;
        Sky2Light {
            common,
            model,
            gain,
            l2w,
            w2l: l2w.inverse(),
            dist: PiecewiseConstant2D::new(&weights, w, h),
            mean_y,
            world_radius: 1.0,
            portals: None,
        }
    }

    pub fn gain(&self) -> f32 {
        self.gain
    }

    /// Radiance toward the light-space direction `d` (unit).
    pub fn le_local(&self, d: Vec3A) -> Rgb {
        xyz_to_rgb(self.model.xyz(d)) * self.gain
    }

    pub fn le(&self, dir: Vec3A) -> Rgb {
        self.le_local(self.w2l.transform_vector3a(dir).normalize_or_zero())
    }

    pub fn sample_li(&self, r: &Interaction, u: Vec2) -> Option<LightSample> {
        latlong::sample_li(&self.dist, &self.l2w, r, u, self.world_radius, |s, t| {
            self.le_local(st_to_dir(s, t).0)
        })
    }

    pub fn pdf_li(&self, wi: Vec3A) -> f32 {
        latlong::pdf(&self.dist, &self.w2l, wi)
    }

    /// Luminous power through a disc of the scene's radius (as the infinite light's).
    pub fn power(&self) -> f32 {
        latlong::sky_power(self.mean_y, self.world_radius)
    }
}

#[cfg(test)]
mod tests;
