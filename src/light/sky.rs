//! `sky` light: the analytic daylight sky of Preetham, Shirley & Smits ("A Practical Analytic
//! Model for Daylight", SIGGRAPH 1999) as LuxRender 1.x has it, as an environment light.
//!
//! **Model.** For a light-space direction ω at zenith angle θ (z is up) and angle γ from the
//! sun (`sundir`, light space, default (0, 0, 1), at zenith angle θs), each of the luminance Y
//! and the chromaticities x, y is `zenith · F(θ, γ) / F(0, θs)` with Perez et al.'s
//! `F(θ, γ) = (1 + A·e^(B / cos θ)) · (1 + C·e^(D·γ) + E·cos²γ)`. The coefficients A..E are
//! Preetham's linear functions of the turbidity T (Table "distribution coefficients"), each
//! multiplied by the scene's `aconst`..`econst` (aliases `horizonbrightness`, `horizonsize`,
//! `sunhalobrightness`, `sunhalosize`, `backscattering`; default 1). Zenith luminance (Preetham
//! eq. A.2): `Yz = ((4.0453·T − 4.9710)·tan χ − 0.2155·T + 2.4192)` kcd/m² with
//! `χ = (4/9 − T/120)·(π − 2θs)`; zenith chromaticities are Preetham's cubic polynomials in θs
//! and quadratic in T. Below the horizon the sky repeats its horizon (θ is clamped to
//! π/2 − 0.001, as LuxRender does), so the ground is lit from below only by its own geometry.
//!
//! **Spectrum and units.** The chromaticity (x, y) becomes the CIE daylight spectrum
//! `S0 + M1·S1 + M2·S2` (CIE 15's M1, M2 formulas), normalised by its luminance
//! `683·Σ S·ȳ` over 360–830 nm and multiplied by Y (cd/m²) and `gain`, exactly as LuxRender's
//! `SkyLight` does; the film XYZ of that spectrum (683 lm/W, 380–720 nm, see
//! [`crate::spectrum::xyz`]) is then the luminance Y in cd/m² (to 0.2 %). A clear sky's zenith
//! is a few thousand cd/m².
//!
//! **Rendering.** The radiance is converted to illuminant RGB (the RGB whose film XYZ is the
//! spectrum's) once at build time on a lat-long grid of vertices (256 × 128 intervals over the
//! sphere; s = φ/2π, t = θ/π as the infinite light has it) and looked up with bilinear
//! interpolation (within 1 % of the analytic value). Directions are importance sampled with a
//! piecewise-constant distribution over the grid cells weighted by their mean luminance ×
//! sin θ, so the pdf is exact.
//!
//! Parameters: `sundir`, `turbidity` (2), `gain` (1), `aconst`..`econst`, `nsamples` (1).

use super::latlong::{self, dir_to_st, st_to_dir};
use super::sun::film_xyz;
use super::sunsky_data as data;
use super::{LightCommon, LightSample};
use crate::geometry::Interaction;
use crate::lxs::ParamSet;
use crate::sampling::PiecewiseConstant2D;
use crate::spectrum::cie::cmf;
use crate::spectrum::xyz::LUMENS_PER_WATT;
use crate::spectrum::{xyz_to_rgb, Rgb};
use glam::{Mat4, Vec2, Vec3A};
use std::f32::consts::{FRAC_PI_2, PI};
use std::sync::OnceLock;

/// Grid intervals in φ and θ of the tabulated sky.
pub const GRID_WIDTH: usize = 256;
pub const GRID_HEIGHT: usize = 128;

/// Preetham's Perez coefficients (A..E) for Y, x and y: `slope · T + offset`.
#[rustfmt::skip]
const PEREZ: [[(f32, f32); 5]; 3] = [
    [(0.1787, -1.4630), (-0.3554, 0.4275), (-0.0227, 5.3251), (0.1206, -2.5771), (-0.0670, 0.3703)],
    [(-0.0193, -0.2592), (-0.0665, 0.0008), (-0.0004, 0.2125), (-0.0641, -0.8989), (-0.0033, 0.0452)],
    [(-0.0167, -0.2608), (-0.0950, 0.0092), (-0.0079, 0.2102), (-0.0441, -1.6537), (-0.0109, 0.0529)],
];

/// Perez et al.'s sky distribution function.
pub fn perez(c: &[f32; 5], theta: f32, gamma: f32) -> f32 {
    let cg = gamma.cos();
    (1.0 + c[0] * (c[1] / theta.cos()).exp()) * (1.0 + c[2] * (c[3] * gamma).exp() + c[4] * cg * cg)
}

/// Preetham's zenith luminance (cd/m²) for turbidity `t` and solar zenith angle `theta_s`.
pub fn zenith_luminance(t: f32, theta_s: f32) -> f32 {
    let chi = (4.0 / 9.0 - t / 120.0) * (PI - 2.0 * theta_s);
    ((4.0453 * t - 4.9710) * chi.tan() - 0.2155 * t + 2.4192) * 1000.0
}

/// Preetham's zenith chromaticity (x, y).
pub fn zenith_chromaticity(t: f32, theta_s: f32) -> (f32, f32) {
    let (t1, t2, t3) = (theta_s, theta_s * theta_s, theta_s * theta_s * theta_s);
    let poly = |c: [[f32; 4]; 3]| {
        let row = |r: [f32; 4]| r[0] * t3 + r[1] * t2 + r[2] * t1 + r[3];
        row(c[0]) * t * t + row(c[1]) * t + row(c[2])
    };
    let x = poly([
        [0.00166, -0.00375, 0.00209, 0.0],
        [-0.02903, 0.06377, -0.03202, 0.00394],
        [0.11693, -0.21196, 0.06052, 0.25886],
    ]);
    let y = poly([
        [0.00275, -0.00610, 0.00317, 0.0],
        [-0.04214, 0.08970, -0.04153, 0.00516],
        [0.15346, -0.26756, 0.06670, 0.26688],
    ]);
    (x, y)
}

/// Film XYZ and full-range luminance of the three CIE daylight basis spectra.
struct DaylightBasis {
    xyz: [[f64; 3]; 3],
    y: [f64; 3],
}

fn daylight_basis() -> &'static DaylightBasis {
    static BASIS: OnceLock<DaylightBasis> = OnceLock::new();
    BASIS.get_or_init(|| {
        let tables = [&data::DAYLIGHT_S0, &data::DAYLIGHT_S1, &data::DAYLIGHT_S2];
        let sample = |k: usize, nm: f32| {
            f64::from(data::sample_regular(
                tables[k],
                data::DAYLIGHT_START,
                data::DAYLIGHT_END,
                nm,
            ))
        };
        DaylightBasis {
            xyz: std::array::from_fn(|k| film_xyz(|nm| sample(k, nm))),
            y: std::array::from_fn(|k| {
                let sum: f64 = (360..=830)
                    .map(|nm| sample(k, nm as f32) * f64::from(cmf(nm as f32)[1]))
                    .sum();
                sum * LUMENS_PER_WATT
            }),
        }
    })
}

/// The sky's radiance distribution in light space.
#[derive(Clone, Debug)]
pub struct SkyModel {
    /// Unit direction toward the sun.
    pub sun: Vec3A,
    /// Zenith Y (cd/m²), x, y, each divided by F(0, θs).
    zenith: [f32; 3],
    coeffs: [[f32; 5]; 3],
}

impl SkyModel {
    /// `consts` are the aconst..econst multipliers of the Perez coefficients.
    pub fn new(sun: Vec3A, turbidity: f32, consts: [f32; 5]) -> SkyModel {
        let sun = sun.normalize_or(Vec3A::Z);
        let theta_s = sun.z.clamp(-1.0, 1.0).acos();
        let coeffs: [[f32; 5]; 3] = std::array::from_fn(|k| {
            std::array::from_fn(|i| {
                let (a, b) = PEREZ[k][i];
                (a * turbidity + b) * consts[i]
            })
        });
        let (zx, zy) = zenith_chromaticity(turbidity, theta_s);
        let z = [zenith_luminance(turbidity, theta_s), zx, zy];
        let zenith = std::array::from_fn(|k| z[k] / perez(&coeffs[k], 0.0, theta_s));
        SkyModel {
            sun,
            zenith,
            coeffs,
        }
    }

    /// Luminance Y (cd/m²) and chromaticity x, y of the sky in direction `w` (unit).
    pub fn yxy(&self, w: Vec3A) -> [f32; 3] {
        let theta = w.z.clamp(-1.0, 1.0).acos().min(FRAC_PI_2 - 0.001);
        let gamma = w.dot(self.sun).clamp(-1.0, 1.0).acos();
        std::array::from_fn(|k| self.zenith[k] * perez(&self.coeffs[k], theta, gamma))
    }

    /// Film XYZ of the sky's spectral radiance in direction `w` (unit), before `gain`.
    pub fn film_xyz(&self, w: Vec3A) -> [f64; 3] {
        let [lum, x, y] = self.yxy(w).map(f64::from);
        let den = 0.0241 + 0.2562 * x - 0.7341 * y;
        let m1 = (-1.3515 - 1.7703 * x + 5.9114 * y) / den;
        let m2 = (0.03 - 31.4424 * x + 30.0717 * y) / den;
        let b = daylight_basis();
        let norm = b.y[0] + m1 * b.y[1] + m2 * b.y[2];
        let out: [f64; 3] = std::array::from_fn(|c| {
            lum * (b.xyz[0][c] + m1 * b.xyz[1][c] + m2 * b.xyz[2][c]) / norm
        });
        if lum > 0.0 && out.iter().all(|v| v.is_finite()) {
            out
        } else {
            [0.0; 3]
        }
    }
}

#[derive(Debug)]
pub struct SkyLight {
    pub common: LightCommon,
    pub model: SkyModel,
    gain: f32,
    l2w: Mat4,
    w2l: Mat4,
    /// RGB radiance at the grid vertices: `GRID_HEIGHT + 1` rows of `GRID_WIDTH`.
    vertices: Vec<Rgb>,
    dist: PiecewiseConstant2D,
    /// Solid-angle mean of the luminance over the sphere.
    mean_y: f32,
    pub world_radius: f32,
    /// Windows it is sampled through (`PortalShape`), see [`super::portal`].
    pub portals: Option<super::portal::Portals>,
}

impl SkyLight {
    pub fn new(params: &ParamSet, l2w: Mat4, common: LightCommon) -> Result<SkyLight, String> {
        let gain = params.float_or("gain", 1.0);
        let turbidity = params.float_or("turbidity", 2.0);
        let sundir = Vec3A::from_array(params.vector("sundir").unwrap_or([0.0, 0.0, 1.0]));
        let sun = sundir
            .try_normalize()
            .ok_or_else(|| "sky: sundir must be a non-zero vector".to_string())?;
        let named = |a: &str, b: &str| params.float(a).or_else(|| params.float(b)).unwrap_or(1.0);
        let consts = [
            named("aconst", "horizonbrightness"),
            named("bconst", "horizonsize"),
            named("cconst", "sunhalobrightness"),
            named("dconst", "sunhalosize"),
            named("econst", "backscattering"),
        ];
        if !(gain.is_finite() && turbidity.is_finite() && consts.iter().all(|c| c.is_finite())) {
            return Err("sky: gain, turbidity and the Perez constants must be finite".into());
        }
        if sun.z < 0.0 {
            tracing::warn!("sky: the sun is below the horizon; the daylight model does not hold");
        }
        Ok(SkyLight::from_model(
            SkyModel::new(sun, turbidity, consts),
            gain,
            l2w,
            common,
        ))
    }

    /// Tabulates `model` × `gain` and builds its sampling distribution.
    pub fn from_model(model: SkyModel, gain: f32, l2w: Mat4, common: LightCommon) -> SkyLight {
        let (w, h) = (GRID_WIDTH, GRID_HEIGHT);
        let mut vertices = Vec::with_capacity(w * (h + 1));
        let mut lum = Vec::with_capacity(w * (h + 1));
        for j in 0..=h {
            for i in 0..w {
                let (d, _) = st_to_dir(i as f32 / w as f32, j as f32 / h as f32);
                let xyz = model.film_xyz(d).map(|v| (v * f64::from(gain)) as f32);
                vertices.push(xyz_to_rgb(xyz));
                lum.push(xyz[1].max(0.0));
            }
        }
        let mut weights = Vec::with_capacity(w * h);
        let mut total = 0.0f64;
        for j in 0..h {
            let sin_c = (PI * (j as f32 + 0.5) / h as f32).sin();
            for i in 0..w {
                let i1 = (i + 1) % w;
                let corners = [
                    lum[j * w + i],
                    lum[j * w + i1],
                    lum[(j + 1) * w + i],
                    lum[(j + 1) * w + i1],
                ];
                let mean = corners.iter().sum::<f32>() / 4.0;
                weights.push(mean * sin_c);
                total += f64::from(mean * sin_c);
            }
        }
        // Σ mean·sinθ·dθ·dφ over the sphere, divided by 4π.
        let cell = (PI / h as f32) * (2.0 * PI / w as f32);
        let mean_y = (total * f64::from(cell) / (4.0 * std::f64::consts::PI)) as f32;
        SkyLight {
            common,
            model,
            gain,
            l2w,
            w2l: l2w.inverse(),
            vertices,
            dist: PiecewiseConstant2D::new(&weights, w, h),
            mean_y,
            world_radius: 1.0,
            portals: None,
        }
    }

    pub fn gain(&self) -> f32 {
        self.gain
    }

    fn vertex(&self, i: usize, j: usize) -> Rgb {
        self.vertices
            .get(j * GRID_WIDTH + i)
            .copied()
            .unwrap_or(Rgb::BLACK)
    }

    /// Bilinear lookup of the table at light-space lat-long coordinates.
    fn lookup(&self, s: f32, t: f32) -> Rgb {
        let u = (s * GRID_WIDTH as f32).max(0.0);
        let v = (t * GRID_HEIGHT as f32).clamp(0.0, GRID_HEIGHT as f32);
        let i0 = (u as usize).min(GRID_WIDTH - 1);
        let j0 = (v as usize).min(GRID_HEIGHT - 1);
        let (fu, fv) = (
            (u - i0 as f32).clamp(0.0, 1.0),
            (v - j0 as f32).clamp(0.0, 1.0),
        );
        let i1 = (i0 + 1) % GRID_WIDTH;
        let top = self.vertex(i0, j0) * (1.0 - fu) + self.vertex(i1, j0) * fu;
        let bottom = self.vertex(i0, j0 + 1) * (1.0 - fu) + self.vertex(i1, j0 + 1) * fu;
        top * (1.0 - fv) + bottom * fv
    }

    /// Radiance toward the light-space direction `d` (unit).
    pub fn le_local(&self, d: Vec3A) -> Rgb {
        let (s, t, _) = dir_to_st(d);
        self.lookup(s, t)
    }

    pub fn le(&self, dir: Vec3A) -> Rgb {
        self.le_local(self.w2l.transform_vector3a(dir).normalize_or_zero())
    }

    pub fn sample_li(&self, r: &Interaction, u: Vec2) -> Option<LightSample> {
        latlong::sample_li(&self.dist, &self.l2w, r, u, self.world_radius, |s, t| {
            self.lookup(s, t)
        })
    }

    pub fn pdf_li(&self, wi: Vec3A) -> f32 {
        latlong::pdf(&self.dist, &self.w2l, wi)
    }

    /// Luminous power through a disc of the scene's radius (as the infinite light's).
    pub fn power(&self) -> f32 {
        latlong::sky_power(self.mean_y, self.world_radius)
    }
}

#[cfg(test)]
mod tests;
