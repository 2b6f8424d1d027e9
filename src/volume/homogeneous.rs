//! `homogeneous`: a medium of constant absorption `sigma_a` and scattering `sigma_s` (colour,
//! per metre, default 0) with a Henyey–Greenstein phase function of asymmetry `g` (LuxRender
//! takes a colour; its three values are averaged into one lobe here), and the common `fresnel`
//! index (default 1, read by glass2 through the material set).
//!
//! Distances are sampled per colour channel (one channel picked uniformly, the density being the
//! average over the channels), so the weights stay bounded when the channels differ.

use super::{channel_avg, read_common, transmittance, HenyeyGreenstein, MediumSample, VolumeError};
use crate::geometry::Ray;
use crate::plugin::Stmt;
use crate::spectrum::Rgb;
use crate::texture::TextureSet;

#[derive(Clone, Debug, PartialEq)]
pub struct Homogeneous {
    pub sigma_a: Rgb,
    pub sigma_s: Rgb,
    pub g: f32,
}

impl Homogeneous {
    pub fn build(s: &mut Stmt, textures: &mut TextureSet) -> Result<Homogeneous, VolumeError> {
        let c = read_common(s, textures)?;
        Ok(Homogeneous {
            sigma_a: c.sigma_a,
            sigma_s: c.sigma_s,
            g: c.g,
        })
    }

    /// The extinction coefficient sigma_a + sigma_s (the same everywhere).
    pub fn sigma_t(&self) -> Rgb {
        self.sigma_a + self.sigma_s
    }

    /// Transmittance over the ray's parametric extent [0, `t_max`].
    pub fn tr(&self, ray: &Ray, t_max: f32) -> Rgb {
        transmittance(self.sigma_t(), t_max * ray.d.length())
    }

    /// Samples where along [0, `t_max`] the ray scatters (or that it passes); see
    /// [`MediumSample`].
    pub fn sample(&self, ray: &Ray, t_max: f32, u: f32, u_channel: f32) -> MediumSample {
        let len = ray.d.length();
        let dist_max = t_max * len;
        let st = self.sigma_t();
        let ch = ((u_channel * 3.0) as usize).min(2);
        let s = st.to_array()[ch];
        let d = if s > 0.0 {
            -(1.0 - u).max(f32::MIN_POSITIVE).ln() / s
        } else {
            f32::INFINITY
        };
        if d < dist_max && len > 0.0 {
            let tr = transmittance(st, d);
            let pdf = channel_avg(st * tr);
            let weight = if pdf > 0.0 {
                self.sigma_s * tr / pdf
            } else {
                Rgb::BLACK
            };
            return MediumSample {
                scatter_t: Some(d / len),
                weight,
                phase: HenyeyGreenstein::new(self.g),
            };
        }
        let tr = transmittance(st, dist_max);
        let pdf = channel_avg(tr);
        MediumSample {
            scatter_t: None,
            weight: if pdf > 0.0 { tr / pdf } else { Rgb::BLACK },
            phase: HenyeyGreenstein::new(self.g),
        }
    }
}
