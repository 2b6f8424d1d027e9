//! `cloth`: LuxRender's woven fabric, the Irawan–Marschner model (see
//! [`super::bxdf::irawan`]) over one of its six measured weaves (`presetname`: `denim`, the
//! default, `silk_charmeuse`, `silk_shantung`, `cotton_twill`, `wool_gabardine`,
//! `polyester_lining_cloth`; an unknown name is denim, as in LuxRender, with a located
//! warning) repeated `repeat_u` × `repeat_v` times (default 100 each) over the uv square.
//! Warp and weft yarns have their own colours: `warp_Kd`, `warp_Ks`, `weft_Kd`, `weft_Ks`
//! (colour textures; LuxRender's sources default them to 0, its scene-format page says 0.5).
//! At a hit the BSDF is a Lambertian lobe of the yarn's Kd plus its Irawan lobe of Ks.

use super::bsdf::Lobes;
use super::bxdf::irawan::{ClothLobes, Irawan, WeavePattern};
use super::cloth_patterns::{pattern, PRESETS};
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{param_loc, ColorTex};

#[derive(Debug)]
pub struct Cloth {
    pub weave: WeavePattern,
    /// Specular normalisation of the weave.
    pub norm: f32,
    /// Warp and weft diffuse colours.
    pub kd: [ColorTex; 2],
    /// Warp and weft specular colours.
    pub ks: [ColorTex; 2],
}

impl Cloth {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Cloth, MaterialError> {
        let p = &e.params;
        let mut name = p.string_or("presetname", PRESETS[0]).to_string();
        if !PRESETS.contains(&name.as_str()) {
            b.warn(
                &param_loc(p, "presetname", &e.loc),
                format!(
                    "cloth preset \"{name}\" does not exist: using \"denim\" as LuxRender does"
                ),
            );
            name = PRESETS[0].to_string();
        }
        let repeat = |key: &str| -> Result<f32, MaterialError> {
            let v = p.float_or(key, 100.0);
            if v.is_finite() {
                Ok(v)
            } else {
                Err(MaterialError::BadParam {
                    loc: param_loc(p, key, &e.loc),
                    message: format!("cloth \"{key}\" must be finite, got {v}"),
                })
            }
        };
        let (ru, rv) = (repeat("repeat_u")?, repeat("repeat_v")?);
        let Some(weave) = pattern(&name, ru, rv) else {
            return Err(MaterialError::BadParam {
                loc: e.loc.clone(),
                message: format!("cloth preset \"{name}\" has no pattern"),
            });
        };
        let norm = weave.specular_normalization();
        let t = &mut b.textures;
        Ok(Cloth {
            weave,
            norm,
            kd: [
                t.color_param(p, "warp_Kd", Rgb::BLACK)?,
                t.color_param(p, "weft_Kd", Rgb::BLACK)?,
            ],
            ks: [
                t.color_param(p, "warp_Ks", Rgb::BLACK)?,
                t.color_param(p, "weft_Ks", Rgb::BLACK)?,
            ],
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let Some(hit) = self.weave.yarn_at(si.uv.x, si.uv.y) else {
            return Lobes::Black;
        };
        let i = hit.yarn.weft as usize;
        let clamp = |c: Rgb| c.map(|v| v.clamp(0.0, 1.0));
        let kd = clamp(self.kd[i].eval(si));
        let ks = clamp(self.ks[i].eval(si));
        Lobes::Cloth(ClothLobes {
            kd,
            spec: Irawan::new(ks, &hit, self.weave.params, self.norm * hit.scale),
        })
    }
}
