//! Perfectly specular lobes: mirror reflection (with an optional conductor Fresnel), smooth
//! dielectric (glass, architectural glass) and the null pass-through.

use super::fresnel;
use super::{avg, refract, LocalSample};
use crate::spectrum::Rgb;
use glam::Vec3A;

fn mirror_dir(wo: Vec3A) -> Vec3A {
    Vec3A::new(-wo.x, -wo.y, wo.z)
}

/// Mirror reflection scaled by `kr` and, when given, a conductor Fresnel term.
#[derive(Clone, Copy, Debug)]
pub struct SpecularReflection {
    pub kr: Rgb,
    pub conductor: Option<(Rgb, Rgb)>,
}

impl SpecularReflection {
    pub fn sample(&self, wo: Vec3A) -> Option<LocalSample> {
        let wi = mirror_dir(wo);
        let c = wi.z.abs();
        if c == 0.0 {
            return None;
        }
        let fr = match self.conductor {
            Some((n, k)) => fresnel::conductor(c, n, k),
            None => Rgb::WHITE,
        };
        Some(LocalSample {
            wi,
            f: self.kr * fr / c,
            pdf: 1.0,
            specular: true,
        })
    }
}

/// Smooth dielectric boundary of index `eta` (outside 1); `architectural` lets light through
/// without bending (thin sheet).
#[derive(Clone, Copy, Debug)]
pub struct SpecularDielectric {
    pub kr: Rgb,
    pub kt: Rgb,
    pub eta: f32,
    pub architectural: bool,
}

impl SpecularDielectric {
    pub fn sample(&self, wo: Vec3A, u: f32) -> Option<LocalSample> {
        let cos_o = wo.z;
        if cos_o == 0.0 {
            return None;
        }
        let entering = cos_o > 0.0;
        let (eta_i, eta_t) = if entering || self.architectural {
            (1.0, self.eta)
        } else {
            (self.eta, 1.0)
        };
        let fr = fresnel::dielectric(cos_o.abs(), eta_i, eta_t);
        let wr = fr * avg(self.kr);
        let wt = (1.0 - fr) * avg(self.kt);
        if wr + wt <= 0.0 {
            return None;
        }
        let p_reflect = wr / (wr + wt);
        if u < p_reflect {
            let wi = mirror_dir(wo);
            return Some(LocalSample {
                wi,
                f: self.kr * (fr / wi.z.abs()),
                pdf: p_reflect,
                specular: true,
            });
        }
        let (wi, scale) = if self.architectural {
            (-wo, 1.0)
        } else {
            let n = if entering { Vec3A::Z } else { -Vec3A::Z };
            let wi = refract(wo, n, eta_i / eta_t)?;
            // Radiance is compressed entering a denser medium (non-symmetric scattering).
            let r = eta_i / eta_t;
            (wi, r * r)
        };
        let c = wi.z.abs();
        if c == 0.0 {
            return None;
        }
        Some(LocalSample {
            wi,
            f: self.kt * ((1.0 - fr) * scale / c),
            pdf: 1.0 - p_reflect,
            specular: true,
        })
    }
}

/// The null material: light continues unchanged.
pub fn pass_through(wo: Vec3A) -> Option<LocalSample> {
    let c = wo.z.abs();
    if c == 0.0 {
        return None;
    }
    Some(LocalSample {
        wi: -wo,
        f: Rgb::splat(1.0 / c),
        pdf: 1.0,
        specular: true,
    })
}
