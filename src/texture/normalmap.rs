//! `normalmap` texture (float): a tangent-space normal map (`filename`, with the image
//! parameters of `imagemap`; `gamma` defaults to 1) for the `bumpmap` slot. Its value is 0;
//! its bump derivatives are LuxRender's: the map's normal (x and y decoded from [0, 1] to
//! [−1, 1], z as stored), taken to world space in the frame of the surface's (s, t) tangents,
//! is turned into the height slopes (dh/ds, dh/dt) that tilt the surface to it, then through
//! the mapping into (u, v) derivatives. Combined with `add`/`mix`/`scale` it adds to other bump
//! textures, as in LuxRender.

use super::imagemap::{image_lookup, Channel, ImageLookup};
use super::mapping::Mapping2D;
use super::{TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;
use glam::{Mat3, Vec2, Vec3};

pub const DEFAULT_GAMMA: f32 = 1.0;

#[derive(Debug)]
pub struct NormalMapTex {
    pub image: ImageLookup,
    pub mapping: Mapping2D,
}

impl NormalMapTex {
    pub fn eval(&self, _si: &SurfaceInteraction) -> Rgb {
        Rgb::BLACK
    }

    pub fn duv(&self, si: &SurfaceInteraction) -> Vec2 {
        let m = self.mapping.map_duv(si);
        let c = self.image.lookup(m.st);
        let n = Vec3::new(2.0 * c.r - 1.0, 2.0 * c.g - 1.0, c.b);
        let det = m.d_du.x * m.d_dv.y - m.d_dv.x * m.d_du.y;
        if det.abs() < 1e-5 || !det.is_finite() {
            return Vec2::ZERO;
        }
        let inv = 1.0 / det;
        let (duds, dudt) = (inv * m.d_dv.y, -inv * m.d_dv.x);
        let (dvds, dvdt) = (-inv * m.d_du.y, inv * m.d_du.x);
        let (dpdu, dpdv) = (Vec3::from(si.shading.dpdu), Vec3::from(si.shading.dpdv));
        let dpds = dpdu * duds + dpdv * dvds;
        let dpdt = dpdu * dudt + dpdv * dvdt;
        let k = dpds.cross(dpdt).normalize_or_zero();
        let (t1, t2) = (dpds.normalize_or_zero(), dpdt.normalize_or_zero());
        let n = Mat3::from_cols(t1, t2, k).mul_vec3(n).normalize_or_zero();
        // Rows of LuxRender's system A·(dh/ds, dh/dt, 1)/λ = n.
        let a = Mat3::from_cols(
            Vec3::new(
                dpdt.z * k.y - dpdt.y * k.z,
                dpdt.x * k.z - dpdt.z * k.x,
                dpdt.y * k.x - dpdt.x * k.y,
            ),
            Vec3::new(
                dpds.y * k.z - dpds.z * k.y,
                dpds.z * k.x - dpds.x * k.z,
                dpds.x * k.y - dpds.y * k.x,
            ),
            Vec3::new(
                dpds.y * dpdt.z - dpds.z * dpdt.y,
                dpds.z * dpdt.x - dpds.x * dpdt.z,
                dpds.x * dpdt.y - dpds.y * dpdt.x,
            ),
        );
        if a.determinant().abs() < 1e-20 {
            return Vec2::ZERO;
        }
        let dh = a.inverse().mul_vec3(n);
        if dh.z.abs() < 1e-20 {
            return Vec2::ZERO;
        }
        let (ds, dt) = (dh.x / dh.z, dh.y / dh.z);
        let d = Vec2::new(ds * m.d_du.x + dt * m.d_du.y, ds * m.d_dv.x + dt * m.d_dv.y);
        if d.is_finite() {
            d
        } else {
            Vec2::ZERO
        }
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    // LuxRender reads `channel` for normal maps too, and ignores it.
    let _ = t.entity.params.string("channel");
    let image = image_lookup(set, t, DEFAULT_GAMMA, Channel::Color)?;
    Ok(TexNode::NormalMap(NormalMapTex {
        image,
        mapping: Mapping2D::from_params(t)?,
    }))
}
