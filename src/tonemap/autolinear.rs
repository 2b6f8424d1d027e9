//! The autolinear kernel (LuxRender's EV operator): a linear exposure chosen from the average
//! luminance of the image so that it maps to middle grey.

/// Scales by `1.25 / Y_avg * (118/255)^gamma`; `average_luminance` is the mean Y of the
/// pixels that received samples. A black image is left unchanged.
pub fn map(xyz: &mut [[f32; 3]], average_luminance: f32, gamma: f32) {
    if average_luminance.is_nan() || average_luminance <= 0.0 {
        return;
    }
    let f = 1.25 / average_luminance * (118.0f32 / 255.0).powf(gamma);
    xyz.iter_mut().for_each(|p| *p = p.map(|c| c * f));
}
