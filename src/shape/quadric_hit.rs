//! Rays against a quadric: the ray taken into object space in f64, the quadratic solve,
//! clipping by z range (or radii for the disk) and φmax, and the hit moved back onto the
//! surface; then the local geometry at a surface point ((u, v), dp/du, dp/dv, the oriented
//! normal and the hit point's error bound), which sampling in `quadric.rs` uses too.

use super::quadric::{solve_quadratic, Quadric, Surface};
use crate::geometry::frame::LocalGeometry;
use crate::geometry::transform::to_f64;
use glam::{DVec3, Vec2, Vec3A};
use std::f64::consts::TAU;

impl Quadric {
    /// Nearest hit distance of the target-space ray `o + t d`, 0 < t < t_max.
    pub fn intersect_t(&self, o: Vec3A, d: Vec3A, t_max: f32) -> Option<f32> {
        let (oo, dd) = self.object_ray(o, d);
        self.solve(oo, dd, t_max as f64).map(|(t, _)| t as f32)
    }

    /// Nearest hit with its local geometry (target space).
    pub fn intersect(&self, o: Vec3A, d: Vec3A, t_max: f32) -> Option<(f32, LocalGeometry)> {
        let (oo, dd) = self.object_ray(o, d);
        let (t, p) = self.solve(oo, dd, t_max as f64)?;
        Some((t as f32, self.geometry_at(p)))
    }

    /// Local geometry (target space) of the hit at distance `t` along the target-space ray
    /// `o + t d`, a distance [`Self::intersect_t`] returned for the same ray: the point is
    /// moved onto the surface as a solve would, without solving again.
    pub fn geometry_at_t(&self, o: Vec3A, d: Vec3A, t: f32) -> LocalGeometry {
        let (oo, dd) = self.object_ray(o, d);
        self.geometry_at(self.project(oo + dd * f64::from(t)))
    }

    fn object_ray(&self, o: Vec3A, d: Vec3A) -> (DVec3, DVec3) {
        let inv = &self.to_space.inv;
        (
            inv.transform_point3(to_f64(o)),
            inv.transform_vector3(to_f64(d)),
        )
    }

    /// Angle of `p` around z measured from the surface's φ = 0 generator, in [0, 2π).
    fn phi(&self, p: DVec3) -> f64 {
        let phi = match self.surface {
            Surface::Hyperboloid { p1, p2 } => {
                let pr = p1.lerp(p2, (p.z - p1.z) / (p2.z - p1.z));
                (pr.x * p.y - p.x * pr.y).atan2(p.x * pr.x + p.y * pr.y)
            }
            _ => p.y.atan2(p.x),
        };
        if phi < 0.0 {
            phi + TAU
        } else {
            phi
        }
    }

    fn inside_clip(&self, p: DVec3) -> bool {
        if let Surface::Disk { r, ri, .. } = self.surface {
            let r2 = p.x * p.x + p.y * p.y;
            if r2 > r * r || r2 < ri * ri {
                return false;
            }
        } else if p.z < self.zmin || p.z > self.zmax {
            return false;
        }
        self.phimax >= TAU || self.phi(p) <= self.phimax
    }

    /// Object-space hit: distance and surface point.
    fn solve(&self, o: DVec3, d: DVec3, t_max: f64) -> Option<(f64, DVec3)> {
        if let Surface::Disk { h, .. } = self.surface {
            if d.z == 0.0 {
                return None;
            }
            let t = (h - o.z) / d.z;
            if t.is_nan() || t <= 0.0 || t >= t_max {
                return None;
            }
            let mut p = o + d * t;
            p.z = h;
            return self.inside_clip(p).then_some((t, p));
        }
        let [a2, a1, _] = self.coef;
        let qa = d.x * d.x + d.y * d.y - a2 * d.z * d.z;
        let qb = 2.0 * (o.x * d.x + o.y * d.y - a2 * o.z * d.z) - a1 * d.z;
        let qc = o.x * o.x + o.y * o.y - self.r_of_z(o.z);
        let roots = solve_quadratic(qa, qb, qc)?;
        for t in roots {
            if t.is_nan() || t <= 0.0 {
                continue;
            }
            if t >= t_max {
                break;
            }
            let p = o + d * t;
            if self.inside_clip(p) {
                return Some((t, self.project(p)));
            }
        }
        None
    }

    /// Moves a point computed from the ray onto the surface.
    pub(super) fn project(&self, mut p: DVec3) -> DVec3 {
        match self.surface {
            Surface::Sphere { r, .. } => {
                let l = p.length();
                if l > 0.0 {
                    p *= r / l;
                }
            }
            Surface::Cylinder { r, .. } => {
                let l = p.truncate().length();
                if l > 0.0 {
                    p.x *= r / l;
                    p.y *= r / l;
                }
            }
            Surface::Disk { h, .. } => p.z = h,
            _ => {
                for _ in 0..2 {
                    let f = p.x * p.x + p.y * p.y - self.r_of_z(p.z);
                    let g = DVec3::new(2.0 * p.x, 2.0 * p.y, -self.dr_of_z(p.z));
                    let g2 = g.length_squared();
                    if g2 > 0.0 {
                        p -= g * (f / g2);
                    }
                }
            }
        }
        p
    }

    /// Unnormalised outward gradient direction at an object-space surface point.
    fn gradient(&self, p: DVec3) -> DVec3 {
        match self.surface {
            Surface::Disk { .. } => DVec3::Z,
            _ => DVec3::new(2.0 * p.x, 2.0 * p.y, -self.dr_of_z(p.z)),
        }
    }

    /// (u, v), dp/du and dp/dv at an object-space surface point.
    pub(super) fn parametrisation(&self, p: DVec3) -> (Vec2, DVec3, DVec3) {
        let phi = self.phi(p);
        let u = if self.phimax > 0.0 {
            phi / self.phimax
        } else {
            0.0
        };
        let dpdu = DVec3::new(-self.phimax * p.y, self.phimax * p.x, 0.0);
        let (cos_phi, sin_phi) = (phi.cos(), phi.sin());
        let (v, dpdv) = match self.surface {
            Surface::Sphere {
                r,
                theta_zmin,
                theta_zmax,
                ..
            } => {
                let cos_t = (p.z / r).clamp(-1.0, 1.0);
                let theta = cos_t.acos();
                let dt = theta_zmax - theta_zmin;
                let v = if dt != 0.0 {
                    (theta - theta_zmin) / dt
                } else {
                    0.0
                };
                let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                let rxy = p.truncate().length();
                let (c, s) = if rxy > 0.0 {
                    (p.x / rxy, p.y / rxy)
                } else {
                    (1.0, 0.0)
                };
                (v, dt * DVec3::new(p.z * c, p.z * s, -r * sin_t))
            }
            Surface::Cylinder { zmin, zmax, .. } => (
                (p.z - zmin) / (zmax - zmin),
                DVec3::new(0.0, 0.0, zmax - zmin),
            ),
            Surface::Cone { r, h } => (p.z / h, DVec3::new(-r * cos_phi, -r * sin_phi, h)),
            Surface::Paraboloid { zmin, zmax, .. } => {
                let dz = zmax - zmin;
                let v = if dz != 0.0 { (p.z - zmin) / dz } else { 0.0 };
                let dpdv = if p.z.abs() > 1e-12 * zmax.abs().max(1e-300) {
                    dz * DVec3::new(p.x / (2.0 * p.z), p.y / (2.0 * p.z), 1.0)
                } else {
                    DVec3::new(cos_phi, sin_phi, 0.0)
                };
                (v, dpdv)
            }
            Surface::Hyperboloid { p1, p2 } => {
                let dp = p2 - p1;
                (
                    (p.z - p1.z) / dp.z,
                    DVec3::new(
                        dp.x * cos_phi - dp.y * sin_phi,
                        dp.x * sin_phi + dp.y * cos_phi,
                        dp.z,
                    ),
                )
            }
            Surface::Disk { r, ri, .. } => {
                let rh = p.truncate().length();
                let dpdv = if rh > 0.0 {
                    DVec3::new(p.x, p.y, 0.0) * ((ri - r) / rh)
                } else {
                    DVec3::new(cos_phi, sin_phi, 0.0) * (ri - r)
                };
                ((r - rh) / (r - ri), dpdv)
            }
        };
        (Vec2::new(u as f32, v as f32), dpdu, dpdv)
    }

    /// Oriented unit object-space normal at a surface point.
    pub(super) fn object_normal(&self, p: DVec3, dpdu: DVec3, dpdv: DVec3) -> DVec3 {
        let mut n = self.gradient(p).normalize_or_zero();
        if dpdu.cross(dpdv).dot(n) < 0.0 {
            n = -n;
        }
        n
    }

    /// Local geometry (target space) at an object-space surface point.
    pub(super) fn geometry_at(&self, p: DVec3) -> LocalGeometry {
        let (uv, dpdu, dpdv) = self.parametrisation(p);
        let n_obj = self.object_normal(p, dpdu, dpdv);
        let residual = match self.surface {
            Surface::Disk { .. } => 0.0,
            _ => {
                let g = self.gradient(p).length();
                let f = p.x * p.x + p.y * p.y - self.r_of_z(p.z);
                if g > 0.0 {
                    (f / g).abs()
                } else {
                    0.0
                }
            }
        };
        let err = DVec3::splat(residual + p.abs().max_element() * 1e-13);
        let (pt, p_error) = self.to_space.point64_with_error(p, err);
        let mut n =
            crate::geometry::transform::to_f32(self.to_space.normal(n_obj)).normalize_or_zero();
        if self.reverse {
            n = -n;
        }
        LocalGeometry {
            p: pt,
            p_error,
            n,
            ns: None,
            uv,
            dpdu: crate::geometry::transform::to_f32(self.to_space.vector(dpdu)),
            dpdv: crate::geometry::transform::to_f32(self.to_space.vector(dpdv)),
            hit: Default::default(),
        }
    }
}
