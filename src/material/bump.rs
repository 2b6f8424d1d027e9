//! Bump mapping as LuxRender's `Material::Bump`: the `bumpmap` float texture displaces the
//! surface along the shading normal; its finite differences (steps of 0.001 in u and v, the
//! value LuxRender uses without ray differentials) tilt the shading tangents and normal. The
//! new normal stays on the side of the original shading normal.

use crate::geometry::{Shading, SurfaceInteraction};
use crate::texture::FloatTex;
use glam::{Vec2, Vec3A};

const DELTA: f32 = 0.001;

pub fn apply(bump: &FloatTex, si: &SurfaceInteraction) -> SurfaceInteraction {
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
    su.it.p += dpdu * DELTA;
    su.uv += Vec2::new(DELTA, 0.0);
    let du = bump.eval(&su);
    let mut sv = *si;
    sv.it.p += dpdv * DELTA;
    sv.uv += Vec2::new(0.0, DELTA);
    let dv = bump.eval(&sv);
    let new_dpdu = dpdu + n * ((du - d) / DELTA);
    let new_dpdv = dpdv + n * ((dv - d) / DELTA);
    let mut nn = new_dpdu.cross(new_dpdv).normalize_or_zero();
    if nn == Vec3A::ZERO || !nn.is_finite() {
        return *si;
    }
    if nn.dot(n) < 0.0 {
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
