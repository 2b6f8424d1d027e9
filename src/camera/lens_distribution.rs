//! The perspective camera's lens sampling distribution (`distribution`, `power`), as
//! LuxRender 1.x applies it to polygonal apertures (`blades` >= 3): the radial sample u of
//! the aperture is remapped before its square root scales the polygon radius.
//!
//! - `uniform`: u;
//! - `exponential`: clamp(-ln(u) / power, 0, 1) (light gathers at the centre);
//! - `inverse exponential`: clamp(1 + ln(u) / power, 0, 1) (a bright ring at the rim);
//! - `gaussian`: clamp(Φ⁻¹(u), 0, 1), Φ⁻¹ the standard normal quantile;
//! - `inverse gaussian`: clamp(1 - Φ⁻¹(u), 0, 1).
//!
//! LuxRender reads `power` with a default of 3 (its source), where the scene format page says
//! 1; luxfarm follows the source.

/// How the radial lens sample is distributed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LensDistribution {
    Uniform,
    Exponential(f32),
    InverseExponential(f32),
    Gaussian,
    InverseGaussian,
}

impl LensDistribution {
    /// From LuxRender's name and `power`; `None` for an unknown name.
    pub fn from_name(name: &str, power: i32) -> Option<LensDistribution> {
        let p = power as f32;
        Some(match name {
            "uniform" => LensDistribution::Uniform,
            "exponential" => LensDistribution::Exponential(p),
            "inverse exponential" => LensDistribution::InverseExponential(p),
            "gaussian" => LensDistribution::Gaussian,
            "inverse gaussian" => LensDistribution::InverseGaussian,
            _ => return None,
        })
    }

    /// The remapped radial sample in [0, 1] for u in [0, 1).
    pub fn remap(&self, u: f32) -> f32 {
        let v = match *self {
            LensDistribution::Uniform => u,
            LensDistribution::Exponential(p) => -u.ln() / p,
            LensDistribution::InverseExponential(p) => 1.0 + u.ln() / p,
            LensDistribution::Gaussian => normal_quantile(u),
            LensDistribution::InverseGaussian => 1.0 - normal_quantile(u),
        };
        if v.is_nan() {
            0.0
        } else {
            v.clamp(0.0, 1.0)
        }
    }
}

/// The standard normal quantile (Acklam's rational approximation, relative error < 1.2e-9);
/// +inf outside (0, 1).
pub fn normal_quantile(p: f32) -> f32 {
    const A: [f64; 6] = [
        -3.969683028665376e+01,
        2.209460984245205e+02,
        -2.759285104469687e+02,
        1.383_577_518_672_69e2,
        -3.066479806614716e+01,
        2.506628277459239e+00,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e+01,
        1.615858368580409e+02,
        -1.556989798598866e+02,
        6.680131188771972e+01,
        -1.328068155288572e+01,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-03,
        -3.223964580411365e-01,
        -2.400758277161838e+00,
        -2.549732539343734e+00,
        4.374664141464968e+00,
        2.938163982698783e+00,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-03,
        3.224671290700398e-01,
        2.445134137142996e+00,
        3.754408661907416e+00,
    ];
    const LOW: f64 = 0.02425;
    let p = f64::from(p);
    if !(p > 0.0 && p < 1.0) {
        return f32::INFINITY;
    }
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    let x = if p < LOW {
        tail((-2.0 * p.ln()).sqrt())
    } else if p <= 1.0 - LOW {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    };
    x as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantile_at_known_points() {
        assert!(normal_quantile(0.5).abs() < 1e-6);
        // Φ(1) = 0.841344746, Φ(-2) = 0.022750132
        assert!((normal_quantile(0.841_344_8) - 1.0).abs() < 1e-5);
        assert!((normal_quantile(0.022_750_132) + 2.0).abs() < 1e-4);
        assert!((normal_quantile(0.977_249_87) - 2.0).abs() < 1e-4);
        assert_eq!(normal_quantile(0.0), f32::INFINITY);
    }

    #[test]
    fn remaps_by_hand() {
        let e = LensDistribution::from_name("exponential", 3).unwrap();
        // -ln(0.5) / 3 = 0.2310491
        assert!((e.remap(0.5) - 0.231_049_1).abs() < 1e-6);
        assert_eq!(e.remap(1e-9), 1.0);
        let ie = LensDistribution::from_name("inverse exponential", 3).unwrap();
        assert!((ie.remap(0.5) - 0.768_950_9).abs() < 1e-6);
        assert_eq!(ie.remap(1e-9), 0.0);
        let g = LensDistribution::from_name("gaussian", 1).unwrap();
        assert_eq!(g.remap(0.3), 0.0);
        assert!((g.remap(0.841_344_8) - 1.0).abs() < 1e-5);
        let ig = LensDistribution::from_name("inverse gaussian", 1).unwrap();
        assert!((ig.remap(0.5) - 1.0).abs() < 1e-6);
        assert_eq!(LensDistribution::Uniform.remap(0.25), 0.25);
        assert!(LensDistribution::from_name("triangular", 1).is_none());
    }
}
