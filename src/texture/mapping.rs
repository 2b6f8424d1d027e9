//! Texture coordinate mappings: 2D (`uv`, `spherical`, `cylindrical`, `planar`, with LuxRender's
//! `uscale`/`vscale`/`udelta`/`vdelta`, or `v1`/`v2` for planar) and the 3D mapping of solid
//! textures (world space into the texture's own space, the inverse of its `object_to_world`).

use super::{param_loc, TextureError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::{ParamSet, TextureDesc};
use glam::{Affine3A, Mat4, Vec2, Vec3A};
use std::f32::consts::PI;

/// A 2D mapping from a hit to texture coordinates (s, t).
#[derive(Clone, Debug)]
pub enum Mapping2D {
    Uv {
        scale: Vec2,
        delta: Vec2,
    },
    Spherical {
        world_to_tex: Affine3A,
        scale: Vec2,
        delta: Vec2,
    },
    Cylindrical {
        world_to_tex: Affine3A,
        scale: Vec2,
        delta: Vec2,
    },
    Planar {
        world_to_tex: Affine3A,
        v1: Vec3A,
        v2: Vec3A,
        delta: Vec2,
    },
}

/// World to texture space of a texture declaration (identity when not invertible).
pub fn world_to_texture(desc: &TextureDesc) -> Affine3A {
    let m = desc.object_to_world.start();
    if m.determinant().abs() < 1e-300 {
        return Affine3A::IDENTITY;
    }
    let inv: Mat4 = m.inverse().as_mat4();
    Affine3A::from_mat4(inv)
}

impl Mapping2D {
    /// Reads `mapping` and its parameters from a texture's parameter list.
    pub fn from_params(desc: &TextureDesc) -> Result<Mapping2D, TextureError> {
        let p: &ParamSet = &desc.entity.params;
        let scale = Vec2::new(p.float_or("uscale", 1.0), p.float_or("vscale", 1.0));
        let delta = Vec2::new(p.float_or("udelta", 0.0), p.float_or("vdelta", 0.0));
        let kind = p.string_or("mapping", "uv").to_string();
        let world_to_tex = world_to_texture(desc);
        Ok(match kind.as_str() {
            "uv" => Mapping2D::Uv { scale, delta },
            "spherical" => Mapping2D::Spherical {
                world_to_tex,
                scale,
                delta,
            },
            "cylindrical" => Mapping2D::Cylindrical {
                world_to_tex,
                scale,
                delta,
            },
            "planar" => {
                let v1 = Vec3A::from(p.vector("v1").unwrap_or([1.0, 0.0, 0.0]));
                let v2 = Vec3A::from(p.vector("v2").unwrap_or([0.0, 1.0, 0.0]));
                Mapping2D::Planar {
                    world_to_tex,
                    v1,
                    v2,
                    delta,
                }
            }
            other => {
                return Err(TextureError::BadParam {
                    loc: param_loc(p, "mapping", &desc.entity.loc),
                    message: format!(
                        "unknown texture mapping \"{other}\" (uv, spherical, cylindrical, planar)"
                    ),
                })
            }
        })
    }

    /// Texture coordinates of a hit.
    pub fn map(&self, si: &SurfaceInteraction) -> Vec2 {
        match self {
            Mapping2D::Uv { scale, delta } => si.uv * *scale + *delta,
            Mapping2D::Spherical {
                world_to_tex,
                scale,
                delta,
            } => {
                let v = world_to_tex.transform_point3a(si.it.p).normalize_or_zero();
                let theta = v.z.clamp(-1.0, 1.0).acos();
                let mut phi = v.y.atan2(v.x);
                if phi < 0.0 {
                    phi += 2.0 * PI;
                }
                Vec2::new(theta / PI, phi / (2.0 * PI)) * *scale + *delta
            }
            Mapping2D::Cylindrical {
                world_to_tex,
                scale,
                delta,
            } => {
                let v = world_to_tex.transform_point3a(si.it.p);
                Vec2::new((PI + v.y.atan2(v.x)) / (2.0 * PI), v.z) * *scale + *delta
            }
            Mapping2D::Planar {
                world_to_tex,
                v1,
                v2,
                delta,
            } => {
                let v = world_to_tex.transform_point3a(si.it.p);
                Vec2::new(v.dot(*v1), v.dot(*v2)) + *delta
            }
        }
    }
}

/// 3D mapping of solid textures: the hit point in texture space.
#[derive(Clone, Debug)]
pub struct Mapping3D {
    pub world_to_tex: Affine3A,
}

impl Mapping3D {
    pub fn from_desc(desc: &TextureDesc) -> Mapping3D {
        Mapping3D {
            world_to_tex: world_to_texture(desc),
        }
    }

    pub fn map(&self, si: &SurfaceInteraction) -> Vec3A {
        self.world_to_tex.transform_point3a(si.it.p)
    }
}
