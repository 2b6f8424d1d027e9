//! Fresnel textures: optical constants (LuxRender's `FresnelGeneral`) for metal2 and the
//! volumes' `fresnel`. The renderer is RGB: a [`Fresnel`] holds the real index `n` and the
//! extinction `k` per channel (a dielectric has k = 0). Spectral sources (n/k tables, Cauchy's
//! and Sellmeier's laws) are converted once at build time, and kept as [`FresnelData`] for
//! spectral rendering: an absorbing table to the (n, k) per channel that reflect what the
//! table reflects ([`crate::spectrum::nk_rgb`]), a dielectric's n by averaging over the red
//! (580–700 nm), green (490–580 nm) and blue (400–490 nm) bands.
//!
//! ```text
//! FresnelTex --eval(hit)--> Fresnel { n: Rgb, k: Rgb }   (constant, data, fresnelcolor, and
//!                                                         mix/scale/band/bilerp/multimix of them)
//! ```

use super::{band, bilerp, fresnelcolor, mix, multimix, scale};
use super::{param_loc, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::nk::{band_averages, NkTable, BANDS};
use crate::spectrum::Rgb;
use std::sync::Arc;

/// Complex index of refraction per RGB channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fresnel {
    pub n: Rgb,
    pub k: Rgb,
}

impl Fresnel {
    /// A dielectric of index `index` (LuxRender's constant fresnel texture).
    pub const fn dielectric(index: f32) -> Fresnel {
        Fresnel {
            n: Rgb::splat(index),
            k: Rgb::splat(0.0),
        }
    }

    /// Linear interpolation of n and k (LuxRender's blend of two `FresnelGeneral`).
    pub fn lerp(t: f32, a: Fresnel, b: Fresnel) -> Fresnel {
        Fresnel {
            n: a.n * (1.0 - t) + b.n * t,
            k: a.k * (1.0 - t) + b.k * t,
        }
    }

    /// n and k scaled by `s`.
    pub fn scaled(self, s: f32) -> Fresnel {
        Fresnel {
            n: self.n * s,
            k: self.k * s,
        }
    }

    pub fn plus(self, o: Fresnel) -> Fresnel {
        Fresnel {
            n: self.n + o.n,
            k: self.k + o.k,
        }
    }

    /// The mean index (LuxRender's float reading of a fresnel texture).
    pub fn index(&self) -> f32 {
        self.n.average()
    }

    /// Whether the material absorbs (a conductor in LuxRender's terms).
    pub fn is_conductor(&self) -> bool {
        self.k.max_component() > 0.0
    }

    /// Approximate optical constants reflecting colour `r` at normal incidence (LuxRender's
    /// `FresnelApproxEta`/`FresnelApproxK`, reflectance clamped to [0, 0.999]).
    pub fn from_reflectance(r: Rgb) -> Fresnel {
        let r = r.map(|c| c.clamp(0.0, 0.999));
        Fresnel {
            n: r.map(|c| (1.0 + c.sqrt()) / (1.0 - c.sqrt())),
            k: r.map(|c| 2.0 * (c / (1.0 - c)).sqrt()),
        }
    }
}

/// Spectral optical data, kept beside its RGB reading.
#[derive(Clone, Debug, PartialEq)]
pub enum FresnelData {
    /// Tabulated n and k (presets, SOPRA and luxpop files).
    Table(NkTable),
    /// Cauchy's law n(λ) = a + b/λ² with λ in µm (k = 0).
    Cauchy { a: f32, b: f32 },
    /// Sellmeier's law n² = A + Σ Bᵢλ²/(λ² − Cᵢ) with λ and √Cᵢ in µm (k = 0).
    Sellmeier { a: f32, b: Vec<f32>, c: Vec<f32> },
}

impl FresnelData {
    /// (n, k) at wavelength `nm`.
    pub fn at(&self, nm: f32) -> (f32, f32) {
        match self {
            FresnelData::Table(t) => t.at(nm),
            FresnelData::Cauchy { a, b } => (a + b * 1e6 / (nm * nm), 0.0),
            FresnelData::Sellmeier { a, b, c } => {
                let w2 = nm * nm;
                let n2 = b
                    .iter()
                    .zip(c)
                    .fold(*a, |acc, (bi, ci)| acc + bi * w2 / (w2 - ci * 1e6));
                (n2.max(0.0).sqrt(), 0.0)
            }
        }
    }

    /// The RGB reading: a table's as [`NkTable::to_rgb`] reads it (fitted to its reflectance
    /// for a metal), band averages of n for the laws (1 nm steps).
    pub fn to_rgb(&self) -> Fresnel {
        if let FresnelData::Table(t) = self {
            let (n, k) = t.to_rgb();
            return Fresnel {
                n: Rgb::from_array(n),
                k: Rgb::from_array(k),
            };
        }
        let (n, k) = band_averages(|nm| self.at(nm));
        Fresnel {
            n: Rgb::from_array(n),
            k: Rgb::from_array(k),
        }
    }

    /// LuxRender's mean index of the data over 380–720 nm (what it reports as the texture's
    /// float value).
    pub fn mean_index(&self) -> f32 {
        let s: f64 = (380..720).map(|nm| self.at(nm as f32).0 as f64).sum();
        (s / 340.0) as f32
    }
}

/// Largest n/k data file read (bytes).
pub const MAX_NK_FILE_BYTES: u64 = 16 << 20;

/// The text of the file named by parameter `param` of `t` (relative to the scene directory),
/// with its path for messages.
pub(crate) fn read_data_file(
    set: &TextureSet,
    t: &TextureDesc,
    param: &str,
) -> Result<(String, String), TextureError> {
    let p = &t.entity.params;
    let loc = param_loc(p, param, &t.entity.loc);
    let name = p.string_or(param, "").to_string();
    let shown = name.clone();
    let err = |message: String| TextureError::Image {
        loc: loc.clone(),
        path: shown.clone(),
        message,
    };
    if name.is_empty() {
        return Err(TextureError::BadParam {
            loc,
            message: format!("{} needs a \"string {param}\"", t.entity.kind),
        });
    }
    let text = super::read_bounded(&set.ctx.files, &name, MAX_NK_FILE_BYTES).map_err(err)?;
    Ok((text, shown))
}

/// One node of a fresnel texture tree.
#[derive(Debug)]
pub enum FresnelNode {
    Const(Fresnel),
    /// Spectral data and its RGB reading.
    Data {
        data: Arc<FresnelData>,
        rgb: Fresnel,
    },
    Color(fresnelcolor::FresnelColorTex),
    Mix(mix::MixFresnel),
    Scale(scale::ScaleFresnel),
    Band(band::BandFresnel),
    Bilerp(bilerp::BilerpFresnel),
    MultiMix(multimix::MultiMixFresnel),
}

impl FresnelNode {
    /// A node of spectral data.
    pub fn data(data: FresnelData) -> FresnelNode {
        FresnelNode::Data {
            rgb: data.to_rgb(),
            data: Arc::new(data),
        }
    }

    pub fn eval(&self, si: &SurfaceInteraction) -> Fresnel {
        match self {
            FresnelNode::Const(f) => *f,
            FresnelNode::Data { rgb, .. } => *rgb,
            FresnelNode::Color(t) => t.eval(si),
            FresnelNode::Mix(t) => t.eval(si),
            FresnelNode::Scale(t) => t.eval(si),
            FresnelNode::Band(t) => t.eval(si),
            FresnelNode::Bilerp(t) => t.eval(si),
            FresnelNode::MultiMix(t) => t.eval(si),
        }
    }

    /// The real index at wavelength `nm` at a hit, for spectral rendering: spectral data at
    /// λ; an RGB value (a constant, fresnelcolor) its channel whose band holds λ; the
    /// combinations combine their operands' indices at λ as their RGB values are combined.
    pub fn index_at(&self, si: &SurfaceInteraction, nm: f32) -> f32 {
        match self {
            FresnelNode::Const(f) => channel_at(f.n, nm),
            FresnelNode::Data { data, .. } => data.at(nm).0,
            FresnelNode::Color(t) => channel_at(t.eval(si).n, nm),
            FresnelNode::Mix(t) => t.index_at(si, nm),
            FresnelNode::Scale(t) => t.index_at(si, nm),
            FresnelNode::Band(t) => t.index_at(si, nm),
            FresnelNode::Bilerp(t) => t.index_at(si, nm),
            FresnelNode::MultiMix(t) => t.index_at(si, nm),
        }
    }

    /// Whether the index may depend on the wavelength: spectral data other than Cauchy's law
    /// with b = 0, an RGB value whose channels differ, or a combination of such.
    pub fn disperses(&self) -> bool {
        let any = |v: &[Arc<FresnelNode>]| v.iter().any(|t| t.disperses());
        match self {
            FresnelNode::Const(f) => f.n.r != f.n.g || f.n.g != f.n.b,
            FresnelNode::Data { data, .. } => {
                !matches!(**data, FresnelData::Cauchy { b, .. } if b == 0.0)
            }
            FresnelNode::Color(_) => true,
            FresnelNode::Mix(t) => t.tex1.disperses() || t.tex2.disperses(),
            FresnelNode::Scale(t) => t.f.disperses(),
            FresnelNode::Band(t) => any(&t.tex),
            FresnelNode::Bilerp(t) => any(&t.v),
            FresnelNode::MultiMix(t) => any(&t.tex),
        }
    }
}

/// The channel of `c` whose band (see `BANDS`) holds wavelength `nm`; below the blue band
/// blue, above the red band red.
fn channel_at(c: Rgb, nm: f32) -> f32 {
    if nm < BANDS[1].0 as f32 {
        c.b
    } else if nm < BANDS[0].0 as f32 {
        c.g
    } else {
        c.r
    }
}

/// A fresnel-valued texture.
#[derive(Clone, Debug)]
pub struct FresnelTex(pub Arc<FresnelNode>);

impl FresnelTex {
    pub fn constant(f: Fresnel) -> FresnelTex {
        FresnelTex(Arc::new(FresnelNode::Const(f)))
    }

    #[inline]
    pub fn eval(&self, si: &SurfaceInteraction) -> Fresnel {
        self.0.eval(si)
    }

    /// The value when it does not vary over the surface.
    pub fn as_const(&self) -> Option<Fresnel> {
        match &*self.0 {
            FresnelNode::Const(f) => Some(*f),
            FresnelNode::Data { rgb, .. } => Some(*rgb),
            _ => None,
        }
    }

    /// The spectral data behind the texture, when it is one data set.
    pub fn data(&self) -> Option<&FresnelData> {
        match &*self.0 {
            FresnelNode::Data { data, .. } => Some(data),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflectance_approximation_inverts_the_normal_incidence_fresnel() {
        // For a dielectric (k ignored) R0 = ((n-1)/(n+1))²: n from R must give R back.
        let f = Fresnel::from_reflectance(Rgb::new(0.04, 0.5, 0.9));
        let n = f.n.r;
        assert!((n - 1.5).abs() < 1e-3, "{n}");
        // Hand values for R = 0.5: n = (1+√.5)/(1−√.5) = 5.8284, k = 2√(0.5/0.5) = 2.
        assert!((f.n.g - 5.828_427).abs() < 1e-3);
        assert!((f.k.g - 2.0).abs() < 1e-5);
        assert!(Fresnel::from_reflectance(Rgb::WHITE).n.is_finite());
    }

    #[test]
    fn cauchy_and_sellmeier_laws() {
        // Cauchy: a = 1.5, b = 0.00420 µm²: at 500 nm, 1.5 + 0.0042/0.25 = 1.5168.
        let c = FresnelData::Cauchy { a: 1.5, b: 0.0042 };
        assert!((c.at(500.0).0 - 1.5168).abs() < 1e-5);
        // BK7's Sellmeier coefficients give n(587.6 nm) = 1.5168.
        let s = FresnelData::Sellmeier {
            a: 1.0,
            b: vec![1.039_612, 0.231_792_3, 1.010_469_5],
            c: vec![0.006_000_699, 0.020_017_914, 103.560_65],
        };
        assert!((s.at(587.6).0 - 1.5168).abs() < 2e-4, "{}", s.at(587.6).0);
        // Dispersion: blue bends more than red.
        let rgb = s.to_rgb();
        assert!(rgb.n.b > rgb.n.g && rgb.n.g > rgb.n.r, "{rgb:?}");
        assert!((s.mean_index() - 1.52).abs() < 0.01);
    }

    #[test]
    fn blends() {
        let a = Fresnel::dielectric(1.0);
        let b = Fresnel {
            n: Rgb::splat(2.0),
            k: Rgb::splat(4.0),
        };
        let m = Fresnel::lerp(0.25, a, b);
        assert_eq!(m.n, Rgb::splat(1.25));
        assert_eq!(m.k, Rgb::splat(1.0));
        assert!(m.is_conductor() && !a.is_conductor());
        assert_eq!(b.scaled(0.5).n, Rgb::splat(1.0));
        assert_eq!(a.plus(b).k, Rgb::splat(4.0));
    }
}
