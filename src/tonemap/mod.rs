//! Tonemapping kernels (reinhard, linear, autolinear, contrast, maxwhite, falsecolors), colour
//! spaces, gamma and clamping: LuxRender's imaging pipeline from film sums to RGB.
//!
//! The pipeline, as LuxRender 1.x's fleximage film runs it:
//! 1. per pixel and enabled light group, the buffer value (per-pixel buffers: sums / weight
//!    sum), adapted by the group's scale, RGB scale and temperature, summed over groups;
//!    alpha = alpha sums / weight sums;
//! 2. XYZ clamped to >= 0, the kernel applied (display luminance 100 cd/m^2);
//!    Bloom and glare come between the clamp and the kernel ([`effects`]);
//! 3. XYZ to RGB through the film colour space, constraining colours outside the gamut;
//!    then the camera response, vignetting and chromatic aberration ([`effects`]).
//!
//! This is the "imaging applied" image (EXR with `write_exr_applyimaging`); LDR outputs then
//! clamp with `ldr_clamp_method` and apply the `gamma`.
//!
//! Place in the back end: `film` -> `tonemap` (here) -> `imageio` -> `output`. This module
//! reads films and the imaging settings the film layer defines
//! ([`crate::film::imaging`], re-exported here) and hands plain RGB images on; it imports
//! neither the image encoders nor the outputs.

pub mod autolinear;
pub mod blackbody;
pub mod colorspace;
pub mod contrast;
pub mod effects;
pub mod falsecolors;
pub mod linear;
pub mod maxwhite;
pub mod reinhard;

pub use crate::film::imaging::{
    ClampMethod, ColorSpaceParams, FalseColors, FalseMethod, FalseScale, Flavour, GroupParams,
    Kernel, TonemapParams,
};
pub use colorspace::{ColorAdaptation, ColorSystem};

use crate::film::{BufferType, Film, PIXEL_VALUES};
use rayon::prelude::*;

/// Display luminance LuxRender passes to the kernels (cd/m^2).
pub const MAX_DISPLAY_Y: f32 = 100.0;

/// An RGB image with alpha, row by row, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<[f32; 3]>,
    pub alpha: Vec<f32>,
}

/// The combined, normalised XYZ of a film before tonemapping.
#[derive(Clone, Debug)]
pub struct XyzImage {
    pub width: u32,
    pub height: u32,
    pub xyz: Vec<[f32; 3]>,
    pub alpha: Vec<f32>,
    /// Mean Y of the pixels that received samples (LuxRender's `averageLuminance`).
    pub average_luminance: f32,
}

/// The colour conversion of a light group: scale, RGB scale and temperature.
pub fn group_adaptation(cs: &ColorSystem, g: &GroupParams) -> ColorAdaptation {
    let white = cs.to_xyz([1.0; 3]);
    let rgb = ColorAdaptation::new(white, cs.to_xyz(g.rgb_scale));
    let conv = match blackbody::blackbody_xyz(g.temperature) {
        Some(temp) if g.temperature > 0.0 => rgb.then(&ColorAdaptation::new(white, temp)),
        _ => rgb,
    };
    conv.scaled(f64::from(g.scale))
}

/// Step 1: the film's normalised XYZ and alpha per pixel, all enabled groups combined.
pub fn film_xyz(film: &Film, params: &TonemapParams) -> XyzImage {
    let cs = ColorSystem::new(&params.colorspace);
    let n = film.pixel_count();
    let mut xyz = vec![[0.0f64; 3]; n];
    let mut alpha = vec![0.0f64; n];
    let mut weight = vec![0.0f64; n];
    for g in 0..film.groups().len() {
        let gp = params.group(g);
        if !gp.enabled {
            continue;
        }
        let conv = group_adaptation(&cs, &gp);
        let screen = n as f64 / film.sample_count(g).max(f64::MIN_POSITIVE);
        for (b, &ty) in film.buffer_types().iter().enumerate() {
            let Some(buf) = film.buffer(g, b) else {
                continue;
            };
            type Item<'a> = ((&'a [f64], (&'a mut [f64; 3], &'a mut f64)), &'a mut f64);
            let add = |((p, (out, a)), w): Item| {
                let ws = p[4];
                *w += ws;
                let scale = match ty {
                    BufferType::PerPixel if ws != 0.0 => 1.0 / ws,
                    BufferType::PerPixel => 0.0,
                    BufferType::PerScreen if ws > 0.0 => screen,
                    BufferType::PerScreenScaled if ws > 0.0 => 1.0,
                    BufferType::PerScreen | BufferType::PerScreenScaled => 0.0,
                    BufferType::Raw => 1.0,
                };
                let c = conv.adapt([p[0] * scale, p[1] * scale, p[2] * scale]);
                (0..3).for_each(|i| out[i] += c[i]);
                if scale != 0.0 || ty == BufferType::Raw {
                    *a += p[3];
                }
            };
            buf.par_chunks(PIXEL_VALUES)
                .zip(xyz.par_iter_mut().zip(alpha.par_iter_mut()))
                .zip(weight.par_iter_mut())
                .for_each(add);
        }
    }
    finish_xyz(film.width(), film.height(), xyz, alpha, &weight)
}

fn finish_xyz(
    width: u32,
    height: u32,
    xyz: Vec<[f64; 3]>,
    alpha: Vec<f64>,
    weight: &[f64],
) -> XyzImage {
    let (mut ysum, mut count) = (0.0f64, 0u64);
    for (p, &w) in xyz.iter().zip(weight) {
        if w > 0.0 {
            ysum += p[1];
            count += 1;
        }
    }
    let alpha = alpha
        .iter()
        .zip(weight)
        .map(|(&a, &w)| if w > 0.0 { (a / w) as f32 } else { a as f32 })
        .collect();
    XyzImage {
        width,
        height,
        xyz: xyz.iter().map(|p| p.map(|c| c as f32)).collect(),
        alpha,
        average_luminance: if count > 0 {
            (ysum / count as f64) as f32
        } else {
            0.0
        },
    }
}

/// Step 2: clamps negative XYZ, applies bloom and glare, then the kernel, in place.
pub fn apply_kernel(img: &mut XyzImage, params: &TonemapParams) {
    img.xyz
        .iter_mut()
        .for_each(|p| *p = p.map(|c| if c > 0.0 { c } else { 0.0 }));
    effects::before_kernel(img, &params.effects);
    let xyz = &mut img.xyz;
    match params.kernel {
        Kernel::Reinhard if params.flavour == Flavour::Lux06 => reinhard::map_06(
            xyz,
            params.reinhard_prescale,
            params.reinhard_postscale,
            params.reinhard_burn,
        ),
        Kernel::Reinhard => reinhard::map(
            xyz,
            params.reinhard_prescale,
            params.reinhard_postscale,
            params.reinhard_burn,
        ),
        Kernel::Linear => linear::map(
            xyz,
            params.linear_sensitivity,
            params.linear_exposure,
            params.linear_fstop,
            params.linear_gamma,
        ),
        Kernel::Contrast => contrast::map(xyz, params.contrast_ywa, MAX_DISPLAY_Y),
        Kernel::MaxWhite => maxwhite::map(xyz),
        Kernel::AutoLinear => autolinear::map(xyz, img.average_luminance, params.gamma),
        Kernel::FalseColors => falsecolors::map(xyz, &params.false_colors),
    }
}

/// XYZ to constrained RGB through the colour space.
pub fn to_rgb(img: XyzImage, cs: &ColorSystem) -> RgbImage {
    RgbImage {
        width: img.width,
        height: img.height,
        rgb: img
            .xyz
            .par_iter()
            .map(|&p| cs.to_rgb_constrained(p))
            .collect(),
        alpha: img.alpha,
    }
}

/// The tonemapped, linear RGB image: bloom, glare, kernel, colour space, camera response,
/// vignetting and aberration applied; no clamping, no gamma.
pub fn tonemap(film: &Film, params: &TonemapParams) -> RgbImage {
    let mut img = film_xyz(film, params);
    apply_kernel(&mut img, params);
    let mut rgb = to_rgb(img, &ColorSystem::new(&params.colorspace));
    effects::after_rgb(&mut rgb, &params.effects);
    rgb
}

/// The untonemapped linear RGB image (EXR without `write_exr_applyimaging`).
pub fn untonemapped(film: &Film, params: &TonemapParams) -> RgbImage {
    to_rgb(
        film_xyz(film, params),
        &ColorSystem::new(&params.colorspace),
    )
}

/// Brings a tonemapped image to display values in [0, 1]: LDR clamp, then gamma (LuxRender
/// 0.6/0.7: gamma, then clamp).
pub fn to_display(img: &mut RgbImage, params: &TonemapParams) {
    let cs = ColorSystem::new(&params.colorspace);
    let inv_gamma = 1.0 / params.gamma;
    let gamma = move |p: [f32; 3]| p.map(|c| if c > 0.0 { c.powf(inv_gamma) } else { 0.0 });
    let (method, legacy) = (params.clamp_method, params.flavour == Flavour::Lux06);
    img.rgb.par_iter_mut().for_each(|p| {
        *p = if legacy {
            cs.limit(gamma(*p), method)
        } else {
            gamma(cs.limit(*p, method))
        };
    });
}

/// Tonemapped, clamped and gamma-corrected RGB in [0, 1] (PNG, TGA, previews).
pub fn tonemap_display(film: &Film, params: &TonemapParams) -> RgbImage {
    display_from_xyz(film_xyz(film, params), params)
}

/// Steps 2 and 3 and the display transform on a film's XYZ image ([`film_xyz`]): what
/// [`tonemap_display`] gives, for a caller that also reads the XYZ image itself.
pub fn display_from_xyz(mut img: XyzImage, params: &TonemapParams) -> RgbImage {
    apply_kernel(&mut img, params);
    let mut rgb = to_rgb(img, &ColorSystem::new(&params.colorspace));
    effects::after_rgb(&mut rgb, &params.effects);
    to_display(&mut rgb, params);
    rgb
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_film_tonemaps_to_black() {
        let film = Film::new(3, 2, vec![]);
        for k in [
            Kernel::Reinhard,
            Kernel::Linear,
            Kernel::Contrast,
            Kernel::MaxWhite,
            Kernel::AutoLinear,
        ] {
            let p = TonemapParams {
                kernel: k,
                ..TonemapParams::default()
            };
            let img = tonemap_display(&film, &p);
            assert!(img.rgb.iter().flatten().all(|&c| c == 0.0), "{k:?}");
        }
    }

    /// The dispatch reaches the falsecolors kernel: with the Film's colour space set to the
    /// kernel's own (Adobe RGB) and gamma 1, the display image holds the scale's colours.
    #[test]
    fn falsecolors_through_the_whole_pipeline() {
        let mut film = Film::new(3, 1, vec![]);
        for (x, y) in [(0, 0.5f32), (1, 2.0), (2, 40.0)] {
            film.add_splat(0, x, 0, [y, y, y], 1.0, 1.0);
        }
        let p = TonemapParams {
            kernel: Kernel::FalseColors,
            false_colors: FalseColors {
                min: 1.0,
                max: 3.0,
                ..FalseColors::default()
            },
            colorspace: falsecolors::scale_space(),
            gamma: 1.0,
            ..TonemapParams::default()
        };
        let img = tonemap_display(&film, &p);
        let want = [[0.0, 0.0, 128.0], [127.0, 255.0, 128.0], [128.0, 0.0, 0.0]];
        for (got, want) in img.rgb.iter().zip(want) {
            let got = got.map(|c| c * 255.0);
            assert!(
                got.iter().zip(want).all(|(g, w)| (g - w).abs() < 0.01),
                "{got:?} {want:?}"
            );
        }
    }

    #[test]
    fn per_pixel_normalisation_and_alpha() {
        let mut film = Film::new(1, 1, vec![]);
        film.add_splat(0, 0, 0, [0.5, 1.0, 0.5], 1.0, 2.0);
        film.add_splat(0, 0, 0, [0.5, 1.0, 0.5], 0.0, 2.0);
        let img = film_xyz(&film, &TonemapParams::default());
        assert!((img.xyz[0][1] - 1.0).abs() < 1e-5);
        assert!((img.alpha[0] - 0.5).abs() < 1e-6);
        assert!((img.average_luminance - 1.0).abs() < 1e-5);
    }

    #[test]
    fn disabled_group_and_scale() {
        let mut film = Film::new(1, 1, vec!["a".into(), "b".into()]);
        film.add_splat(0, 0, 0, [1.0, 1.0, 1.0], 1.0, 1.0);
        film.add_splat(1, 0, 0, [1.0, 1.0, 1.0], 1.0, 1.0);
        let p = TonemapParams {
            groups: vec![
                GroupParams {
                    scale: 2.0,
                    ..GroupParams::default()
                },
                GroupParams {
                    enabled: false,
                    ..GroupParams::default()
                },
            ],
            ..TonemapParams::default()
        };
        let img = film_xyz(&film, &p);
        assert!((img.xyz[0][1] - 2.0).abs() < 1e-3, "{:?}", img.xyz[0]);
    }
}
