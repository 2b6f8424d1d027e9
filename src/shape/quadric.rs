//! Analytic quadrics of revolution about z (sphere, cylinder, cone, paraboloid, hyperboloid)
//! and the disk, intersected in f64 in their object space.
//!
//! Every surface of revolution here is `x² + y² = R(z)` with `R(z) = a2 z² + a1 z + a0`, so one
//! quadratic solver serves them all. Working in f64 (ray transformed into object space in f64,
//! hit point re-projected onto the surface) leaves the hit point's error at the final f32
//! rounding, which [`Transform::point64_with_error`] bounds; a ray spawned outside that bound
//! finds its own surface behind it (t < 0) at any scale.
//!
//! The (u, v) parametrisation and the normal orientation follow pbrt/LuxRender: u = φ/φmax,
//! n = dp/du × dp/dv (outward for the standard shapes), turned by ReverseOrientation.

use super::{Build, BuildError};
use crate::geometry::frame::LocalGeometry;
use crate::geometry::transform::to_f64;
use crate::geometry::Transform;
use crate::sampling::DiscreteDistribution;
use glam::{DMat3, DVec3, Vec2, Vec3A};
use std::f64::consts::TAU;

/// The shape-specific part of a quadric, in its object space.
#[derive(Clone, Debug, PartialEq)]
pub enum Surface {
    Sphere {
        r: f64,
        zmin: f64,
        zmax: f64,
        theta_zmin: f64,
        theta_zmax: f64,
    },
    Cylinder {
        r: f64,
        zmin: f64,
        zmax: f64,
    },
    Cone {
        r: f64,
        h: f64,
    },
    /// `x² + y² = r² z / zcap` clipped to [zmin, zmax].
    Paraboloid {
        r: f64,
        zmin: f64,
        zmax: f64,
        zcap: f64,
    },
    /// The segment p1–p2 swept around z.
    Hyperboloid {
        p1: DVec3,
        p2: DVec3,
    },
    Disk {
        h: f64,
        r: f64,
        ri: f64,
    },
}

/// Number of z bands of the area table used to sample paraboloids and hyperboloids.
const BANDS: usize = 256;

#[derive(Clone, Debug)]
pub struct Quadric {
    pub surface: Surface,
    pub phimax: f64,
    /// Object space to the target space.
    pub to_space: Transform,
    pub reverse: bool,
    /// R(z) coefficients [a2, a1, a0] (unused by the disk).
    coef: [f64; 3],
    zmin: f64,
    zmax: f64,
    /// Object-space area.
    area_obj: f64,
    /// Area table over z bands (paraboloid, hyperboloid).
    bands: Option<DiscreteDistribution>,
    /// Squared scale of a similarity transform (area factor), `None` for other transforms.
    similarity: Option<f64>,
    /// Target-space area.
    area: f64,
}

impl Quadric {
    pub(crate) fn new(b: &Build, surface: Surface, phimax: f64) -> Result<Quadric, BuildError> {
        let (coef, zmin, zmax) = surface_coefficients(&surface);
        if zmax.is_nan() || zmin.is_nan() || zmax < zmin || !coef.iter().all(|c| c.is_finite()) {
            return Err(b.err("degenerate parameters (empty z range or non-finite values)"));
        }
        let mut q = Quadric {
            surface,
            phimax,
            to_space: b.to_space,
            reverse: b.reverse(),
            coef,
            zmin,
            zmax,
            area_obj: 0.0,
            bands: None,
            similarity: similarity_factor(&b.to_space),
            area: 0.0,
        };
        q.area_obj = q.object_area();
        if q.area_obj.is_nan() || q.area_obj <= 0.0 || !q.area_obj.is_finite() {
            return Err(b.err("the surface has no area (check radius, z range and phimax)"));
        }
        q.area = match q.similarity {
            Some(s2) => s2 * q.area_obj,
            None => q.estimate_area(),
        };
        Ok(q)
    }

    /// Area in the target space.
    pub fn area(&self) -> f64 {
        self.area
    }

    /// Axis-aligned bounds in the target space.
    pub fn bounds(&self) -> (Vec3A, Vec3A) {
        let (rmax, z0, z1) = match self.surface {
            Surface::Sphere { r, zmin, zmax, .. } => (r, zmin, zmax),
            Surface::Cylinder { r, zmin, zmax } => (r, zmin, zmax),
            Surface::Cone { r, h } => (r, 0.0, h),
            Surface::Paraboloid {
                r,
                zmin,
                zmax,
                zcap,
                ..
            } => (r * (zmax / zcap).max(0.0).sqrt(), zmin, zmax),
            Surface::Hyperboloid { p1, p2 } => (
                p1.truncate().length().max(p2.truncate().length()),
                p1.z.min(p2.z),
                p1.z.max(p2.z),
            ),
            Surface::Disk { h, r, .. } => (r, h, h),
        };
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for i in 0..8 {
            let c = DVec3::new(
                if i & 1 == 0 { -rmax } else { rmax },
                if i & 2 == 0 { -rmax } else { rmax },
                if i & 4 == 0 { z0 } else { z1 },
            );
            let w = self.to_space.point(c);
            lo = lo.min(w);
            hi = hi.max(w);
        }
        let pad = (lo.abs().max(hi.abs())) * 1e-6;
        (
            crate::geometry::transform::to_f32(lo - pad),
            crate::geometry::transform::to_f32(hi + pad),
        )
    }

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

    fn r_of_z(&self, z: f64) -> f64 {
        let [a2, a1, a0] = self.coef;
        (a2 * z + a1) * z + a0
    }

    fn dr_of_z(&self, z: f64) -> f64 {
        2.0 * self.coef[0] * z + self.coef[1]
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
    fn project(&self, mut p: DVec3) -> DVec3 {
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
    fn parametrisation(&self, p: DVec3) -> (Vec2, DVec3, DVec3) {
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
    fn object_normal(&self, p: DVec3, dpdu: DVec3, dpdv: DVec3) -> DVec3 {
        let mut n = self.gradient(p).normalize_or_zero();
        if dpdu.cross(dpdv).dot(n) < 0.0 {
            n = -n;
        }
        n
    }

    /// Local geometry (target space) at an object-space surface point.
    fn geometry_at(&self, p: DVec3) -> LocalGeometry {
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

    fn object_area(&mut self) -> f64 {
        let phimax = self.phimax;
        match self.surface {
            Surface::Sphere { r, zmin, zmax, .. } | Surface::Cylinder { r, zmin, zmax } => {
                phimax * r * (zmax - zmin)
            }
            Surface::Cone { r, h } => 0.5 * phimax * r * (r * r + h * h).sqrt(),
            Surface::Disk { r, ri, .. } => 0.5 * phimax * (r * r - ri * ri),
            Surface::Paraboloid { .. } | Surface::Hyperboloid { .. } => {
                let dz = (self.zmax - self.zmin) / BANDS as f64;
                let w: Vec<f64> = (0..BANDS)
                    .map(|i| {
                        let z0 = self.zmin + dz * i as f64;
                        let (a, m, b) = (
                            self.da_dz(z0),
                            self.da_dz(z0 + 0.5 * dz),
                            self.da_dz(z0 + dz),
                        );
                        dz / 6.0 * (a + 4.0 * m + b)
                    })
                    .collect();
                let total = w.iter().sum();
                self.bands = DiscreteDistribution::new(&w);
                total
            }
        }
    }

    /// Area per unit z (object space) of a surface of revolution: φmax r(z) sqrt(1 + r'(z)²).
    fn da_dz(&self, z: f64) -> f64 {
        let r2 = self.r_of_z(z).max(0.0);
        let dr2 = self.dr_of_z(z);
        self.phimax * (r2 + 0.25 * dr2 * dr2).max(0.0).sqrt()
    }

    /// A point of the object-space surface and its density with respect to object area.
    fn sample_object(&self, u: Vec2) -> (DVec3, f64) {
        let (u0, u1) = (u.x as f64, u.y as f64);
        let phi = u1 * self.phimax;
        let uniform = 1.0 / self.area_obj;
        let around = |rxy: f64, z: f64| DVec3::new(rxy * phi.cos(), rxy * phi.sin(), z);
        match self.surface {
            Surface::Sphere { r, zmin, zmax, .. } => {
                let z = zmin + u0 * (zmax - zmin);
                (around((r * r - z * z).max(0.0).sqrt(), z), uniform)
            }
            Surface::Cylinder { r, zmin, zmax } => (around(r, zmin + u0 * (zmax - zmin)), uniform),
            Surface::Cone { r, h } => {
                let rr = r * u0.sqrt();
                (around(rr, h * (1.0 - rr / r)), uniform)
            }
            Surface::Disk { h, r, ri } => {
                let rr = (ri * ri + u0 * (r * r - ri * ri)).sqrt();
                (around(rr, h), uniform)
            }
            Surface::Paraboloid { .. } | Surface::Hyperboloid { .. } => {
                let Some(bands) = &self.bands else {
                    return (DVec3::ZERO, 0.0);
                };
                let (i, rem) = bands.sample(u.x);
                let dz = (self.zmax - self.zmin) / BANDS as f64;
                let z = self.zmin + dz * (i as f64 + rem as f64);
                let pdf_z = bands.pmf(i) / dz;
                let density = self.da_dz(z);
                let pdf = if density > 0.0 { pdf_z / density } else { 0.0 };
                let p = match self.surface {
                    Surface::Hyperboloid { p1, p2 } => {
                        let pr = p1.lerp(p2, (z - p1.z) / (p2.z - p1.z));
                        let (s, c) = phi.sin_cos();
                        DVec3::new(pr.x * c - pr.y * s, pr.x * s + pr.y * c, z)
                    }
                    _ => around(self.r_of_z(z).max(0.0).sqrt(), z),
                };
                (p, pdf)
            }
        }
    }

    /// Ratio of target-space to object-space area around a point with unit object normal n.
    fn area_factor(&self, n_obj: DVec3) -> f64 {
        if let Some(s2) = self.similarity {
            return s2;
        }
        let l = DMat3::from_mat4(self.to_space.m);
        l.determinant().abs() * (l.inverse().transpose() * n_obj).length()
    }

    /// A point on the surface and its density with respect to target-space area (uniform by
    /// area when the transform is a similarity).
    pub fn sample(&self, u: Vec2) -> (LocalGeometry, f32) {
        let (p, pdf_obj) = self.sample_object(u);
        let p = self.project(p);
        let g = self.geometry_at(p);
        let (_, dpdu, dpdv) = self.parametrisation(p);
        let factor = self.area_factor(self.object_normal(p, dpdu, dpdv));
        let pdf = if factor > 0.0 { pdf_obj / factor } else { 0.0 };
        (g, pdf as f32)
    }

    /// Target-space area under a non-similarity transform, by stratified integration.
    fn estimate_area(&self) -> f64 {
        const N: usize = 64;
        let mut sum = 0.0;
        for i in 0..N {
            for j in 0..N {
                let u = Vec2::new((i as f32 + 0.5) / N as f32, (j as f32 + 0.5) / N as f32);
                let (p, pdf) = self.sample_object(u);
                if pdf > 0.0 {
                    let (_, dpdu, dpdv) = self.parametrisation(p);
                    sum += self.area_factor(self.object_normal(p, dpdu, dpdv)) / pdf;
                }
            }
        }
        sum / (N * N) as f64
    }
}

/// R(z) coefficients and the z range of a surface.
fn surface_coefficients(s: &Surface) -> ([f64; 3], f64, f64) {
    match *s {
        Surface::Sphere { r, zmin, zmax, .. } => ([-1.0, 0.0, r * r], zmin, zmax),
        Surface::Cylinder { r, zmin, zmax } => ([0.0, 0.0, r * r], zmin, zmax),
        Surface::Cone { r, h } => {
            let k = (r / h) * (r / h);
            ([k, -2.0 * k * h, k * h * h], 0.0, h)
        }
        Surface::Paraboloid {
            r,
            zmin,
            zmax,
            zcap,
            ..
        } => ([0.0, r * r / zcap, 0.0], zmin, zmax),
        Surface::Hyperboloid { p1, p2 } => {
            let d = p2 - p1;
            let (alpha, beta) = (1.0 / d.z, -p1.z / d.z);
            let a = p1.x * p1.x + p1.y * p1.y;
            let b = p1.x * d.x + p1.y * d.y;
            let c = d.x * d.x + d.y * d.y;
            (
                [
                    c * alpha * alpha,
                    2.0 * b * alpha + 2.0 * c * alpha * beta,
                    a + 2.0 * b * beta + c * beta * beta,
                ],
                p1.z.min(p2.z),
                p1.z.max(p2.z),
            )
        }
        Surface::Disk { h, .. } => ([0.0; 3], h, h),
    }
}

/// Squared scale factor if the transform's linear part is a similarity.
fn similarity_factor(t: &Transform) -> Option<f64> {
    let l = DMat3::from_mat4(t.m);
    let g = l.transpose() * l;
    let s2 = (g.x_axis.x + g.y_axis.y + g.z_axis.z) / 3.0;
    let off = (g - DMat3::from_diagonal(DVec3::splat(s2))).to_cols_array();
    off.iter().all(|e| e.abs() <= 1e-9 * s2).then_some(s2)
}

/// Real roots of a t² + b t + c in increasing order (numerically stable form).
pub fn solve_quadratic(a: f64, b: f64, c: f64) -> Option<[f64; 2]> {
    if a == 0.0 {
        if b == 0.0 {
            return None;
        }
        let t = -c / b;
        return Some([t, t]);
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return None;
    }
    let root = disc.sqrt();
    let q = if b < 0.0 {
        -0.5 * (b - root)
    } else {
        -0.5 * (b + root)
    };
    let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
    Some(if t0 <= t1 { [t0, t1] } else { [t1, t0] })
}

/// Sphere/cylinder/paraboloid z range from `zmin`/`zmax` parameters (swapped if reversed).
pub(crate) fn z_range(
    b: &Build,
    zmin_default: f32,
    zmax_default: f32,
) -> Result<(f64, f64), BuildError> {
    let z0 = b.float("zmin", zmin_default)?;
    let z1 = b.float("zmax", zmax_default)?;
    Ok((z0.min(z1), z0.max(z1)))
}
