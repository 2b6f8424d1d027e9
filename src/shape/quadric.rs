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
//!
//! This file builds a quadric, bounds it, measures its area and samples it; intersection and
//! the local geometry at a point are in `quadric_hit.rs`.

use super::{Build, BuildError};
use crate::geometry::frame::LocalGeometry;
use crate::geometry::Transform;
use crate::sampling::DiscreteDistribution;
use glam::{DMat3, DVec3, Vec2, Vec3A};

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
    pub(super) coef: [f64; 3],
    pub(super) zmin: f64,
    pub(super) zmax: f64,
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

    pub(super) fn r_of_z(&self, z: f64) -> f64 {
        let [a2, a1, a0] = self.coef;
        (a2 * z + a1) * z + a0
    }

    pub(super) fn dr_of_z(&self, z: f64) -> f64 {
        2.0 * self.coef[0] * z + self.coef[1]
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
