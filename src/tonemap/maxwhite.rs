//! The maxwhite kernel: the brightest pixel maps to white.

pub fn map(xyz: &mut [[f32; 3]]) {
    let max_y = xyz.iter().map(|p| p[1]).fold(0.0f32, f32::max);
    if max_y.is_nan() || max_y <= 0.0 {
        return;
    }
    let s = 1.0 / max_y;
    xyz.iter_mut().for_each(|p| *p = p.map(|c| c * s));
}
