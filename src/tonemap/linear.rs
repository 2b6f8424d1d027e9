//! The linear kernel: a camera-like exposure (ISO sensitivity, exposure time, f-stop) mapping
//! the ISO "saturation-based" middle grey (118/255 at the given gamma).

/// The factor LuxRender's `linear` kernel multiplies every pixel by.
pub fn factor(sensitivity: f32, exposure: f32, fstop: f32, gamma: f32) -> f32 {
    exposure / (fstop * fstop) * sensitivity * 0.65 / 10.0 * (118.0f32 / 255.0).powf(gamma)
}

pub fn map(xyz: &mut [[f32; 3]], sensitivity: f32, exposure: f32, fstop: f32, gamma: f32) {
    let f = factor(sensitivity, exposure, fstop, gamma);
    xyz.iter_mut().for_each(|p| *p = p.map(|c| c * f));
}
