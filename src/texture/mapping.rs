//! Texture coordinate mappings, as LuxRender 1.x defines them.
//!
//! 2D (`mapping`): `uv` (s = uscale·u + udelta, t = vscale·v + vdelta), `spherical` (s from
//! the azimuth φ/2π, t from θ/π of the point in texture space, scaled and offset the same way),
//! `cylindrical` (s = uscale·φ/2π + udelta, t = 0.5 − 0.5·z; LuxRender ignores vscale/vdelta
//! there) and `planar` (s = udelta + p·v1, t = vdelta + p·v2 with the world-space point).
//!
//! 3D (`coordinates`): `global` (world point in texture space: the inverse of the texture's
//! `object_to_world`), `uv` ((u, v, 0) in texture space), `globalnormal` (the normal), then the
//! texture's `scale`, `rotate` (degrees about X, Y, Z) and `translate` options applied as
//! LuxRender does (`W2T · Scale(1/s) · RotX · RotY · RotZ · Translate(−t)`). `local` and
//! `localnormal` need the hit object's own transform, which a hit does not carry: they fall
//! back to the global variants with a warning.

use super::{param_loc, TextureError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::{ParamSet, TextureDesc};
use glam::{Affine3A, Mat4, Vec2, Vec3, Vec3A};
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
                Mapping2D::Planar { v1, v2, delta }
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
                Vec2::new(phi / (2.0 * PI), theta / PI) * *scale + *delta
            }
            Mapping2D::Cylindrical {
                world_to_tex,
                scale,
                delta,
            } => {
                let v = world_to_tex.transform_point3a(si.it.p);
                let len = (v.x * v.x + v.y * v.y).sqrt();
                let (x, y) = if len > 0.0 {
                    (v.x / len, v.y / len)
                } else {
                    (1.0, 0.0)
                };
                let mut phi = y.atan2(x);
                if phi < 0.0 {
                    phi += 2.0 * PI;
                }
                Vec2::new(phi / (2.0 * PI) * scale.x + delta.x, 0.5 - 0.5 * v.z)
            }
            Mapping2D::Planar { v1, v2, delta } => {
                let p = si.it.p;
                Vec2::new(p.dot(*v1), p.dot(*v2)) + *delta
            }
        }
    }
}

/// What a 3D mapping transforms into texture space.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coordinates {
    Global,
    Uv,
    GlobalNormal,
}

/// 3D mapping of solid textures.
#[derive(Clone, Debug)]
pub struct Mapping3D {
    pub world_to_tex: Affine3A,
    pub coords: Coordinates,
}

impl Mapping3D {
    /// Reads `coordinates`, `scale`, `rotate` and `translate`. The second value is a warning
    /// for coordinate systems that fell back.
    pub fn from_desc(desc: &TextureDesc) -> (Mapping3D, Option<String>) {
        let p = &desc.entity.params;
        let kind = p.string_or("coordinates", "global").to_string();
        let mut warning = None;
        let coords = match kind.as_str() {
            "global" => Coordinates::Global,
            "uv" => Coordinates::Uv,
            "globalnormal" => Coordinates::GlobalNormal,
            "local" | "localnormal" => {
                warning = Some(format!(
                    "3D texture coordinates \"{kind}\" need the object transform at the hit, \
                     which is not available: using the global variant"
                ));
                if kind == "local" {
                    Coordinates::Global
                } else {
                    Coordinates::GlobalNormal
                }
            }
            other => {
                warning = Some(format!(
                    "unknown 3D texture coordinates \"{other}\": using global"
                ));
                Coordinates::Global
            }
        };
        let v = |name: &str, d: f32| Vec3::from(p.vector(name).unwrap_or([d; 3]));
        let scale = v("scale", 1.0);
        let rotate = v("rotate", 0.0);
        let translate = v("translate", 0.0);
        let inv = |x: f32| if x != 0.0 { 1.0 / x } else { 1.0 };
        let options = Affine3A::from_scale(Vec3::new(inv(scale.x), inv(scale.y), inv(scale.z)))
            * Affine3A::from_rotation_x(rotate.x.to_radians())
            * Affine3A::from_rotation_y(rotate.y.to_radians())
            * Affine3A::from_rotation_z(rotate.z.to_radians())
            * Affine3A::from_translation(-translate);
        (
            Mapping3D {
                world_to_tex: world_to_texture(desc) * options,
                coords,
            },
            warning,
        )
    }

    pub fn map(&self, si: &SurfaceInteraction) -> Vec3A {
        match self.coords {
            Coordinates::Global => self.world_to_tex.transform_point3a(si.it.p),
            Coordinates::Uv => self
                .world_to_tex
                .transform_point3a(Vec3A::new(si.uv.x, si.uv.y, 0.0)),
            Coordinates::GlobalNormal => {
                let n = if si.shading.n == Vec3A::ZERO {
                    si.it.n
                } else {
                    si.shading.n
                };
                self.world_to_tex.transform_vector3a(n)
            }
        }
    }
}
