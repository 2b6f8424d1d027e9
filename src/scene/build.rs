//! [`World::build`]: turns a SceneDescription into a World in three steps — geometry
//! ([`super::geometry`]), the materials the built shapes use (bound to the shapes' volumes
//! where a glass2 needs them; material warnings join the build's), then the lights (built by
//! [`crate::light`]) and their selection — building only what is referenced.

use super::{geometry, portals, World};
use crate::fileio::SceneFiles;
use crate::light::{Light, LightSelector, LightStrategy};
use crate::lxs::{Diagnostic, SceneDescription};
use crate::material::{MaterialCtx, MaterialSet};
use crate::plugin::{report_unused, warn, BuildError};
use crate::shape::ShapeCtx;
use crate::texture::{TextureCtx, TextureSet};
use crate::volume::MediaSet;

/// What the render setup tells the world about how it will be used.
#[derive(Clone, Copy, Debug)]
pub struct WorldOptions {
    /// How direct lighting picks lights (the integrator's `lightstrategy`).
    pub light_strategy: LightStrategy,
    /// Whether participating media are rendered (the volume integrator is not `none`).
    pub media: bool,
}

impl World {
    /// Builds the world; `files` opens the files the scene names (relative to its directory,
    /// confined to it on a farm). Problems that do not stop the build are pushed to
    /// `warnings` (and logged).
    pub fn build(
        desc: &SceneDescription,
        files: &SceneFiles,
        opts: WorldOptions,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<World, BuildError> {
        let groups = if desc.light_groups.is_empty() {
            vec!["default".to_string()]
        } else {
            desc.light_groups.clone()
        };
        let mut textures = TextureSet::new(
            desc,
            TextureCtx {
                files: files.clone(),
            },
        );
        let ctx = ShapeCtx {
            files: files.clone(),
            displacement: crate::shape::loopsubdiv::displacement_maps(desc, &mut textures)?,
        };
        let built = geometry::build(desc, &ctx, warnings)?;
        let (mut geometry, mut prims) = (built.geometry, built.prims);

        // Materials used by the built shapes.
        let mut used: Vec<usize> = prims.iter().filter_map(|p| p.material).collect();
        used.sort_unstable();
        used.dedup();
        let mctx = MaterialCtx {
            files: files.clone(),
        };
        // One texture set for materials, lights and media: an image they share loads once.
        let mut materials = MaterialSet::build_with_textures(desc, &used, &mctx, &mut textures)?;
        // glass2 takes its index from each shape's volumes.
        for (prim, &(interior, exterior)) in prims.iter_mut().zip(&built.media) {
            if let Some(m) = prim.material {
                prim.material = Some(materials.bind_media(desc, m, interior, exterior)?);
            }
        }
        warnings.append(&mut materials.warnings);

        // Lights, then the area lights on the built shapes.
        let mut media = if opts.media {
            MediaSet::build(desc, &built.media, &mut textures, warnings)?.map(Box::new)
        } else {
            None
        };
        let group_of = |name: &str| groups.iter().position(|g| g == name).unwrap_or(0);
        let mut lights = Vec::new();
        let mut built_lights = Vec::with_capacity(desc.lights.len());
        for ld in &desc.lights {
            let start = lights.len();
            lights.extend(Light::build(
                ld,
                group_of(&ld.light_group),
                &mut textures,
                files,
            )?);
            built_lights.push(start..lights.len());
        }
        portals::attach(desc, &ctx, &built_lights, &mut lights, warnings);
        let mut emitters = Vec::new();
        let mut area_prims = Vec::with_capacity(built.pending.len());
        for pa in &built.pending {
            let area = geometry.prepare_sampling(pa.shape);
            let light = Light::build_area(
                pa.entity,
                group_of(pa.group),
                &mut textures,
                (emitters.len() as u32, area),
                files,
            )?;
            emitters.push(pa.shape);
            if let Some(pi) = prims.get_mut(pa.prim as usize) {
                pi.light = Some(lights.len());
            }
            area_prims.push((lights.len(), pa.prim));
            lights.push(light);
        }
        if let Some(ms) = media.as_mut() {
            ms.index_lights(&built_lights, lights.len(), &area_prims);
        }
        let (center, radius) = scene_sphere(geometry.bounds(), media.as_deref());
        for l in lights.iter_mut() {
            l.preprocess(center, radius.max(1e-6));
        }
        let infinite = (0..lights.len())
            .filter(|&i| lights[i].is_infinite())
            .collect();
        let primitive = (0..lights.len())
            .filter(|&i| lights[i].is_primitive())
            .collect();
        let selector = LightSelector::new(opts.light_strategy, &lights);
        let emitting_media = media
            .as_ref()
            .is_some_and(|m| m.media.iter().any(|v| v.emits()));
        if lights.is_empty() && !emitting_media {
            let loc = desc
                .camera
                .as_ref()
                .map(|c| c.entity.loc.clone())
                .unwrap_or_default();
            warn(
                warnings,
                &loc,
                "the scene has no lights nor emitting volumes: the image will be black",
            );
        }
        warnings.append(&mut textures.warnings);
        // Every material built, including the components of mix, glossycoating, ...
        let built_materials: Vec<usize> = (0..desc.materials.len())
            .filter(|&i| materials.is_built(i))
            .collect();
        report_world_unused(desc, &built_materials, warnings);
        let summary = BuiltSummary {
            shapes: geometry.shape_count(),
            objects: built.objects,
            materials: {
                let mut v: Vec<String> = built_materials
                    .iter()
                    .map(|&i| material_name(desc, i))
                    .collect();
                v.sort();
                v
            },
            textures: textures.built_names(),
            images: textures.images_loaded(),
            lights: lights.len(),
        };
        summary.log();
        let has_null = prims.iter().any(|p| materials.get(p.material).is_null());
        let spectral = dispersing_material(desc, &prims, &materials);
        if let Some(name) = &spectral {
            tracing::info!(
                "scene needs spectra: {name} disperses; paths through it carry one wavelength"
            );
        }
        let mut world = World {
            built: summary,
            spectral: spectral.is_some(),
            lights_read_pick: true,
            media,
            has_null,
            groups,
            geometry,
            materials,
            prims,
            lights,
            infinite,
            primitive,
            emitters,
            selector,
            sphere: crate::light::BoundingSphere {
                center,
                radius: radius.max(1e-6),
            },
        };
        world.lights_read_pick = world.lights.iter().any(|l| l.reads_pick(&world));
        Ok(world)
    }
}

/// What [`World::build`] built — only what the scene references: the world's shapes, the
/// objects its instances use, the materials of those shapes (with their components) and
/// the textures and image files those materials and the lights read. Logged at info level.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BuiltSummary {
    /// World-level shapes (each instanced object counts once, in `objects`).
    pub shapes: usize,
    pub objects: usize,
    /// Names of the materials built, sorted (`#i` for an unnamed `Material` statement).
    pub materials: Vec<String>,
    /// Names of the named textures built, sorted.
    pub textures: Vec<String>,
    /// Image files read.
    pub images: usize,
    pub lights: usize,
}

impl BuiltSummary {
    fn log(&self) {
        tracing::info!(
            shapes = self.shapes,
            objects = self.objects,
            materials = %names(&self.materials),
            textures = %names(&self.textures),
            images = self.images,
            lights = self.lights,
            "world built"
        );
    }
}

/// A list for the log: its length and up to 12 names.
fn names(v: &[String]) -> String {
    const SHOWN: usize = 12;
    let mut s = format!("{} [{}", v.len(), v[..v.len().min(SHOWN)].join(", "));
    if v.len() > SHOWN {
        s.push_str(&format!(", +{} more", v.len() - SHOWN));
    }
    s.push(']');
    s
}

fn material_name(desc: &SceneDescription, i: usize) -> String {
    desc.materials
        .get(i)
        .and_then(|m| m.name.clone())
        .unwrap_or_else(|| format!("#{i}"))
}

/// The first material a primitive uses that disperses light, named for the log
/// ("glass 'prism'"); `None` when the scene stays RGB.
fn dispersing_material(
    desc: &SceneDescription,
    prims: &[super::PrimInfo],
    materials: &MaterialSet,
) -> Option<String> {
    let p = prims
        .iter()
        .find(|p| materials.get(p.material).disperses())?;
    let m = materials.get(p.material);
    let name = p
        .material
        .and_then(|i| desc.materials.get(i))
        .and_then(|d| d.name.clone())
        .unwrap_or_else(|| "(unnamed)".into());
    Some(format!("{} '{name}'", m.type_name))
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

/// The sphere lights at infinity send their light from: around the geometry and the region
/// volumes' boxes. Region boxes far larger than the geometry (past [`MAX_REGION_REACH`] times
/// its radius) or not finite are left out, with a log line: the light would start so far out
/// that its subpaths would rarely meet the scene.
fn scene_sphere(
    (lo, hi): (glam::Vec3A, glam::Vec3A),
    media: Option<&MediaSet>,
) -> (glam::Vec3A, f32) {
    let sphere = |lo: glam::Vec3A, hi: glam::Vec3A| {
        if lo.cmple(hi).all() {
            ((lo + hi) * 0.5, (hi - lo).length() * 0.5)
        } else {
            (glam::Vec3A::ZERO, 1.0)
        }
    };
    let geometry = sphere(lo, hi);
    let Some(m) = media else {
        return geometry;
    };
    let (rlo, rhi) = m.region_bounds();
    let (center, radius) = sphere(lo.min(rlo), hi.max(rhi));
    let reach = MAX_REGION_REACH * geometry.1.max(1.0);
    if center.is_finite() && radius.is_finite() && radius <= reach {
        (center, radius)
    } else {
        tracing::warn!(
            radius,
            "region volumes reach far beyond the geometry: lights at infinity start from the \
             geometry's bounding sphere"
        );
        geometry
    }
}

/// How far (in radii of the geometry's bounding sphere, at least 1) the region volumes may
/// widen the sphere lights at infinity start from.
const MAX_REGION_REACH: f32 = 1000.0;
