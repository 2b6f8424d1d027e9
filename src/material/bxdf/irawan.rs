//! The Irawan–Marschner woven-cloth model as LuxRender's cloth material uses it (Piti Irawan,
//! "The Appearance of Woven Cloth", by way of Mitsuba's port).
//!
//! A [`WeavePattern`] is a tile of warp and weft yarn segments repeated `repeat_u × repeat_v`
//! times over the uv square. [`WeavePattern::yarn_at`] finds the segment under a uv point,
//! its local coordinates (u along the fibre's inclination, v across the yarn), its maximum
//! inclination (varied by Perlin noise when the pattern has a `period`) and a random
//! specular scale (`fineness` seeds per unit of texture). [`Irawan`] evaluates the specular
//! scattering of that segment: a filament integrand (untwisted yarn, `psi` = 0) or a staple
//! integrand (twisted fibres), each a product of a geometry term, a von Mises forward
//! scattering lobe plus a uniform part, and Seeliger's attenuation.
//!
//! The lobe is reflection only and cosine sampled; `f = Ks · spec(wo, wi) · norm / π`, where
//! `norm` makes the specular part reflect `Ks` on average under diffuse light (computed once
//! per pattern by [`WeavePattern::specular_normalization`]).

use super::{cosine_hemisphere, same_hemisphere, LocalSample};
use crate::spectrum::Rgb;
use glam::{Vec2, Vec3A};
use std::f32::consts::{FRAC_1_PI, PI};

/// One yarn segment of a weave tile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Yarn {
    /// Fibre twist angle (radians); 0 means a filament yarn.
    pub psi: f32,
    /// Maximum inclination angle (radians).
    pub umax: f32,
    /// Spine curvature.
    pub kappa: f32,
    /// Width and length of the segment rectangle (tile units).
    pub width: f32,
    pub length: f32,
    /// Segment centre in the tile ([0, 1]², origin lower left).
    pub center_u: f32,
    pub center_v: f32,
    /// Weft (true) or warp (false): the weft is rotated by π/2.
    pub weft: bool,
}

impl Yarn {
    /// A yarn from LuxRender's preset values (angles in degrees).
    pub fn new(deg: [f32; 2], kappa: f32, size: [f32; 2], center: [f32; 2], weft: bool) -> Yarn {
        Yarn {
            psi: deg[0].to_radians(),
            umax: deg[1].to_radians(),
            kappa,
            width: size[0],
            length: size[1],
            center_u: center[0],
            center_v: center[1],
            weft,
        }
    }
}

/// The scattering parameters shared by all yarns of a pattern.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WeaveParams {
    /// Uniform scattering.
    pub alpha: f32,
    /// Forward scattering (von Mises concentration).
    pub beta: f32,
    /// Filament smoothing.
    pub ss: f32,
    /// Highlight width.
    pub h_width: f32,
    pub warp_area: f32,
    pub weft_area: f32,
}

/// A weave: tile layout, yarns and noise parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct WeavePattern {
    pub params: WeaveParams,
    pub tile_width: u32,
    pub tile_height: u32,
    /// Umax variation (radians) of warp and weft along the warp and weft directions.
    pub d_warp_umax_over_d_warp: f32,
    pub d_warp_umax_over_d_weft: f32,
    pub d_weft_umax_over_d_warp: f32,
    pub d_weft_umax_over_d_weft: f32,
    pub fineness: f32,
    pub period: f32,
    pub repeat_u: f32,
    pub repeat_v: f32,
    /// Yarn index (1-based, as LuxRender lists them) of each tile cell, row by row.
    pub pattern: Vec<u8>,
    pub yarns: Vec<Yarn>,
}

/// The yarn segment under a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct YarnHit {
    pub yarn: Yarn,
    /// Local (u, v) coordinates on the segment.
    pub uv: Vec2,
    pub umax: f32,
    /// Random specular scale (1 without `fineness`).
    pub scale: f32,
}

/// TEA hash of two words (LuxRender/Mitsuba's `sampleTEA`).
fn tea(mut v0: u32, mut v1: u32, rounds: u32) -> u64 {
    let mut sum = 0u32;
    for _ in 0..rounds {
        sum = sum.wrapping_add(0x9e37_79b9);
        v0 = v0.wrapping_add(
            (v1 << 4).wrapping_add(0xA341_316C)
                ^ v1.wrapping_add(sum)
                ^ (v1 >> 5).wrapping_add(0xC801_3EA4),
        );
        v1 = v1.wrapping_add(
            (v0 << 4).wrapping_add(0xAD90_777D)
                ^ v0.wrapping_add(sum)
                ^ (v0 >> 5).wrapping_add(0x7E95_761E),
        );
    }
    ((v1 as u64) << 32) + v0 as u64
}

/// A float in [0, 1) from the TEA hash (the mantissa trick of `sampleTEAfloat`).
fn tea_float(v0: f32, v1: f32) -> f32 {
    // LuxRender converts the float arguments to unsigned words by truncation.
    let bits = (((tea(v0 as u32, v1 as u32, 8) & 0xFFFF_FFFF) >> 9) as u32) | 0x3f80_0000;
    f32::from_bits(bits) - 1.0
}

/// Blender's improved Perlin noise along x (`newPerlin(x, 0, 0)`), with Blender's hash table.
fn perlin(x: f32) -> f32 {
    super::perlin::new_perlin(x, 0.0, 0.0)
}

impl WeavePattern {
    fn cell(&self, lx: u32, ly: u32) -> Option<&Yarn> {
        let i = (lx + self.tile_width * ly) as usize;
        let id = *self.pattern.get(i)? as usize;
        self.yarns.get(id.checked_sub(1)?)
    }

    /// The yarn segment at texture coordinates (u, v).
    pub fn yarn_at(&self, u: f32, v: f32) -> Option<YarnHit> {
        let (tw, th) = (self.tile_width as f32, self.tile_height as f32);
        let (su, sv) = (u * self.repeat_u, v * self.repeat_v);
        if !(su.is_finite() && sv.is_finite()) {
            return None;
        }
        let (bu, bv) = (su.floor(), sv.floor());
        let (ou, ov) = (su - bu, sv - bv);
        let lx = ((ou * tw) as u32).min(self.tile_width - 1);
        let ly = self.tile_height - 1 - ((ov * th) as u32).min(self.tile_height - 1);
        let yarn = *self.cell(lx, ly)?;
        let center = Vec2::new((bu + yarn.center_u) * tw, (bv + yarn.center_v) * th);
        let xy = Vec2::new((ou - yarn.center_u) * tw, (ov - yarn.center_v) * th);
        let mut umax = yarn.umax;
        if self.period > 0.0 {
            let r1 = perlin(
                (center.x * (th * self.repeat_v + tea_float(center.x, 2.0 * center.y)) + center.y)
                    / self.period,
            );
            let r2 = perlin(
                (center.y * (tw * self.repeat_u + tea_float(center.x, 2.0 * center.y + 1.0))
                    + center.x)
                    / self.period,
            );
            umax += if yarn.weft {
                r1 * self.d_weft_umax_over_d_warp + r2 * self.d_weft_umax_over_d_weft
            } else {
                r1 * self.d_warp_umax_over_d_warp + r2 * self.d_warp_umax_over_d_weft
            };
        }
        let uv = if yarn.weft {
            Vec2::new(xy.x * 2.0 * umax / yarn.length, -xy.y * PI / yarn.width)
        } else {
            Vec2::new(xy.y * 2.0 * umax / yarn.length, xy.x * PI / yarn.width)
        };
        let mut scale = 1.0;
        if self.fineness > 0.0 {
            let i1 = (center.x + xy.x) * self.fineness;
            let i2 = (center.y + xy.y) * self.fineness;
            let xi = tea_float(i1, i2);
            scale = (-xi.ln()).min(10.0);
        }
        Some(YarnHit {
            yarn,
            uv,
            umax,
            scale,
        })
    }

    /// The factor that makes the specular part reflect `Ks` on average: the inverse of the
    /// mean of `spec · scale` over cosine-distributed direction pairs and uniform positions
    /// (LuxRender estimates it with 100 000 samples; so does this, deterministically).
    pub fn specular_normalization(&self) -> f32 {
        let mut rng = SplitMix(0x6c07_8965_d5a3_b1e1);
        let n = 100_000u32;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let wi = cosine_hemisphere(Vec2::new(rng.next(), rng.next()));
            let wo = cosine_hemisphere(Vec2::new(rng.next(), rng.next()));
            let (u, v) = (rng.next(), rng.next());
            if let Some(hit) = self.yarn_at(u, v) {
                let lobe = Irawan::new(Rgb::WHITE, &hit, self.params, 1.0);
                sum += (lobe.eval_specular(wo, wi) * hit.scale) as f64;
            }
        }
        if sum > 0.0 && sum.is_finite() {
            (n as f64 / sum) as f32
        } else {
            0.0
        }
    }
}

/// Small deterministic generator for the normalisation estimate.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// The von Mises distribution of concentration `b` at `cos_x`.
fn von_mises(cos_x: f32, b: f32) -> f32 {
    let factor = (b * cos_x).exp() / (2.0 * PI);
    let ab = b.abs();
    if ab <= 3.75 {
        let t0 = ab / 3.75;
        let t = t0 * t0;
        factor
            / (1.0
                + t * (3.515_622_9
                    + t * (3.089_942_4
                        + t * (1.206_749_2
                            + t * (0.265_973_2 + t * (0.036_076_8 + t * 0.004_581_3))))))
    } else {
        let t = 3.75 / ab;
        factor * ab.sqrt()
            / (ab.exp()
                * (0.398_942_3
                    + t * (0.013_285_92
                        + t * (0.002_253_19
                            + t * (-0.001_575_65
                                + t * (0.009_162_81
                                    + t * (-0.020_577_06
                                        + t * (0.026_355_37
                                            + t * (-0.016_476_33 + t * 0.003_923_77)))))))))
    }
}

/// Seeliger's attenuation for a scattering-only layer (albedo 1).
fn seeliger(cos1: f32, cos2: f32) -> f32 {
    let (c1, c2) = (cos1.max(0.0), cos2.max(0.0));
    if c1 == 0.0 || c2 == 0.0 {
        return 0.0;
    }
    0.5 / (2.0 * PI) * c1 * c2 / (c1 + c2)
}

fn smooth_step(x: f32) -> f32 {
    let v = x.clamp(0.0, 1.0);
    v * v * (3.0 - 2.0 * v)
}

/// The specular lobe of one yarn segment.
#[derive(Clone, Copy, Debug)]
pub struct Irawan {
    pub ks: Rgb,
    pub yarn: Yarn,
    pub weave: WeaveParams,
    pub uv: Vec2,
    pub umax: f32,
    /// Normalisation times the segment's random scale.
    pub norm: f32,
}

impl Irawan {
    pub fn new(ks: Rgb, hit: &YarnHit, weave: WeaveParams, norm: f32) -> Irawan {
        Irawan {
            ks,
            yarn: hit.yarn,
            weave,
            uv: hit.uv,
            umax: hit.umax,
            norm,
        }
    }

    /// The specular integrand for the pair (both taken to the upper side).
    pub fn eval_specular(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        let flip = |w: Vec3A| if w.z < 0.0 { -w } else { w };
        let (mut om_i, mut om_r) = (flip(wi), flip(wo));
        let area = if self.yarn.weft {
            // The weft runs across the warp: rotate both directions by π/2 about z.
            om_i = Vec3A::new(-om_i.y, om_i.x, om_i.z);
            om_r = Vec3A::new(-om_r.y, om_r.x, om_r.z);
            self.weave.weft_area
        } else {
            self.weave.warp_area
        };
        if area <= 0.0 {
            return 0.0;
        }
        let v = if self.yarn.psi != 0.0 {
            self.staple(om_i, om_r)
        } else {
            self.filament(om_i, om_r)
        };
        let s = v * (self.weave.warp_area + self.weave.weft_area) / area;
        if s.is_finite() {
            s.max(0.0)
        } else {
            0.0
        }
    }

    fn filament(&self, om_i: Vec3A, om_r: Vec3A) -> f32 {
        let (w, y) = (&self.weave, &self.yarn);
        let (u, v, umax) = (self.uv.x, self.uv.y, self.umax);
        if !(0.0..1.0).contains(&w.ss) || y.width * umax.sin() >= y.length || y.kappa < -1.0 {
            return 0.0;
        }
        let h = (om_r + om_i).normalize_or_zero();
        let u_of_v = h.y.atan2(h.z);
        if u_of_v.abs() >= umax {
            return 0.0;
        }
        let delta_u = umax * w.h_width;
        if (u_of_v - u).abs() >= delta_u {
            return 0.0;
        }
        let n =
            Vec3A::new(v.sin(), u_of_v.sin() * v.cos(), u_of_v.cos() * v.cos()).normalize_or_zero();
        let t = Vec3A::new(0.0, u_of_v.cos(), -u_of_v.sin()).normalize_or_zero();
        let r =
            self.radius_of_curvature(u_of_v.abs().min((1.0 - w.ss) * umax), (1.0 - w.ss) * umax);
        let a = 0.5 * y.width;
        let gu = a * (r + a * v.cos()) / ((om_i + om_r).length() * t.cross(h).x.abs());
        let fc = w.alpha + von_mises(-om_i.dot(om_r), w.beta);
        let mut att = seeliger(n.dot(om_i), n.dot(om_r));
        if w.ss > 0.0 {
            att *= smooth_step((umax - u_of_v.abs()) / (w.ss * umax));
        }
        gu * fc * att * PI / w.h_width
    }

    fn staple(&self, om_i: Vec3A, om_r: Vec3A) -> f32 {
        let (w, y) = (&self.weave, &self.yarn);
        let (u, v, umax) = (self.uv.x, self.uv.y, self.umax);
        if y.width * umax.sin() >= y.length || y.kappa < -1.0 {
            return 0.0;
        }
        let h = (om_i + om_r).normalize_or_zero();
        let (su, cu) = u.sin_cos();
        let d = (h.y * cu - h.z * su)
            / ((h.x * h.x + (h.y * su + h.z * cu).powi(2)).sqrt() * y.psi.tan());
        if d.is_nan() || d.abs() >= 1.0 {
            return 0.0;
        }
        let v_of_u = (-h.y * su - h.z * cu).atan2(h.x) + d.acos();
        let delta_v = 0.5 * PI * w.h_width;
        if (v_of_u - v).abs() >= delta_v {
            return 0.0;
        }
        let n = Vec3A::new(v_of_u.sin(), su * v_of_u.cos(), cu * v_of_u.cos()).normalize_or_zero();
        let r = self.radius_of_curvature(u.abs(), umax);
        let a = 0.5 * y.width;
        let gv =
            a * (r + a * v_of_u.cos()) / ((om_i + om_r).length() * n.dot(h) * y.psi.sin().abs());
        let fc = w.alpha + von_mises(-om_i.dot(om_r), w.beta);
        let att = seeliger(n.dot(om_i), n.dot(om_r));
        gv * fc * att * 2.0 * umax / w.h_width
    }

    /// Radius of curvature of the yarn spine at inclination `u` (an ellipse, parabola or
    /// hyperbola segment depending on kappa; a circle when the shape factor is 1).
    fn radius_of_curvature(&self, u: f32, umax: f32) -> f32 {
        let y = &self.yarn;
        let rhat = 1.0 + y.kappa * (1.0 + 1.0 / umax.tan());
        let a = 0.5 * y.width;
        if rhat == 1.0 {
            0.5 * y.length / umax.sin() - a
        } else if rhat > 0.0 {
            let tmax = (rhat * umax.tan()).atan();
            let bhat = (0.5 * y.length - a * umax.sin()) / tmax.sin();
            let ahat = bhat / rhat;
            let t = (rhat * u.tan()).atan();
            (bhat * bhat * t.cos().powi(2) + ahat * ahat * t.sin().powi(2)).powf(1.5)
                / (ahat * bhat)
        } else if rhat < 0.0 {
            let tmax = -(rhat * umax.tan()).atanh();
            let bhat = (0.5 * y.length - a * umax.sin()) / tmax.sinh();
            let ahat = bhat / rhat;
            let t = -(rhat * u.tan()).atanh();
            -(bhat * bhat * t.cosh().powi(2) + ahat * ahat * t.sinh().powi(2)).powf(1.5)
                / (ahat * bhat)
        } else {
            let tmax = umax.tan();
            let ahat = (0.5 * y.length - a * umax.sin()) / (2.0 * tmax);
            let t = u.tan();
            2.0 * ahat * (1.0 + t * t).powf(1.5)
        }
    }

    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if !same_hemisphere(wo, wi) {
            return Rgb::BLACK;
        }
        self.ks * (self.eval_specular(wo, wi) * self.norm * FRAC_1_PI)
    }
}

/// LuxRender's cloth BSDF: a Lambertian lobe of the yarn's `Kd` plus its Irawan lobe of `Ks`,
/// both cosine sampled (so the pdf is the cosine density).
#[derive(Clone, Copy, Debug)]
pub struct ClothLobes {
    pub kd: Rgb,
    pub spec: Irawan,
}

impl ClothLobes {
    pub fn f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        if !same_hemisphere(wo, wi) {
            return Rgb::BLACK;
        }
        self.kd * FRAC_1_PI + self.spec.f(wo, wi)
    }

    pub fn pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        if same_hemisphere(wo, wi) {
            wi.z.abs() * FRAC_1_PI
        } else {
            0.0
        }
    }

    pub fn sample(&self, wo: Vec3A, u2: Vec2) -> Option<LocalSample> {
        let mut wi = cosine_hemisphere(u2);
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        let pdf = self.pdf(wo, wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(LocalSample {
            wi,
            f: self.f(wo, wi),
            pdf,
            specular: false,
        })
    }
}
