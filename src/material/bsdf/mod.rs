//! `Bsdf`: a material's scattering at one hit, in world space. Directions are converted to the
//! shading frame (`SurfaceInteraction.shading`: normal and a tangent from `dpdu`), and the
//! geometric normal decides reflection against transmission so that shading normals never let
//! light leak through a surface: a lobe contributes only when the local and geometric sides
//! agree.
//!
//! Materials made of other materials (glossycoating, doubleside, layered) hold the `Bsdf`s of
//! their components in a boxed [`Composite`], which works in world space with its own side
//! rules; only those materials allocate.
//!
//! `f` and `pdf` are defined for any pair of directions (not only sampled ones), so that
//! reverse densities are available to bidirectional methods: `pdf(wi, wo)` is the density of
//! sampling `wo` from `wi`.

pub mod composite;

use crate::geometry::{unit_or, SurfaceInteraction};
use crate::material::bxdf::asperity::Asperity;
use crate::material::bxdf::carpaint::CarPaintLobes;
use crate::material::bxdf::diffuse::Diffuse;
use crate::material::bxdf::fresnel_blend::FresnelBlend;
use crate::material::bxdf::glossy_translucent::GlossyTranslucentLobes;
use crate::material::bxdf::irawan::ClothLobes;
use crate::material::bxdf::microfacet::MicrofacetReflection;
use crate::material::bxdf::rough_dielectric::RoughDielectric;
use crate::material::bxdf::scatter::SchlickScatter;
use crate::material::bxdf::schlick::{Coating, SchlickBrdf};
use crate::material::bxdf::specular::{pass_through, SpecularDielectric, SpecularReflection};
use crate::material::bxdf::translucent::Translucent;
use crate::material::bxdf::LocalSample;
use crate::spectrum::Rgb;
use composite::Composite;
use glam::{Vec2, Vec3A};

/// A sampled direction in world space. `f` has no cosine; for specular samples `pdf` is the
/// lobe's discrete probability and `f` already holds the 1/|cos| of a delta lobe.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    pub wi: Vec3A,
    pub f: Rgb,
    pub pdf: f32,
    pub specular: bool,
}

/// Orthonormal shading frame.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    pub s: Vec3A,
    pub t: Vec3A,
    pub n: Vec3A,
}

impl Frame {
    /// From a normal and a (not necessarily orthogonal) tangent.
    pub fn new(n: Vec3A, dpdu: Vec3A) -> Frame {
        let n = unit_or(n, Vec3A::Z);
        let mut s = (dpdu - n * n.dot(dpdu)).normalize_or_zero();
        if s == Vec3A::ZERO {
            s = n.any_orthonormal_vector();
        }
        let t = n.cross(s);
        Frame { s, t, n }
    }

    pub fn to_local(&self, v: Vec3A) -> Vec3A {
        Vec3A::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    pub fn to_world(&self, v: Vec3A) -> Vec3A {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

/// The scattering model of a hit (closed set: enum dispatch).
#[derive(Clone, Debug)]
pub enum Lobes {
    /// Absorbs everything.
    Black,
    Diffuse(Diffuse),
    /// Diffuse reflection and transmission.
    Translucent(Translucent),
    /// Velvet (asperity scattering).
    Velvet(Asperity),
    /// Car paint: microfacet layers over a diffuse base.
    CarPaint(CarPaintLobes),
    /// Double-sided coating with diffuse transmission.
    GlossyTranslucent(GlossyTranslucentLobes),
    /// Glossy: Schlick coating over a diffuse base.
    Coating(Coating),
    /// Glossy with `separable` false.
    SchlickBrdf(SchlickBrdf),
    /// glossy_lossy (and the legacy plastic, substrate).
    FresnelBlend(FresnelBlend),
    Microfacet(MicrofacetReflection),
    /// Shinymetal: glossy conductor plus a mirror term, each picked with probability
    /// proportional to its weight.
    GlossyMirror {
        glossy: MicrofacetReflection,
        mirror: SpecularReflection,
        p_mirror: f32,
    },
    Mirror(SpecularReflection),
    Dielectric(SpecularDielectric),
    RoughDielectric(RoughDielectric),
    /// Scatter: a volume-like phase function on the surface.
    Scatter(SchlickScatter),
    /// Cloth: Lambertian plus the Irawan yarn lobe.
    Cloth(ClothLobes),
    /// Materials built from other materials' BSDFs.
    Composite(Box<Composite>),
    Null,
}

#[derive(Clone, Debug)]
pub struct Bsdf {
    pub frame: Frame,
    /// Geometric normal.
    pub ng: Vec3A,
    pub lobes: Lobes,
}

impl Bsdf {
    /// Raises the index of refraction of its dielectric lobes by `delta` (dispersion: the
    /// index at the path's wavelength); other lobes are unchanged.
    pub fn disperse(&mut self, delta: f32) {
        match &mut self.lobes {
            Lobes::Dielectric(d) if !d.architectural => d.eta = (d.eta + delta).max(1e-3),
            Lobes::RoughDielectric(r) => r.eta = (r.eta + delta).max(1e-3),
            _ => {}
        }
    }

    /// A BSDF in the shading frame of `si`.
    #[inline(always)]
    pub fn new(si: &SurfaceInteraction, lobes: Lobes) -> Bsdf {
        let n = if si.shading.n == Vec3A::ZERO {
            si.it.n
        } else {
            si.shading.n
        };
        let dpdu = if si.shading.dpdu == Vec3A::ZERO {
            si.dpdu
        } else {
            si.shading.dpdu
        };
        Bsdf {
            frame: Frame::new(n, dpdu),
            ng: unit_or(si.it.n, n),
            lobes,
        }
    }

    /// Whether some lobe is not a delta distribution (light sampling is worthwhile).
    pub fn has_non_specular(&self) -> bool {
        match &self.lobes {
            Lobes::Black | Lobes::Mirror(_) | Lobes::Dielectric(_) | Lobes::Null => false,
            Lobes::Composite(c) => c.has_non_specular(),
            _ => true,
        }
    }

    /// Whether sampling may pick a delta lobe (a mirror, a smooth dielectric, a pass-through),
    /// which light sampling cannot reach. Conservative: a composite answers true.
    pub fn may_be_specular(&self) -> bool {
        matches!(
            &self.lobes,
            Lobes::GlossyMirror { .. }
                | Lobes::Mirror(_)
                | Lobes::Dielectric(_)
                | Lobes::Composite(_)
                | Lobes::Null
        )
    }

    /// Which of [`Self::sample_f`]'s samples its lobes read: the 1D lobe choice `u` and the
    /// 2D direction `u2` (a diffuse lobe reads only `u2`, a smooth dielectric only `u`, a
    /// mirror neither). An integrator draws only those; the others are not evaluated.
    pub fn sample_uses(&self) -> (bool, bool) {
        match &self.lobes {
            Lobes::Black | Lobes::Mirror(_) | Lobes::Null => (false, false),
            Lobes::Diffuse(_)
            | Lobes::Velvet(_)
            | Lobes::Microfacet(_)
            | Lobes::Scatter(_)
            | Lobes::Cloth(_) => (false, true),
            Lobes::Dielectric(_) => (true, false),
            Lobes::Translucent(_)
            | Lobes::CarPaint(_)
            | Lobes::GlossyTranslucent(_)
            | Lobes::Coating(_)
            | Lobes::SchlickBrdf(_)
            | Lobes::FresnelBlend(_)
            | Lobes::GlossyMirror { .. }
            | Lobes::RoughDielectric(_)
            | Lobes::Composite(_) => (true, true),
        }
    }

    /// True when local and geometric sides agree on reflection vs transmission.
    fn consistent(&self, wo_w: Vec3A, wi_w: Vec3A, wo: Vec3A, wi: Vec3A) -> bool {
        let geo_reflect = wo_w.dot(self.ng) * wi_w.dot(self.ng) > 0.0;
        let loc_reflect = wo.z * wi.z > 0.0;
        geo_reflect == loc_reflect
    }

    /// BSDF value for the pair (no cosine), zero for delta lobes.
    pub fn f(&self, wo_w: Vec3A, wi_w: Vec3A) -> Rgb {
        if let Lobes::Composite(c) = &self.lobes {
            return finite_or_black(c.f(self, wo_w, wi_w));
        }
        let (wo, wi) = (self.frame.to_local(wo_w), self.frame.to_local(wi_w));
        if wo.z == 0.0 || !self.consistent(wo_w, wi_w, wo, wi) {
            return Rgb::BLACK;
        }
        self.local_f(wo, wi)
    }

    /// The lobes' value for local directions on consistent sides (black if not finite).
    fn local_f(&self, wo: Vec3A, wi: Vec3A) -> Rgb {
        let v = match &self.lobes {
            Lobes::Diffuse(d) => d.f(wo, wi),
            Lobes::Translucent(t) => t.f(wo, wi),
            Lobes::Velvet(v) => v.f(wo, wi),
            Lobes::CarPaint(c) => c.f(wo, wi),
            Lobes::GlossyTranslucent(g) => g.f(wo, wi),
            Lobes::Coating(c) => c.f(wo, wi),
            Lobes::SchlickBrdf(s) => s.f(wo, wi),
            Lobes::FresnelBlend(b) => b.f(wo, wi),
            Lobes::Microfacet(m) => m.f(wo, wi),
            Lobes::GlossyMirror { glossy, .. } => glossy.f(wo, wi),
            Lobes::RoughDielectric(r) => r.f(wo, wi),
            Lobes::Scatter(s) => s.f(wo, wi),
            Lobes::Cloth(c) => c.f(wo, wi),
            Lobes::Black
            | Lobes::Mirror(_)
            | Lobes::Dielectric(_)
            | Lobes::Composite(_)
            | Lobes::Null => Rgb::BLACK,
        };
        finite_or_black(v)
    }

    /// Density of [`Bsdf::sample_f`] producing `wi` (solid angle), zero for delta lobes.
    pub fn pdf(&self, wo_w: Vec3A, wi_w: Vec3A) -> f32 {
        if let Lobes::Composite(c) = &self.lobes {
            return finite_or_zero(c.pdf(self, wo_w, wi_w));
        }
        let (wo, wi) = (self.frame.to_local(wo_w), self.frame.to_local(wi_w));
        if wo.z == 0.0 || !self.consistent(wo_w, wi_w, wo, wi) {
            return 0.0;
        }
        self.local_pdf(wo, wi)
    }

    /// [`Self::f`] and [`Self::pdf`] together (one change of frame, one side test).
    pub fn f_pdf(&self, wo_w: Vec3A, wi_w: Vec3A) -> (Rgb, f32) {
        if let Lobes::Composite(c) = &self.lobes {
            return (
                finite_or_black(c.f(self, wo_w, wi_w)),
                finite_or_zero(c.pdf(self, wo_w, wi_w)),
            );
        }
        let (wo, wi) = (self.frame.to_local(wo_w), self.frame.to_local(wi_w));
        if wo.z == 0.0 || !self.consistent(wo_w, wi_w, wo, wi) {
            return (Rgb::BLACK, 0.0);
        }
        (self.local_f(wo, wi), self.local_pdf(wo, wi))
    }

    /// The lobes' density for local directions on consistent sides.
    fn local_pdf(&self, wo: Vec3A, wi: Vec3A) -> f32 {
        let p = match &self.lobes {
            Lobes::Diffuse(d) => d.pdf(wo, wi),
            Lobes::Translucent(t) => t.pdf(wo, wi),
            Lobes::Velvet(v) => v.pdf(wo, wi),
            Lobes::CarPaint(c) => c.pdf(wo, wi),
            Lobes::GlossyTranslucent(g) => g.pdf(wo, wi),
            Lobes::Coating(c) => c.pdf(wo, wi),
            Lobes::SchlickBrdf(s) => s.pdf(wo, wi),
            Lobes::FresnelBlend(b) => b.pdf(wo, wi),
            Lobes::Microfacet(m) => m.pdf(wo, wi),
            Lobes::GlossyMirror {
                glossy, p_mirror, ..
            } => (1.0 - p_mirror) * glossy.pdf(wo, wi),
            Lobes::RoughDielectric(r) => r.pdf(wo, wi),
            Lobes::Scatter(s) => s.pdf(wo, wi),
            Lobes::Cloth(c) => c.pdf(wo, wi),
            Lobes::Black
            | Lobes::Mirror(_)
            | Lobes::Dielectric(_)
            | Lobes::Composite(_)
            | Lobes::Null => 0.0,
        };
        finite_or_zero(p)
    }

    /// Light subpaths carry importance, for which refraction does not compress radiance: a
    /// value of [`Self::sample_f`] (or [`Self::f`]) for the pair (`wo`, `wi`) crossing a
    /// refracting boundary is multiplied by `(η_wi / η_wo)²` (the indices on each side) to
    /// give the adjoint BSDF's. 1 for reflection and for lobes that do not bend light.
    pub fn adjoint_scale(&self, wo_w: Vec3A, wi_w: Vec3A) -> f32 {
        let eta = match &self.lobes {
            Lobes::Dielectric(d) if !d.architectural => d.eta,
            Lobes::RoughDielectric(r) => r.eta,
            _ => return 1.0,
        };
        let (zo, zi) = (self.frame.n.dot(wo_w), self.frame.n.dot(wi_w));
        if zo * zi >= 0.0 || !(eta > 0.0 && eta.is_finite()) {
            return 1.0;
        }
        let (eta_o, eta_i) = if zo > 0.0 { (1.0, eta) } else { (eta, 1.0) };
        let r = eta_i / eta_o;
        r * r
    }

    /// Samples an incident direction. `u` picks a lobe, `u2` the direction within it.
    pub fn sample_f(&self, wo_w: Vec3A, u: f32, u2: Vec2) -> Option<BsdfSample> {
        if let Lobes::Composite(c) = &self.lobes {
            let s = c.sample_f(self, wo_w, u, u2)?;
            return (s.pdf > 0.0 && s.pdf.is_finite() && s.f.is_finite()).then_some(s);
        }
        let wo = self.frame.to_local(wo_w);
        if wo.z == 0.0 {
            return None;
        }
        let s: LocalSample = match &self.lobes {
            Lobes::Black => return None,
            Lobes::Diffuse(d) => d.sample(wo, u2)?,
            Lobes::Translucent(t) => t.sample(wo, u, u2)?,
            Lobes::Velvet(v) => v.sample(wo, u2)?,
            Lobes::CarPaint(c) => c.sample(wo, u, u2)?,
            Lobes::GlossyTranslucent(g) => g.sample(wo, u, u2)?,
            Lobes::Coating(c) => c.sample(wo, u, u2)?,
            Lobes::SchlickBrdf(s) => s.sample(wo, u, u2)?,
            Lobes::FresnelBlend(b) => b.sample(wo, u, u2)?,
            Lobes::Microfacet(m) => m.sample(wo, u2)?,
            Lobes::GlossyMirror {
                glossy,
                mirror,
                p_mirror,
            } => {
                if u < *p_mirror {
                    let mut s = mirror.sample(wo)?;
                    s.pdf *= p_mirror;
                    s
                } else {
                    let mut s = glossy.sample(wo, u2)?;
                    s.pdf *= 1.0 - p_mirror;
                    s
                }
            }
            Lobes::Mirror(m) => m.sample(wo)?,
            Lobes::Dielectric(d) => d.sample(wo, u)?,
            Lobes::RoughDielectric(r) => r.sample(wo, u, u2)?,
            Lobes::Scatter(s) => s.sample(wo, u2)?,
            Lobes::Cloth(c) => c.sample(wo, u2)?,
            Lobes::Composite(_) => return None,
            Lobes::Null => pass_through(wo)?,
        };
        let wi_w = self.frame.to_world(s.wi);
        if !s.specular && !self.consistent(wo_w, wi_w, wo, s.wi) {
            return None;
        }
        if !(s.pdf > 0.0 && s.pdf.is_finite() && s.f.is_finite()) {
            return None;
        }
        Some(BsdfSample {
            wi: wi_w,
            f: s.f,
            pdf: s.pdf,
            specular: s.specular,
        })
    }
}

fn finite_or_black(v: Rgb) -> Rgb {
    if v.is_finite() {
        v
    } else {
        Rgb::BLACK
    }
}

fn finite_or_zero(p: f32) -> f32 {
    if p.is_finite() {
        p
    } else {
        0.0
    }
}
