//! Perfectly specular lobes: mirror reflection (with an optional [`FresnelGeneral`] term and
//! thin film), smooth dielectric (glass, glass2, architectural glass) and the null
//! pass-through.
//!
//! Glass follows LuxRender's two components: reflection `Kr F` (times the thin-film factor)
//! and transmission `Kt (1 - F)`, radiance scaled by `(eta_i / eta_t)²` when it bends.
//! Architectural glass reflects on its front side only; light entering it passes straight
//! through both faces of the sheet with `1 - F (1 + (1 - F)²)` and light leaving it (the back
//! side) passes unchanged, as LuxRender's `ArchitecturalReflection`/`SpecularTransmission`.
//! A lobe is picked with probability proportional to its average weight.

use super::fresnel::{self, FresnelGeneral};
use super::thin_film::ThinFilm;
use super::{avg, refract, LocalSample};
use crate::spectrum::Rgb;
use glam::Vec3A;

fn mirror_dir(wo: Vec3A) -> Vec3A {
    Vec3A::new(-wo.x, -wo.y, wo.z)
}

/// Mirror reflection scaled by `kr`, a Fresnel term when given and a thin film when given.
#[derive(Clone, Copy, Debug)]
pub struct SpecularReflection {
    pub kr: Rgb,
    pub fresnel: Option<FresnelGeneral>,
    pub film: Option<ThinFilm>,
}

impl SpecularReflection {
    /// The reflectance toward the mirror direction of `wo`.
    pub fn reflectance(&self, wo: Vec3A) -> Rgb {
        let mut r = self.kr;
        if let Some(f) = &self.fresnel {
            r *= f.eval(wo.z);
        }
        if let Some(film) = &self.film {
            r *= film.factor(wo.z.abs());
        }
        r
    }

    pub fn sample(&self, wo: Vec3A) -> Option<LocalSample> {
        let wi = mirror_dir(wo);
        let c = wi.z.abs();
        if c == 0.0 {
            return None;
        }
        Some(LocalSample {
            wi,
            f: self.reflectance(wo) / c,
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
    pub film: Option<ThinFilm>,
}

impl SpecularDielectric {
    /// (reflection, transmission) weights before `Kr`/`Kt` for `cos_o` (signed).
    fn split(&self, cos_o: f32) -> (f32, f32) {
        let entering = cos_o > 0.0;
        if self.architectural {
            if !entering {
                return (0.0, 1.0);
            }
            let f = fresnel::dielectric(cos_o, 1.0, self.eta);
            return (f, 1.0 - f * (1.0 + (1.0 - f) * (1.0 - f)));
        }
        let (eta_i, eta_t) = if entering {
            (1.0, self.eta)
        } else {
            (self.eta, 1.0)
        };
        let f = fresnel::dielectric(cos_o.abs(), eta_i, eta_t);
        (f, 1.0 - f)
    }

    pub fn sample(&self, wo: Vec3A, u: f32) -> Option<LocalSample> {
        let cos_o = wo.z;
        if cos_o == 0.0 {
            return None;
        }
        let (fr, ft) = self.split(cos_o);
        let kr = match &self.film {
            Some(film) => self.kr * film.factor(cos_o.abs()),
            None => self.kr,
        };
        let wr = fr * avg(kr);
        let wt = ft * avg(self.kt);
        let total = wr + wt;
        if total.is_nan() || total <= 0.0 {
            return None;
        }
        let p_reflect = wr / total;
        if u < p_reflect {
            let wi = mirror_dir(wo);
            return Some(LocalSample {
                wi,
                f: kr * (fr / wi.z.abs()),
                pdf: p_reflect,
                specular: true,
            });
        }
        let (wi, scale) = if self.architectural {
            (-wo, 1.0)
        } else {
            let entering = cos_o > 0.0;
            let (eta_i, eta_t) = if entering {
                (1.0, self.eta)
            } else {
                (self.eta, 1.0)
            };
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
            f: self.kt * (ft * scale / c),
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
