//! One region `Volume` statement (pbrt's volume regions, deprecated in LuxRender 1.x but
//! still read): `homogeneous` (also spelled `homogenous`), `exponential`, `volumegrid` and
//! `cloud`, each filling the box between `p0` (default 0 0 0) and `p1` (1 1 1) of the
//! statement's space with `sigma_a`, `sigma_s` (colours, default 0), `g`, and emitted radiance
//! `Le` (colour per unit length, default 0). `exponential` scales the three colours by
//! a·e^(-b·h), h measured from the box's low corner along `updir` (default 0 1 0) in the
//! volume's space; `volumegrid` by its `density` grid ([`super::grid`]); `cloud` by its cloud
//! density ([`super::cloud`]); these three are marched in steps of `stepsize` (the
//! statement's, else the VolumeIntegrator's, else 1). LuxRender's `DensityRegion` scales
//! `Le` by the density as it scales the coefficients; a homogeneous region emits `Le`
//! everywhere in its box.
//!
//! ```text
//! Volume (VolumeDesc, no name) --Region::build--> Region { box, Inner }
//!   Region::pieces: the ray clipped to the box, cut into pieces of constant coefficients
//!   (one for a homogeneous region, one per marching step otherwise: the step's midpoint)
//!   super::regions merges the pieces of every region along a ray
//! ```

use super::cloud::CloudRegion;
use super::grid::Grid;
use super::heterogeneous::{Coeffs, Density, Field, Heterogeneous};
use super::{constant_color, Homogeneous};
use crate::geometry::Ray;
use crate::lxs::{Diagnostic, VolumeDesc};
use crate::plugin::{BuildError, Stmt};
use crate::texture::TextureSet;
use glam::{Affine3A, DVec3, Vec3A};

/// A medium confined to a box.
#[derive(Debug)]
pub struct Region {
    /// World space to the volume's space.
    to_volume: Affine3A,
    lo: Vec3A,
    hi: Vec3A,
    inner: Inner,
}

/// What fills a region's box.
#[derive(Debug)]
enum Inner {
    /// The same coefficients everywhere (homogeneous).
    Uniform { c: Coeffs, g: f32 },
    /// Coefficients that vary: marched.
    Marched(Heterogeneous),
}

/// A stretch [t0, t1] of a ray (ray parameters) over which a region's coefficients are `c`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    pub t0: f32,
    pub t1: f32,
    pub c: Coeffs,
}

/// The region kinds [`Region::build`] renders.
pub fn is_supported(kind: &str) -> bool {
    matches!(
        kind,
        "homogeneous" | "homogenous" | "exponential" | "volumegrid" | "cloud"
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
        let scaled = |s: &mut Stmt, textures: &mut TextureSet| -> Result<Coeffs, BuildError> {
            Ok(Coeffs {
                sigma_a: constant_color(s, textures, "sigma_a")?,
                sigma_s: constant_color(s, textures, "sigma_s")?,
                le,
            })
        };
        let inner = match v.entity.kind.as_str() {
            "homogeneous" | "homogenous" => {
                let h = Homogeneous::build(&mut s, textures)?;
                let c = Coeffs {
                    sigma_a: h.sigma_a,
                    sigma_s: h.sigma_s,
                    le,
                };
                Inner::Uniform { c, g: h.g }
            }
            "exponential" => {
                let c = scaled(&mut s, textures)?;
                Inner::Marched(exponential_region(&mut s, c, m, lo, default_step)?)
            }
            "volumegrid" => {
                let c = scaled(&mut s, textures)?;
                match grid(&mut s, c, to_volume, lo, hi, default_step)? {
                    Some(h) => Inner::Marched(h),
                    None => return Ok(None),
                }
            }
            "cloud" => {
                let c = scaled(&mut s, textures)?;
                let field = Field::Cloud(Box::new(CloudRegion::build(&mut s, to_volume, lo, hi)?));
                Inner::Marched(marched(&mut s, c, field, default_step)?)
            }
            other => {
                s.warn(format!("region volume \"{other}\" is not rendered"));
                return Ok(None);
            }
        };
        Ok(Some(Region {
            to_volume,
            lo,
            hi,
            inner,
        }))
    }

    /// A homogeneous region over the box `lo`–`hi` of world space (tests build regions
    /// without a scene).
    #[cfg(test)]
    pub fn uniform(lo: Vec3A, hi: Vec3A, c: Coeffs, g: f32) -> Region {
        Region {
            to_volume: Affine3A::IDENTITY,
            lo,
            hi,
            inner: Inner::Uniform { c, g },
        }
    }

    /// The Henyey–Greenstein asymmetry of the region's scattering.
    pub fn g(&self) -> f32 {
        match &self.inner {
            Inner::Uniform { g, .. } => *g,
            Inner::Marched(h) => h.g,
        }
    }

    /// Whether the region neither attenuates nor emits (all its coefficients zero).
    pub fn is_vacuum(&self) -> bool {
        match &self.inner {
            Inner::Uniform { c, .. } => {
                c.sigma_a.is_black() && c.sigma_s.is_black() && c.le.is_black()
            }
            Inner::Marched(h) => h.density.is_vacuum(),
        }
    }

    /// Whether the region can scatter light.
    pub fn scatters(&self) -> bool {
        match &self.inner {
            Inner::Uniform { c, .. } => !c.sigma_s.is_black(),
            Inner::Marched(h) => h.density.scatters(),
        }
    }

    /// The world-space box around the region (its box's corners carried out of the
    /// volume's space).
    pub fn world_bounds(&self) -> (Vec3A, Vec3A) {
        let to_world = self.to_volume.inverse();
        let (mut lo, mut hi) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
        for i in 0..8 {
            let pick = |bit: usize, a: f32, b: f32| if i & bit == 0 { a } else { b };
            let c = Vec3A::new(
                pick(1, self.lo.x, self.hi.x),
                pick(2, self.lo.y, self.hi.y),
                pick(4, self.lo.z, self.hi.z),
            );
            let w = to_world.transform_point3a(c);
            (lo, hi) = (lo.min(w), hi.max(w));
        }
        (lo, hi)
    }

    /// Whether the region emits light (`Le` not black).
    pub fn emits(&self) -> bool {
        match &self.inner {
            Inner::Uniform { c, .. } => !c.le.is_black(),
            Inner::Marched(h) => match &h.density {
                Density::Scaled { c, .. } => !c.le.is_black(),
                Density::Textures { .. } => false,
            },
        }
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

    /// The coefficients at world point `p` (0 outside the box).
    pub fn coeffs(&self, p: Vec3A) -> Coeffs {
        let q = self.to_volume.transform_point3a(p);
        if !(q.cmpge(self.lo).all() && q.cmple(self.hi).all()) {
            return Coeffs::default();
        }
        match &self.inner {
            Inner::Uniform { c, .. } => *c,
            Inner::Marched(h) => h.density.coeffs(p),
        }
    }

    /// The pieces of constant coefficients along `ray`'s extent [0, `t_max`] inside the box
    /// (`None` when the ray misses it): the whole clipped part for a homogeneous region, the
    /// marching steps (coefficients at each step's middle) otherwise.
    pub fn pieces(&self, ray: &Ray, t_max: f32) -> Option<Pieces<'_>> {
        let (t0, t1) = self.clip(ray, t_max)?;
        let len = ray.d.length();
        if !(len > 0.0 && t1.is_finite()) {
            return None;
        }
        let (step, n) = match &self.inner {
            Inner::Uniform { .. } => (t1 - t0, 1),
            Inner::Marched(h) => {
                let (step, n) = h.steps((t1 - t0) * len);
                (step / len, n)
            }
        };
        Some(Pieces {
            region: self,
            o: ray.o,
            d: ray.d,
            t0,
            t1,
            step,
            n,
            i: 0,
        })
    }
}

/// The pieces of one region along a ray, in order ([`Region::pieces`]).
pub struct Pieces<'a> {
    region: &'a Region,
    o: Vec3A,
    d: Vec3A,
    t0: f32,
    t1: f32,
    step: f32,
    n: u32,
    i: u32,
}

impl Iterator for Pieces<'_> {
    type Item = Piece;

    fn next(&mut self) -> Option<Piece> {
        if self.i >= self.n {
            return None;
        }
        // Both ends from the same expression: consecutive pieces share their boundary.
        let at = |i: u32| {
            if i >= self.n {
                self.t1
            } else {
                self.t0 + i as f32 * self.step
            }
        };
        let (a, b) = (at(self.i), at(self.i + 1).min(self.t1));
        self.i += 1;
        let c = match &self.region.inner {
            Inner::Uniform { c, .. } => *c,
            Inner::Marched(h) => h.density.coeffs(self.o + self.d * (0.5 * (a + b))),
        };
        Some(Piece { t0: a, t1: b, c })
    }
}

fn step(s: &Stmt, default_step: f32) -> Result<f32, BuildError> {
    s.positive("stepsize", default_step)
}

/// The exponential region: sigma × a·e^(-b·h), h measured from the box's low corner along
/// the unit `updir` of the volume's space (default 0 1 0), expressed in world space.
fn exponential_region(
    s: &mut Stmt,
    c: Coeffs,
    m: glam::DMat4,
    lo: Vec3A,
    default_step: f32,
) -> Result<Heterogeneous, BuildError> {
    let a = s.finite("a", 1.0)?;
    let b = s.finite("b", 1.0)?;
    let up = s.params().vector("updir").unwrap_or([0.0, 1.0, 0.0]);
    let up_obj = DVec3::from(up.map(f64::from))
        .try_normalize()
        .unwrap_or(DVec3::Y);
    // h = up_obj · (M⁻¹ p - lo) = (L⁻ᵀ up_obj) · (p - M lo), L the linear part of M.
    let up_world = glam::DMat3::from_mat4(m).inverse().transpose() * up_obj;
    let origin = m.transform_point3(lo.as_dvec3());
    let field = Field::Exponential {
        a,
        b,
        up: Vec3A::from(up_world.as_vec3()),
        origin: Vec3A::from(origin.as_vec3()),
    };
    marched(s, c, field, default_step)
}

/// A marched region of coefficients `c` scaled by `field`, with the statement's `g` and
/// `stepsize`.
fn marched(
    s: &mut Stmt,
    c: Coeffs,
    field: Field,
    default_step: f32,
) -> Result<Heterogeneous, BuildError> {
    Ok(Heterogeneous {
        density: Density::Scaled { c, field },
        g: super::read_g(s),
        step: step(s, default_step)?,
    })
}

/// The `volumegrid` medium, or `None` (warned) when its values do not fit its size, as
/// LuxRender drops such a grid; a grid past [`super::grid::MAX_CELLS`] is an error.
fn grid(
    s: &mut Stmt,
    c: Coeffs,
    to_volume: Affine3A,
    lo: Vec3A,
    hi: Vec3A,
    default_step: f32,
) -> Result<Option<Heterogeneous>, BuildError> {
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
    marched(s, c, Field::Grid(Box::new(grid)), default_step).map(Some)
}
