//! `Scene::build`: turns a SceneDescription into a Scene, building only what is referenced.

use super::{PrimInfo, Scene};
use crate::accel::{GeometryBuilder, ObjectId, ShapeId};
use crate::camera::{Camera, FilmGeometry};
use crate::film::FilmParams;
use crate::filter::Filter;
use crate::integrator::Integrator;
use crate::light::{
    sunsky, AreaLight, DistantLight, Emission, InfiniteLight, Light, LightColor, LightCommon,
    LightSelector, PointLight, SpotLight,
};
use crate::lxs::{Diagnostic, Entity, LightDesc, Loc, ParamSet, SceneDescription};
use crate::material::{MaterialCtx, MaterialSet};
use crate::sampler::Sampler;
use crate::shape::ShapeCtx;
use crate::spectrum::{illuminant_y, Rgb};
use crate::texture::{TextureCtx, TextureSet};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

/// Why a scene could not be built; every variant names the place in the scene files.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{0}")]
    Film(#[from] crate::film::FilmError),
    #[error("{0}")]
    Camera(#[from] crate::camera::CameraError),
    #[error("{0}")]
    Filter(#[from] crate::filter::FilterError),
    #[error("{0}")]
    Sampler(#[from] crate::sampler::SamplerError),
    #[error("{0}")]
    Integrator(#[from] crate::integrator::IntegratorError),
    #[error("{0}")]
    Shape(#[from] crate::shape::ShapeError),
    #[error("{0}")]
    Material(#[from] crate::material::MaterialError),
    #[error("{0}")]
    Texture(#[from] crate::texture::TextureError),
    #[error("{0}")]
    Light(#[from] crate::light::LightError),
    #[error("{0}: {1}")]
    Other(Loc, String),
}

/// A world-level area light waiting for the geometry (its area) to be built.
struct PendingArea<'a> {
    prim: u32,
    shape: ShapeId,
    entity: &'a Entity,
    group: String,
}

impl Scene {
    /// Builds the scene; `base_dir` is the directory relative file names resolve against.
    pub fn build(desc: &SceneDescription, base_dir: &Path) -> Result<Scene, SceneError> {
        let mut warnings = Vec::new();
        let film_params = FilmParams::from_entity(desc.film.as_ref())?;
        let cam_desc = desc.camera.as_ref().ok_or_else(|| {
            SceneError::Other(
                Loc {
                    file: desc.root_file.as_str().into(),
                    line: 1,
                    col: 1,
                },
                "the scene has no Camera statement".into(),
            )
        })?;
        let fg = FilmGeometry {
            xres: film_params.xres,
            yres: film_params.yres,
            crop: film_params.crop,
        };
        let mut camera = Camera::build(cam_desc, &fg)?;
        let filter = Filter::from_entity(desc.pixel_filter.as_ref())?;
        let sampler = Sampler::from_entity(desc.sampler.as_ref())?;
        let integrator = Integrator::from_entity(desc.surface_integrator.as_ref(), &mut warnings)?;
        let groups = if desc.light_groups.is_empty() {
            vec!["default".to_string()]
        } else {
            desc.light_groups.clone()
        };

        // Geometry: world shapes, then the objects instances use.
        let ctx = ShapeCtx {
            base_dir: base_dir.to_path_buf(),
        };
        let mut gb = GeometryBuilder::new();
        let mut prims: Vec<PrimInfo> = Vec::new();
        let mut pending = Vec::new();
        for shape in desc.shapes.iter().filter(|s| !s.portal) {
            let prim = prims.len() as u32;
            let id = gb.add_shape(shape, prim, &ctx)?;
            prims.push(PrimInfo {
                material: shape.material,
                light: None,
            });
            if let Some(al) = &shape.area_light {
                pending.push(PendingArea {
                    prim,
                    shape: id,
                    entity: &al.entity,
                    group: al.light_group.clone(),
                });
            }
        }
        let mut objects: BTreeMap<usize, ObjectId> = BTreeMap::new();
        for inst in desc.instances.iter().filter(|i| !i.portal) {
            let Some(obj) = desc.objects.get(inst.object) else {
                return Err(SceneError::Other(inst.loc.clone(), "unknown object".into()));
            };
            let oid = match objects.get(&inst.object) {
                Some(o) => *o,
                None => {
                    let ids: Vec<u32> = obj
                        .shapes
                        .iter()
                        .map(|s| {
                            if s.area_light.is_some() {
                                warn(&mut warnings, &s.entity.loc, "area lights inside objects are not supported: the shape is rendered without emission");
                            }
                            prims.push(PrimInfo {
                                material: s.material,
                                light: None,
                            });
                            prims.len() as u32 - 1
                        })
                        .collect();
                    let o = gb.add_object(obj, &ids, &ctx)?;
                    objects.insert(inst.object, o);
                    o
                }
            };
            gb.add_instance(oid, &inst.instance_to_world);
        }
        let mut geometry = gb.build();

        // Materials used by the built shapes.
        let mut used: Vec<usize> = prims.iter().filter_map(|p| p.material).collect();
        used.sort_unstable();
        used.dedup();
        let mctx = MaterialCtx {
            base_dir: base_dir.to_path_buf(),
        };
        let materials = MaterialSet::build(desc, &used, &mctx)?;

        // Lights.
        let mut textures = TextureSet::new(
            desc,
            TextureCtx {
                base_dir: base_dir.to_path_buf(),
            },
        );
        let group_of = |name: &str| groups.iter().position(|g| g == name).unwrap_or(0);
        let mut lights = Vec::new();
        for ld in &desc.lights {
            let common = LightCommon::from_params(&ld.entity.params, group_of(&ld.light_group));
            let (e, l2w) = (&ld.entity, ld.light_to_world.start().as_mat4());
            if let Some(built) = sunsky::build(&e.kind, &e.params, l2w, common, &e.loc) {
                lights.extend(built?);
                continue;
            }
            lights.push(build_light(ld, common, &mut textures, base_dir)?);
        }
        let mut emitters = Vec::new();
        for pa in &pending {
            let p = &pa.entity.params;
            if pa.entity.kind != "area" {
                return Err(SceneError::Other(
                    pa.entity.loc.clone(),
                    format!("unknown AreaLightSource \"{}\"", pa.entity.kind),
                ));
            }
            let color = light_color(&mut textures, p)?;
            let common = LightCommon::from_params(p, group_of(&pa.group));
            let area = geometry.prepare_sampling(pa.shape);
            let light = AreaLight::new(p, &color, emitters.len() as u32, area, common);
            emitters.push(pa.shape);
            if let Some(pi) = prims.get_mut(pa.prim as usize) {
                pi.light = Some(lights.len());
            }
            lights.push(Light::Area(light));
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
        let selector = LightSelector::new(integrator.direct_settings().strategy, &lights);
        if lights.is_empty() {
            warn(
                &mut warnings,
                &cam_desc.entity.loc,
                "the scene has no lights: the image will be black",
            );
        }
        if camera.needs_autofocus() {
            camera.autofocus(|r| geometry.intersect(r).map(|si| si.t));
        }
        warnings.append(&mut textures.warnings);
        report_unused(desc, &used, &mut warnings);
        tracing::info!(
            shapes = geometry.shape_count(),
            objects = objects.len(),
            materials = used.len(),
            textures = textures.built_names().len(),
            images = textures.images_loaded(),
            lights = lights.len(),
            "scene built"
        );
        Ok(Scene {
            camera,
            film_params,
            filter,
            sampler,
            integrator,
            groups,
            warnings,
            geometry,
            materials,
            prims,
            lights,
            infinite,
            emitters,
            selector,
        })
    }
}

fn warn(w: &mut Vec<Diagnostic>, loc: &Loc, message: &str) {
    tracing::warn!("{loc}: {message}");
    w.push(Diagnostic {
        loc: loc.clone(),
        message: message.to_string(),
    });
}

/// The `L` parameter (colour or texture; white by default) with its luminance.
fn light_color(textures: &mut TextureSet, p: &ParamSet) -> Result<LightColor, SceneError> {
    let tex = textures.color_param(p, "L", Rgb::WHITE)?;
    Ok(match tex.as_const() {
        Some(c) => LightColor {
            emission: Emission::Const(c),
            y: illuminant_y(c),
        },
        None => {
            let y = illuminant_y(tex.eval(&Default::default()));
            LightColor {
                emission: Emission::Tex(Arc::new(move |si| tex.eval(si))),
                y,
            }
        }
    })
}

fn build_light(
    ld: &LightDesc,
    common: LightCommon,
    textures: &mut TextureSet,
    base_dir: &Path,
) -> Result<Light, SceneError> {
    let e = &ld.entity;
    let p = &e.params;
    let l2w = ld.light_to_world.start().as_mat4();
    let color = light_color(textures, p)?;
    Ok(match e.kind.as_str() {
        "point" => Light::Point(PointLight::new(p, l2w, &color, common)),
        "spot" => Light::Spot(SpotLight::new(p, l2w, &color, common)),
        "distant" => Light::Distant(DistantLight::new(p, l2w, &color, common)),
        "infinite" | "infinitesample" => {
            let map = p.string("mapname").filter(|s| !s.is_empty());
            let path = map.map(|m| base_dir.join(m));
            let l = InfiniteLight::new(p, l2w, &color, path.as_deref(), common)
                .map_err(|m| crate::light::LightError::new(&e.loc, m))?;
            Light::Infinite(Box::new(l))
        }
        other => {
            return Err(SceneError::Other(
                e.loc.clone(),
                format!(
                    "LightSource \"{other}\" is not supported by luxfarm yet \
                     (point, spot, distant, infinite, sun, sky, sunsky, area)"
                ),
            ))
        }
    })
}

/// Warns about parameters no built plugin consumed.
fn report_unused(desc: &SceneDescription, used: &[usize], w: &mut Vec<Diagnostic>) {
    let mut check = |label: &str, e: &Entity| {
        for p in e.params.unused() {
            let message = format!("{label} \"{}\": unused parameter \"{}\"", e.kind, p.name);
            tracing::warn!("{}: {message}", p.loc);
            w.push(Diagnostic {
                loc: p.loc.clone(),
                message,
            });
        }
    };
    let singles = [
        ("Camera", desc.camera.as_ref().map(|c| &c.entity)),
        ("Film", desc.film.as_ref()),
        ("PixelFilter", desc.pixel_filter.as_ref()),
        ("Sampler", desc.sampler.as_ref()),
        ("SurfaceIntegrator", desc.surface_integrator.as_ref()),
    ];
    for (label, e) in singles {
        if let Some(e) = e {
            check(label, e);
        }
    }
    for l in &desc.lights {
        check("LightSource", &l.entity);
    }
    for s in desc.shapes.iter().filter(|s| !s.portal) {
        check("Shape", &s.entity);
        if let Some(a) = &s.area_light {
            check("AreaLightSource", &a.entity);
        }
    }
    for &m in used {
        if let Some(md) = desc.materials.get(m) {
            check("Material", &md.entity);
        }
    }
}
