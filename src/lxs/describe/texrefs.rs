//! Texture references (`"texture Kd" "wood"`): checked against the textures in scope when the
//! referencing statement is read, and bound exactly as LuxRender binds them.
//!
//! LuxRender resolves a texture name when the material (or texture, or light) is created, in
//! the namespaces of the current graphics state, which AttributeBegin/AttributeEnd scope. The
//! description refers to textures by name and `named_textures` keeps the definition in force
//! at the end of the file, so where a name was redefined (or shadowed in a block) a reference
//! can mean an earlier definition: [`bind_aliases`] then rewrites such references to a unique
//! alias `name@INDEX` registered in `named_textures`. Named materials referenced by mix and
//! layered materials (`"string namedmaterial1"`) get the same treatment in `named_materials`.

use super::refs;
pub use super::state::Binding;
use super::state::GraphicsState;
use crate::lxs::description::{SceneDescription, TextureType};
use crate::lxs::error::{LxsError, LxsErrorKind, LxsResult};
use crate::lxs::params::{ParamSet, ParamValue};

/// Whose parameter list holds a reference.
#[derive(Clone, Copy, Debug)]
pub enum Owner {
    Material(usize),
    Texture(usize),
    Light(usize),
    /// The area light of a world shape.
    AreaLight(usize),
}

/// Resolves every texture parameter of `params` in the scope of `gs`. `own` is the value type
/// of the texture being defined (None for materials and lights).
pub fn resolve(
    gs: &GraphicsState,
    params: &ParamSet,
    own: Option<TextureType>,
    suggest: impl Fn(&str, &str, Vec<&str>) -> LxsError,
) -> LxsResult<Vec<Binding>> {
    let mut out = Vec::new();
    for (i, p) in params.params.iter().enumerate() {
        let ParamValue::Texture(tex) = &p.value else {
            continue;
        };
        let lookup = |ty: TextureType| gs.textures(ty).get(tex.as_str()).map(|&t| (ty, t));
        let ns = refs::namespace(&p.name, own);
        let found = match ns {
            Some(ty) => lookup(ty),
            None => lookup(TextureType::Float)
                .or_else(|| lookup(TextureType::Color))
                .or_else(|| lookup(TextureType::Fresnel)),
        };
        match found {
            Some((ty, texture)) => out.push(Binding {
                param: i,
                ty,
                texture,
            }),
            None => {
                let what = match ns {
                    Some(TextureType::Float) => "float texture",
                    Some(TextureType::Color) => "color texture",
                    Some(TextureType::Fresnel) => "fresnel texture",
                    None => "texture",
                };
                // The same name in another namespace: say so rather than suggest it.
                let other = match ns {
                    Some(own) => [TextureType::Float, TextureType::Color, TextureType::Fresnel]
                        .into_iter()
                        .filter(|&t| t != own)
                        .find_map(|t| lookup(t).map(|_| type_word(t))),
                    None => None,
                };
                let message = match other {
                    Some(o) => {
                        format!("{what} \"{tex}\" is not defined here (\"{tex}\" is a {o} texture)")
                    }
                    None => {
                        let mut known: Vec<&str> =
                            gs.float_textures.keys().map(String::as_str).collect();
                        known.extend(gs.color_textures.keys().map(String::as_str));
                        known.extend(gs.fresnel_textures.keys().map(String::as_str));
                        suggest(what, tex, known).message
                    }
                };
                return Err(LxsError::new(
                    LxsErrorKind::Undefined,
                    p.loc.clone(),
                    format!("parameter '{}': {message}", p.name),
                ));
            }
        }
    }
    Ok(out)
}

fn type_word(t: TextureType) -> &'static str {
    match t {
        TextureType::Float => "float",
        TextureType::Color => "color",
        TextureType::Fresnel => "fresnel",
    }
}

fn params_of(desc: &mut SceneDescription, owner: Owner) -> Option<&mut ParamSet> {
    Some(match owner {
        Owner::Material(i) => &mut desc.materials.get_mut(i)?.entity.params,
        Owner::Texture(i) => &mut desc.textures.get_mut(i)?.entity.params,
        Owner::Light(i) => &mut desc.lights.get_mut(i)?.entity.params,
        Owner::AreaLight(i) => &mut desc.shapes.get_mut(i)?.area_light.as_mut()?.entity.params,
    })
}

/// Rewrites references whose name no longer maps to the texture they were bound to.
pub fn bind_aliases(desc: &mut SceneDescription, refs: &[(Owner, Binding)]) {
    for &(owner, b) in refs {
        let Some(name) = params_of(desc, owner)
            .and_then(|ps| ps.params.get(b.param))
            .and_then(|p| match &p.value {
                ParamValue::Texture(t) => Some(t.clone()),
                _ => None,
            })
        else {
            continue;
        };
        if desc.named_textures.get(&(b.ty, name.clone())) == Some(&b.texture) {
            continue;
        }
        let alias = format!("{name}@{}", b.texture);
        desc.named_textures.insert((b.ty, alias.clone()), b.texture);
        if let Some(p) = params_of(desc, owner).and_then(|ps| ps.params.get_mut(b.param)) {
            p.value = ParamValue::Texture(alias);
        }
    }
}

/// Rewrites `namedmaterialN` references whose name no longer maps to the material they were
/// bound to. Each entry: (material, parameter, item, bound material).
pub fn bind_material_aliases(desc: &mut SceneDescription, refs: &[(usize, usize, usize, usize)]) {
    for &(m, p, k, bound) in refs {
        let Some(name) = desc
            .materials
            .get(m)
            .and_then(|md| md.entity.params.params.get(p))
            .and_then(|p| match &p.value {
                ParamValue::String(v) => v.get(k).cloned(),
                _ => None,
            })
        else {
            continue;
        };
        if desc.named_materials.get(&name) == Some(&bound) {
            continue;
        }
        let alias = format!("{name}@{bound}");
        desc.named_materials.insert(alias.clone(), bound);
        let item = desc
            .materials
            .get_mut(m)
            .and_then(|md| md.entity.params.params.get_mut(p))
            .and_then(|p| match &mut p.value {
                ParamValue::String(v) => v.get_mut(k),
                _ => None,
            });
        if let Some(item) = item {
            *item = alias;
        }
    }
}
