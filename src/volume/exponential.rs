//! `exponential`: a medium whose density falls off with height, a·e^(-b·h), h measured along
//! `updir` (default 0 1 0) from the statement's origin (its transform applied), scaling
//! `sigma_a` and `sigma_s` (colours, default 0); `a` and `b` default to 1, `g` and `fresnel`
//! as every medium. Integrals are marched ([`super::heterogeneous`]) in steps of `stepsize`
//! (default 1).

use super::heterogeneous::{Coeffs, Density, Field, Heterogeneous};
use super::{constant_color, VolumeError};
use crate::lxs::Xform;
use crate::plugin::Stmt;
use crate::texture::TextureSet;
use glam::Vec3A;

pub fn build(
    s: &mut Stmt,
    textures: &mut TextureSet,
    to_world: &Xform,
) -> Result<Heterogeneous, VolumeError> {
    let sigma_a = constant_color(s, textures, "sigma_a")?;
    let sigma_s = constant_color(s, textures, "sigma_s")?;
    let a = s.finite("a", 1.0)?;
    let b = s.finite("b", 1.0)?;
    let up = s.params().vector("updir").unwrap_or([0.0, 1.0, 0.0]);
    let m = to_world.start();
    let up = m.transform_vector3(glam::DVec3::from(up.map(f64::from)));
    let origin = m.transform_point3(glam::DVec3::ZERO);
    let up = Vec3A::from(up.as_vec3()).normalize_or(Vec3A::Y);
    let g = super::read_g(s);
    let step = s.positive("stepsize", 1.0)?;
    super::read_fresnel(s.params(), s.loc(), textures)?;
    Ok(Heterogeneous {
        density: Density::Scaled {
            c: Coeffs {
                sigma_a,
                sigma_s,
                le: crate::spectrum::Rgb::BLACK,
            },
            field: Field::Exponential {
                a,
                b,
                up,
                origin: Vec3A::from(origin.as_vec3()),
            },
        },
        g,
        step,
    })
}
