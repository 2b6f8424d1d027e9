//! Texture coordinate mappings, as LuxRender 1.x defines them (`core/texture.cpp`).
//!
//! 2D (`mapping`, [`Mapping2D`]): `uv` (s = uscale·u + udelta, t = vscale·v + vdelta),
//! `spherical` (s = uscale·φ/2π + udelta, t = vscale·θ/π + vdelta of the normalised point in
//! texture space), `cylindrical` (s = uscale·φ/2π + udelta, t = 0.5 − 0.5·z: LuxRender reads
//! no vscale/vdelta there) and `planar` (s = udelta + p·v1, t = vdelta + p·v2 with the world
//! point). Spherical and cylindrical work in the space of the texture's declaration (the
//! inverse of its transform), as LuxRender's `Inverse(tex2world)`.
//!
//! 3D (`coordinates`, [`Mapping3D`]): `global` (the world point), `local` (the point in the
//! object space of the hit shape), `uv` ((u, v, 0)), `globalnormal` and `localnormal` (the
//! shading normal in world or object space), then `M · Scale(1/scale) · RotX · RotY · RotZ ·
//! Translate(−translate)` with `M` the transform in force at the texture's declaration,
//! applied as LuxRender applies it: its 3D mappings take that transform itself as their
//! world-to-texture matrix (pbrt's convention), so `Scale 2 2 2` before a 3D texture makes its
//! pattern twice as fine. `local` needs the hit shape's transform: [`ObjectFrames`] holds it
//! per primitive.
//!
//! Each mapping also gives its derivatives with respect to the surface's (u, v)
//! (LuxRender's `MapDuv`), which bump mapping uses.

use super::{param_loc, TextureError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::{ParamSet, TextureDesc};
use glam::{Affine3A, DMat4, Mat4, Vec2, Vec3, Vec3A};
use std::f32::consts::PI;
use std::sync::Arc;

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

/// Texture coordinates and their derivatives with respect to the surface (u, v).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MappedDuv {
    pub st: Vec2,
    /// (ds/du, dt/du)
    pub d_du: Vec2,
    /// (ds/dv, dt/dv)
    pub d_dv: Vec2,
}

fn affine(m: DMat4) -> Affine3A {
    Affine3A::from_mat4(m.as_mat4())
}

/// The transform in force at the texture's declaration (texture to world).
pub fn texture_to_world(desc: &TextureDesc) -> Affine3A {
    affine(desc.object_to_world.start())
}

/// World to the space of the texture's declaration (identity when not invertible).
pub fn world_to_texture(desc: &TextureDesc) -> Affine3A {
    let m = desc.object_to_world.start();
    if m.determinant().abs() <= 1e-300 || m.determinant().is_nan() {
        return Affine3A::IDENTITY;
    }
    affine(m.inverse())
}

/// Azimuth of (x, y) in [0, 2π) (LuxRender's `SphericalPhi`).
fn spherical_phi(x: f32, y: f32) -> f32 {
    let p = y.atan2(x);
    if p < 0.0 {
        p + 2.0 * PI
    } else {
        p
    }
}

impl Mapping2D {
    /// Reads `mapping` and its parameters from a texture's parameter list.
    pub fn from_params(desc: &TextureDesc) -> Result<Mapping2D, TextureError> {
        let p: &ParamSet = &desc.entity.params;
        let kind = p.string_or("mapping", "uv").to_string();
        let delta = || Vec2::new(p.float_or("udelta", 0.0), p.float_or("vdelta", 0.0));
        Ok(match kind.as_str() {
            "uv" => Mapping2D::Uv {
                scale: Vec2::new(p.float_or("uscale", 1.0), p.float_or("vscale", 1.0)),
                delta: delta(),
            },
            "spherical" => Mapping2D::Spherical {
                world_to_tex: world_to_texture(desc),
                scale: Vec2::new(p.float_or("uscale", 1.0), p.float_or("vscale", 1.0)),
                delta: delta(),
            },
            "cylindrical" => Mapping2D::Cylindrical {
                world_to_tex: world_to_texture(desc),
                scale: Vec2::new(p.float_or("uscale", 1.0), 1.0),
                delta: Vec2::new(p.float_or("udelta", 0.0), 0.0),
            },
            "planar" => {
                let v1 = Vec3A::from(p.vector("v1").unwrap_or([1.0, 0.0, 0.0]));
                let v2 = Vec3A::from(p.vector("v2").unwrap_or([0.0, 1.0, 0.0]));
                Mapping2D::Planar {
                    v1,
                    v2,
                    delta: delta(),
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
    #[inline]
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
                Vec2::new(spherical_phi(v.x, v.y) / (2.0 * PI), theta / PI) * *scale + *delta
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
                Vec2::new(
                    spherical_phi(x, y) / (2.0 * PI) * scale.x + delta.x,
                    0.5 - 0.5 * v.z,
                )
            }
            Mapping2D::Planar { v1, v2, delta } => {
                let p = si.it.p;
                Vec2::new(p.dot(*v1), p.dot(*v2)) + *delta
            }
        }
    }

    /// Texture coordinates and their (u, v) derivatives (LuxRender's `MapDuv`), taken along
    /// the shading tangents of the hit. As in LuxRender, the spherical and cylindrical
    /// derivatives use the normalised point (exact on the unit sphere and cylinder).
    pub fn map_duv(&self, si: &SurfaceInteraction) -> MappedDuv {
        let st = self.map(si);
        let (dpdu, dpdv) = (si.shading.dpdu, si.shading.dpdv);
        let (d_du, d_dv) = match self {
            Mapping2D::Uv { scale, .. } => (Vec2::new(scale.x, 0.0), Vec2::new(0.0, scale.y)),
            Mapping2D::Spherical {
                world_to_tex,
                scale,
                ..
            } => {
                let p = world_to_tex.transform_point3a(si.it.p).normalize_or_zero();
                let du = world_to_tex.transform_vector3a(dpdu);
                let dv = world_to_tex.transform_vector3a(dpdv);
                let xy2 = p.x * p.x + p.y * p.y;
                let s = if xy2 > 0.0 {
                    scale.x / (2.0 * PI) / xy2
                } else {
                    0.0
                };
                let hypo = (1.0 - p.z * p.z).max(0.0).sqrt();
                let t = if hypo > 0.0 { scale.y / PI / hypo } else { 0.0 };
                (
                    Vec2::new((du.y * p.x - p.y * du.x) * s, du.z * t),
                    Vec2::new((dv.y * p.x - p.y * dv.x) * s, dv.z * t),
                )
            }
            Mapping2D::Cylindrical {
                world_to_tex,
                scale,
                ..
            } => {
                let v = world_to_tex.transform_point3a(si.it.p);
                let len = (v.x * v.x + v.y * v.y).sqrt();
                let (x, y) = if len > 0.0 {
                    (v.x / len, v.y / len)
                } else {
                    (1.0, 0.0)
                };
                let du = world_to_tex.transform_vector3a(dpdu);
                let dv = world_to_tex.transform_vector3a(dpdv);
                let s = scale.x / (2.0 * PI);
                (
                    Vec2::new((du.y * x - y * du.x) * s, -0.5 * du.z),
                    Vec2::new((dv.y * x - y * dv.x) * s, -0.5 * dv.z),
                )
            }
            Mapping2D::Planar { v1, v2, .. } => (
                Vec2::new(dpdu.dot(*v1), dpdu.dot(*v2)),
                Vec2::new(dpdv.dot(*v1), dpdv.dot(*v2)),
            ),
        };
        MappedDuv { st, d_du, d_dv }
    }
}

/// World-to-object transform of every primitive (indexed like `SurfaceInteraction::prim`),
/// for the `local` and `localnormal` 3D coordinate systems.
#[derive(Clone, Debug, Default)]
pub struct ObjectFrames(pub Arc<[Affine3A]>);

impl ObjectFrames {
    #[inline]
    fn world_to_object(&self, prim: u32) -> Affine3A {
        self.0
            .get(prim as usize)
            .copied()
            .unwrap_or(Affine3A::IDENTITY)
    }
}

/// What a 3D mapping transforms into texture space.
#[derive(Clone, Debug)]
pub enum Coordinates {
    Global,
    Local(ObjectFrames),
    Uv,
    GlobalNormal,
    LocalNormal(ObjectFrames),
}

/// 3D mapping of solid textures.
#[derive(Clone, Debug)]
pub struct Mapping3D {
    pub world_to_tex: Affine3A,
    pub coords: Coordinates,
}

/// The shading normal of a hit (the geometric one when the shape gave none).
#[inline]
fn shading_normal(si: &SurfaceInteraction) -> Vec3A {
    if si.shading.n == Vec3A::ZERO {
        si.it.n
    } else {
        si.shading.n
    }
}

impl Mapping3D {
    /// Reads `coordinates`, `scale`, `rotate` and `translate`; `frames` gives the object
    /// transforms `local` and `localnormal` need (asked for only by those). Unknown coordinate
    /// systems fall back to `global` as in LuxRender; the second value says so.
    pub fn from_desc(
        desc: &TextureDesc,
        frames: impl FnOnce() -> ObjectFrames,
    ) -> (Mapping3D, Option<String>) {
        let p = &desc.entity.params;
        let kind = p.string_or("coordinates", "global").to_string();
        let mut warning = None;
        let coords = match kind.as_str() {
            "global" => Coordinates::Global,
            "local" => Coordinates::Local(frames()),
            "uv" => Coordinates::Uv,
            "globalnormal" => Coordinates::GlobalNormal,
            "localnormal" => Coordinates::LocalNormal(frames()),
            other => {
                warning = Some(format!(
                    "unknown 3D texture coordinates \"{other}\" (global, local, uv, globalnormal, \
                     localnormal): using global, as LuxRender does"
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
                world_to_tex: texture_to_world(desc) * options,
                coords,
            },
            warning,
        )
    }

    /// A mapping of the world point through `world_to_tex` (tests and internal use).
    pub fn global(world_to_tex: Affine3A) -> Mapping3D {
        Mapping3D {
            world_to_tex,
            coords: Coordinates::Global,
        }
    }

    /// The texture-space point of a hit.
    #[inline]
    pub fn map(&self, si: &SurfaceInteraction) -> Vec3A {
        match &self.coords {
            Coordinates::Global => self.world_to_tex.transform_point3a(si.it.p),
            Coordinates::Local(f) => {
                let m = self.world_to_tex * f.world_to_object(si.prim);
                m.transform_point3a(si.it.p)
            }
            Coordinates::Uv => self
                .world_to_tex
                .transform_point3a(Vec3A::new(si.uv.x, si.uv.y, 0.0)),
            Coordinates::GlobalNormal => transform_normal(&self.world_to_tex, shading_normal(si)),
            Coordinates::LocalNormal(f) => {
                let m = self.world_to_tex * f.world_to_object(si.prim);
                transform_normal(&m, shading_normal(si))
            }
        }
    }

    /// The texture-space point and its derivatives with respect to the surface (u, v)
    /// (LuxRender's `MapDuv`; the normal systems give zero: the normal's derivatives are not
    /// kept at a hit).
    pub fn map_duv(&self, si: &SurfaceInteraction) -> (Vec3A, Vec3A, Vec3A) {
        let p = self.map(si);
        let (du, dv) = match &self.coords {
            Coordinates::Global => (
                self.world_to_tex.transform_vector3a(si.shading.dpdu),
                self.world_to_tex.transform_vector3a(si.shading.dpdv),
            ),
            Coordinates::Local(f) => {
                let m = self.world_to_tex * f.world_to_object(si.prim);
                (
                    m.transform_vector3a(si.shading.dpdu),
                    m.transform_vector3a(si.shading.dpdv),
                )
            }
            Coordinates::Uv => (
                self.world_to_tex.transform_vector3a(Vec3A::X),
                self.world_to_tex.transform_vector3a(Vec3A::Y),
            ),
            Coordinates::GlobalNormal | Coordinates::LocalNormal(_) => (Vec3A::ZERO, Vec3A::ZERO),
        };
        (p, du, dv)
    }
}

/// A normal through `m` (the inverse transpose of its linear part).
fn transform_normal(m: &Affine3A, n: Vec3A) -> Vec3A {
    let inv_t = Mat4::from(*m).inverse().transpose();
    Vec3A::from(inv_t.transform_vector3(Vec3::from(n)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::tests::si_at;

    #[test]
    fn uv_mapping_derivatives_are_the_scales() {
        let m = Mapping2D::Uv {
            scale: Vec2::new(-32.0, 2.0),
            delta: Vec2::new(0.5, 0.0),
        };
        let d = m.map_duv(&si_at(0.25, 0.5, Vec3A::ZERO));
        assert_eq!(d.st, Vec2::new(-7.5, 1.0));
        assert_eq!(d.d_du, Vec2::new(-32.0, 0.0));
        assert_eq!(d.d_dv, Vec2::new(0.0, 2.0));
    }

    #[test]
    fn planar_and_spherical_derivatives_match_finite_differences() {
        let maps = [
            Mapping2D::Planar {
                v1: Vec3A::new(1.0, 0.5, 0.0),
                v2: Vec3A::new(0.0, 1.0, 0.0),
                delta: Vec2::ZERO,
            },
            Mapping2D::Spherical {
                world_to_tex: Affine3A::IDENTITY,
                scale: Vec2::new(2.0, 1.0),
                delta: Vec2::ZERO,
            },
            Mapping2D::Cylindrical {
                world_to_tex: Affine3A::IDENTITY,
                scale: Vec2::new(3.0, 1.0),
                delta: Vec2::ZERO,
            },
        ];
        // LuxRender's spherical and cylindrical derivatives are exact on the unit sphere and
        // cylinder (they use the normalised point): check there.
        for m in maps {
            let p = Vec3A::new(0.6, 0.8, 0.0);
            let si = si_at(0.0, 0.0, p);
            let d = m.map_duv(&si);
            let h = 1e-3;
            let mut su = si;
            su.it.p += si.shading.dpdu * h;
            let fd = (m.map(&su) - d.st) / h;
            assert!(
                (fd - d.d_du).length() < 2e-2,
                "{m:?}: {fd:?} vs {:?}",
                d.d_du
            );
            let mut sv = si;
            sv.it.p += si.shading.dpdv * h;
            let fd = (m.map(&sv) - d.st) / h;
            assert!(
                (fd - d.d_dv).length() < 2e-2,
                "{m:?}: {fd:?} vs {:?}",
                d.d_dv
            );
        }
    }

    #[test]
    fn local_coordinates_use_the_primitive_frame() {
        let frames = ObjectFrames(Arc::from(vec![
            Affine3A::IDENTITY,
            Affine3A::from_translation(Vec3::new(-10.0, 0.0, 0.0)),
        ]));
        let m = Mapping3D {
            world_to_tex: Affine3A::IDENTITY,
            coords: Coordinates::Local(frames),
        };
        let mut si = si_at(0.0, 0.0, Vec3A::new(10.5, 1.0, 2.0));
        si.prim = 1;
        assert_eq!(m.map(&si), Vec3A::new(0.5, 1.0, 2.0));
        si.prim = 0;
        assert_eq!(m.map(&si), Vec3A::new(10.5, 1.0, 2.0));
        // Unknown primitives keep world coordinates.
        si.prim = 7;
        assert_eq!(m.map(&si), Vec3A::new(10.5, 1.0, 2.0));
    }
}
