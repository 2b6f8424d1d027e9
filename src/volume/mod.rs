//! Participating media ("volumes"): the plugin family of `MakeNamedVolume` — `clear`,
//! `homogeneous`, `heterogeneous`, `exponential` — the old region `Volume` statements
//! (`homogeneous`, `exponential`, `volumegrid`, `cloud`, with emission `Le`), and
//! [`MediaSet`], which tells a renderer which medium a ray travels in.
//!
//! ```text
//! MakeNamedVolume (VolumeDesc) --Medium::build (one file per medium)--> Medium
//! region Volume statements --Region::build (region.rs, cloud.rs)--> Region
//!     all regions --Regions (regions.rs: summed where they overlap)--> the medium where
//!     none is named
//! shapes' Interior/Exterior names, camera's Exterior --MediaSet::build--> MediaSet
//!     (only the media something references; none at all when no referenced medium acts on
//!      light: the world then holds no MediaSet and rays take no medium code path)
//! ```
//!
//! A shape with an Interior or Exterior is a medium boundary: a ray crossing it against its
//! geometric normal enters the interior medium, along it the exterior one (an unset side is
//! vacuum). A shape with neither leaves the ray's medium unchanged. The camera starts in its
//! Exterior; without one, in the medium named "world" when the scene defines it (the default
//! medium LuxBlend writes on every shape's outside), else in vacuum.
//!
//! Only region volumes emit ([`Medium::emits`], checked once per segment by the
//! integrators, so media without emission cost nothing more).
//!
//! Units: coefficients are per scene unit (metres), distances are along the ray.

pub mod clear;
pub mod cloud;
pub mod exponential;
pub mod grid;
pub mod heterogeneous;
pub mod homogeneous;
pub mod phase;
pub mod region;
pub mod regions;

use crate::geometry::Ray;
use crate::lxs::{Diagnostic, Loc, ParamSet, SceneDescription};
use crate::plugin::{report_unused, warn, BuildError, Stmt};
use crate::spectrum::Rgb;
use crate::texture::{param_loc, FresnelTex, TextureError, TextureSet};
use glam::Vec3A;
use std::collections::BTreeMap;

pub use clear::Clear;
pub use heterogeneous::Heterogeneous;
pub use homogeneous::Homogeneous;
pub use phase::HenyeyGreenstein;
pub use region::Region;
pub use regions::Regions;

/// Why a medium could not be built.
#[derive(Debug, thiserror::Error)]
pub enum VolumeError {
    #[error(transparent)]
    Build(#[from] BuildError),
    #[error(transparent)]
    Texture(#[from] TextureError),
}

impl From<VolumeError> for BuildError {
    fn from(e: VolumeError) -> BuildError {
        match e {
            VolumeError::Build(b) => b,
            VolumeError::Texture(t) => t.into(),
        }
    }
}

/// Index of a medium in [`MediaSet::media`].
pub type MediumId = u32;

/// Where a ray scatters in a medium, or that it passes to the end of its segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MediumSample {
    /// Ray parameter of the scattering point; `None`: the ray reaches the segment's end.
    pub scatter_t: Option<f32>,
    /// What the path throughput is multiplied by (transmittance, times sigma_s at a
    /// scattering point, over the sampling density).
    pub weight: Rgb,
    /// The phase function at the scattering point (the medium's lobe; in overlapping region
    /// volumes of different `g`, the lobe chosen there: [`regions`]).
    pub phase: HenyeyGreenstein,
}

#[derive(Debug)]
pub enum Medium {
    Clear(Clear),
    Homogeneous(Homogeneous),
    /// `heterogeneous` and `exponential`: ray marched.
    Marched(Heterogeneous),
    /// The region `Volume`s: media confined to boxes, summed where they overlap.
    Region(Box<Regions>),
}

impl Medium {
    /// Builds a medium from its statement; `None` for a name no medium has.
    pub fn build(
        v: &crate::lxs::VolumeDesc,
        textures: &mut TextureSet,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Medium, BuildError> {
        let mut s = Stmt::new("volume", &v.entity, warnings);
        Ok(match v.entity.kind.as_str() {
            "clear" => Medium::Clear(Clear::build(&mut s, textures)?),
            "homogeneous" | "homogenous" => {
                Medium::Homogeneous(Homogeneous::build(&mut s, textures)?)
            }
            "heterogeneous" => Medium::Marched(Heterogeneous::build(&mut s, textures)?),
            "exponential" => {
                Medium::Marched(exponential::build(&mut s, textures, &v.object_to_world)?)
            }
            other => {
                return Err(s.err(format!(
                    "unknown volume \"{other}\" (clear, homogeneous, heterogeneous, exponential)"
                )))
            }
        })
    }

    /// Whether light crosses the medium unchanged (a clear medium without absorption).
    pub fn is_vacuum(&self) -> bool {
        match self {
            Medium::Clear(c) => c.absorption.is_black(),
            Medium::Homogeneous(h) => h.sigma_a.is_black() && h.sigma_s.is_black(),
            Medium::Marched(m) => m.density.is_vacuum(),
            // Regions::new keeps only regions that attenuate or emit.
            Medium::Region(_) => false,
        }
    }

    /// Whether the medium can scatter light.
    pub fn scatters(&self) -> bool {
        match self {
            Medium::Clear(_) => false,
            Medium::Homogeneous(h) => !h.sigma_s.is_black(),
            Medium::Marched(m) => m.density.scatters(),
            Medium::Region(r) => r.scatters(),
        }
    }

    /// Transmittance along the ray over its parametric extent [0, `t_max`].
    pub fn tr(&self, ray: &Ray, t_max: f32) -> Rgb {
        match self {
            Medium::Clear(c) => c.tr(ray, t_max),
            Medium::Homogeneous(h) => h.tr(ray, t_max),
            Medium::Marched(m) => m.tr(ray, t_max),
            Medium::Region(r) => r.tr(ray, t_max),
        }
    }

    /// The extinction coefficient sigma_a + sigma_s at world point `p` (distance sampling's
    /// density of stopping at `p` is its channel average times the transmittance to `p`).
    pub fn sigma_t(&self, p: Vec3A) -> Rgb {
        match self {
            Medium::Clear(c) => c.absorption,
            Medium::Homogeneous(h) => h.sigma_t(),
            Medium::Marched(m) => m.sigma_t(p),
            Medium::Region(r) => r.sigma_t(p),
        }
    }

    /// Samples a scattering point along [0, `t_max`] (`u`, `u_channel` uniform in [0, 1)).
    /// Media that do not scatter only attenuate.
    pub fn sample(&self, ray: &Ray, t_max: f32, u: f32, u_channel: f32) -> MediumSample {
        match self {
            Medium::Homogeneous(h) => h.sample(ray, t_max, u, u_channel),
            Medium::Marched(m) => m.sample(ray, t_max, u, u_channel),
            Medium::Region(r) => r.sample(ray, t_max, u, u_channel),
            Medium::Clear(c) => MediumSample {
                scatter_t: None,
                weight: c.tr(ray, t_max),
                phase: HenyeyGreenstein::new(0.0),
            },
        }
    }

    /// Whether the medium emits light (only region volumes with `Le` do): integrators
    /// check this once per segment before asking for [`Medium::emission`].
    pub fn emits(&self) -> bool {
        match self {
            Medium::Region(r) => r.emits(),
            _ => false,
        }
    }

    /// The radiance the medium emits toward the ray's origin along [0, `t_max`],
    /// attenuated on its way: ∫ Tr(t)·Le(t) dt ([`Regions::emission`]); black for media
    /// that do not emit.
    pub fn emission(&self, ray: &Ray, t_max: f32) -> Rgb {
        match self {
            Medium::Region(r) => r.emission(ray, t_max),
            _ => Rgb::BLACK,
        }
    }
}

/// Exp(-sigma × distance) per channel (1 where sigma is 0, even over an infinite distance).
pub fn transmittance(sigma: Rgb, dist: f32) -> Rgb {
    sigma.map(|s| if s > 0.0 { (-s * dist).exp() } else { 1.0 })
}

/// The average of the three channels.
pub fn channel_avg(c: Rgb) -> f32 {
    (c.r + c.g + c.b) / 3.0
}

/// The coefficients every scattering medium reads.
struct Common {
    sigma_a: Rgb,
    sigma_s: Rgb,
    g: f32,
}

fn read_common(s: &mut Stmt, textures: &mut TextureSet) -> Result<Common, VolumeError> {
    let sigma_a = constant_color(s, textures, "sigma_a")?;
    let sigma_s = constant_color(s, textures, "sigma_s")?;
    let g = read_g(s);
    read_fresnel(s.params(), s.loc(), textures)?;
    Ok(Common {
        sigma_a,
        sigma_s,
        g,
    })
}

/// LuxRender's default `fresnel` of a volume: the index of vacuum.
pub const DEFAULT_FRESNEL: f32 = 1.0;

/// A volume's `fresnel` (every medium kind takes it): a float index of refraction (default
/// [`DEFAULT_FRESNEL`]) or the name of a fresnel texture (cauchy, sellmeier, fresnelname,
/// sopra, luxpop, fresnelcolor, constant, and their mixes), as LuxRender's volumes read it.
/// The medium itself does not use it (light in a medium travels straight); glass2 takes its
/// index from it ([`crate::material::MaterialSet::bind_media`]). Reading it when the medium is
/// built also reports, located, a texture name that is missing or not a fresnel texture and
/// an index that is not a positive number.
pub fn read_fresnel(
    params: &ParamSet,
    loc: &Loc,
    textures: &mut TextureSet,
) -> Result<FresnelTex, TextureError> {
    if let Some(v) = params.float("fresnel") {
        if !(v.is_finite() && v > 0.0) {
            return Err(TextureError::BadParam {
                loc: param_loc(params, "fresnel", loc),
                message: format!("volume \"fresnel\" must be a positive index, got {v}"),
            });
        }
    }
    textures.fresnel_param(params, "fresnel", DEFAULT_FRESNEL)
}

/// `g`: a float or a colour (LuxRender's colour texture), averaged into one asymmetry.
fn read_g(s: &mut Stmt) -> f32 {
    let p = s.params();
    let g = match p.get("g").map(|p| &p.value) {
        Some(crate::lxs::ParamValue::Float(v)) => v.first().copied().unwrap_or(0.0),
        Some(crate::lxs::ParamValue::Color(v)) => {
            v.first().map_or(0.0, |c| (c[0] + c[1] + c[2]) / 3.0)
        }
        Some(_) => {
            s.warn("volume \"g\" must be a float or a color; using 0");
            0.0
        }
        None => 0.0,
    };
    if g.is_finite() && g.abs() < 1.0 {
        g
    } else {
        s.warn(format!("volume \"g\" must be in (-1, 1), got {g}; clamped"));
        if g.is_finite() {
            g.clamp(-0.99, 0.99)
        } else {
            0.0
        }
    }
}

/// A colour coefficient that is constant over the medium (a colour, a float, or a texture
/// that evaluates to a constant such as `colordepth` of constants), ≥ 0 and finite.
fn constant_color(s: &mut Stmt, textures: &mut TextureSet, name: &str) -> Result<Rgb, VolumeError> {
    let t = textures.color_param(s.params(), name, Rgb::BLACK)?;
    let c = match t.as_const() {
        Some(c) => c,
        None => {
            s.warn(format!(
                "volume \"{}\": \"{name}\" is not constant; its value at the origin is used \
                 (use \"heterogeneous\" for media that vary in space)",
                s.kind()
            ));
            t.eval(&crate::geometry::SurfaceInteraction::default())
        }
    };
    if c.is_finite() && c.r >= 0.0 && c.g >= 0.0 && c.b >= 0.0 {
        Ok(c)
    } else {
        Err(s
            .err(format!(
                "volume \"{}\": \"{name}\" must be finite and ≥ 0, got {} {} {}",
                s.kind(),
                c.r,
                c.g,
                c.b
            ))
            .into())
    }
}

/// Interior and exterior medium of a primitive that is a medium boundary.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Boundary {
    pub interior: Option<MediumId>,
    pub exterior: Option<MediumId>,
}

/// The media a scene's rays travel in, shared by the render threads.
#[derive(Debug)]
pub struct MediaSet {
    pub media: Vec<Medium>,
    /// Per primitive id: `Some` when the primitive is a medium boundary.
    boundaries: Vec<Option<Boundary>>,
    /// The medium camera rays start in.
    pub camera: Option<MediumId>,
    /// Per light (the scene description's lights, then per built light after
    /// [`Self::index_lights`]): the medium its rays start in, when its `LightSource` statement
    /// had an `Exterior` in effect (LuxRender 1.x gives a light the exterior volume current
    /// at its statement); `None` when it had none.
    light_start: Vec<Option<Option<MediumId>>>,
    /// Per built light: the primitive an area light emits from, when that primitive is a
    /// medium boundary ([`Self::area_light_side`]).
    area_prims: Vec<Option<u32>>,
    /// Whether some medium scatters.
    pub scatters: bool,
}

impl MediaSet {
    /// Builds the media that `prim_media` (Interior/Exterior names per primitive id) and the
    /// camera reference. `None` when none of them acts on light: such a scene renders as one
    /// without media.
    pub fn build(
        desc: &SceneDescription,
        prim_media: &[(Option<&str>, Option<&str>)],
        textures: &mut TextureSet,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Option<MediaSet>, BuildError> {
        let mut ids: BTreeMap<String, Option<MediumId>> = BTreeMap::new();
        let mut media = Vec::new();
        // The region volume, if any, fills every place no medium is named for.
        let region = match build_region(desc, textures, warnings)? {
            Some(m) if !m.is_vacuum() => {
                media.push(m);
                Some(media.len() as MediumId - 1)
            }
            _ => None,
        };
        let mut resolve = |name: Option<&str>,
                           media: &mut Vec<Medium>,
                           warnings: &mut Vec<Diagnostic>|
         -> Result<Option<MediumId>, BuildError> {
            let Some(name) = name else {
                return Ok(None);
            };
            if let Some(id) = ids.get(name) {
                return Ok(*id);
            }
            let Some(v) = desc
                .named_volumes
                .get(name)
                .and_then(|&i| desc.volumes.get(i))
            else {
                ids.insert(name.to_string(), None);
                return Ok(None);
            };
            let m = Medium::build(v, textures, warnings)?;
            report_unused("MakeNamedVolume", &v.entity, warnings);
            let id = if m.is_vacuum() {
                None
            } else {
                media.push(m);
                Some(media.len() as MediumId - 1)
            };
            ids.insert(name.to_string(), id);
            Ok(id)
        };
        let mut side = |name: Option<&str>,
                        media: &mut Vec<Medium>,
                        warnings: &mut Vec<Diagnostic>|
         -> Result<Option<MediumId>, BuildError> {
            match name {
                None => Ok(region),
                Some(_) => resolve(name, media, warnings),
            }
        };
        let mut boundaries = Vec::with_capacity(prim_media.len());
        for &(interior, exterior) in prim_media {
            if interior.is_none() && exterior.is_none() {
                boundaries.push(None);
                continue;
            }
            boundaries.push(Some(Boundary {
                interior: side(interior, &mut media, warnings)?,
                exterior: side(exterior, &mut media, warnings)?,
            }));
        }
        let camera_name = desc
            .camera
            .as_ref()
            .and_then(|c| c.exterior.as_deref())
            .or_else(|| desc.named_volumes.contains_key("world").then_some("world"));
        let camera = side(camera_name, &mut media, warnings)?;
        let mut light_start = Vec::with_capacity(desc.lights.len());
        for l in &desc.lights {
            light_start.push(match l.exterior.as_deref() {
                Some(name) => Some(resolve(Some(name), &mut media, warnings)?),
                None => None,
            });
        }
        if media.is_empty() {
            return Ok(None);
        }
        let scatters = media.iter().any(Medium::scatters);
        tracing::info!(
            media = media.len(),
            scatters,
            "scene has participating media"
        );
        Ok(Some(MediaSet {
            media,
            boundaries,
            camera,
            light_start,
            area_prims: Vec::new(),
            scatters,
        }))
    }

    /// Re-indexes the lights' start media from the scene description's lights to the built
    /// lights: `built[i]` are the built lights of description light i (a sunsky is two).
    /// `areas` are the area lights, as (built light, primitive it emits from): an area light
    /// on a medium boundary starts each ray on the side it leaves by, the exterior along the
    /// shape's normal and the interior against it (an IES profile emits on both sides), as
    /// LuxRender 1.x takes a light path's first medium from the emitting primitive's
    /// volumes; one on a plain surface has no start medium of its own.
    pub fn index_lights(
        &mut self,
        built: &[std::ops::Range<usize>],
        count: usize,
        areas: &[(usize, u32)],
    ) {
        let mut per_light = vec![None; count];
        for (range, start) in built.iter().zip(&self.light_start) {
            for i in range.clone().filter(|&i| i < count) {
                per_light[i] = *start;
            }
        }
        self.light_start = per_light;
        self.area_prims = vec![None; count];
        for &(light, prim) in areas {
            if self.boundary(prim).is_some() {
                if let Some(slot) = self.area_prims.get_mut(light) {
                    *slot = Some(prim);
                }
            }
        }
    }

    /// The medium a ray leaving area light `i` at a point of normal `n` in direction `d`
    /// starts in, when the light's shape is a medium boundary (`None` otherwise).
    pub fn area_light_side(&self, i: usize, n: Vec3A, d: Vec3A) -> Option<Option<MediumId>> {
        let prim = self.area_prims.get(i).copied().flatten()?;
        Some(self.after(prim, n, d, None))
    }

    /// The medium built light `i`'s rays start in, when its statement named one (`Some(None)`:
    /// a vacuum or unknown name); `None` when it did not, and the medium must be found from
    /// where its rays go.
    pub fn light_start(&self, i: usize) -> Option<Option<MediumId>> {
        self.light_start.get(i).copied().flatten()
    }

    pub fn get(&self, id: MediumId) -> Option<&Medium> {
        self.media.get(id as usize)
    }

    /// The world-space box around the region volumes, which have no shape of their own
    /// (empty, lo > hi, when there are none): the scene's bounds take it in, so lights at
    /// infinity emit over the regions too.
    pub fn region_bounds(&self) -> (Vec3A, Vec3A) {
        let mut b = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
        for m in &self.media {
            if let Medium::Region(r) = m {
                let (lo, hi) = r.world_bounds();
                b = (b.0.min(lo), b.1.max(hi));
            }
        }
        b
    }

    /// The boundary a primitive is, if any.
    pub fn boundary(&self, prim: u32) -> Option<Boundary> {
        self.boundaries.get(prim as usize).copied().flatten()
    }

    /// The medium a ray is in after leaving primitive `prim`'s surface in direction `d` (`n`
    /// its geometric normal), coming from `current`.
    pub fn after(
        &self,
        prim: u32,
        n: Vec3A,
        d: Vec3A,
        current: Option<MediumId>,
    ) -> Option<MediumId> {
        match self.boundary(prim) {
            Some(b) if d.dot(n) < 0.0 => b.interior,
            Some(b) => b.exterior,
            None => current,
        }
    }
}

/// The region `Volume` statements (no name), in scene order.
fn regions(desc: &SceneDescription) -> impl Iterator<Item = &crate::lxs::VolumeDesc> {
    desc.volumes.iter().filter(|v| v.name.is_none())
}

/// The region volumes of kinds that are rendered, built into one aggregate medium (their
/// coefficients and emission add where they overlap, [`regions`]); `None` when there are
/// none or none acts on light. The marching step defaults to the VolumeIntegrator's
/// `stepsize`.
/// Region volumes rendered at most: every ray is clipped against each of them, so a scene of
/// thousands would slow every ray (the ones past it are ignored, with a located warning).
pub const MAX_REGIONS: usize = 256;

fn build_region(
    desc: &SceneDescription,
    textures: &mut TextureSet,
    warnings: &mut Vec<Diagnostic>,
) -> Result<Option<Medium>, BuildError> {
    let step = desc
        .volume_integrator
        .as_ref()
        .and_then(|e| e.params.float("stepsize"))
        .filter(|s| s.is_finite() && *s > 0.0)
        .unwrap_or(1.0);
    let mut built = Vec::new();
    for v in regions(desc).filter(|v| region::is_supported(&v.entity.kind)) {
        if built.len() >= MAX_REGIONS {
            warn(
                warnings,
                &v.entity.loc,
                format!(
                    "Volume \"{}\": more than {MAX_REGIONS} region volumes; this one and later \
                     ones are ignored (every ray is clipped against each region)",
                    v.entity.kind
                ),
            );
            report_unused("Volume", &v.entity, warnings);
            continue;
        }
        if let Some(r) = Region::build(v, textures, warnings, step)? {
            built.push(r);
        }
        report_unused("Volume", &v.entity, warnings);
    }
    Ok(Regions::new(built).map(|all| Medium::Region(Box::new(all))))
}

/// Warns (located) about the region `Volume` statements of kinds that are not rendered
/// (homogeneous, exponential, volumegrid and cloud regions are: [`region`]).
pub fn warn_unrendered(desc: &SceneDescription, warnings: &mut Vec<Diagnostic>) {
    for v in regions(desc).filter(|v| !region::is_supported(&v.entity.kind)) {
        warn(
            warnings,
            &v.entity.loc,
            format!(
                "Volume \"{}\" (a region volume) is ignored: only homogeneous, exponential, \
                 volumegrid and cloud regions are rendered",
                v.entity.kind
            ),
        );
        report_unused("Volume", &v.entity, warnings);
    }
}
