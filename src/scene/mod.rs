//! The world: what is in the scene — geometry (with its BVH), materials, textures, lights and
//! the light selection — built from a [`crate::lxs::SceneDescription`]. Only what the
//! description references is built: shapes (and the objects that instances use), the
//! materials those shapes use (with their textures), the lights and their `L` textures.
//! Unused parameters of what was built are reported as warnings with file:line:column, and
//! the log says what was built.
//!
//! How the world is looked at (camera, sampler, filter, integrator, film) is the render
//! setup's business ([`crate::render::setup`]): the world imports no integrator; integrators
//! receive a `&World`.
//!
//! ```text
//! SceneDescription --geometry::build--> Geometry + primitive table + pending area lights
//!                  --MaterialSet::build--> materials (with their textures)
//!                  --Light::build / Light::build_area--> lights --> LightSelector
//!                  --portals::attach--> infinite/sky lights sampled through windows
//! ```

mod build;
mod geometry;
mod portals;
#[cfg(test)]
mod tests;

use crate::accel::{Geometry, ShapeId};
use crate::geometry::{Interaction, Ray, SurfaceInteraction};
use crate::light::{AreaLight, BoundingSphere, Light, LightSample, LightSelector, ShapeSampler};
use crate::material::{Material, MaterialSet};
use crate::spectrum::Rgb;
use crate::volume::{MediaSet, Medium, MediumId};
use glam::{Vec2, Vec3A};

pub use build::{BuiltSummary, WorldOptions};

/// What the renderer knows about a primitive id (`SurfaceInteraction::prim`).
#[derive(Clone, Copy, Debug, Default)]
pub struct PrimInfo {
    /// Index into `SceneDescription::materials`; `None`: LuxRender's default material.
    pub material: Option<usize>,
    /// Index into the scene's lights when the primitive is an area light.
    pub light: Option<usize>,
}

/// What the scene contains, immutable once built (shared by the render threads).
pub struct World {
    /// What was built (and logged): only what the scene references.
    pub built: BuiltSummary,
    /// Light group names, in film group order.
    groups: Vec<String>,
    geometry: Geometry,
    materials: MaterialSet,
    prims: Vec<PrimInfo>,
    lights: Vec<Light>,
    infinite: Vec<usize>,
    /// Indices of the lights that are not geometry (area primitives), found along rays.
    primitive: Vec<usize>,
    /// World shape of each area light (`AreaLight::shape` indexes this).
    emitters: Vec<ShapeId>,
    selector: LightSelector,
    /// The bounding sphere lights at infinity emit from.
    sphere: BoundingSphere,
    /// Whether some primitive has the null material (shadow rays then cross null surfaces).
    has_null: bool,
    /// The participating media; `None` when the scene has none that acts on light (or the
    /// volume integrator is `none`): rays then take no medium code path.
    media: Option<Box<MediaSet>>,
    /// Whether some material disperses light: paths through it then carry a wavelength.
    spectral: bool,
    /// Whether some light's sampling reads its `u_pick` ([`Light::reads_pick`]).
    lights_read_pick: bool,
}

/// Where a segment walked by [`World::walk_segment`] ends: at a point (stopping just short
/// of it), or never (the unbounded ray along a direction).
#[derive(Clone, Copy, Debug)]
pub enum SegmentEnd<'a> {
    Point(&'a Interaction),
    Direction(Vec3A),
}

/// Null-material surfaces a visibility test passes through before giving up.
const MAX_NULL_CROSSINGS: u32 = 64;

impl World {
    /// Light group names, in film group order (at least "default").
    pub fn groups(&self) -> &[String] {
        &self.groups
    }

    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// Indices of the lights seen by rays that leave the scene.
    pub fn infinite_lights(&self) -> &[usize] {
        &self.infinite
    }

    pub fn selector(&self) -> &LightSelector {
        &self.selector
    }

    /// Calls `f(light index, crossing)` for every point where `ray` (0 < t < `t_max`) passes
    /// through an area primitive (lights that are not geometry and do not stop rays).
    pub fn crossed_lights(
        &self,
        ray: &Ray,
        t_max: f32,
        mut f: impl FnMut(usize, &SurfaceInteraction),
    ) {
        for &i in &self.primitive {
            if let Some(light) = self.lights.get(i) {
                light.crossings(ray, t_max, &mut |si| f(i, si));
            }
        }
    }

    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceInteraction> {
        self.geometry.intersect(ray)
    }

    /// Whether nothing blocks the segment from `from` to the light sample. Surfaces with the
    /// null material do not block light (LuxRender's null is invisible to every ray).
    pub fn unoccluded(&self, from: &Interaction, ls: &LightSample) -> bool {
        let ray = if ls.infinite {
            from.spawn_ray(ls.wi)
        } else {
            from.spawn_ray_to(&ls.p_light)
        };
        if !self.has_null {
            return !self.geometry.intersect_p(&ray);
        }
        let mut ray = ray;
        // The same bound as the integrators' pass-through of null surfaces.
        for _ in 0..64 {
            let Some(si) = self.geometry.intersect(&ray) else {
                return true;
            };
            if !self.material(si.prim).is_null() {
                return false;
            }
            ray = if ls.infinite {
                si.it.spawn_ray(ls.wi)
            } else {
                si.it.spawn_ray_to(&ls.p_light)
            };
        }
        false
    }

    /// Whether some material disperses light (the scene needs spectral paths).
    pub fn spectral(&self) -> bool {
        self.spectral
    }

    /// Whether light sampling needs its `u_pick` in this scene: some light reads it. Decided
    /// per scene, not per light, so that every light sample draws the same dimensions and a
    /// pixel's later dimensions stay aligned (stratified) whichever light its samples pick.
    pub fn lights_read_pick(&self) -> bool {
        self.lights_read_pick
    }

    /// The scene's participating media, when it has any that act on light.
    pub fn media(&self) -> Option<&MediaSet> {
        self.media.as_deref()
    }

    /// The fraction of light that reaches `from` from the light sample, starting in medium
    /// `medium`: black when a surface that is not null blocks it, otherwise the product of
    /// the transmittances of the media it crosses (null surfaces that bound media change the
    /// medium). Without media this is [`Self::unoccluded`] as 0 or 1.
    pub fn transmittance(
        &self,
        from: &Interaction,
        ls: &LightSample,
        medium: Option<MediumId>,
    ) -> Rgb {
        let end = if ls.infinite {
            SegmentEnd::Direction(ls.wi)
        } else {
            SegmentEnd::Point(&ls.p_light)
        };
        self.transmittance_along(from, end, medium)
    }

    /// The fraction of light carried along the segment from `from` to `end` that starts in
    /// `medium` ([`Self::walk_segment`]): black when blocked, else the media's transmittance.
    pub fn transmittance_along(
        &self,
        from: &Interaction,
        end: SegmentEnd,
        medium: Option<MediumId>,
    ) -> Rgb {
        let mut tr = Rgb::WHITE;
        let open = self.walk_segment(from, end, medium, |m, ray, t_end| {
            if let Some(m) = m.filter(|_| !tr.is_black()) {
                tr *= m.tr(ray, t_end);
            }
        });
        if open {
            tr
        } else {
            Rgb::BLACK
        }
    }

    /// Walks the segment from `from` to `end` through surfaces of the null material (which
    /// light passes unchanged), starting in `medium` and changing medium where it crosses a
    /// medium boundary. `piece(medium, ray, t_end)` is called for every part between two
    /// crossings, in order, with the medium it runs in (`None`: vacuum) and its ray's extent.
    /// Returns false when a surface that is not null blocks the segment. Shadow rays, the
    /// connections of bidirectional path tracing and their densities all walk segments here.
    pub fn walk_segment(
        &self,
        from: &Interaction,
        end: SegmentEnd,
        medium: Option<MediumId>,
        mut piece: impl FnMut(Option<&Medium>, &Ray, f32),
    ) -> bool {
        let spawn = |it: &Interaction| match end {
            SegmentEnd::Point(p) => it.spawn_ray_to(p),
            SegmentEnd::Direction(d) => it.spawn_ray(d),
        };
        let media = self.media();
        let mut ray = spawn(from);
        if media.is_none() && !self.has_null {
            if self.geometry.intersect_p(&ray) {
                return false;
            }
            piece(None, &ray, ray.t_max);
            return true;
        }
        let mut medium = medium;
        for _ in 0..MAX_NULL_CROSSINGS {
            let hit = self.geometry.intersect(&ray);
            let t_end = hit.as_ref().map_or(ray.t_max, |h| h.t);
            piece(
                medium.and_then(|id| media.and_then(|ms| ms.get(id))),
                &ray,
                t_end,
            );
            let Some(si) = hit else {
                return true;
            };
            if !self.material(si.prim).is_null() {
                return false;
            }
            if let Some(ms) = media {
                medium = ms.after(si.prim, si.it.n, ray.d, medium);
            }
            ray = spawn(&si.it);
        }
        false
    }

    /// The scene's bounding sphere (lights at infinity emit from its radius).
    pub fn bounding_sphere(&self) -> BoundingSphere {
        self.sphere
    }

    /// Whether light travels along the segment `ray` (parametric extent `t_max`): nothing
    /// blocks it but surfaces of the null material, which light passes unchanged.
    pub fn transmits(&self, ray: &Ray) -> bool {
        if !self.geometry.intersect_p(ray) {
            return true;
        }
        if !self.has_null {
            return false;
        }
        let mut r = *ray;
        for _ in 0..MAX_NULL_CROSSINGS {
            let Some(si) = self.geometry.intersect(&r) else {
                return true;
            };
            if !self.material(si.prim).is_null() {
                return false;
            }
            let left = r.t_max - si.t;
            r = si.it.spawn_ray(r.d);
            r.t_max = left;
            if left <= 0.0 {
                return true;
            }
        }
        false
    }

    /// The area light of a primitive, with its light index.
    pub fn area_light(&self, prim: u32) -> Option<(usize, &AreaLight)> {
        let i = self.prims.get(prim as usize)?.light?;
        match self.lights.get(i)? {
            Light::Area(a) => Some((i, a)),
            _ => None,
        }
    }

    pub fn material(&self, prim: u32) -> &Material {
        self.materials
            .get(self.prims.get(prim as usize).and_then(|p| p.material))
    }
}

impl ShapeSampler for World {
    fn sample_shape(
        &self,
        shape: u32,
        u: Vec2,
        u_pick: f32,
        time: f32,
    ) -> Option<(Interaction, Vec2, f32)> {
        let id = *self.emitters.get(shape as usize)?;
        let (it, uv, pdf) = self.geometry.sample(id, u, u_pick, time);
        (pdf > 0.0).then_some((it, uv, pdf))
    }

    fn reads_pick(&self, shape: u32) -> bool {
        self.emitters
            .get(shape as usize)
            .is_none_or(|&id| self.geometry.sample_reads_pick(id))
    }
}
