//! Chromaticity of a black body, for light group colour temperatures: the spectrum module's
//! blackbody (Planck's law against the tabulated CIE 1931 functions over LuxRender's
//! 380–720 nm range), normalised to Y = 1.

/// XYZ of a black body at `kelvin`, normalised to Y = 1; `None` for a non-positive or
/// non-finite temperature.
pub fn blackbody_xyz(kelvin: f32) -> Option<[f32; 3]> {
    let xyz = crate::spectrum::xyz::blackbody_xyz(kelvin);
    if !(xyz[1].is_finite() && xyz[1] > 0.0) {
        return None;
    }
    Some(xyz.map(|v| v / xyz[1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn d65_like_chromaticity_at_6504k() {
        let [x, y, z] = blackbody_xyz(6504.0).unwrap();
        let (cx, cy) = (x / (x + y + z), y / (x + y + z));
        // Planckian locus at 6504 K: about (0.3135, 0.3236).
        assert!(
            (cx - 0.3135).abs() < 0.005 && (cy - 0.3236).abs() < 0.005,
            "{cx} {cy}"
        );
        assert!(blackbody_xyz(0.0).is_none());
    }
}
