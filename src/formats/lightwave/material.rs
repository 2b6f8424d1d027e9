//! Mapping a LightWave surface onto LuxRender materials, textures and emission.
//!
//! ```text
//! Surface --base: matte (no specular) or glossy (Ks = specular × highlight colour,
//!           roughness from glossiness)--> + mirror by reflection + glass by transparency
//!           (mix materials) --> named materials; luminosity --> area light colour;
//!         image layers on COLR/DIFF --> imagemap textures (+ the mesh's uv source)
//! ```
//!
//! What maps exactly: the diffuse colour (colour × diffuse, LightWave's Lambert term once
//! lights are scaled by π, see lights.rs), image colour and diffuse layers with UV maps and
//! planar/cylindrical/spherical/cubic projections, opacity of a single layer (a mix texture),
//! luminosity as emitted radiance. What is approximate (documented, no warning each time):
//! specular highlights become a Schlick glossy coat with reflectance = specular level and
//! roughness √(2/(n+2)) for LightWave's Phong exponent n = 2^(10·gloss+2); reflection and
//! transparency are stochastic mixes with a mirror and a glass. Not rendered, with a warning:
//! translucency, bump, procedural/gradient/shader layers, layers on other channels, negative
//! images, front projection, mirrored wrapping, further layers on a channel.

use super::model::{BlockKind, Projection, Surface, TexBlock};
use crate::lxs::{ParamSet, ParamValue};

/// A texture to declare: `Texture name value_type kind params`.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureDef {
    pub name: String,
    pub value_type: &'static str,
    pub kind: &'static str,
    pub params: ParamSet,
}

/// A named material to declare (`params` holds its `string type`).
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialDef {
    pub name: String,
    pub params: ParamSet,
}

/// Everything a surface becomes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfacePlan {
    pub textures: Vec<TextureDef>,
    /// In declaration order; the last one is the surface's material.
    pub materials: Vec<MaterialDef>,
    /// Emitted radiance of a luminous surface.
    pub emission: Option<[f32; 3]>,
    /// The texture layer whose coordinates the mesh must carry.
    pub uv_block: Option<usize>,
    /// Emits from both sides (LightWave's double-sided surfaces).
    pub double_sided: bool,
    pub warnings: Vec<String>,
}

impl SurfacePlan {
    /// The name of the surface's material.
    pub fn material_name(&self) -> &str {
        self.materials.last().map_or("", |m| m.name.as_str())
    }
}

pub fn color(c: [f32; 3]) -> ParamValue {
    ParamValue::Color(vec![c])
}

pub fn float(v: f32) -> ParamValue {
    ParamValue::Float(vec![v])
}

pub fn string(s: &str) -> ParamValue {
    ParamValue::String(vec![s.to_string()])
}

fn params(list: Vec<(&str, ParamValue)>) -> ParamSet {
    let mut ps = ParamSet::new();
    for (k, v) in list {
        ps.add(k, v);
    }
    ps
}

/// Roughness of the glossy coat for a LightWave glossiness in [0, 1].
pub fn roughness(glossiness: f32) -> f32 {
    let n = 2f32.powf(10.0 * glossiness.clamp(0.0, 1.0) + 2.0);
    (2.0 / (n + 2.0)).sqrt()
}

fn channel_name(c: [u8; 4]) -> String {
    String::from_utf8_lossy(&c).trim().to_string()
}

/// Plans surface `s` under the name `prefix`. `image` resolves an image layer's file to a
/// texture `filename` (or a reason it cannot).
pub fn plan(
    s: &Surface,
    prefix: &str,
    image: &mut dyn FnMut(&TexBlock) -> Result<String, String>,
) -> SurfacePlan {
    let mut out = SurfacePlan {
        double_sided: s.double_sided,
        ..SurfacePlan::default()
    };
    let colr = image_layer(s, prefix, *b"COLR", image, &mut out);
    let diff = image_layer(s, prefix, *b"DIFF", image, &mut out);
    report_unrendered_layers(s, &mut out);
    let coords = |i: usize| -> (Projection, Option<&str>) {
        let b = &s.blocks[i];
        (b.projection, b.uv_map.as_deref())
    };
    out.uv_block = colr.as_ref().or(diff.as_ref()).map(|l| l.block);
    if let (Some(a), Some(b)) = (&colr, &diff) {
        if coords(a.block) != coords(b.block) {
            out.warnings.push(format!(
                "surface \"{}\": the diffuse image uses other coordinates than the colour image: rendered with the colour image's",
                s.name
            ));
        }
    }
    let kd = kd_param(s, prefix, colr.as_ref(), diff.as_ref(), &mut out);
    let base = if s.specular > 0.0 {
        let hl = [0, 1, 2].map(|i| s.specular * (1.0 + s.color_highlights * (s.color[i] - 1.0)));
        let r = roughness(s.glossiness);
        params(vec![
            ("type", string("glossy")),
            ("Kd", kd),
            ("Ks", color(hl)),
            ("uroughness", float(r)),
            ("vroughness", float(r)),
        ])
    } else {
        params(vec![("type", string("matte")), ("Kd", kd)])
    };
    let mut current = format!("{prefix}.base");
    out.materials.push(MaterialDef {
        name: current.clone(),
        params: base,
    });
    if s.reflection > 0.0 {
        let mirror = format!("{prefix}.mirror");
        out.materials.push(MaterialDef {
            name: mirror.clone(),
            params: params(vec![("type", string("mirror")), ("Kr", color([1.0; 3]))]),
        });
        current = mix(
            &mut out,
            &current,
            &mirror,
            s.reflection,
            &format!("{prefix}.refl"),
        );
    }
    if s.transparency > 0.0 {
        let glass = format!("{prefix}.glass");
        let kt = [0, 1, 2].map(|i| 1.0 + s.color_filter * (s.color[i] - 1.0));
        out.materials.push(MaterialDef {
            name: glass.clone(),
            params: params(vec![
                ("type", string("glass")),
                ("Kr", color([1.0; 3])),
                ("Kt", color(kt)),
                ("index", float(s.index.max(1.0))),
            ]),
        });
        current = mix(
            &mut out,
            &current,
            &glass,
            s.transparency,
            &format!("{prefix}.tran"),
        );
    }
    // The last material declared is the surface's: it takes the surface's own name (nothing
    // refers to it under its working name).
    if let Some(last) = out.materials.last_mut() {
        debug_assert_eq!(last.name, current);
        last.name = prefix.to_string();
    }
    if s.luminosity > 0.0 {
        out.emission = Some(s.color.map(|c| c * s.luminosity));
        if colr.is_some() {
            out.warnings.push(format!(
                "surface \"{}\": a luminous surface emits its base colour, not its colour image",
                s.name
            ));
        }
    }
    if s.translucency > 0.0 {
        out.warnings.push(format!(
            "surface \"{}\": translucency is not rendered",
            s.name
        ));
    }
    out
}

/// A mix of two named materials (`amount` of the second); returns the mix's name.
fn mix(out: &mut SurfacePlan, a: &str, b: &str, amount: f32, name: &str) -> String {
    out.materials.push(MaterialDef {
        name: name.to_string(),
        params: params(vec![
            ("type", string("mix")),
            ("namedmaterial1", string(a)),
            ("namedmaterial2", string(b)),
            ("amount", float(amount.clamp(0.0, 1.0))),
        ]),
    });
    name.to_string()
}

/// An image layer that will be rendered.
struct ImageLayer {
    /// Index into the surface's blocks.
    block: usize,
    /// The imagemap texture's name.
    texture: String,
    opacity: f32,
}

/// The top enabled image layer on `channel` that resolves to a file, declared as an imagemap
/// texture named `{prefix}.{channel}`.
fn image_layer(
    s: &Surface,
    prefix: &str,
    channel: [u8; 4],
    image: &mut dyn FnMut(&TexBlock) -> Result<String, String>,
    out: &mut SurfacePlan,
) -> Option<ImageLayer> {
    let layers: Vec<usize> = (0..s.blocks.len())
        .filter(|&i| {
            let b = &s.blocks[i];
            b.enabled && b.channel == channel && b.kind == BlockKind::Image
        })
        .collect();
    let ch = channel_name(channel);
    if layers.len() > 1 {
        out.warnings.push(format!(
            "surface \"{}\": {} image layers on {ch}: only the top one is rendered",
            s.name,
            layers.len()
        ));
    }
    // LightWave lists layers bottom first; the last is on top.
    let &i = layers.last()?;
    let b = &s.blocks[i];
    let warn = |out: &mut SurfacePlan, what: &str| {
        out.warnings
            .push(format!("surface \"{}\": {ch} image layer: {what}", s.name));
    };
    if b.projection == Projection::Front {
        warn(out, "front projection is not supported: layer not rendered");
        return None;
    }
    if b.negative {
        warn(out, "negative images are rendered as positives");
    }
    if b.wrap.0 == 2 || b.wrap.1 == 2 {
        warn(out, "mirrored wrapping is rendered as repeat");
    }
    let file = match image(b) {
        Ok(f) => f,
        Err(why) => {
            warn(out, &format!("{why}: layer not rendered"));
            return None;
        }
    };
    let wrap = match b.wrap.0 {
        0 => "black",
        3 => "clamp",
        _ => "repeat",
    };
    let texture = format!("{prefix}.{}", ch.to_lowercase());
    out.textures.push(TextureDef {
        name: texture.clone(),
        value_type: "color",
        kind: "imagemap",
        params: params(vec![
            ("filename", string(&file)),
            ("gamma", float(1.0)),
            ("wrap", string(wrap)),
            ("mapping", string("uv")),
        ]),
    });
    Some(ImageLayer {
        block: i,
        texture,
        opacity: b.opacity.clamp(0.0, 1.0),
    })
}

/// A layer over a base value: the image itself when opaque, else mix(base, image, opacity).
fn over_base(out: &mut SurfacePlan, layer: &ImageLayer, base: [f32; 3], name: String) -> String {
    if layer.opacity >= 1.0 {
        return layer.texture.clone();
    }
    out.textures.push(TextureDef {
        name: name.clone(),
        value_type: "color",
        kind: "mix",
        params: params(vec![
            ("amount", float(layer.opacity)),
            ("tex1", color(base)),
            ("tex2", ParamValue::Texture(layer.texture.clone())),
        ]),
    });
    name
}

/// `Kd`: colour (or colour image) × diffuse (or diffuse image), with layer opacities.
fn kd_param(
    s: &Surface,
    prefix: &str,
    colr: Option<&ImageLayer>,
    diff: Option<&ImageLayer>,
    out: &mut SurfacePlan,
) -> ParamValue {
    let d = s.diffuse;
    let tex1 = match colr {
        Some(l) => ParamValue::Texture(over_base(out, l, s.color, format!("{prefix}.colr.mix"))),
        None if diff.is_none() => return color(s.color.map(|c| c * d)),
        None => color(s.color),
    };
    let tex2 = match diff {
        Some(l) => ParamValue::Texture(over_base(out, l, [d; 3], format!("{prefix}.diff.mix"))),
        None => color([d; 3]),
    };
    let kd = format!("{prefix}.kd");
    out.textures.push(TextureDef {
        name: kd.clone(),
        value_type: "color",
        kind: "scale",
        params: params(vec![("tex1", tex1), ("tex2", tex2)]),
    });
    ParamValue::Texture(kd)
}

/// Warnings for enabled layers the mapping does not render.
fn report_unrendered_layers(s: &Surface, out: &mut SurfacePlan) {
    for b in s.blocks.iter().filter(|b| b.enabled) {
        let ch = channel_name(b.channel);
        let what = match (&b.kind, &b.channel) {
            (BlockKind::Image, b"COLR" | b"DIFF") => continue,
            (BlockKind::Image, b"BUMP") => "bump maps are not rendered".to_string(),
            (BlockKind::Image, _) => format!("image layers on {ch} are not rendered"),
            (BlockKind::Procedural(n), _) => {
                format!("procedural texture \"{n}\" on {ch} is not rendered")
            }
            (BlockKind::Gradient, _) => format!("gradient on {ch} is not rendered"),
            (BlockKind::Shader(n), _) => format!("shader \"{n}\" is not rendered"),
        };
        let msg = format!("surface \"{}\": {what}", s.name);
        if !out.warnings.contains(&msg) {
            out.warnings.push(msg);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn no_images(_: &TexBlock) -> Result<String, String> {
        Err("no image".into())
    }

    #[test]
    fn diffuse_only_is_matte() {
        let mut s = Surface::default_named("A");
        s.color = [0.5, 0.5, 0.5];
        s.diffuse = 0.8;
        let p = plan(&s, "obj:A", &mut no_images);
        assert_eq!(p.materials.len(), 1);
        let m = &p.materials[0];
        assert_eq!(m.name, "obj:A");
        assert_eq!(m.params.string("type"), Some("matte"));
        assert_eq!(m.params.color("Kd"), Some([0.4, 0.4, 0.4]));
        assert!(p.emission.is_none());
    }

    #[test]
    fn specular_reflection_transparency_and_luminosity() {
        let mut s = Surface::default_named("B");
        s.specular = 0.5;
        s.glossiness = 0.4;
        s.reflection = 0.25;
        s.transparency = 0.5;
        s.index = 1.5;
        s.luminosity = 2.0;
        s.color = [1.0, 0.5, 0.0];
        let p = plan(&s, "o:B", &mut no_images);
        let names: Vec<&str> = p.materials.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(
            names,
            vec!["o:B.base", "o:B.mirror", "o:B.refl", "o:B.glass", "o:B"]
        );
        assert_eq!(p.materials[0].params.string("type"), Some("glossy"));
        assert!(
            (p.materials[0].params.float("uroughness").unwrap() - (2.0f32 / 66.0).sqrt()).abs()
                < 1e-6
        );
        let last = p.materials.last().unwrap();
        assert_eq!(last.params.string("type"), Some("mix"));
        assert_eq!(last.params.string("namedmaterial1"), Some("o:B.refl"));
        assert_eq!(last.params.float("amount"), Some(0.5));
        assert_eq!(p.emission, Some([2.0, 1.0, 0.0]));
        assert_eq!(p.material_name(), "o:B");
    }

    #[test]
    fn colour_image_makes_textures_and_picks_uvs() {
        let mut s = Surface::default_named("C");
        let mut b = TexBlock::new(*b"COLR", BlockKind::Image, 0);
        b.projection = Projection::Uv;
        b.uv_map = Some("uv".into());
        b.opacity = 0.5;
        s.blocks.push(b);
        s.blocks.push(TexBlock::new(
            *b"BUMP",
            BlockKind::Procedural("Turbulence".into()),
            0,
        ));
        let p = plan(&s, "o:C", &mut |_| Ok("img.png".into()));
        assert_eq!(p.uv_block, Some(0));
        let names: Vec<&str> = p.textures.iter().map(|t| t.name.as_str()).collect();
        assert_eq!(names, vec!["o:C.colr", "o:C.colr.mix", "o:C.kd"]);
        assert_eq!(p.textures[0].params.string("filename"), Some("img.png"));
        assert_eq!(p.warnings.len(), 1, "{:?}", p.warnings);
        let missing = plan(&s, "o:C", &mut no_images);
        assert!(missing.uv_block.is_none());
        assert!(missing.warnings.iter().any(|w| w.contains("no image")));
    }
}
