//! The old region `Volume` statement (pbrt's volume regions, deprecated in LuxRender 1.x but
//! still read): `homogeneous` (also spelled `homogenous`), `exponential` and `volumegrid`,
//! each filling the box between `p0` (default 0 0 0) and `p1` (1 1 1) of the statement's
//! space with `sigma_a`, `sigma_s` (colours, default 0) and `g`. `exponential` scales them by
//! a·e^(-b·h), h measured from the box's low corner along `updir` (default 0 1 0) in the
//! volume's space; `volumegrid` by its `density` grid ([`super::grid`]); both are marched in
//! steps of `stepsize` (the statement's, else the VolumeIntegrator's, else 1).
//!
//! ```text
//! Volume (VolumeDesc, no name) --Region::build--> Region { box, inner Medium }
//!   MediaSet::build: the region is the medium wherever a ray's medium is not set
//!   tr / sample: the ray clipped to the box, the inner medium over the clipped part
//! ```
//!
//! `Le` (emission) is not rendered (a located warning); the `cloud` region is not built.

use super::grid::Grid;
use super::heterogeneous::{Density, Heterogeneous};
use super::{constant_color, Homogeneous, Medium, MediumSample};
use crate::geometry::Ray;
use crate::lxs::{Diagnostic, VolumeDesc};
use crate::plugin::{BuildError, Stmt};
use crate::spectrum::Rgb;
use crate::texture::TextureSet;
use glam::{Affine3A, DVec3, Vec3A};

/// A medium confined to a box.
#[derive(Debug)]
pub struct Region {
    /// World space to the volume's space.
    to_volume: Affine3A,
    lo: Vec3A,
    hi: Vec3A,
    pub inner: Box<Medium>,
}

/// The region kinds [`Region::build`] renders.
pub fn is_supported(kind: &str) -> bool {
    matches!(
        kind,
        "homogeneous" | "homogenous" | "exponential" | "volumegrid"
    )
}

impl Region {
    /// Builds the region of `v`; `Ok(None)` (with a located warning) for a kind that is not
    /// rendered or a grid LuxRender would drop. `default_step` is the marching step when the
    /// statement gives none.
    pub fn build(
        v: &VolumeDesc,
        textures: &mut TextureSet,
        warnings: &mut Vec<Diagnostic>,
        default_step: f32,
    ) -> Result<Option<Region>, BuildError> {
        let mut s = Stmt::new("volume", &v.entity, warnings);
        let m = v.object_to_world.start();
        let inv = m.inverse();
        if !(m.is_finite() && inv.is_finite() && m.determinant() != 0.0) {
            return Err(s.err("the region volume's transform is singular or not finite"));
        }
        let to_volume = Affine3A::from_mat4(inv.as_mat4());
        let p0 = Vec3A::from(s.params().point("p0").unwrap_or([0.0; 3]));
        let p1 = Vec3A::from(s.params().point("p1").unwrap_or([1.0; 3]));
        let (lo, hi) = (p0.min(p1), p0.max(p1));
        if !(lo.is_finite() && hi.is_finite()) {
            return Err(s.err("region volume: p0 and p1 must be finite"));
        }
        let le = constant_color(&mut s, textures, "Le")?;
        if !le.is_black() {
            s.warn("region volume: emission (\"Le\") is not rendered");
        }
        let inner = match v.entity.kind.as_str() {
            "homogeneous" | "homogenous" => {
                Medium::Homogeneous(Homogeneous::build(&mut s, textures)?)
            }
            "exponential" => {
                Medium::Marched(exponential_region(&mut s, textures, m, lo, default_step)?)
            }
            "volumegrid" => match grid(&mut s, textures, to_volume, lo, hi, default_step)? {
                Some(h) => Medium::Marched(h),
                None => return Ok(None),
            },
            other => {
                s.warn(format!("region volume \"{other}\" is not rendered"));
                return Ok(None);
            }
        };
        Ok(Some(Region {
            to_volume,
            lo,
            hi,
            inner: Box::new(inner),
        }))
    }

    /// The part of `ray`'s extent [0, `t_max`] inside the box, if any.
    fn clip(&self, ray: &Ray, t_max: f32) -> Option<(f32, f32)> {
        let o = self.to_volume.transform_point3a(ray.o);
        let d = self.to_volume.transform_vector3a(ray.d);
        let (mut t0, mut t1) = (0.0f32, t_max);
        for k in 0..3 {
            if d[k] == 0.0 {
                if o[k] < self.lo[k] || o[k] > self.hi[k] {
                    return None;
                }
                continue;
            }
            let (a, b) = ((self.lo[k] - o[k]) / d[k], (self.hi[k] - o[k]) / d[k]);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        (t0 < t1).then_some((t0, t1))
    }

    /// The inner medium's extinction at world point `p` inside the box, 0 outside it.
    pub fn sigma_t(&self, p: Vec3A) -> Rgb {
        let q = self.to_volume.transform_point3a(p);
        if q.cmpge(self.lo).all() && q.cmple(self.hi).all() {
            self.inner.sigma_t(p)
        } else {
            Rgb::BLACK
        }
    }

    /// Transmittance over [0, `t_max`]: the inner medium's over the part inside the box.
    pub fn tr(&self, ray: &Ray, t_max: f32) -> Rgb {
        match self.clip(ray, t_max) {
            Some((t0, t1)) => self.inner.tr(&shifted(ray, t0), t1 - t0),
            None => Rgb::WHITE,
        }
    }

    /// Samples a scattering point inside the box (the ray passes freely outside it).
    pub fn sample(&self, ray: &Ray, t_max: f32, u: f32, u_channel: f32) -> MediumSample {
        match self.clip(ray, t_max) {
            Some((t0, t1)) => {
                let s = self.inner.sample(&shifted(ray, t0), t1 - t0, u, u_channel);
                MediumSample {
                    scatter_t: s.scatter_t.map(|t| t0 + t),
                    weight: s.weight,
                }
            }
            None => MediumSample {
                scatter_t: None,
                weight: Rgb::WHITE,
            },
        }
    }
}

/// The ray starting at parameter `t0` of `ray`.
fn shifted(ray: &Ray, t0: f32) -> Ray {
    Ray {
        o: ray.o + ray.d * t0,
        t_max: ray.t_max - t0,
        ..*ray
    }
}

fn step(s: &Stmt, default_step: f32) -> Result<f32, BuildError> {
    s.positive("stepsize", default_step)
}

/// The exponential region: sigma × a·e^(-b·h), h measured from the box's low corner along
/// the unit `updir` of the volume's space (default 0 1 0), expressed in world space.
fn exponential_region(
    s: &mut Stmt,
    textures: &mut TextureSet,
    m: glam::DMat4,
    lo: Vec3A,
    default_step: f32,
) -> Result<Heterogeneous, BuildError> {
    let sigma_a = constant_color(s, textures, "sigma_a")?;
    let sigma_s = constant_color(s, textures, "sigma_s")?;
    let a = s.finite("a", 1.0)?;
    let b = s.finite("b", 1.0)?;
    let up = s.params().vector("updir").unwrap_or([0.0, 1.0, 0.0]);
    let up_obj = DVec3::from(up.map(f64::from))
        .try_normalize()
        .unwrap_or(DVec3::Y);
    // h = up_obj · (M⁻¹ p - lo) = (L⁻ᵀ up_obj) · (p - M lo), L the linear part of M.
    let up_world = glam::DMat3::from_mat4(m).inverse().transpose() * up_obj;
    let origin = m.transform_point3(lo.as_dvec3());
    Ok(Heterogeneous {
        density: Density::Exponential {
            sigma_a,
            sigma_s,
            a,
            b,
            up: Vec3A::from(up_world.as_vec3()),
            origin: Vec3A::from(origin.as_vec3()),
        },
        g: super::read_g(s),
        step: step(s, default_step)?,
    })
}

/// The `volumegrid` medium, or `None` (warned) when its values do not fit its size, as
/// LuxRender drops such a grid; a grid past [`super::grid::MAX_CELLS`] is an error.
fn grid(
    s: &mut Stmt,
    textures: &mut TextureSet,
    to_volume: Affine3A,
    lo: Vec3A,
    hi: Vec3A,
    default_step: f32,
) -> Result<Option<Heterogeneous>, BuildError> {
    let sigma_a = constant_color(s, textures, "sigma_a")?;
    let sigma_s = constant_color(s, textures, "sigma_s")?;
    let g = super::read_g(s);
    let dims = [
        s.int_at_least("nx", 1, 1)?,
        s.int_at_least("ny", 1, 1)?,
        s.int_at_least("nz", 1, 1)?,
    ];
    let Some(values) = s.params().floats("density") else {
        s.warn("volumegrid has no \"density\" values: the region is dropped (as LuxRender)");
        return Ok(None);
    };
    let grid = match Grid::new(dims, values, to_volume, lo, hi) {
        Ok(g) => g,
        Err(e @ super::grid::GridError::Count { .. }) => {
            s.warn(format!(
                "volumegrid: {e}: the region is dropped (as LuxRender)"
            ));
            return Ok(None);
        }
        Err(e) => return Err(s.err(format!("volumegrid: {e}"))),
    };
    Ok(Some(Heterogeneous {
        density: Density::Grid {
            sigma_a,
            sigma_s,
            grid: Box::new(grid),
        },
        g,
        step: step(s, default_step)?,
    }))
}
