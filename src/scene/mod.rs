//! Building a renderable [`Scene`] from a [`crate::lxs::SceneDescription`]: only what the description
//! references is built — shapes (and the objects that instances use), the materials those
//! shapes use (with their textures), the lights and their `L` textures. Unused parameters of
//! what was built are reported as warnings with file:line:column, and the log says what was
//! built.

mod build;

use crate::accel::{Geometry, ShapeId};
use crate::camera::Camera;
use crate::film::FilmParams;
use crate::filter::Filter;
use crate::geometry::{Interaction, Ray, SurfaceInteraction};
use crate::integrator::Integrator;
use crate::light::{AreaLight, Light, LightSample, LightSelector, ShapeSampler};
use crate::lxs::Diagnostic;
use crate::material::{Material, MaterialSet};
use crate::sampler::Sampler;
use glam::Vec2;

pub use build::SceneError;

/// What the renderer knows about a primitive id (`SurfaceInteraction::prim`).
#[derive(Clone, Copy, Debug, Default)]
pub struct PrimInfo {
    /// Index into `SceneDescription::materials`; `None`: LuxRender's default material.
    pub material: Option<usize>,
    /// Index into the scene's lights when the primitive is an area light.
    pub light: Option<usize>,
}

/// Everything a render needs, immutable once built (shared by the render threads).
pub struct Scene {
    pub camera: Camera,
    pub film_params: FilmParams,
    pub filter: Filter,
    pub sampler: Sampler,
    pub integrator: Integrator,
    /// Light group names, in film group order.
    pub groups: Vec<String>,
    /// Problems that did not stop the build (unused parameters, fallbacks).
    pub warnings: Vec<Diagnostic>,
    geometry: Geometry,
    materials: MaterialSet,
    prims: Vec<PrimInfo>,
    lights: Vec<Light>,
    infinite: Vec<usize>,
    /// World shape of each area light (`AreaLight::shape` indexes this).
    emitters: Vec<ShapeId>,
    selector: LightSelector,
}

impl Scene {
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

    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceInteraction> {
        self.geometry.intersect(ray)
    }

    /// Whether nothing blocks the segment from `from` to the light sample.
    pub fn unoccluded(&self, from: &Interaction, ls: &LightSample) -> bool {
        let ray = if ls.infinite {
            from.spawn_ray(ls.wi)
        } else {
            from.spawn_ray_to(&ls.p_light)
        };
        !self.geometry.intersect_p(&ray)
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

impl ShapeSampler for Scene {
    fn sample_shape(&self, shape: u32, u: Vec2, u_pick: f32) -> Option<(Interaction, Vec2, f32)> {
        let id = *self.emitters.get(shape as usize)?;
        let (it, uv, pdf) = self.geometry.sample(id, u, u_pick);
        (pdf > 0.0).then_some((it, uv, pdf))
    }
}
