//! Unit tests of the Hosek–Wilkie sky: hand-computed radiances from the tables, the
//! interpolation in turbidity, and the importance sampling's consistency.

use super::*;
use crate::lxs::ParamValue;

fn common() -> LightCommon {
    LightCommon::single(0)
}

#[test]
fn zenith_sun_uses_the_last_control_point() {
    // Sun at the zenith: normalised elevation 1, only the sixth control point counts.
    // Turbidity 1, albedo 0, red channel: A..I = -1.139072, -0.1796056, 1.923311, 6.788529,
    // -2.364389, -1.064041, 0.1717010, 1.534681, 0.5015810 and R = 4.324573, so by hand
    // L(zenith) = (1 + A e^(B/1.01)) (C + D + F + G·2/(1 − I)³ + H) · R · 683 = 1642.02 and
    // at the horizon (cos θ = 0, γ = 90°): (1 + A e^(B/0.01)) (C + D e^(E π/2) + G/(1 + I²)^1.5)
    // · R · 683 = 6531.91.
    let m = Sky2Model::new(Vec3A::Z, 1.0, 0.0);
    let zenith = m.srgb(Vec3A::Z)[0];
    assert!((zenith - 1642.02).abs() < 0.01 * 1642.02, "{zenith}");
    let horizon = m.srgb(Vec3A::X)[0];
    assert!((horizon - 6531.91).abs() < 0.01 * 6531.91, "{horizon}");
}

#[test]
fn turbidity_interpolates_linearly_between_tables() {
    let sun = Vec3A::new(0.5, 0.2, 0.7).normalize();
    let w = Vec3A::new(-0.3, 0.4, 0.5).normalize();
    let (a, b, mid) = (
        Sky2Model::new(sun, 3.0, 0.0),
        Sky2Model::new(sun, 4.0, 0.0),
        Sky2Model::new(sun, 3.25, 0.0),
    );
    for c in 0..3 {
        for i in 0..data::PARAMS {
            let want = 0.75 * a.params[c][i] + 0.25 * b.params[c][i];
            assert!((mid.params[c][i] - want).abs() < 1e-4 * (1.0 + want.abs()));
        }
    }
    // Turbidity beyond the tables is clamped to them.
    let hi = Sky2Model::new(sun, 10.0, 0.0).srgb(w);
    assert_eq!(Sky2Model::new(sun, 30.0, 0.0).srgb(w), hi);
}

#[test]
fn sky_is_blue_overhead_and_brighter_near_the_sun() {
    let sun = Vec3A::new(0.866, 0.0, 0.5);
    let m = Sky2Model::new(sun, 3.0, 0.0);
    let zenith = m.srgb(Vec3A::Z);
    assert!(zenith[2] > zenith[1] && zenith[1] > zenith[0], "{zenith:?}");
    let near = m.xyz(Vec3A::new(0.8, 0.1, 0.59).normalize())[1];
    let far = m.xyz(Vec3A::new(-0.7, 0.0, 0.71).normalize())[1];
    assert!(near > 2.0 * far, "{near} {far}");
}

#[test]
fn sampling_pdf_matches_and_estimates_irradiance() {
    let mut ps = ParamSet::new();
    ps.add("sundir", ParamValue::Vector(vec![[0.3, -0.4, 0.6]]));
    ps.add("turbidity", ParamValue::Float(vec![3.0]));
    ps.add("gain", ParamValue::Float(vec![0.01]));
    let rot = Mat4::from_rotation_x(0.3);
    let l = Sky2Light::new(&ps, rot, common()).unwrap();
    // Irradiance on a surface facing world +z: importance-sampled estimate against a
    // midpoint quadrature of the radiance over the hemisphere.
    let r = Interaction::default();
    let n = 160;
    let mut est = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            if let Some(s) = l.sample_li(&r, u) {
                let pdf = l.pdf_li(s.wi);
                assert!((pdf - s.pdf).abs() < 2e-3 * s.pdf, "{pdf} {}", s.pdf);
                let le = l.le(s.wi);
                assert!((le.g - s.li.g).abs() < 1e-3 * (1.0 + le.g));
                est += f64::from(s.li.g * s.wi.z.max(0.0) / s.pdf);
            }
        }
    }
    est /= (n * n) as f64;
    let (nt, np) = (200, 400);
    let mut quad = 0.0f64;
    for i in 0..nt {
        let theta = (i as f32 + 0.5) / nt as f32 * FRAC_PI_2;
        for j in 0..np {
            let phi = (j as f32 + 0.5) / np as f32 * 2.0 * PI;
            let w = Vec3A::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            let dw = theta.sin() * (FRAC_PI_2 / nt as f32) * (2.0 * PI / np as f32);
            quad += f64::from(l.le(w).g * w.z * dw);
        }
    }
    assert!((est - quad).abs() < 0.02 * quad, "{est} {quad}");
    assert!(l.power() > 0.0);
}

#[test]
fn bad_parameters_are_refused() {
    let mut ps = ParamSet::new();
    ps.add("sundir", ParamValue::Vector(vec![[0.0; 3]]));
    assert!(Sky2Light::new(&ps, Mat4::IDENTITY, common()).is_err());
    let mut ps = ParamSet::new();
    ps.add("gain", ParamValue::Float(vec![f32::NAN]));
    assert!(Sky2Light::new(&ps, Mat4::IDENTITY, common()).is_err());
    let mut ps = ParamSet::new();
    ps.add("gain", ParamValue::Float(vec![-1.0]));
    assert!(Sky2Light::new(&ps, Mat4::IDENTITY, common()).is_err());
}
