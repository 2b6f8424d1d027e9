//! [`World::build`]: turns a SceneDescription into a World in three steps — geometry
//! ([`super::geometry`]), the materials the built shapes use, then the lights (built by
//! [`crate::light`]) and their selection — building only what is referenced.

use super::{geometry, World};
use crate::light::{Light, LightSelector, LightStrategy};
use crate::lxs::{Diagnostic, SceneDescription};
use crate::material::{MaterialCtx, MaterialSet};
use crate::plugin::{report_unused, warn, BuildError};
use crate::shape::ShapeCtx;
use crate::texture::{TextureCtx, TextureSet};
use std::path::Path;

/// What the render setup tells the world about how it will be used.
#[derive(Clone, Copy, Debug)]
pub struct WorldOptions {
    /// How direct lighting picks lights (the integrator's `lightstrategy`).
    pub light_strategy: LightStrategy,
}

impl World {
    /// Builds the world; `base_dir` is the directory relative file names resolve against.
    /// Problems that do not stop the build are pushed to `warnings` (and logged).
    pub fn build(
        desc: &SceneDescription,
        base_dir: &Path,
        opts: WorldOptions,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<World, BuildError> {
        let groups = if desc.light_groups.is_empty() {
            vec!["default".to_string()]
        } else {
            desc.light_groups.clone()
        };
        let ctx = ShapeCtx {
            base_dir: base_dir.to_path_buf(),
        };
        let built = geometry::build(desc, &ctx, warnings)?;
        let (mut geometry, mut prims) = (built.geometry, built.prims);

        // Materials used by the built shapes.
        let mut used: Vec<usize> = prims.iter().filter_map(|p| p.material).collect();
        used.sort_unstable();
        used.dedup();
        let mctx = MaterialCtx {
            base_dir: base_dir.to_path_buf(),
        };
        let materials = MaterialSet::build(desc, &used, &mctx)?;

        // Lights, then the area lights on the built shapes.
        let mut textures = TextureSet::new(
            desc,
            TextureCtx {
                base_dir: base_dir.to_path_buf(),
            },
        );
        let group_of = |name: &str| groups.iter().position(|g| g == name).unwrap_or(0);
        let mut lights = Vec::new();
        for ld in &desc.lights {
            lights.extend(Light::build(
                ld,
                group_of(&ld.light_group),
                &mut textures,
                base_dir,
            )?);
        }
        let mut emitters = Vec::new();
        for pa in &built.pending {
            let area = geometry.prepare_sampling(pa.shape);
            let light = Light::build_area(
                pa.entity,
                group_of(pa.group),
                &mut textures,
                emitters.len() as u32,
                area,
            )?;
            emitters.push(pa.shape);
            if let Some(pi) = prims.get_mut(pa.prim as usize) {
                pi.light = Some(lights.len());
            }
            lights.push(light);
        }
        let (lo, hi) = geometry.bounds();
        let (center, radius) = if lo.cmple(hi).all() {
            ((lo + hi) * 0.5, (hi - lo).length() * 0.5)
        } else {
            (glam::Vec3A::ZERO, 1.0)
        };
        for l in lights.iter_mut() {
            l.preprocess(center, radius.max(1e-6));
        }
        let infinite = (0..lights.len())
            .filter(|&i| lights[i].is_infinite())
            .collect();
        let selector = LightSelector::new(opts.light_strategy, &lights);
        let has_null = used.iter().any(|&m| materials.get(Some(m)).is_null());
        if lights.is_empty() {
            let loc = desc
                .camera
                .as_ref()
                .map(|c| c.entity.loc.clone())
                .unwrap_or_default();
            warn(
                warnings,
                &loc,
                "the scene has no lights: the image will be black",
            );
        }
        warnings.append(&mut textures.warnings);
        report_world_unused(desc, &used, warnings);
        tracing::info!(
            shapes = geometry.shape_count(),
            objects = built.objects,
            materials = used.len(),
            textures = textures.built_names().len(),
            images = textures.images_loaded(),
            lights = lights.len(),
            "world built"
        );
        Ok(World {
            groups,
            geometry,
            materials,
            prims,
            lights,
            infinite,
            emitters,
            selector,
            sphere: crate::light::BoundingSphere {
                center,
                radius: radius.max(1e-6),
            },
            has_null,
        })
    }
}

/// Warns about parameters of world statements (lights, shapes, area lights, the materials
/// built) that no plugin consumed.
fn report_world_unused(desc: &SceneDescription, used: &[usize], w: &mut Vec<Diagnostic>) {
    for l in &desc.lights {
        report_unused("LightSource", &l.entity, w);
    }
    for s in desc.shapes.iter().filter(|s| !s.portal) {
        report_unused("Shape", &s.entity, w);
        if let Some(a) = &s.area_light {
            report_unused("AreaLightSource", &a.entity, w);
        }
    }
    for &m in used {
        if let Some(md) = desc.materials.get(m) {
            report_unused("Material", &md.entity, w);
        }
    }
}
