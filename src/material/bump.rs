//! Bump mapping as LuxRender's `Material::Bump`: the `bumpmap` float texture displaces the
//! surface along the shading normal; its finite differences over `bumpmapsampledistance`
//! (default 0.001, the step LuxRender uses without ray differentials) in u and v tilt the
//! shading tangents and normal, which is then oriented to the side of the geometric normal.

use crate::geometry::{Shading, SurfaceInteraction};
use crate::texture::FloatTex;
use glam::{Vec2, Vec3A};

/// LuxRender's default `bumpmapsampledistance`.
pub const DEFAULT_DISTANCE: f32 = 0.001;

pub fn apply(bump: &FloatTex, distance: f32, si: &SurfaceInteraction) -> SurfaceInteraction {
    let delta = if distance > 0.0 {
        distance
    } else {
        DEFAULT_DISTANCE
    };
    let n = if si.shading.n == Vec3A::ZERO {
        si.it.n
    } else {
        si.shading.n
    };
    let dpdu = if si.shading.dpdu == Vec3A::ZERO {
        si.dpdu
    } else {
        si.shading.dpdu
    };
    let dpdv = if si.shading.dpdv == Vec3A::ZERO {
        si.dpdv
    } else {
        si.shading.dpdv
    };
    let d = bump.eval(si);
    let mut su = *si;
    su.it.p += dpdu * delta;
    su.uv += Vec2::new(delta, 0.0);
    let du = bump.eval(&su);
    let mut sv = *si;
    sv.it.p += dpdv * delta;
    sv.uv += Vec2::new(0.0, delta);
    let dv = bump.eval(&sv);
    let new_dpdu = dpdu + n * ((du - d) / delta);
    let new_dpdv = dpdv + n * ((dv - d) / delta);
    let mut nn = new_dpdu.cross(new_dpdv).normalize_or_zero();
    if nn == Vec3A::ZERO || !nn.is_finite() {
        return *si;
    }
    if nn.dot(si.it.n) < 0.0 {
        nn = -nn;
    }
    let mut out = *si;
    out.shading = Shading {
        n: nn,
        dpdu: new_dpdu,
        dpdv: new_dpdv,
    };
    out
}
