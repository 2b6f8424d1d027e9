//! `bilerp` texture: bilinear interpolation of four values over the fractional part of the
//! 2D-mapped (s, t): `v00` at (0, 0), `v01` at (0, 1), `v10` at (1, 0), `v11` at (1, 1)
//! (defaults 0, 1, 0, 1). For float and colour textures the values are constants (as in
//! LuxRender); for fresnel textures they are fresnel textures. The bump derivative is the exact
//! one through the mapping's.

use super::mapping::Mapping2D;
use super::{Fresnel, FresnelNode, TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::{TextureDesc, TextureType};
use crate::spectrum::Rgb;
use glam::Vec2;
use std::sync::Arc;

pub const DEFAULTS: [f32; 4] = [0.0, 1.0, 0.0, 1.0];
const NAMES: [&str; 4] = ["v00", "v01", "v10", "v11"];

fn frac(st: Vec2) -> Vec2 {
    st - st.floor()
}

#[derive(Debug)]
pub struct BilerpTex {
    pub mapping: Mapping2D,
    /// v00, v01, v10, v11.
    pub v: [Rgb; 4],
}

impl BilerpTex {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        let Vec2 { x: s, y: t } = frac(self.mapping.map(si));
        let [v00, v01, v10, v11] = self.v;
        v00 * ((1.0 - s) * (1.0 - t))
            + v01 * ((1.0 - s) * t)
            + v10 * (s * (1.0 - t))
            + v11 * (s * t)
    }

    /// Exact derivative of the first channel.
    pub fn duv(&self, si: &SurfaceInteraction) -> Vec2 {
        let m = self.mapping.map_duv(si);
        let Vec2 { x: s, y: t } = frac(m.st);
        let [v00, v01, v10, v11] = self.v.map(|c| c.r);
        let d = v00 + v11 - v01 - v10;
        let ds = v10 - v00 + t * d;
        let dt = v01 - v00 + s * d;
        Vec2::new(m.d_du.x * ds + m.d_du.y * dt, m.d_dv.x * ds + m.d_dv.y * dt)
    }
}

pub fn build(_set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let p = &t.entity.params;
    let mut v = [Rgb::BLACK; 4];
    for i in 0..4 {
        let d = DEFAULTS[i];
        v[i] = match t.value_type {
            TextureType::Color => p
                .color(NAMES[i])
                .map(Rgb::from_array)
                .or_else(|| p.float(NAMES[i]).map(Rgb::splat))
                .unwrap_or(Rgb::splat(d)),
            _ => Rgb::splat(p.float_or(NAMES[i], d)),
        };
    }
    Ok(TexNode::Bilerp(BilerpTex {
        mapping: Mapping2D::from_params(t)?,
        v,
    }))
}

#[derive(Debug)]
pub struct BilerpFresnel {
    pub mapping: Mapping2D,
    pub v: [Arc<FresnelNode>; 4],
}

impl BilerpFresnel {
    pub fn eval(&self, si: &SurfaceInteraction) -> Fresnel {
        let Vec2 { x: s, y: t } = frac(self.mapping.map(si));
        let [v00, v01, v10, v11] = [0, 1, 2, 3].map(|i| self.v[i].eval(si));
        v00.scaled((1.0 - s) * (1.0 - t))
            .plus(v01.scaled((1.0 - s) * t))
            .plus(v10.scaled(s * (1.0 - t)))
            .plus(v11.scaled(s * t))
    }

    /// The real index at wavelength `nm` (see [`FresnelNode::index_at`]).
    pub fn index_at(&self, si: &SurfaceInteraction, nm: f32) -> f32 {
        let Vec2 { x: s, y: t } = frac(self.mapping.map(si));
        let [v00, v01, v10, v11] = [0, 1, 2, 3].map(|i| self.v[i].index_at(si, nm));
        v00 * (1.0 - s) * (1.0 - t) + v01 * (1.0 - s) * t + v10 * s * (1.0 - t) + v11 * s * t
    }
}

pub fn build_fresnel(set: &mut TextureSet, t: &TextureDesc) -> Result<FresnelNode, TextureError> {
    let p = &t.entity.params;
    let v = [
        set.fresnel_node_param(p, NAMES[0], DEFAULTS[0])?,
        set.fresnel_node_param(p, NAMES[1], DEFAULTS[1])?,
        set.fresnel_node_param(p, NAMES[2], DEFAULTS[2])?,
        set.fresnel_node_param(p, NAMES[3], DEFAULTS[3])?,
    ];
    Ok(FresnelNode::Bilerp(BilerpFresnel {
        mapping: Mapping2D::from_params(t)?,
        v,
    }))
}
