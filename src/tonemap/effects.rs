//! The image effects at their places in the tonemapping pipeline, in LuxRender 1.x's order:
//! bloom then glare on the clamped XYZ image before the kernel ([`before_kernel`]); camera
//! response, then vignetting and chromatic aberration on the RGB image after the colour space
//! conversion ([`after_rgb`]). The gamma comes later ([`super::to_display`]).
//!
//! The pixel operations are the film layer's ([`crate::film::effects`]); this file only feeds
//! them the tonemapping stage's images and the Film's settings.

use super::{RgbImage, XyzImage};
use crate::film::effects::{aberration, bloom, glare, vignetting, Pixels};
use crate::film::imaging::Effects;

/// Bloom and glare on the (clamped) XYZ image.
pub fn before_kernel(img: &mut XyzImage, e: &Effects) {
    let (w, h) = (img.width as usize, img.height as usize);
    if e.bloom_applies() {
        let px = Pixels {
            width: w,
            height: h,
            data: &mut img.xyz,
        };
        bloom::apply(px, e.bloom_radius, e.bloom_weight);
    }
    if e.glare_applies() {
        let px = Pixels {
            width: w,
            height: h,
            data: &mut img.xyz,
        };
        let g = glare::Glare {
            amount: e.glare_amount,
            radius: e.glare_radius,
            blades: e.glare_blades,
            threshold: e.glare_threshold,
        };
        glare::apply(px, g);
    }
}

/// The camera response, then vignetting and chromatic aberration on the RGB image (the aberrated image is vignetted, as
/// LuxRender pairs them in one pass).
pub fn after_rgb(img: &mut RgbImage, e: &Effects) {
    let (w, h) = (img.width as usize, img.height as usize);
    if let Some(crf) = &e.response {
        img.rgb.iter_mut().for_each(|p| *p = crf.map(*p));
    }
    if e.aberration_applies() {
        img.rgb = aberration::apply(&img.rgb, w, h, e.aberration_amount);
    }
    if e.vignetting_applies() {
        vignetting::apply(&mut img.rgb, w, h, e.vignetting_scale);
    }
}
