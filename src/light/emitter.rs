//! The emission profile every area emitter shares — `area` lights on shapes and the
//! rectangle, disc, sphere and cylinder primitives: which side emits, how emission varies
//! with the angle at the emitter, how it falls off with distance, whether the camera sees it.
//!
//! ```text
//! ParamSet --EmissionProfile::from_params--> profile
//! L × profile.factor(cosθ_l, d²) = what reaches a point at distance d along a ray
//! ```
//!
//! Parameters (all optional; the defaults are LuxRender's physical area light):
//! - `float falloffexponent` k (2): illumination falls off as 1/d^k (see [`super::falloff`]);
//! - `float cosineexponent` e (1): an element dA emits the intensity L·cos^e θ_l·dA, so e = 1
//!   is a Lambertian surface of radiance L (seen along a ray: L·cos^(e−1) θ_l), e = 0 an
//!   array of isotropic point emitters (mental ray's base lights and sphere lights), e > 1 a
//!   narrower beam (mental ray's `cos_exp`);
//! - `bool twosided` (false): both sides emit; otherwise only the side of the normal;
//! - `bool visible` (true): whether camera rays see the emitter; when false it still lights
//!   the scene and is still found by BSDF-sampled rays (so MIS stays unbiased), mirrors
//!   included.

use super::falloff::{falloff_exponent, radiance_falloff};
use crate::lxs::ParamSet;
use std::f32::consts::PI;

/// How an area emitter's radiance depends on angle, side and distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmissionProfile {
    /// k of the 1/d^k falloff of illumination.
    pub falloff_exponent: f32,
    /// e of the cos^e θ_l intensity distribution of each element.
    pub cos_exponent: f32,
    pub two_sided: bool,
    /// Seen by camera rays.
    pub visible: bool,
}

impl Default for EmissionProfile {
    fn default() -> Self {
        EmissionProfile {
            falloff_exponent: 2.0,
            cos_exponent: 1.0,
            two_sided: false,
            visible: true,
        }
    }
}

impl EmissionProfile {
    /// Reads the profile parameters; a negative or non-finite `cosineexponent` is an error.
    pub fn from_params(p: &ParamSet) -> Result<EmissionProfile, String> {
        let e = p.float_or("cosineexponent", 1.0);
        if !(e.is_finite() && e >= 0.0) {
            return Err(format!("cosineexponent must be finite and >= 0, got {e}"));
        }
        Ok(EmissionProfile {
            falloff_exponent: falloff_exponent(p),
            cos_exponent: e,
            two_sided: p.bool_or("twosided", false),
            visible: p.bool_or("visible", true),
        })
    }

    /// The factor on L for light leaving an element whose normal makes cosine `cos_l` with
    /// the direction of travel, toward a point at squared distance `d2` (`None`: seen by
    /// the camera, no falloff). 0 on a side that does not emit.
    pub fn factor(&self, cos_l: f32, d2: Option<f32>) -> f32 {
        let c = if self.two_sided { cos_l.abs() } else { cos_l };
        if c.is_nan() || c <= 0.0 {
            return 0.0;
        }
        let mut f = if self.cos_exponent == 1.0 {
            1.0
        } else {
            c.powf(self.cos_exponent - 1.0)
        };
        if let Some(d2) = d2 {
            f *= radiance_falloff(d2, self.falloff_exponent);
        }
        f
    }

    /// Flux per unit area and unit L: ∫ cos^e θ dω over the emitting hemisphere (2π/(e+1),
    /// π for a Lambertian surface), twice that when both sides emit.
    pub fn flux_per_area(&self) -> f32 {
        let one = 2.0 * PI / (self.cos_exponent + 1.0);
        if self.two_sided {
            2.0 * one
        } else {
            one
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lxs::ParamValue;

    #[test]
    fn defaults_are_a_one_sided_lambertian_surface() {
        let p = EmissionProfile::from_params(&ParamSet::new()).unwrap();
        assert_eq!(p, EmissionProfile::default());
        assert_eq!(p.factor(0.3, Some(9.0)), 1.0);
        assert_eq!(p.factor(-0.3, None), 0.0);
        assert!((p.flux_per_area() - PI).abs() < 1e-6);
    }

    #[test]
    fn cosine_exponent_side_and_falloff() {
        let mut ps = ParamSet::new();
        ps.add("cosineexponent", ParamValue::Float(vec![0.0]));
        ps.add("twosided", ParamValue::Bool(vec![true]));
        ps.add("falloffexponent", ParamValue::Float(vec![1.0]));
        let p = EmissionProfile::from_params(&ps).unwrap();
        // Isotropic elements: the ray "radiance" is 1/cosθ; falloff 1/d gives × d at d = 3.
        assert!((p.factor(-0.5, Some(9.0)) - 2.0 * 3.0).abs() < 1e-5);
        assert!((p.factor(0.5, None) - 2.0).abs() < 1e-6);
        // ∫ over both hemispheres of cos^0 = 4π.
        assert!((p.flux_per_area() - 4.0 * PI).abs() < 1e-5);
        let mut bad = ParamSet::new();
        bad.add("cosineexponent", ParamValue::Float(vec![-1.0]));
        assert!(EmissionProfile::from_params(&bad).is_err());
    }
}
