//! `blender_musgrave`: Musgrave's fractals over a noise basis. `type`: `multifractal` (the
//! default), `ridged_multifractal`, `hybrid_multifractal`, `hetero_terrain`, `fbm`; `h` (1),
//! `lacu` (2), `octs` (2), `gain` (1), `offset` (1), `noisesize` (0.25, the point is divided by
//! it), `outscale` (1, scales the result), `noisebasis`.

use super::noiselib::Fractal;
use super::{BriCont, Params, TexResult};
use crate::texture::TextureError;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    MultiFractal,
    Ridged,
    Hybrid,
    HeteroTerrain,
    Fbm,
}

#[derive(Debug)]
pub struct Musgrave {
    pub kind: Kind,
    pub fractal: Fractal,
    pub size: f32,
    pub outscale: f32,
}

impl Musgrave {
    pub fn eval(&self, p: [f32; 3], bc: &BriCont) -> TexResult {
        let q = p.map(|c| c / self.size);
        let f = &self.fractal;
        let v = match self.kind {
            Kind::MultiFractal => f.multifractal(q),
            Kind::Fbm => f.fbm(q),
            Kind::Ridged => f.ridged(q),
            Kind::Hybrid => f.hybrid(q),
            Kind::HeteroTerrain => f.hetero_terrain(q),
        };
        TexResult::int(bc.int(self.outscale * v))
    }
}

pub fn build(p: &mut Params) -> Result<Musgrave, TextureError> {
    let kind = p.choice("type", None, ("multifractal", Kind::MultiFractal), |s| {
        Some(match s {
            "multifractal" => Kind::MultiFractal,
            "ridged_multifractal" => Kind::Ridged,
            "hybrid_multifractal" => Kind::Hybrid,
            "hetero_terrain" => Kind::HeteroTerrain,
            "fbm" => Kind::Fbm,
            _ => return None,
        })
    });
    let basis = p.basis("noisebasis");
    Ok(Musgrave {
        kind,
        fractal: Fractal {
            h: p.float("h", None, 1.0)?,
            lacunarity: p.float("lacu", None, 2.0)?,
            octaves: p.float("octs", None, 2.0)?,
            offset: p.float("offset", None, 1.0)?,
            gain: p.float("gain", None, 1.0)?,
            basis,
        },
        size: p.noise_size()?,
        outscale: p.float("outscale", None, 1.0)?,
    })
}
