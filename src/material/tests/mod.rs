//! Material tests: white furnace (albedo ≤ 1, sampling estimates equal numeric integrals),
//! pdfs integrating to the fraction of successful samples, sample/f/pdf consistency (and
//! `f`/`pdf` for pairs that were not sampled), Fresnel at normal incidence, mix selection,
//! bump mapping, building from a scene description. Shared helpers here; the tests by group
//! in the submodules.

mod basic;
mod composite;
mod hand_values;
mod media;
mod new_lobes;

use super::bxdf::diffuse::Diffuse;
use super::bxdf::microfacet::{Fresnel, MicrofacetReflection};
use super::bxdf::rough_dielectric::RoughDielectric;
use super::bxdf::schlick::{Coating, SchlickCoat, SchlickDist};
use super::*;
use crate::lxs::{MaterialDesc, ParamSet, ParamValue, SceneDescription};
use crate::spectrum::Rgb;
use crate::texture::tests::{loc, si_at};
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;

/// Small deterministic generator (xorshift64*).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (v >> 40) as f32 / (1u64 << 24) as f32
    }
    fn next2(&mut self) -> Vec2 {
        Vec2::new(self.next(), self.next())
    }
}

fn flat_si() -> SurfaceInteraction {
    si_at(0.5, 0.5, Vec3A::ZERO)
}

fn dir(theta_deg: f32, phi_deg: f32) -> Vec3A {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3A::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

/// Numeric ∫ g(wi) dω over the sphere (midpoint rule, uniform in z and φ), for two integrands
/// at once.
fn sphere_integral(nz: usize, nphi: usize, g: impl Fn(Vec3A) -> (f64, f64)) -> (f64, f64) {
    let mut sum = (0.0, 0.0);
    for i in 0..nz {
        let z = -1.0 + (i as f32 + 0.5) * 2.0 / nz as f32;
        let r = (1.0 - z * z).max(0.0).sqrt();
        for j in 0..nphi {
            let phi = (j as f32 + 0.5) * 2.0 * PI / nphi as f32;
            let v = g(Vec3A::new(r * phi.cos(), r * phi.sin(), z));
            sum.0 += v.0;
            sum.1 += v.1;
        }
    }
    let w = (2.0 / nz as f64) * (2.0 * std::f64::consts::PI / nphi as f64);
    (sum.0 * w, sum.1 * w)
}

/// (MC estimate of ∫ f cos, fraction of successful samples), averaged over channels.
fn sampled_albedo(b: &Bsdf, wo: Vec3A, n: usize) -> (f64, f64) {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let (mut sum, mut ok) = (0.0f64, 0usize);
    for _ in 0..n {
        let u = rng.next();
        if let Some(s) = b.sample_f(wo, u, rng.next2()) {
            ok += 1;
            sum += (s.f.average() * s.wi.dot(b.frame.n).abs() / s.pdf) as f64;
        }
    }
    (sum / n as f64, ok as f64 / n as f64)
}

/// (∫ f cos dω, ∫ pdf dω) by numeric integration.
fn numeric(b: &Bsdf, wo: Vec3A) -> (f64, f64) {
    sphere_integral(1200, 600, |wi| {
        let f = (b.f(wo, wi).average() * wi.dot(b.frame.n).abs()) as f64;
        (f, b.pdf(wo, wi) as f64)
    })
}

fn numeric_albedo(b: &Bsdf, wo: Vec3A) -> f64 {
    numeric(b, wo).0
}

/// Checks sampling against evaluation for one BSDF and outgoing direction.
fn check_lobe(name: &str, b: &Bsdf, wo: Vec3A, max_albedo: f64) {
    let (mc, success) = sampled_albedo(b, wo, 200_000);
    let (num, pdf_int) = numeric(b, wo);
    assert!(num <= max_albedo, "{name}: albedo {num} > {max_albedo}");
    assert!(
        (mc - num).abs() <= 0.02 * num.max(0.05),
        "{name}: sampled albedo {mc} vs numeric {num}"
    );
    assert!(
        (pdf_int - success).abs() < 0.02,
        "{name}: pdf integrates to {pdf_int}, {success} of samples succeed"
    );
    // Every sample agrees with f() and pdf().
    let mut rng = Rng(7);
    for _ in 0..2000 {
        let u = rng.next();
        if let Some(s) = b.sample_f(wo, u, rng.next2()) {
            assert!(!s.specular);
            let f = b.f(wo, s.wi);
            let p = b.pdf(wo, s.wi);
            for i in 0..3 {
                assert!(
                    (f[i] - s.f[i]).abs() <= 1e-4 * f[i].abs().max(1.0),
                    "{name}: f"
                );
            }
            assert!(
                (p - s.pdf).abs() <= 1e-3 * p.max(1e-3),
                "{name}: pdf {p} vs {}",
                s.pdf
            );
        }
    }
}

fn bsdf(lobes: Lobes) -> Bsdf {
    Bsdf::new(&flat_si(), lobes)
}

fn mat(name: &str, kind: &str, params: Vec<(&str, ParamValue)>, line: u32) -> MaterialDesc {
    let mut ps = ParamSet::new();
    for (n, v) in params {
        ps.add(n, v);
    }
    MaterialDesc {
        name: Some(name.to_string()),
        entity: crate::lxs::Entity {
            kind: kind.to_string(),
            params: ps,
            loc: loc(line),
        },
    }
}

fn scene(mats: Vec<MaterialDesc>) -> SceneDescription {
    let mut d = SceneDescription::default();
    for m in mats {
        if let Some(n) = &m.name {
            d.named_materials.insert(n.clone(), d.materials.len());
        }
        d.materials.push(m);
    }
    d
}

fn s(v: &str) -> ParamValue {
    ParamValue::String(vec![v.to_string()])
}

fn f(v: f32) -> ParamValue {
    ParamValue::Float(vec![v])
}
