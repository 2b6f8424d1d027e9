//! [`TextureSet`]: builds the textures a scene references, on first use, and caches them with
//! the images and image pyramids they load. Parameters of materials and lights that may be
//! textures go through [`TextureSet::color_param`], [`TextureSet::float_param`] and
//! [`TextureSet::fresnel_param`] (a `texture` reference, a constant, or the default).

use super::image_io::ImageCache;
use super::mapping::{Mapping3D, ObjectFrames};
use super::{
    build_fresnel, build_node, param_loc, type_name, ColorTex, FloatTex, Fresnel, FresnelNode,
    FresnelTex, TexNode, TextureCtx, TextureError,
};
use crate::lxs::{Diagnostic, Loc, ParamSet, SceneDescription, TextureDesc, TextureType};
use crate::plugin::report_unused;
use crate::spectrum::Rgb;
use glam::{Affine3A, DMat4};
use std::collections::HashMap;
use std::sync::Arc;

/// A built texture of either tree.
#[derive(Clone, Debug)]
enum Built {
    Node(Arc<TexNode>),
    Fresnel(Arc<FresnelNode>),
}

/// Builds referenced textures on demand and caches them (and their images).
pub struct TextureSet<'a> {
    desc: &'a SceneDescription,
    pub(crate) ctx: TextureCtx,
    built: HashMap<(TextureType, String), Built>,
    building: Vec<(TextureType, String)>,
    pub(crate) images: ImageCache,
    frames: Option<ObjectFrames>,
    /// Non-fatal problems (unsupported options that fell back, unused parameters), located.
    pub warnings: Vec<Diagnostic>,
}

impl<'a> TextureSet<'a> {
    pub fn new(desc: &'a SceneDescription, ctx: TextureCtx) -> TextureSet<'a> {
        TextureSet {
            desc,
            ctx,
            built: HashMap::new(),
            building: Vec::new(),
            images: ImageCache::default(),
            frames: None,
            warnings: Vec::new(),
        }
    }

    /// Number of distinct image files loaded so far.
    pub fn images_loaded(&self) -> usize {
        self.images.len()
    }

    /// Names of the textures built so far.
    pub fn built_names(&self) -> Vec<String> {
        let mut v: Vec<String> = self.built.keys().map(|k| k.1.clone()).collect();
        v.sort();
        v
    }

    pub(crate) fn warn(&mut self, loc: &Loc, message: String) {
        crate::plugin::warn(&mut self.warnings, loc, message);
    }

    /// A colour parameter: a `texture` reference, a constant `color`, a `float` (grey), or the
    /// default.
    pub fn color_param(
        &mut self,
        params: &ParamSet,
        name: &str,
        default: Rgb,
    ) -> Result<ColorTex, TextureError> {
        Ok(ColorTex(self.node_param(
            TextureType::Color,
            params,
            name,
            default,
        )?))
    }

    /// A float parameter: a `texture` reference, a constant `float`, or the default.
    pub fn float_param(
        &mut self,
        params: &ParamSet,
        name: &str,
        default: f32,
    ) -> Result<FloatTex, TextureError> {
        Ok(FloatTex(self.node_param(
            TextureType::Float,
            params,
            name,
            Rgb::splat(default),
        )?))
    }

    /// An optional float texture parameter (`bumpmap`): `None` when absent.
    pub fn optional_float(
        &mut self,
        params: &ParamSet,
        name: &str,
    ) -> Result<Option<FloatTex>, TextureError> {
        if !params.contains(name) {
            return Ok(None);
        }
        self.float_param(params, name, 0.0).map(Some)
    }

    /// A fresnel parameter (metal2's `fresnel`, the volumes' `fresnel`): a `texture` reference
    /// to a fresnel texture, or a constant `float` index of refraction (LuxRender's
    /// `GetFresnelTexture`), or `default_index`.
    pub fn fresnel_param(
        &mut self,
        params: &ParamSet,
        name: &str,
        default_index: f32,
    ) -> Result<FresnelTex, TextureError> {
        Ok(FresnelTex(self.fresnel_node_param(
            params,
            name,
            default_index,
        )?))
    }

    pub(crate) fn fresnel_node_param(
        &mut self,
        params: &ParamSet,
        name: &str,
        default_index: f32,
    ) -> Result<Arc<FresnelNode>, TextureError> {
        if let Some(tex) = params.texture(name) {
            let tex = tex.to_string();
            let loc = param_loc(params, name, &Loc::default());
            return self.named_fresnel(&tex, &loc);
        }
        let index = params.float(name).unwrap_or(default_index);
        Ok(Arc::new(FresnelNode::Const(Fresnel::dielectric(index))))
    }

    pub(crate) fn node_param(
        &mut self,
        ty: TextureType,
        params: &ParamSet,
        name: &str,
        default: Rgb,
    ) -> Result<Arc<TexNode>, TextureError> {
        if let Some(tex) = params.texture(name) {
            let tex = tex.to_string();
            let loc = param_loc(params, name, &Loc::default());
            return self.named(ty, &tex, &loc);
        }
        if ty == TextureType::Color {
            if let Some(c) = params.color(name) {
                return Ok(Arc::new(TexNode::Const(Rgb::from_array(c))));
            }
        }
        if let Some(v) = params.float(name) {
            return Ok(Arc::new(TexNode::Const(Rgb::splat(v))));
        }
        Ok(Arc::new(TexNode::Const(default)))
    }

    /// The float or colour texture `name` of type `ty`, built on first use.
    pub fn named(
        &mut self,
        ty: TextureType,
        name: &str,
        loc: &Loc,
    ) -> Result<Arc<TexNode>, TextureError> {
        match self.get(ty, name, loc)? {
            Built::Node(n) => Ok(n),
            Built::Fresnel(_) => Err(TextureError::Missing {
                loc: loc.clone(),
                ty: type_name(ty).to_string(),
                name: name.to_string(),
            }),
        }
    }

    /// The fresnel texture `name`, built on first use; a float or colour texture of that name
    /// is reported as the wrong kind.
    pub fn named_fresnel(
        &mut self,
        name: &str,
        loc: &Loc,
    ) -> Result<Arc<FresnelNode>, TextureError> {
        if self.desc.texture(TextureType::Fresnel, name).is_none() {
            let other = [TextureType::Float, TextureType::Color]
                .into_iter()
                .find(|&o| self.desc.texture(o, name).is_some());
            if let Some(o) = other {
                return Err(TextureError::WrongType {
                    loc: loc.clone(),
                    ty: "fresnel".to_string(),
                    name: name.to_string(),
                    actual: type_name(o).to_string(),
                });
            }
        }
        match self.get(TextureType::Fresnel, name, loc)? {
            Built::Fresnel(n) => Ok(n),
            Built::Node(_) => Err(TextureError::Missing {
                loc: loc.clone(),
                ty: "fresnel".to_string(),
                name: name.to_string(),
            }),
        }
    }

    fn get(&mut self, ty: TextureType, name: &str, loc: &Loc) -> Result<Built, TextureError> {
        let key = (ty, name.to_string());
        if let Some(b) = self.built.get(&key) {
            return Ok(b.clone());
        }
        if self.building.contains(&key) {
            return Err(TextureError::Cycle {
                loc: loc.clone(),
                name: name.to_string(),
            });
        }
        let desc = self.desc;
        let Some(tdesc) = desc.texture(ty, name) else {
            return Err(TextureError::Missing {
                loc: loc.clone(),
                ty: type_name(ty).to_string(),
                name: name.to_string(),
            });
        };
        self.building.push(key.clone());
        let built = match ty {
            TextureType::Fresnel => build_fresnel(self, tdesc).map(|n| Built::Fresnel(Arc::new(n))),
            _ => build_node(self, tdesc).map(|n| Built::Node(Arc::new(n))),
        };
        self.building.pop();
        let built = built?;
        report_unused("Texture", &tdesc.entity, &mut self.warnings);
        tracing::debug!(
            "built {} texture \"{name}\" ({})",
            type_name(ty),
            tdesc.entity.kind
        );
        self.built.insert(key, built.clone());
        Ok(built)
    }

    /// The two operands `tex1`/`tex2` of a binary texture, typed like the texture itself.
    pub(crate) fn operands(
        &mut self,
        t: &TextureDesc,
        d1: f32,
        d2: f32,
    ) -> Result<(Arc<TexNode>, Arc<TexNode>), TextureError> {
        let p = &t.entity.params;
        let a = self.node_param(t.value_type, p, "tex1", Rgb::splat(d1))?;
        let b = self.node_param(t.value_type, p, "tex2", Rgb::splat(d2))?;
        Ok((a, b))
    }

    /// A sub-texture parameter typed like the texture being built.
    pub(crate) fn same_type(
        &mut self,
        t: &TextureDesc,
        name: &str,
        default: f32,
    ) -> Result<Arc<TexNode>, TextureError> {
        self.node_param(t.value_type, &t.entity.params, name, Rgb::splat(default))
    }

    /// The `amount`-like float parameter of a texture.
    pub(crate) fn float_of(
        &mut self,
        t: &TextureDesc,
        name: &str,
        default: f32,
    ) -> Result<Arc<TexNode>, TextureError> {
        self.node_param(
            TextureType::Float,
            &t.entity.params,
            name,
            Rgb::splat(default),
        )
    }

    /// The 3D mapping of a texture (`coordinates`, `scale`, `rotate`, `translate`), with a
    /// located warning for unknown coordinate systems.
    pub(crate) fn mapping3d(&mut self, t: &TextureDesc) -> Mapping3D {
        let (m, warning) = Mapping3D::from_desc(t, || self.object_frames());
        if let Some(w) = warning {
            let loc = param_loc(&t.entity.params, "coordinates", &t.entity.loc);
            self.warn(&loc, w);
        }
        m
    }

    /// World-to-object transforms of the scene's primitives, indexed like
    /// `SurfaceInteraction::prim` (built on the first `local`/`localnormal` mapping). The
    /// numbering is the world build's (`scene::geometry`): world shapes that are not portals
    /// in order, then the shapes of each object in the order objects are first instanced.
    /// Shapes of objects use their transform inside the object.
    pub(crate) fn object_frames(&mut self) -> ObjectFrames {
        if let Some(f) = &self.frames {
            return f.clone();
        }
        let d = self.desc;
        let inverse = |m: DMat4| -> Affine3A {
            if m.determinant().abs() > 1e-300 {
                Affine3A::from_mat4(m.inverse().as_mat4())
            } else {
                Affine3A::IDENTITY
            }
        };
        let mut v: Vec<Affine3A> = d
            .shapes
            .iter()
            .filter(|s| !s.portal)
            .map(|s| inverse(s.object_to_world.start()))
            .collect();
        let mut seen = Vec::new();
        for inst in d.instances.iter().filter(|i| !i.portal) {
            if seen.contains(&inst.object) {
                continue;
            }
            seen.push(inst.object);
            if let Some(obj) = d.objects.get(inst.object) {
                v.extend(
                    obj.shapes
                        .iter()
                        .map(|s| inverse(s.object_to_world.start())),
                );
            }
        }
        let f = ObjectFrames(Arc::from(v));
        self.frames = Some(f.clone());
        f
    }
}
