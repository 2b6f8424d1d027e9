//! The `blender_*` textures (float): LuxRender 1.x's emulation of Blender's procedural
//! textures (one file per texture, the noise library in [`noiselib`] with its bases in
//! [`noise_bases`] and its tables in [`tables`]).
//!
//! ```text
//! hit --3D mapping--> P --<texture>::eval (Blender's texlib: intensity, maybe RGB)-->
//!     BRICONT (bright/contrast, clamp) --RGB? 0.35 r + 0.45 g + 0.2 b--> a
//!     value = lerp(a, tex1, tex2)      (tex1 default 0, tex2 default 1)
//! ```
//!
//! Every one reads `bright` (1), `contrast` (1), `tex1`, `tex2` and the 3D mapping
//! parameters; their own parameters are in their files. Names are LuxRender's
//! (`noisesize`, `noisedepth`, `noisetype`); the `noise_size`/`noise_depth`/`noise_type`
//! spellings of the scene format document are accepted too. Unknown type names fall back to
//! the first type, with a located warning, as in LuxRender. Bump derivatives are LuxRender's:
//! finite differences of the pattern with the world tangents added to the mapped point.

pub mod blend;
pub mod clouds;
pub mod distortednoise;
pub mod magic;
pub mod marble;
pub mod musgrave;
pub mod noise;
pub mod noise_bases;
pub mod noiselib;
pub mod stucci;
pub mod tables;
pub mod voronoi;
pub mod wood;

use super::mapping::Mapping3D;
use super::{param_loc, TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use glam::{Vec2, Vec3A};
use noiselib::NoiseBasis;
use std::sync::Arc;

/// What a Blender pattern gives at a point: an intensity, and a colour for the coloured
/// variants (then the intensity is taken from the colour).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexResult {
    pub tin: f32,
    pub rgb: Option<[f32; 3]>,
}

impl TexResult {
    pub fn int(tin: f32) -> TexResult {
        TexResult { tin, rgb: None }
    }

    /// The value the texture blends with: the intensity, or LuxRender's weighting of the
    /// colour, at most 1.
    pub fn value(&self) -> f32 {
        match self.rgb {
            Some([r, g, b]) => (0.35 * r + 0.45 * g + 0.2 * b).min(1.0),
            None => self.tin,
        }
    }
}

/// Blender's brightness/contrast.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BriCont {
    pub bright: f32,
    pub contrast: f32,
}

impl BriCont {
    /// `BRICONT`: the intensity through contrast and brightness, clamped to [0, 1].
    pub fn int(&self, tin: f32) -> f32 {
        ((tin - 0.5) * self.contrast + self.bright - 0.5).clamp(0.0, 1.0)
    }

    /// `BRICONTRGB`: each channel through contrast and brightness, clamped at 0.
    pub fn rgb(&self, c: [f32; 3]) -> [f32; 3] {
        c.map(|v| ((v - 0.5) * self.contrast + self.bright - 0.5).max(0.0))
    }
}

/// The pattern of one Blender texture.
#[derive(Debug)]
pub enum Pattern {
    Blend(blend::Blend),
    Clouds(clouds::Clouds),
    DistortedNoise(distortednoise::DistortedNoise),
    Magic(magic::Magic),
    Marble(marble::Marble),
    Musgrave(musgrave::Musgrave),
    Noise(noise::Noise),
    Stucci(stucci::Stucci),
    Voronoi(voronoi::Voronoi),
    Wood(wood::Wood),
}

impl Pattern {
    pub fn eval(&self, p: Vec3A, bc: &BriCont) -> TexResult {
        let p = [p.x, p.y, p.z];
        match self {
            Pattern::Blend(t) => t.eval(p, bc),
            Pattern::Clouds(t) => t.eval(p, bc),
            Pattern::DistortedNoise(t) => t.eval(p, bc),
            Pattern::Magic(t) => t.eval(p, bc),
            Pattern::Marble(t) => t.eval(p, bc),
            Pattern::Musgrave(t) => t.eval(p, bc),
            Pattern::Noise(t) => t.eval(p, bc),
            Pattern::Stucci(t) => t.eval(p, bc),
            Pattern::Voronoi(t) => t.eval(p, bc),
            Pattern::Wood(t) => t.eval(p, bc),
        }
    }
}

#[derive(Debug)]
pub struct BlenderTex {
    pub mapping: Mapping3D,
    pub pattern: Pattern,
    pub bricont: BriCont,
    pub tex1: Arc<TexNode>,
    pub tex2: Arc<TexNode>,
}

impl BlenderTex {
    /// The pattern's blend factor at texture-space point `p` (0 where a degenerate parameter,
    /// such as a zero `noisesize` of the Musgrave, Voronoi and distorted noise patterns, makes
    /// it undefined).
    pub fn factor(&self, p: Vec3A) -> f32 {
        let a = self.pattern.eval(p, &self.bricont).value();
        if a.is_finite() {
            a
        } else {
            0.0
        }
    }

    pub fn value(&self, si: &SurfaceInteraction) -> f32 {
        let a = self.factor(self.mapping.map(si));
        let (t1, t2) = (self.tex1.value(si), self.tex2.value(si));
        t1 + a * (t2 - t1)
    }

    /// LuxRender's `BlenderTexture3D::GetDuv`.
    pub fn duv(&self, si: &SurfaceInteraction, delta: f32) -> Vec2 {
        let p = self.mapping.map(si);
        let a = self.factor(p);
        let e = self.tex2.value(si) - self.tex1.value(si);
        let (d1, d2) = (self.tex1.duv(si, delta), self.tex2.duv(si, delta));
        let step = |dir: Vec3A| -> f32 {
            let len = dir.length();
            if !(len > 0.0 && delta > 0.0) {
                return 0.0;
            }
            let h = delta / len;
            let d = (self.factor(p + dir * h) - a) / h;
            if d.is_finite() {
                d
            } else {
                0.0
            }
        };
        let da = Vec2::new(step(si.shading.dpdu), step(si.shading.dpdv));
        d1 * (1.0 - a) + d2 * a + da * e
    }
}

/// The class name's texture kind, when it is a Blender texture.
pub fn kind(class: &str) -> Option<&'static str> {
    Some(match class {
        "blender_blend" => "blend",
        "blender_clouds" => "clouds",
        "blender_distortednoise" => "distortednoise",
        "blender_magic" => "magic",
        "blender_marble" => "marble",
        "blender_musgrave" => "musgrave",
        "blender_noise" => "noise",
        "blender_stucci" => "stucci",
        "blender_voronoi" => "voronoi",
        "blender_wood" => "wood",
        _ => return None,
    })
}

/// Parameter reading shared by the Blender textures.
pub struct Params<'s, 'a, 't> {
    pub set: &'s mut TextureSet<'a>,
    pub t: &'t TextureDesc,
}

impl Params<'_, '_, '_> {
    /// A float parameter under LuxRender's name or the document's alternate spelling.
    pub fn float(
        &self,
        name: &str,
        alias: Option<&str>,
        default: f32,
    ) -> Result<f32, TextureError> {
        let p = &self.t.entity.params;
        let v = p
            .float(name)
            .or_else(|| alias.and_then(|a| p.float(a)))
            .unwrap_or(default);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(TextureError::param(
                self.t,
                name,
                format!("{} {name} must be finite", self.t.entity.kind),
            ))
        }
    }

    pub fn int(&self, name: &str, alias: Option<&str>, default: i32) -> i32 {
        let p = &self.t.entity.params;
        p.int(name)
            .or_else(|| alias.and_then(|a| p.int(a)))
            .unwrap_or(default)
    }

    /// A named choice: `parse` maps names to values; absent, `default`; unknown names take
    /// `default` too, with a located warning (LuxRender's fallback).
    pub fn choice<T>(
        &mut self,
        name: &str,
        alias: Option<&str>,
        default: (&str, T),
        parse: impl Fn(&str) -> Option<T>,
    ) -> T {
        let p = &self.t.entity.params;
        let Some(given) = p
            .string(name)
            .or_else(|| alias.and_then(|a| p.string(a)))
            .map(str::to_string)
        else {
            return default.1;
        };
        if let Some(v) = parse(&given) {
            return v;
        }
        let loc = param_loc(p, name, &self.t.entity.loc);
        self.set.warn(
            &loc,
            format!(
                "{}: unknown {name} \"{given}\": using \"{}\", as LuxRender does",
                self.t.entity.kind, default.0
            ),
        );
        default.1
    }

    /// `noisetype`: hard noise?
    pub fn hard(&mut self) -> bool {
        self.choice(
            "noisetype",
            Some("noise_type"),
            ("soft_noise", false),
            |s| match s {
                "soft_noise" => Some(false),
                "hard_noise" => Some(true),
                _ => None,
            },
        )
    }

    pub fn basis(&mut self, name: &str) -> NoiseBasis {
        self.choice(
            name,
            None,
            ("blender_original", NoiseBasis::BlenderOriginal),
            NoiseBasis::from_name,
        )
    }

    /// `turbulence` (5), or LuxRender's older spelling `turbulance` of magic and stucci.
    pub fn turbulence(&self) -> Result<f32, TextureError> {
        let alias = if self.t.entity.params.contains("turbulence") {
            None
        } else {
            Some("turbulance")
        };
        self.float("turbulence", alias, 5.0)
    }

    pub fn noise_size(&self) -> Result<f32, TextureError> {
        self.float("noisesize", Some("noise_size"), 0.25)
    }

    pub fn noise_depth(&self) -> i32 {
        self.int("noisedepth", Some("noise_depth"), 2)
    }
}

/// Builds a `blender_*` texture of kind `kind`.
pub fn build(set: &mut TextureSet, t: &TextureDesc, kind: &str) -> Result<TexNode, TextureError> {
    let mut params = Params { set: &mut *set, t };
    let pattern = match kind {
        "blend" => Pattern::Blend(blend::build(&mut params)?),
        "clouds" => Pattern::Clouds(clouds::build(&mut params)?),
        "distortednoise" => Pattern::DistortedNoise(distortednoise::build(&mut params)?),
        "magic" => Pattern::Magic(magic::build(&mut params)?),
        "marble" => Pattern::Marble(marble::build(&mut params)?),
        "musgrave" => Pattern::Musgrave(musgrave::build(&mut params)?),
        "noise" => Pattern::Noise(noise::build(&mut params)?),
        "stucci" => Pattern::Stucci(stucci::build(&mut params)?),
        "voronoi" => Pattern::Voronoi(voronoi::build(&mut params)?),
        _ => Pattern::Wood(wood::build(&mut params)?),
    };
    let bricont = BriCont {
        bright: params.float("bright", None, 1.0)?,
        contrast: params.float("contrast", None, 1.0)?,
    };
    let tex1 = set.float_of(t, "tex1", 0.0)?;
    let tex2 = set.float_of(t, "tex2", 1.0)?;
    Ok(TexNode::Blender(Box::new(BlenderTex {
        mapping: set.mapping3d(t),
        pattern,
        bricont,
        tex1,
        tex2,
    })))
}
