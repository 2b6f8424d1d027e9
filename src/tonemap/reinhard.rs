//! Reinhard's global operator (equation 4 of "Photographic Tone Reproduction"), with
//! LuxRender's Indigo-compatible prescale, postscale and burn.

/// Scales every pixel (XYZ, in place) as LuxRender 1.x's `reinhard` kernel.
pub fn map(xyz: &mut [[f32; 3]], prescale: f32, postscale: f32, burn: f32) {
    const KEY: f32 = 0.1;
    let (sum, n) = xyz
        .iter()
        .filter(|p| p[1] > 0.0)
        .fold((0.0f64, 0u64), |(s, n), p| {
            (s + f64::from(p[1].max(1e-6).ln()), n + 1)
        });
    let ywa = if n > 0 {
        (sum / n as f64).exp() as f32
    } else {
        1.0
    };
    let inv_b2 = if burn > 0.0 { 1.0 / (burn * burn) } else { 1e5 };
    let scale = KEY / ywa;
    let pre = scale / prescale;
    let post = scale * postscale;
    for p in xyz.iter_mut() {
        let ys = p[1] * pre;
        let s = post * (1.0 + ys * inv_b2) / (1.0 + ys);
        *p = p.map(|c| c * s);
    }
}

/// LuxRender 0.6/0.7's `reinhard`: arithmetic mean adaptation luminance over all pixels, and
/// the burn applied to the unscaled luminance.
pub fn map_06(xyz: &mut [[f32; 3]], prescale: f32, postscale: f32, burn: f32) {
    const KEY: f32 = 0.1;
    let n = xyz.len().max(1) as f64;
    let sum: f64 = xyz
        .iter()
        .filter(|p| p[1] > 0.0)
        .map(|p| f64::from(p[1]))
        .sum();
    let ywa = match (sum / n) as f32 {
        y if y > 0.0 => y,
        _ => 1.0,
    };
    let yw = prescale * KEY * burn;
    let inv_y2 = if yw > 0.0 { 1.0 / (yw * yw) } else { 1e5 };
    let scale = postscale * prescale * KEY / ywa;
    for p in xyz.iter_mut() {
        let ys = p[1];
        let s = scale * (1.0 + ys * inv_y2) / (1.0 + ys);
        *p = p.map(|c| c * s);
    }
}
