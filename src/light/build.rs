//! Building lights from their statements: [`Light::build`] for a `LightSource` (point, spot,
//! distant, infinite, the daylight plugins of [`super::sunsky`], and the area primitives
//! rectangle, disc, sphere, cylinder of [`super::primitive`]) and
//! [`Light::build_area`] for an `AreaLightSource` once its shape is in the geometry. Both read
//! the `L` colour or texture through the scene's [`TextureSet`], the parameters every light
//! shares ([`LightCommon`]), and hand the rest to the light's own file.
//!
//! ```text
//! LightDesc (kind, params, light-to-world) --Light::build--> Vec<Light>   (sunsky gives two)
//! AreaLightSource entity + its shape's area --Light::build_area--> Light::Area
//! ```

use super::gonio::Goniometric;
use super::{
    sunsky, AreaLight, DistantLight, Emission, EmissionProfile, InfiniteLight, Light, LightColor,
    LightCommon, MovingLight, PointLight, PrimShape, PrimitiveLight, SpotLight, PRIMITIVE_KINDS,
};
use crate::fileio::SceneFiles;
use crate::geometry::motion::MotionTransform;
use crate::lxs::{Entity, LightDesc, ParamSet};
use crate::plugin::BuildError;
use crate::spectrum::{illuminant_y, Rgb};
use crate::texture::{image_io, param_loc, TextureSet};
use glam::Mat4;
use std::sync::Arc;

/// The `LightSource` plugin names luxfarm builds.
pub const KINDS: &str =
    "point, goniometric, projection, spot, distant, infinite, sun, sky, sunsky, sky2, sunsky2, rectangle, disc, sphere, cylinder";

impl Light {
    /// Builds the light(s) of a `LightSource` statement; `group` is its film light group.
    /// A light placed by a moving object instance moves with it: lights with a position and
    /// lights at infinity through [`MovingLight`], area primitives by rebuilding their shape
    /// at each time ([`PrimitiveLight::with_motion`]).
    pub fn build(
        ld: &LightDesc,
        group: usize,
        textures: &mut TextureSet,
        files: &SceneFiles,
    ) -> Result<Vec<Light>, BuildError> {
        let e = &ld.entity;
        if ld.light_to_world.is_animated() {
            tracing::warn!(
                "{}: LightSource \"{}\": a light inside MotionBegin does not move (as in \
                 LuxRender): using its first key; a light moves inside an object instanced \
                 with motion",
                e.loc,
                e.kind
            );
        }
        let l2w = ld.light_to_world.start();
        let Some(keys) = ld.instance_motion.as_ref().filter(|m| m.is_animated()) else {
            let l2w = match &ld.instance_motion {
                Some(m) => m.start() * l2w,
                None => l2w,
            };
            return Light::build_at(ld, l2w.as_mat4(), group, textures, files);
        };
        let Some(motion) = MotionTransform::from_matrices(&keys.keys) else {
            tracing::warn!(
                "{}: LightSource \"{}\": its instance's motion keys are singular or not \
                 finite: using the first key",
                e.loc,
                e.kind
            );
            return Light::build_at(ld, (keys.start() * l2w).as_mat4(), group, textures, files);
        };
        if PRIMITIVE_KINDS.contains(&e.kind.as_str()) {
            // An area primitive: built at the first key, its shape rebuilt at each time.
            let first =
                Light::build_at(ld, (keys.start() * l2w).as_mat4(), group, textures, files)?;
            return Ok(first
                .into_iter()
                .map(|l| match l {
                    Light::Primitive(p) => {
                        Light::Primitive(p.with_motion(&e.kind, &e.params, l2w, motion.clone()))
                    }
                    other => other,
                })
                .collect());
        }
        let lights = Light::build_at(ld, l2w.as_mat4(), group, textures, files)?;
        if !lights.iter().all(MovingLight::can_move) {
            tracing::warn!(
                "{}: LightSource \"{}\" in an object instanced with motion does not move: using \
                 the instance's first key",
                e.loc,
                e.kind
            );
            return Light::build_at(ld, (keys.start() * l2w).as_mat4(), group, textures, files);
        }
        Ok(lights
            .into_iter()
            .filter_map(|l| MovingLight::new(l, motion.clone()))
            .map(|m| Light::Moving(Box::new(m)))
            .collect())
    }

    /// Builds the light(s) of a `LightSource` statement placed by `l2w`.
    fn build_at(
        ld: &LightDesc,
        l2w: Mat4,
        group: usize,
        textures: &mut TextureSet,
        files: &SceneFiles,
    ) -> Result<Vec<Light>, BuildError> {
        let e = &ld.entity;
        let p = &e.params;
        let common = LightCommon::from_params(p, group);
        if let Some(built) = sunsky::build(&e.kind, p, l2w, common, &e.loc) {
            return built;
        }
        let color = light_color(textures, &e.kind, p)?;
        if let Some(shape) = PrimShape::build(&e.kind, p, l2w) {
            let err =
                |m: String| BuildError::new(&e.loc, format!("LightSource \"{}\": {m}", e.kind));
            let light = PrimitiveLight::new(p, &color, common, shape.map_err(err)?).map_err(err)?;
            return Ok(vec![Light::Primitive(light)]);
        }
        Ok(vec![match e.kind.as_str() {
            "point" | "goniometric" => {
                let profile = Goniometric::from_params(p, files)
                    .map_err(|(name, m)| BuildError::new(&param_loc(p, name, &e.loc), m))?;
                if e.kind == "goniometric" && profile.is_none() {
                    return Err(BuildError::new(
                        &e.loc,
                        "LightSource \"goniometric\" needs a \"mapname\"".to_string(),
                    ));
                }
                Light::Point(PointLight::with_profile(p, l2w, &color, common, profile))
            }
            "projection" => {
                let slide = Goniometric::projection_from_params(p, files)
                    .map_err(|(name, m)| BuildError::new(&param_loc(p, name, &e.loc), m))?;
                Light::Point(PointLight::projection(p, l2w, &color, common, slide))
            }
            "spot" => {
                let profile = Goniometric::from_params(p, files)
                    .map_err(|(name, m)| BuildError::new(&param_loc(p, name, &e.loc), m))?;
                Light::Spot(SpotLight::with_profile(p, l2w, &color, common, profile))
            }
            "distant" => Light::Distant(DistantLight::new(p, l2w, &color, common)),
            "infinite" | "infinitesample" => {
                let map = match p.string("mapname").filter(|s| !s.is_empty()) {
                    Some(name) => Some(
                        image_io::load_scene_rgb(files, name)
                            .map_err(|m| BuildError::new(&param_loc(p, "mapname", &e.loc), m))?,
                    ),
                    None => None,
                };
                let l = InfiniteLight::new(p, l2w, &color, map, common)
                    .map_err(|m| BuildError::new(&e.loc, m))?;
                Light::Infinite(Box::new(l))
            }
            other => {
                return Err(BuildError::new(
                    &e.loc,
                    format!("LightSource \"{other}\" is not supported by luxfarm yet ({KINDS})"),
                ))
            }
        }])
    }

    /// Builds an `AreaLightSource` on emitter `emitter` (its index among the scene's emitting
    /// shapes), whose surface area is `area`; `files` opens its `iesname`/`mapname`.
    pub fn build_area(
        entity: &Entity,
        group: usize,
        textures: &mut TextureSet,
        (emitter, area): (u32, f32),
        files: &SceneFiles,
    ) -> Result<Light, BuildError> {
        if entity.kind != "area" {
            return Err(BuildError::new(
                &entity.loc,
                format!("unknown AreaLightSource \"{}\"", entity.kind),
            ));
        }
        let p = &entity.params;
        let color = light_color(textures, &entity.kind, p)?;
        let common = LightCommon::from_params(p, group);
        let profile = EmissionProfile::from_params(p)
            .map_err(|m| BuildError::new(&entity.loc, format!("AreaLightSource \"area\": {m}")))?;
        let gonio = Goniometric::from_params(p, files)
            .map_err(|(name, m)| BuildError::new(&param_loc(p, name, &entity.loc), m))?;
        Ok(Light::Area(AreaLight::with_ies(
            p, &color, emitter, area, common, profile, gonio,
        )))
    }
}

/// The `L` parameter (colour or texture; white by default) with its luminance. The LuxRender
/// scene-format document names the colour of point, spot, goniometric and projection lights
/// `I` (pbrt's name); LuxRender 1.x reads `L` for every light, so `I` is taken for those four
/// when a scene gives no `L`.
fn light_color(
    textures: &mut TextureSet,
    kind: &str,
    p: &ParamSet,
) -> Result<LightColor, BuildError> {
    let intensity_named_i = matches!(kind, "point" | "spot" | "goniometric" | "projection");
    let name = if intensity_named_i && !p.contains("L") && p.contains("I") {
        "I"
    } else {
        "L"
    };
    let tex = textures.color_param(p, name, Rgb::WHITE)?;
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
