//! Point lights with IES and image profiles: intensities in chosen directions by hand, files
//! read through the scene's confined files, and emission sampling consistent with the
//! profile.

use super::*;
use crate::geometry::Interaction;
use crate::light::{Emission, LightColor, LightCommon, PointLight};
use crate::lxs::ParamValue;
use glam::Mat4;

const IES: &str = "IESNA:LM-63-2002\nTILT=NONE\n1 1000 2 3 2 1 2 0.1 0.1 0\n1.0 1.0 50\n\
0 45 90\n0 90\n1000 800 0\n1000 400 0\n";

fn white() -> LightColor {
    LightColor {
        emission: Emission::Const(Rgb::WHITE),
        y: 1.0,
    }
}

fn scene_dir() -> (tempfile::TempDir, SceneFiles) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("lamp.ies"), IES).unwrap();
    let files = SceneFiles::confined(dir.path(), dir.path()).unwrap();
    (dir, files)
}

fn ies_params(name: &str) -> ParamSet {
    let mut ps = ParamSet::new();
    ps.add("iesname", ParamValue::String(vec![name.into()]));
    ps
}

#[test]
fn point_light_with_ies_gives_the_profile_candela() {
    let (_dir, files) = scene_dir();
    let ps = ies_params("lamp.ies");
    let profile = Goniometric::from_params(&ps, &files).unwrap();
    let light = PointLight::with_profile(
        &ps,
        Mat4::IDENTITY,
        &white(),
        LightCommon::single(0),
        profile,
    );
    // A point 2 units from the light at V 45°, H 90°: 800 cd / 2² (light space = world).
    let (v, h) = (45f32.to_radians(), 90f32.to_radians());
    let d = Vec3A::new(v.sin() * h.cos(), v.sin() * h.sin(), v.cos());
    let r = Interaction {
        p: d * 2.0,
        ..Default::default()
    };
    let s = light.sample_li(&r).unwrap();
    assert!((s.li.g - 200.0).abs() < 0.5, "{}", s.li.g);
    // Straight along +z (nadir of the profile): 2000 cd.
    assert!((light.intensity_toward(Vec3A::Z).g - 2000.0).abs() < 1.0);
    // flipz turns it over: now −z is the nadir.
    let mut ps = ies_params("lamp.ies");
    ps.add("flipz", ParamValue::Bool(vec![true]));
    let profile = Goniometric::from_params(&ps, &files).unwrap();
    let flipped = PointLight::with_profile(
        &ps,
        Mat4::IDENTITY,
        &white(),
        LightCommon::single(0),
        profile,
    );
    assert!((flipped.intensity_toward(-Vec3A::Z).g - 2000.0).abs() < 1.0);
    assert_eq!(flipped.intensity_toward(Vec3A::Z).g, 0.0);
    // The light's transform turns the profile: rotated 90° about x, nadir +z goes to −y.
    let rot = Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let profile = Goniometric::from_params(&ies_params("lamp.ies"), &files).unwrap();
    let turned = PointLight::with_profile(
        &ies_params("lamp.ies"),
        rot,
        &white(),
        LightCommon::single(0),
        profile,
    );
    assert!((turned.intensity_toward(-Vec3A::Y).g - 2000.0).abs() < 1.0);
}

#[test]
fn ies_files_are_read_inside_the_scene_only() {
    let (dir, _) = scene_dir();
    let sub = dir.path().join("scene");
    std::fs::create_dir(&sub).unwrap();
    let files = SceneFiles::confined(&sub, &sub).unwrap();
    let e = Goniometric::from_params(&ies_params("../lamp.ies"), &files).unwrap_err();
    assert_eq!(e.0, "iesname");
    assert!(e.1.contains("leaves"), "{}", e.1);
    let e = Goniometric::from_params(&ies_params("missing.ies"), &files).unwrap_err();
    assert!(e.1.contains("not found"), "{}", e.1);
    std::fs::write(sub.join("bad.ies"), "TILT=NONE\n1 2\n").unwrap();
    let e = Goniometric::from_params(&ies_params("bad.ies"), &files).unwrap_err();
    assert!(e.1.contains("bad.ies") && e.1.contains("line"), "{}", e.1);
}

#[test]
fn image_profile_and_emission_sampling() {
    // A 4×4 lat-long map: rows of 2 over the upper hemisphere, of 0.5 over the lower one.
    let texels = [vec![Rgb::splat(2.0); 8], vec![Rgb::splat(0.5); 8]].concat();
    let g = Goniometric::new(None, Some((4, 4, texels)), false);
    let at = |theta: f32| g.eval(Vec3A::new(theta.sin(), 0.0, theta.cos())).g;
    // θ = 45° and 135° lie between two rows of one value.
    assert!((at(PI / 4.0) - 2.0).abs() < 1e-5);
    assert!((at(3.0 * PI / 4.0) - 0.5).abs() < 1e-5);
    // Bilinear between the row centres next to the horizon: their mean.
    assert!((g.eval(Vec3A::X).g - 1.25).abs() < 1e-3);
    // At the poles the map repeats, as LuxRender's: the first and last rows blend.
    assert!((g.eval(Vec3A::Z).g - 1.25).abs() < 1e-3);
    assert!((g.eval(-Vec3A::Z).g - 1.25).abs() < 1e-3);
    // ∫ profile dω over the sphere, by sampling ∝ the profile, equals 4π × mean.
    let n = 200;
    let mut sum = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            let (d, pdf) = g.sample(u).unwrap();
            assert!((g.pdf(d) - pdf).abs() < 1e-3 * pdf);
            sum += f64::from(luminance(g.eval(d)) / pdf);
        }
    }
    let integral = sum / (n * n) as f64;
    let want = 4.0 * std::f64::consts::PI * f64::from(g.mean());
    assert!((integral - want).abs() < 0.02 * want, "{integral} {want}");
    // The bilinear profile is 2 and 0.5 on most of each hemisphere, 1.25 near the horizon and
    // the poles: its integral is close to 2π·(2 + 0.5) = 5π.
    assert!(
        (want - 5.0 * std::f64::consts::PI).abs() < 0.03 * want,
        "{want}"
    );
}

#[test]
fn projector_by_hand() {
    // A 2×1 slide (aspect 2): texels 1 and 3; fov 90° so tan(fov/2) = 1, window [−2, 2] × [−1, 1],
    // LuxRender's A = 4·1/2 = 2.
    let slide = vec![Rgb::splat(1.0), Rgb::splat(3.0)];
    let p = Projector::new(2, 1, slide, 90.0).unwrap();
    // On the axis: s = 0.5, halfway between the texel centres: 2 / A = 1.
    assert!((p.eval(Vec3A::Z).g - 1.0).abs() < 1e-5);
    // Toward (0.5, 0, 1): s = 0.625, the slide gives 1·0.25 + 3·0.75 = 2.5; cos θ = 1/√1.25.
    let d = Vec3A::new(0.5, 0.0, 1.0).normalize();
    let want = 2.5 / (2.0 * d.z.powi(3));
    assert!(
        (p.eval(d).g - want).abs() < 1e-4 * want,
        "{} {want}",
        p.eval(d).g
    );
    // Outside the window, and behind the projector: dark.
    assert_eq!(p.eval(Vec3A::new(2.5, 0.0, 1.0).normalize()).g, 0.0);
    assert_eq!(p.eval(Vec3A::new(0.0, 1.2, 1.0).normalize()).g, 0.0);
    assert_eq!(p.eval(-Vec3A::Z).g, 0.0);
    assert!(Projector::new(2, 1, vec![Rgb::WHITE; 2], 0.0).is_err());

    // Through a projection light: a wall at z = 2 gets the even irradiance slide / (A·d²).
    // LuxRender's projection light reads no power or efficacy: given, they change nothing.
    let mut ps = ParamSet::new();
    ps.add("power", ParamValue::Float(vec![100.0]));
    ps.add("efficacy", ParamValue::Float(vec![17.0]));
    let light = PointLight::projection(
        &ps,
        Mat4::IDENTITY,
        &white(),
        LightCommon::single(0),
        Goniometric::projection(Projector::new(1, 1, vec![Rgb::splat(4.0)], 60.0).unwrap()),
    );
    let unused: Vec<&str> = ps.unused().map(|p| p.name.as_str()).collect();
    assert_eq!(unused, ["power", "efficacy"]);
    let tan = 30f32.to_radians().tan();
    let a = 4.0 * tan * tan;
    for x in [0.0f32, 0.5, 1.0] {
        let r = Interaction {
            p: Vec3A::new(x, 0.3, 2.0),
            ..Default::default()
        };
        match light.sample_li(&r) {
            Some(s) => {
                let e = s.li.g * (-s.wi.z);
                let want = 4.0 / (a * 4.0);
                assert!(
                    x < 2.0 * tan && (e - want).abs() < 1e-3 * want,
                    "x {x}: {e} {want}"
                );
            }
            None => assert!(x >= 2.0 * tan, "x {x} is inside the window"),
        }
    }
}
