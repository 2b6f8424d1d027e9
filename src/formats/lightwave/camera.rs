//! The LightWave camera as a LuxRender Film and perspective Camera.
//!
//! ```text
//! CameraItem + Globals + the camera's frame at the shutter times
//!   --> Film (resolution, crop window, output name, LightWave's linear pixel values)
//!   --> Camera "perspective" (fov, aspect, lens radius and focal distance, shutter)
//!   --> LookAt per shutter time (eye, target, up in luxfarm space)
//! ```
//!
//! Facts: LightWave's zoom factor z is 1 / tan(vertical fov / 2) (the default 3.2 with the
//! default 15 mm aperture height is a 24 mm lens); LuxRender's `fov` spans the shorter image
//! side, so it is 2·atan(1/z) for landscape frames and 2·atan(aspect/z) for portrait ones.
//! The focal length is z × aperture height / 2, and the lens radius focal length / (2 ×
//! f-stop). `FrameSize` × `ResolutionMultiplier` (or the global ones with
//! `UseGlobalResolution`) give the resolution, `PixelAspect` the frame aspect, `LimitedRegion`
//! with `RegionLimits` the crop window. The camera looks down its +Z with +Y up.
//!
//! LightWave shows its colour values without a display gamma and adds light linearly, so the
//! Film uses the linear tonemap with a factor of exactly 1 and gamma 1: a surface of colour c
//! lit at 100% shows c, as in LightWave.

use super::coords::swap_yz;
use super::envelope::Animated;
use super::items::{CameraItem, Globals};
use super::material::{float, string};
use crate::lxs::{Loc, ParamSet, ParamValue};
use crate::spectrum::{rgb_to_xyz, Rgb};
use glam::{DMat4, DVec3};

/// Samples per pixel when nothing else says (LightWave has no equivalent setting).
pub const DEFAULT_HALTSPP: i32 = 64;

/// One camera position: the shutter time and LookAt eye, target, up (luxfarm space).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    pub time: f32,
    pub eye: [f64; 3],
    pub target: [f64; 3],
    pub up: [f64; 3],
}

pub struct CameraOut {
    pub film: ParamSet,
    pub camera: ParamSet,
    pub views: Vec<View>,
    pub warnings: Vec<(Loc, String)>,
}

/// The view of a camera frame (LightWave space; scale is ignored).
pub fn view(frame: &DMat4, time: f32) -> View {
    let eye = frame.transform_point3(DVec3::ZERO);
    let fwd = frame.transform_vector3(DVec3::Z).normalize_or(DVec3::Z);
    let up = frame.transform_vector3(DVec3::Y).normalize_or(DVec3::Y);
    View {
        time,
        eye: swap_yz(eye).to_array(),
        target: swap_yz(eye + fwd).to_array(),
        up: swap_yz(up).to_array(),
    }
}

/// The linear tonemap sensitivity that maps a white radiance of 1 to a pixel value of 1 at
/// exposure 1, f-stop 1 and linear gamma 1: LuxRender's linear factor is sensitivity × 0.065
/// × 118/255, and the film holds the luminance of RGB (1, 1, 1) as Y = `rgb_to_xyz(white)`
/// (683 lm/W times the spectral integral).
fn unit_sensitivity() -> f32 {
    let y_white = rgb_to_xyz(Rgb::WHITE)[1];
    1.0 / (0.065 * 118.0 / 255.0 * y_white)
}

/// The Film and Camera of `cam` at `time`; `frames` are the camera's frames at the shutter
/// times (one, or open and close with motion blur).
pub fn setup(
    cam: &CameraItem,
    g: &Globals,
    time: f64,
    frames: &[(f32, DMat4)],
    output_name: &str,
) -> CameraOut {
    let mut warnings = Vec::new();
    let loc = cam.common.loc.clone();
    let (size, mult, pa) = if cam.use_global_resolution {
        (
            g.global_frame_size,
            g.global_multiplier,
            g.global_pixel_aspect,
        )
    } else {
        (
            cam.frame_size.or(g.global_frame_size),
            cam.multiplier,
            cam.pixel_aspect,
        )
    };
    let (w, h) = size.unwrap_or((640, 480));
    let mult = if mult.is_finite() && mult > 0.0 {
        mult
    } else {
        1.0
    };
    let xres = ((f64::from(w) * mult).round() as i64).clamp(1, 65536) as i32;
    let yres = ((f64::from(h) * mult).round() as i64).clamp(1, 65536) as i32;
    let pa = if pa.is_finite() && pa > 0.0 { pa } else { 1.0 };
    let aspect = f64::from(xres) * pa / f64::from(yres);

    let mut film = ParamSet::new();
    film.add("xresolution", ParamValue::Integer(vec![xres]));
    film.add("yresolution", ParamValue::Integer(vec![yres]));
    film.add("filename", string(output_name));
    film.add("haltspp", ParamValue::Integer(vec![DEFAULT_HALTSPP]));
    film.add("tonemapkernel", string("linear"));
    film.add("linear_sensitivity", float(unit_sensitivity()));
    film.add("linear_exposure", float(1.0));
    film.add("linear_fstop", float(1.0));
    film.add("linear_gamma", float(1.0));
    film.add("gamma", float(1.0));
    if cam.limited_region.0 != 0 {
        let r = cam.region;
        let ok = r.iter().all(|v| (0.0..=1.0).contains(v)) && r[0] < r[1] && r[2] < r[3];
        if ok {
            film.add(
                "cropwindow",
                ParamValue::Float(r.map(|v| v as f32).to_vec()),
            );
        } else {
            let at = cam.limited_region.1.clone().unwrap_or_else(|| loc.clone());
            warnings.push((
                at,
                format!(
                    "RegionLimits {r:?} are not a region of the frame: the whole frame is rendered"
                ),
            ));
        }
    }

    let zoom = positive(&cam.zoom, time, 3.2);
    let half = if aspect >= 1.0 {
        1.0 / zoom
    } else {
        aspect / zoom
    };
    let mut camera = ParamSet::new();
    camera.add("fov", float((2.0 * half.atan()).to_degrees() as f32));
    if (pa - 1.0).abs() > 1e-9 {
        camera.add("frameaspectratio", float(aspect as f32));
    }
    if cam.depth_of_field {
        let focal_length = zoom * cam.aperture_height / 2.0;
        let fstop = positive(&cam.fstop, time, 4.0);
        camera.add("lensradius", float((focal_length / (2.0 * fstop)) as f32));
        camera.add(
            "focaldistance",
            float(positive(&cam.focal_distance, time, 1.0) as f32),
        );
    }
    if frames.len() > 1 {
        camera.add("shutteropen", float(0.0));
        camera.add("shutterclose", float(1.0));
    }
    match &cam.handler {
        Some((name, _)) if name == "Perspective" => {}
        Some((name, at)) => warnings.push((
            at.clone(),
            format!("camera type {name} is not supported: rendered as a perspective camera"),
        )),
        None => {}
    }
    let views = frames.iter().map(|(t, f)| view(f, *t)).collect();
    CameraOut {
        film,
        camera,
        views,
        warnings,
    }
}

/// A positive, finite value of `a` at `time`, else `default`.
fn positive(a: &Animated, time: f64, default: f64) -> f64 {
    let v = a.at(time);
    if v.is_finite() && v > 0.0 {
        v
    } else {
        default
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::lightwave::items::ItemCommon;

    fn cam() -> CameraItem {
        CameraItem {
            common: ItemCommon::new(0x3000_0000, "Camera".into(), Loc::default()),
            zoom: Animated::Const(3.2),
            frame_size: Some((640, 480)),
            multiplier: 1.0,
            pixel_aspect: 1.0,
            motion_blur: 0,
            blur_length: Animated::Const(0.5),
            depth_of_field: false,
            focal_distance: Animated::Const(1.0),
            fstop: Animated::Const(4.0),
            aperture_height: 0.015,
            limited_region: (0, None),
            region: [0.0, 1.0, 0.0, 1.0],
            use_global_resolution: false,
            use_global_blur: false,
            handler: None,
        }
    }

    #[test]
    fn zoom_gives_the_vertical_fov_of_landscape_frames() {
        let out = setup(
            &cam(),
            &Globals::default(),
            0.0,
            &[(0.0, DMat4::IDENTITY)],
            "x",
        );
        let fov = out.camera.float("fov").unwrap();
        assert!((fov - 34.708).abs() < 1e-3, "{fov}");
        assert_eq!(out.film.int("xresolution"), Some(640));
        let mut portrait = cam();
        portrait.frame_size = Some((480, 640));
        let out = setup(
            &portrait,
            &Globals::default(),
            0.0,
            &[(0.0, DMat4::IDENTITY)],
            "x",
        );
        let fov = out.camera.float("fov").unwrap() as f64;
        assert!((fov - 2.0 * (0.75f64 / 3.2).atan().to_degrees()).abs() < 1e-4);
    }

    #[test]
    fn depth_of_field_and_region() {
        let mut c = cam();
        c.depth_of_field = true;
        c.focal_distance = Animated::Const(5.0);
        c.limited_region = (1, None);
        c.region = [0.25, 0.75, 0.0, 0.5];
        let out = setup(&c, &Globals::default(), 0.0, &[(0.0, DMat4::IDENTITY)], "x");
        // 24 mm lens at f/4: radius 3 mm
        assert!((out.camera.float("lensradius").unwrap() - 0.003).abs() < 1e-7);
        assert_eq!(out.camera.float("focaldistance"), Some(5.0));
        assert_eq!(
            out.film.floats("cropwindow"),
            Some(&[0.25, 0.75, 0.0, 0.5][..])
        );
    }

    #[test]
    fn unit_linear_factor() {
        let f = crate::tonemap::linear::factor(unit_sensitivity(), 1.0, 1.0, 1.0);
        let y = rgb_to_xyz(Rgb::WHITE)[1];
        assert!((f * y - 1.0).abs() < 1e-5, "{f}");
    }

    #[test]
    fn the_view_looks_down_plus_z_converted() {
        let v = view(&DMat4::from_translation(DVec3::new(1.0, 2.0, 3.0)), 0.0);
        assert_eq!(v.eye, [1.0, 3.0, 2.0]);
        assert_eq!(v.target, [1.0, 4.0, 2.0]);
        assert_eq!(v.up, [0.0, 0.0, 1.0]);
    }
}
