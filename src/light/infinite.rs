//! Infinite (environment) light: constant radiance `L × gain`, optionally times a map
//! (`mapname`, EXR/HDR/PNG/...; `gamma` applied to the texel values) looked up with the
//! light-space direction through its `mapping` (`latlong`, `angular` or `vcross`, see
//! [`super::envmapping`]). Constant environments are sampled uniformly over the sphere;
//! maps are importance sampled with a 2D piecewise-constant distribution over texels
//! weighted by luminance × the solid angle the texel covers (dω/(ds dt) at its centre); the
//! solid-angle pdf is that density over the mapping's Jacobian (texel lookup is nearest, so
//! the pdf is exact).

use super::envmapping::EnvMapping;
use super::{LightColor, LightCommon, LightSample};
use crate::geometry::{Interaction, SurfaceInteraction};
use crate::lxs::ParamSet;
use crate::sampling::PiecewiseConstant2D;
use crate::sampling::{uniform_sphere, UNIFORM_SPHERE_PDF};
use crate::spectrum::Rgb;
use crate::texture::image_io;
use glam::{Mat4, Vec2, Vec3A};
use std::f32::consts::PI;

/// A lat-long radiance map with its sampling distribution.
#[derive(Debug)]
pub struct EnvMap {
    pub width: usize,
    pub height: usize,
    pub mapping: EnvMapping,
    texels: Vec<Rgb>,
    dist: PiecewiseConstant2D,
    /// Solid-angle mean of the luminance over the sphere.
    mean: f32,
}

impl EnvMap {
    /// A lat-long map.
    pub fn new(width: usize, height: usize, texels: Vec<Rgb>) -> Result<EnvMap, String> {
        EnvMap::with_mapping(width, height, texels, EnvMapping::LatLong)
    }

    pub fn with_mapping(
        width: usize,
        height: usize,
        texels: Vec<Rgb>,
        mapping: EnvMapping,
    ) -> Result<EnvMap, String> {
        if width == 0 || height == 0 || texels.len() != width * height {
            return Err(format!(
                "environment map of {width}×{height} has {} texels",
                texels.len()
            ));
        }
        let mut weights = Vec::with_capacity(texels.len());
        let mut sum = 0.0f64;
        for (i, t) in texels.iter().enumerate() {
            let (x, y) = (i % width, i / width);
            let s = (x as f32 + 0.5) / width as f32;
            let tt = (y as f32 + 0.5) / height as f32;
            let jac = mapping.to_dir(s, tt).map_or(0.0, |(_, j)| j);
            let w = luminance(*t).max(0.0) * jac;
            sum += f64::from(w);
            weights.push(w);
        }
        let dist = PiecewiseConstant2D::new(&weights, width, height);
        let mean = (sum / texels.len() as f64 / (4.0 * std::f64::consts::PI)) as f32;
        Ok(EnvMap {
            width,
            height,
            mapping,
            texels,
            dist,
            mean,
        })
    }

    /// The texel toward the unit light-space direction `d`.
    fn at(&self, d: Vec3A) -> Rgb {
        let (s, t) = self.mapping.to_st(d);
        self.texel(s, t)
    }

    /// A light-space direction drawn ∝ the map's luminance, with its solid-angle pdf.
    fn sample(&self, u: Vec2) -> Option<(Vec3A, f32)> {
        let ([s, t], pdf_st) = self.dist.sample(u.x, u.y);
        let (d, jac) = self.mapping.to_dir(s, t)?;
        (pdf_st > 0.0).then(|| (d, pdf_st / jac))
    }

    /// Solid-angle density of [`Self::sample`] at the unit light-space direction `d`.
    fn pdf(&self, d: Vec3A) -> f32 {
        let (s, t) = self.mapping.to_st(d);
        match self.mapping.to_dir(s, t) {
            Some((_, jac)) => self.dist.pdf(s, t) / jac,
            None => 0.0,
        }
    }

    fn texel(&self, s: f32, t: f32) -> Rgb {
        let x = ((s * self.width as f32) as usize).min(self.width - 1);
        let y = ((t * self.height as f32) as usize).min(self.height - 1);
        self.texels
            .get(y * self.width + x)
            .copied()
            .unwrap_or(Rgb::BLACK)
    }
}

fn luminance(c: Rgb) -> f32 {
    0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b
}

#[derive(Debug)]
pub struct InfiniteLight {
    pub common: LightCommon,
    pub radiance: Rgb,
    l2w: Mat4,
    w2l: Mat4,
    map: Option<EnvMap>,
    y: f32,
    pub world_radius: f32,
    /// Windows it is sampled through (`PortalShape`), see [`super::portal`].
    pub portals: Option<super::portal::Portals>,
}

impl InfiniteLight {
    /// `map` is the image `mapname` names, already read through the scene's files.
    pub fn new(
        params: &ParamSet,
        l2w: Mat4,
        color: &LightColor,
        map: Option<image_io::RgbImage>,
        common: LightCommon,
    ) -> Result<Self, String> {
        let gain = params.float_or("gain", 1.0);
        let gamma = params.float_or("gamma", 1.0);
        let name = params.string_or("mapping", "latlong");
        let mapping = EnvMapping::from_name(name).ok_or_else(|| {
            format!("infinite light mapping \"{name}\" is unknown (latlong, angular, vcross)")
        })?;
        let map = match map {
            Some((w, h, mut texels)) => {
                if gamma != 1.0 {
                    for t in texels.iter_mut() {
                        *t = t.map(|v| v.max(0.0).powf(gamma));
                    }
                }
                Some(EnvMap::with_mapping(w, h, texels, mapping)?)
            }
            None => None,
        };
        Ok(InfiniteLight {
            common,
            radiance: color.emission.eval(&SurfaceInteraction::default()) * gain,
            l2w,
            w2l: l2w.inverse(),
            map,
            y: color.y * gain,
            world_radius: 1.0,
            portals: None,
        })
    }

    /// Builds a light around an in-memory map (tests, generated environments).
    pub fn with_map(radiance: Rgb, l2w: Mat4, map: Option<EnvMap>, common: LightCommon) -> Self {
        InfiniteLight {
            common,
            radiance,
            l2w,
            w2l: l2w.inverse(),
            map,
            y: luminance(radiance),
            world_radius: 1.0,
            portals: None,
        }
    }

    pub fn le(&self, dir: Vec3A) -> Rgb {
        match &self.map {
            None => self.radiance,
            Some(m) => {
                let d = self.w2l.transform_vector3a(dir).normalize_or_zero();
                self.radiance * m.at(d)
            }
        }
    }

    pub fn sample_li(&self, r: &Interaction, u: Vec2) -> Option<LightSample> {
        let (wi, pdf) = match &self.map {
            None => (uniform_sphere(u), UNIFORM_SPHERE_PDF),
            Some(m) => {
                let (d, pdf) = m.sample(u)?;
                (self.l2w.transform_vector3a(d).normalize_or_zero(), pdf)
            }
        };
        Some(LightSample::from_infinity(
            r,
            wi,
            self.le(wi),
            pdf,
            false,
            self.world_radius,
        ))
    }

    pub fn pdf_li(&self, wi: Vec3A) -> f32 {
        match &self.map {
            None => UNIFORM_SPHERE_PDF,
            Some(m) => m.pdf(self.w2l.transform_vector3a(wi).normalize_or_zero()),
        }
    }

    pub fn power(&self) -> f32 {
        let mean = self.map.as_ref().map_or(1.0, |m| m.mean);
        self.y * mean * PI * 4.0 * PI * self.world_radius * self.world_radius
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn common() -> LightCommon {
        LightCommon::single(0)
    }

    #[test]
    fn map_sampling_estimates_irradiance() {
        // A map bright in its upper half: irradiance on an upward surface through importance
        // sampling must equal the closed form ∫_{upper} L cosθ dω = π·L (L = 2 above).
        let (w, h) = (64, 32);
        let texels: Vec<Rgb> = (0..w * h)
            .map(|i| {
                if i / w < h / 2 {
                    Rgb::splat(2.0)
                } else {
                    Rgb::splat(0.0)
                }
            })
            .collect();
        let map = EnvMap::new(w, h, texels).unwrap();
        let l = InfiniteLight::with_map(Rgb::WHITE, Mat4::IDENTITY, Some(map), common());
        let r = Interaction::default();
        let n = 200;
        let mut e = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                if let Some(s) = l.sample_li(&r, u) {
                    assert!((l.pdf_li(s.wi) - s.pdf).abs() < 1e-3 * s.pdf);
                    e += f64::from(s.li.r * s.wi.z.max(0.0) / s.pdf);
                }
            }
        }
        e /= (n * n) as f64;
        assert!((e - 2.0 * std::f64::consts::PI).abs() < 0.03 * e, "{e}");
    }

    #[test]
    fn angular_and_vcross_maps_are_importance_sampled_consistently() {
        // Maps whose texels hold a function of their direction (bright toward +z and +x):
        // the importance-sampled irradiance on an upward surface matches a quadrature of the
        // light's own radiance, and sample pdfs match pdf_li.
        for mapping in [EnvMapping::Angular, EnvMapping::VerticalCross] {
            let (w, h) = match mapping {
                EnvMapping::VerticalCross => (48, 64),
                _ => (64, 64),
            };
            let texels: Vec<Rgb> = (0..w * h)
                .map(|i| {
                    let (s, t) = (
                        ((i % w) as f32 + 0.5) / w as f32,
                        ((i / w) as f32 + 0.5) / h as f32,
                    );
                    match mapping.to_dir(s, t) {
                        Some((d, _)) => Rgb::splat(0.2 + d.z.max(0.0) * 3.0 + d.x.max(0.0)),
                        None => Rgb::BLACK,
                    }
                })
                .collect();
            let map = EnvMap::with_mapping(w, h, texels, mapping).unwrap();
            let l = InfiniteLight::with_map(Rgb::WHITE, Mat4::IDENTITY, Some(map), common());
            let r = Interaction::default();
            let n = 200;
            let mut est = 0.0f64;
            for i in 0..n {
                for j in 0..n {
                    let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    if let Some(s) = l.sample_li(&r, u) {
                        let pdf = l.pdf_li(s.wi);
                        assert!(
                            (pdf - s.pdf).abs() < 1e-2 * s.pdf,
                            "{mapping:?} {pdf} {}",
                            s.pdf
                        );
                        est += f64::from(s.li.g * s.wi.z.max(0.0) / s.pdf);
                    }
                }
            }
            est /= (n * n) as f64;
            let (nt, np) = (300, 600);
            let mut quad = 0.0f64;
            for i in 0..nt {
                let th = (i as f32 + 0.5) / nt as f32 * std::f32::consts::FRAC_PI_2;
                for j in 0..np {
                    let ph = (j as f32 + 0.5) / np as f32 * 2.0 * PI;
                    let d = Vec3A::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
                    let dw = th.sin()
                        * (std::f32::consts::FRAC_PI_2 / nt as f32)
                        * (2.0 * PI / np as f32);
                    quad += f64::from(l.le(d).g * d.z * dw);
                }
            }
            assert!(
                (est - quad).abs() < 0.02 * quad,
                "{mapping:?}: {est} vs {quad}"
            );
        }
    }

    #[test]
    fn constant_environment() {
        let l = InfiniteLight::with_map(Rgb::splat(0.5), Mat4::IDENTITY, None, common());
        assert_eq!(l.le(Vec3A::X), Rgb::splat(0.5));
        let s = l
            .sample_li(&Interaction::default(), Vec2::new(0.3, 0.6))
            .unwrap();
        assert!((s.pdf - UNIFORM_SPHERE_PDF).abs() < 1e-7);
    }
}
