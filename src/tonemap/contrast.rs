//! Ward's contrast-based scale factor, with display adaptation luminance `ywa`.

/// Scales every pixel by Ward's factor for a display of maximum luminance `max_display_y`.
pub fn map(xyz: &mut [[f32; 3]], display_ywa: f32, max_display_y: f32) {
    let (sum, n) = xyz
        .iter()
        .filter(|p| p[1] > 0.0)
        .fold((0.0f64, 0u64), |(s, n), p| {
            (s + f64::from(p[1].ln()), n + 1)
        });
    let ywa = (sum / n.max(1) as f64).exp() as f32;
    let s = ((1.219 + display_ywa.powf(0.4)) / (1.219 + ywa.powf(0.4))).powf(2.5) / max_display_y;
    xyz.iter_mut().for_each(|p| *p = p.map(|c| c * s));
}
