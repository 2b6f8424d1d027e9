//! `sun` light: the sun of Preetham, Shirley & Smits ("A Practical Analytic Model for
//! Daylight", SIGGRAPH 1999) as LuxRender 1.x has it.
//!
//! **Spectrum.** The extraterrestrial solar radiance (W·m⁻²·sr⁻¹·nm⁻¹, see
//! [`super::sunsky_data`]) times the transmittance of the atmosphere along the sun's path,
//! sampled every 5 nm from 350 to 800 nm and linearly interpolated in between:
//! Rayleigh scattering `exp(−m·0.008735·λ^−4.08)`, aerosols `exp(−m·β·λ^−1.3)` with
//! Ångström's `β = 0.04608365822050·T − 0.04586025928522` (T the turbidity), ozone
//! `exp(−m·k_o·0.35 cm)`, mixed gases `exp(−1.41·k_g·m / (1 + 118.93·k_g·m)^0.45)` and water
//! vapour `exp(−0.2385·k_wa·w·m / (1 + 20.07·k_wa·w·m)^0.45)` with w = 2 cm (λ in µm in the
//! first two). `m = 1 / (cos θs + 0.00094·(1.6386 − θs)^−1.253)` is the relative optical air
//! mass at the sun's zenith angle θs, taken (as LuxRender does) from the world-space sun
//! direction. A sun below the horizon (where the air mass formula breaks down) emits nothing.
//!
//! **Units and scale.** The spectrum is the sun's radiance, times `gain / relsize²`; the film
//! receives `683 lm/W · ∫ L(λ) [x̄ ȳ z̄](λ) dλ` over 380–720 nm as for every LuxRender light
//! (see [`crate::spectrum::xyz`]), so a clear high sun has a luminance of about 1.5·10⁹ cd/m²
//! and an illuminance of about 10⁵ lux at normal incidence. The spectrum is integrated once
//! at build time and kept as the illuminant RGB with that XYZ.
//!
//! **Shape.** A disc of angular radius θmax with `sin θmax = relsize · 695 500 km /
//! 149 600 000 km` (the sun's radius and mean distance, NASA), i.e. a cone of directions
//! around `sundir` (light space, default (0, 0, −1)), of uniform radiance, sampled uniformly
//! (pdf 1 / (2π(1 − cos θmax)), with 1 − cos θmax computed from sin²θmax to keep its precision).
//! `relsize` scales the disc while keeping the irradiance (radiance ∝ 1/relsize²); a disc larger
//! than a hemisphere is clamped to it with a warning.
//!
//! Parameters: `sundir`, `turbidity` (2), `gain` (1), `relsize` (1), `nsamples` (1).

use super::sunsky_data as data;
use super::{LightCommon, LightSample};
use crate::geometry::frame::coordinate_system;
use crate::geometry::Interaction;
use crate::lxs::ParamSet;
use crate::spectrum::cie::cmf;
use crate::spectrum::xyz::LUMENS_PER_WATT;
use crate::spectrum::{xyz_to_rgb, Rgb};
use glam::{Mat4, Vec2, Vec3A};
use std::f32::consts::PI;

/// The sun's radius, km (NASA Solar System Exploration).
pub const SUN_RADIUS_KM: f64 = 695_500.0;
/// The sun's mean distance from the Earth, km.
pub const SUN_DISTANCE_KM: f64 = 149_600_000.0;

/// First wavelength, step and count of the sun's sampled spectrum (350–800 nm by 5 nm).
pub const SPECTRUM_START: f32 = 350.0;
pub const SPECTRUM_STEP: f32 = 5.0;
pub const SPECTRUM_LEN: usize = 91;

/// `683 · Σ s(λ) [x̄ ȳ z̄](λ)` over 380–720 nm in 1 nm steps: the film XYZ of a spectral
/// radiance `s` (W·m⁻²·sr⁻¹·nm⁻¹), as LuxRender's film integrates it.
pub fn film_xyz(s: impl Fn(f32) -> f64) -> [f64; 3] {
    let mut acc = [0.0f64; 3];
    for nm in 380..=720 {
        let v = s(nm as f32);
        let c = cmf(nm as f32);
        for (a, ci) in acc.iter_mut().zip(c) {
            *a += f64::from(ci) * v;
        }
    }
    acc.map(|a| a * LUMENS_PER_WATT)
}

/// Relative optical air mass at solar zenith angle `theta_s` (radians, at most π/2).
pub fn air_mass(theta_s: f32) -> f32 {
    1.0 / (theta_s.cos() + 0.00094 * (1.6386 - theta_s).powf(-1.253))
}

/// Transmittance of the atmosphere at `nm` along a path of air mass `m` with turbidity `t`.
pub fn transmittance(nm: f32, m: f32, t: f32) -> f32 {
    let um = nm / 1000.0;
    let beta = 0.046_083_66 * t - 0.045_860_26;
    let rayleigh = (-m * 0.008735 * um.powf(-4.08)).exp();
    let aerosol = (-m * beta * um.powf(-1.3)).exp();
    let ozone = (-m * data::sample_irregular(&data::OZONE_NM, &data::OZONE_K, nm) * 0.35).exp();
    let kg = data::sample_irregular(&data::GAS_NM, &data::GAS_K, nm);
    let gases = (-1.41 * kg * m / (1.0 + 118.93 * kg * m).powf(0.45)).exp();
    let kwa = data::sample_irregular(&data::WATER_NM, &data::WATER_K, nm);
    let w = 2.0;
    let water = (-0.2385 * kwa * w * m / (1.0 + 20.07 * kwa * w * m).powf(0.45)).exp();
    rayleigh * aerosol * ozone * gases * water
}

/// The sun's spectral radiance (W·m⁻²·sr⁻¹·nm⁻¹) at the ground for a sun at zenith angle
/// `theta_s` (at most π/2) and turbidity `t`, sampled at 350, 355, ..., 800 nm.
pub fn sun_spectrum(theta_s: f32, t: f32) -> [f32; SPECTRUM_LEN] {
    let m = air_mass(theta_s);
    std::array::from_fn(|i| {
        let nm = SPECTRUM_START + SPECTRUM_STEP * i as f32;
        let sol = data::sample_regular(
            &data::SOLAR_RADIANCE,
            data::SOLAR_START,
            data::SOLAR_END,
            nm,
        );
        sol * transmittance(nm, m, t)
    })
}

/// Film XYZ of a spectrum sampled as [`sun_spectrum`] returns it (linear in between).
pub fn spectrum_xyz(samples: &[f32; SPECTRUM_LEN]) -> [f64; 3] {
    let end = SPECTRUM_START + SPECTRUM_STEP * (SPECTRUM_LEN - 1) as f32;
    film_xyz(|nm| f64::from(data::sample_regular(samples, SPECTRUM_START, end, nm)))
}

#[derive(Debug)]
pub struct SunLight {
    pub common: LightCommon,
    /// Unit world direction toward the sun's centre, with a frame (s, t) around it.
    pub to_light: Vec3A,
    frame: (Vec3A, Vec3A),
    /// Radiance of the disc.
    pub radiance: Rgb,
    /// sin²θmax and 1 − cos θmax of the disc's angular radius.
    sin2_max: f32,
    one_minus_cos: f32,
    y: f32,
    pub world_radius: f32,
}

impl SunLight {
    pub fn new(params: &ParamSet, l2w: Mat4, common: LightCommon) -> Result<SunLight, String> {
        let gain = params.float_or("gain", 1.0);
        let turbidity = params.float_or("turbidity", 2.0);
        let relsize = params.float_or("relsize", 1.0);
        let dir = Vec3A::from_array(params.vector("sundir").unwrap_or([0.0, 0.0, -1.0]));
        if !(relsize > 0.0 && relsize.is_finite()) {
            return Err(format!("sun: relsize must be positive (got {relsize})"));
        }
        if !(gain.is_finite() && turbidity.is_finite()) {
            return Err("sun: gain and turbidity must be finite".into());
        }
        let to_light = l2w.transform_vector3a(dir).try_normalize().ok_or_else(|| {
            "sun: sundir must be a non-zero vector in the light's space".to_string()
        })?;
        let (sin2_max, one_minus_cos) = disc(relsize);
        let radiance_xyz = if to_light.z >= 0.0 {
            let theta_s = to_light.z.clamp(0.0, 1.0).acos();
            let scale = f64::from(gain) / f64::from(relsize).powi(2);
            spectrum_xyz(&sun_spectrum(theta_s, turbidity)).map(|v| v * scale)
        } else {
            tracing::warn!("sun: the sun is below the horizon (sundir z < 0): it emits nothing");
            [0.0; 3]
        };
        let xyz = radiance_xyz.map(|v| v as f32);
        Ok(SunLight {
            common,
            to_light,
            frame: coordinate_system(to_light),
            radiance: xyz_to_rgb(xyz),
            sin2_max,
            one_minus_cos,
            y: xyz[1],
            world_radius: 1.0,
        })
    }

    /// Solid angle of the disc.
    pub fn solid_angle(&self) -> f32 {
        2.0 * PI * self.one_minus_cos
    }

    fn pdf(&self) -> f32 {
        1.0 / self.solid_angle()
    }

    /// Whether `wi` (unit) points into the disc.
    fn in_disc(&self, wi: Vec3A) -> bool {
        let (s, t) = self.frame;
        let (a, b) = (wi.dot(s), wi.dot(t));
        wi.dot(self.to_light) > 0.0 && a * a + b * b <= self.sin2_max
    }

    pub fn sample_li(&self, r: &Interaction, u: Vec2) -> Option<LightSample> {
        let omc = u.x * self.one_minus_cos;
        let cos_t = 1.0 - omc;
        let sin_t = (omc * (2.0 - omc)).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let (s, t) = self.frame;
        let wi = (s * (sin_t * phi.cos()) + t * (sin_t * phi.sin()) + self.to_light * cos_t)
            .normalize_or(self.to_light);
        Some(LightSample::from_infinity(
            r,
            wi,
            self.radiance,
            self.pdf(),
            false,
            self.world_radius,
        ))
    }

    pub fn pdf_li(&self, wi: Vec3A) -> f32 {
        if self.in_disc(wi) {
            self.pdf()
        } else {
            0.0
        }
    }

    pub fn le(&self, dir: Vec3A) -> Rgb {
        if self.in_disc(dir.normalize_or_zero()) {
            self.radiance
        } else {
            Rgb::BLACK
        }
    }

    /// Luminous power through a disc of the scene's radius (radiance × solid angle × area).
    pub fn power(&self) -> f32 {
        self.y * self.solid_angle() * PI * self.world_radius * self.world_radius
    }
}

/// sin²θmax and 1 − cos θmax of the sun's disc at `relsize` (clamped to a hemisphere).
fn disc(relsize: f32) -> (f32, f32) {
    let sin_max = f64::from(relsize) * SUN_RADIUS_KM / SUN_DISTANCE_KM;
    if sin_max > 1.0 {
        tracing::warn!(
            "sun: relsize {relsize} is larger than the sky; reducing it to {}",
            SUN_DISTANCE_KM / SUN_RADIUS_KM
        );
        return (1.0, 1.0);
    }
    let s2 = sin_max * sin_max;
    (s2 as f32, (s2 / (1.0 + (1.0 - s2).sqrt())) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lxs::ParamValue;
    use crate::spectrum::rgb_to_xyz;

    fn common() -> LightCommon {
        LightCommon::single(0)
    }

    fn sun(dir: [f32; 3], extra: &[(&str, f32)]) -> SunLight {
        let mut ps = ParamSet::new();
        ps.add("sundir", ParamValue::Vector(vec![dir]));
        for (k, v) in extra {
            ps.add(k, ParamValue::Float(vec![*v]));
        }
        SunLight::new(&ps, Mat4::IDENTITY, common()).unwrap()
    }

    /// Transmittance at 550 nm for a zenith sun and turbidity 2, by hand from the model's
    /// formulas: m = 1/(1 + 0.00094·1.6386^−1.253) = 0.999494; Rayleigh exp(−m·0.008735·
    /// 0.55^−4.08) = 0.90476; aerosols β = 0.046307, exp(−m·β·0.55^−1.3) = 0.90422; ozone
    /// exp(−m·0.085·0.35) = 0.97069; product 0.79411.
    #[test]
    fn transmittance_by_hand() {
        let m = air_mass(0.0);
        assert!((m - 0.999_494).abs() < 1e-5, "{m}");
        let t = transmittance(550.0, m, 2.0);
        assert!((t - 0.79411).abs() < 2e-4, "{t}");
    }

    /// The spectrum → XYZ chain against an independent computation (numpy, from the same
    /// tables and formulas: 1 nm sums of the 5 nm-sampled spectrum times the CIE 1931 5 nm table,
    /// both interpolated linearly): zenith sun, turbidity 2, and a sun 77.4°
    /// from the zenith (sunsky_low) at turbidity 2.
    #[test]
    fn spectrum_xyz_matches_independent_values() {
        let zenith = spectrum_xyz(&sun_spectrum(0.0, 2.0));
        let expected = [1.4516e9, 1.4963e9, 1.4468e9];
        for (a, b) in zenith.iter().zip(expected) {
            assert!((a - b).abs() < 2e-3 * b, "{zenith:?} vs {expected:?}");
        }
        let low = spectrum_xyz(&sun_spectrum(0.217_989f32.acos(), 2.0));
        let expected = [6.6844e8, 6.7651e8, 4.2976e8];
        for (a, b) in low.iter().zip(expected) {
            assert!((a - b).abs() < 2e-3 * b, "{low:?} vs {expected:?}");
        }
    }

    /// LuxCore 2.11 (pyluxcore; an independent implementation of the same sun model) rendering
    /// a kd = 1 matte plane lit by its `sun` at gain 1, direct light only: the plane's radiance
    /// is E·cos θ/π; its mean linear sRGB, converted to XYZ with the sRGB matrix, gives the
    /// chromaticity and Y/cos θ below (tests/data/luxcore_sun.py, 16×16 px × 16 spp). Ours:
    /// xy within 0.001, Y within 0.8 %.
    #[test]
    fn sun_matches_luxcore_renders() {
        let cases = [
            ([0.0, 0.0, 1.0], 2.0, (0.3293, 0.3399), 3.240e4),
            (
                [-0.419128, -0.881370, 0.217989],
                2.0,
                (0.3764, 0.3803),
                1.474e4,
            ),
            ([0.0, 0.0, 1.0], 6.0, (0.3439, 0.3517), 2.185e4),
            (
                [-0.305558, -0.652300, 0.693642],
                2.0,
                (0.3352, 0.3458),
                2.939e4,
            ),
        ];
        for (dir, t, (lx, ly), ly_cos) in cases {
            let s = sun(dir, &[("turbidity", t)]);
            let xyz = rgb_to_xyz(s.radiance);
            let sum = xyz[0] + xyz[1] + xyz[2];
            let (x, y) = (xyz[0] / sum, xyz[1] / sum);
            assert!(
                (x - lx).abs() < 0.003 && (y - ly).abs() < 0.003,
                "{dir:?} {t}: {x} {y}"
            );
            let plane = xyz[1] * s.solid_angle() / PI;
            eprintln!(
                "T {t} {dir:?}: xy ({x:.4}, {y:.4}), plane Y ratio {:.4}",
                plane / ly_cos
            );
            assert!(
                (plane - ly_cos).abs() < 0.015 * ly_cos,
                "{dir:?} {t}: {plane}"
            );
        }
    }

    #[test]
    fn low_sun_is_dimmer_and_redder() {
        let high = sun([0.0, 0.0, 1.0], &[]);
        let low = sun([0.9, 0.0, 0.2], &[]);
        let (h, l) = (rgb_to_xyz(high.radiance), rgb_to_xyz(low.radiance));
        assert!(l[1] < 0.8 * h[1], "{l:?} vs {h:?}");
        assert!(low.radiance.r / low.radiance.b > high.radiance.r / high.radiance.b);
        // Film Y of the RGB equals the spectrum's Y.
        let y = spectrum_xyz(&sun_spectrum(0.0, 2.0))[1];
        assert!((f64::from(h[1]) - y).abs() < 1e-3 * y, "{} vs {y}", h[1]);
        // More turbidity, less light.
        let hazy = sun([0.0, 0.0, 1.0], &[("turbidity", 6.0)]);
        assert!(rgb_to_xyz(hazy.radiance)[1] < 0.9 * h[1]);
    }

    #[test]
    fn below_horizon_is_black_and_gain_scales() {
        assert!(sun([0.0, 0.0, -1.0], &[]).radiance.is_black());
        let a = sun([0.0, 0.3, 1.0], &[]);
        let b = sun([0.0, 0.3, 1.0], &[("gain", 0.5)]);
        assert!((b.radiance.g - 0.5 * a.radiance.g).abs() < 1e-4 * a.radiance.g);
    }

    /// Irradiance at normal incidence does not depend on relsize; the disc does.
    #[test]
    fn relsize_keeps_the_irradiance() {
        let a = sun([0.0, 0.0, 1.0], &[]);
        let b = sun([0.0, 0.0, 1.0], &[("relsize", 4.0)]);
        let ea = a.radiance.g * a.solid_angle();
        let eb = b.radiance.g * b.solid_angle();
        assert!((ea - eb).abs() < 1e-3 * ea, "{ea} vs {eb}");
        assert!((b.solid_angle() / a.solid_angle() - 16.0).abs() < 0.01);
        // About 6.8e-5 sr for the real sun.
        assert!(
            (a.solid_angle() - 6.79e-5).abs() < 0.01e-5,
            "{}",
            a.solid_angle()
        );
        // Illuminance of a clear zenith sun: ~1e5 lux.
        let e = rgb_to_xyz(a.radiance)[1] * a.solid_angle();
        assert!(e > 8e4 && e < 1.2e5, "{e}");
    }

    #[test]
    fn sampling_agrees_with_pdf_and_stays_in_the_disc() {
        let s = sun([0.3, -0.2, 0.9], &[("relsize", 30.0)]);
        let r = Interaction::default();
        let n = 64;
        let mut inside = 0;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let ls = s.sample_li(&r, u).unwrap();
                assert!((ls.wi.length() - 1.0).abs() < 1e-5);
                if s.pdf_li(ls.wi) > 0.0 {
                    inside += 1;
                    assert!((s.pdf_li(ls.wi) - ls.pdf).abs() < 1e-6 * ls.pdf);
                    assert_eq!(s.le(ls.wi), ls.li);
                }
            }
        }
        // Samples on the rim may round outside; nearly all are inside.
        assert!(inside >= n * n - n, "{inside}");
        assert_eq!(s.pdf_li(-s.to_light), 0.0);
        assert!(s.le(Vec3A::new(0.0, 1.0, 0.0)).is_black());
        // The pdf integrates to 1 over the sphere: a fine grid over the disc's neighbourhood.
        let (fs, ft) = coordinate_system(s.to_light);
        let half = 1.5 * s.sin2_max.sqrt();
        let g = 400;
        let mut total = 0.0f64;
        for i in 0..g {
            for j in 0..g {
                let a = -half + 2.0 * half * (i as f32 + 0.5) / g as f32;
                let b = -half + 2.0 * half * (j as f32 + 0.5) / g as f32;
                let c2 = 1.0 - a * a - b * b;
                if c2 <= 0.0 {
                    continue;
                }
                let wi = fs * a + ft * b + s.to_light * c2.sqrt();
                // Solid angle of a cell of the tangent-plane grid: dA / cos θ.
                let dw = (2.0 * half / g as f32).powi(2) / c2.sqrt();
                total += f64::from(s.pdf_li(wi) * dw);
            }
        }
        assert!((total - 1.0).abs() < 0.02, "{total}");
    }
}
