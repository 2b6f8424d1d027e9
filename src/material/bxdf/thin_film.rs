//! Thin-film interference of LuxRender's specular reflections (`film`, `filmindex` of mirror,
//! glass and shinymetal): a coating of thickness `t` nm and index `n_f` multiplies the
//! reflected spectrum by `cos²(4π t s / λ + π)` with `s = sqrt(n_f² - sin²θ_o)`.
//!
//! The renderer is RGB, so the factor is converted once per optical path `d = t s` (nm): the
//! spectrum `cos²(4π d / λ)` as a reflectance under LuxRender's white illuminant gives an XYZ
//! (1 nm steps over 380–720 nm, the range LuxRender samples), and [`xyz_to_rgb`] turns it
//! into the RGB reflectance with that XYZ. The factors are tabulated every [`STEP`] nm up to
//! [`D_MAX`] nm on first use (interpolated linearly); beyond, the fringes are finer than the
//! colour bands and the factor is the table's last value.

use crate::spectrum::cie::cmf;
use crate::spectrum::{smits, xyz_to_rgb, Rgb};
use std::f64::consts::PI;
use std::sync::OnceLock;

/// Largest tabulated optical path (nm).
pub const D_MAX: f32 = 3000.0;
/// Table step (nm).
pub const STEP: f32 = 0.5;

/// A thin film on a specular reflection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinFilm {
    /// Thickness in nanometres (> 0).
    pub thickness: f32,
    /// Index of refraction of the film.
    pub index: f32,
}

impl ThinFilm {
    /// The film of `film`/`filmindex` values, `None` when the thickness disables it.
    pub fn new(thickness: f32, index: f32) -> Option<ThinFilm> {
        (thickness > 0.0 && thickness.is_finite() && index.is_finite())
            .then_some(ThinFilm { thickness, index })
    }

    /// The RGB factor on a reflection seen at `cos_o` (the cosine of the outgoing direction).
    pub fn factor(&self, cos_o: f32) -> Rgb {
        let sin2 = (1.0 - cos_o * cos_o).max(0.0);
        let s = (self.index * self.index - sin2).max(0.0).sqrt();
        path_factor(self.thickness * s)
    }
}

/// The RGB factor for optical path `d` nm.
pub fn path_factor(d: f32) -> Rgb {
    let t = table();
    let x = (d.max(0.0) / STEP).min((t.len() - 1) as f32);
    let i = (x as usize).min(t.len() - 2);
    let f = x - i as f32;
    t[i] * (1.0 - f) + t[i + 1] * f
}

fn table() -> &'static [Rgb] {
    static TABLE: OnceLock<Vec<Rgb>> = OnceLock::new();
    TABLE.get_or_init(|| {
        let weights = xyz_weights();
        let n = (D_MAX / STEP) as usize + 1;
        (0..n)
            .map(|i| spectral_factor(i as f64 * STEP as f64, &weights))
            .collect()
    })
}

/// Per wavelength (380..=720 nm): XYZ weight of a unit reflectance under the white
/// illuminant, with LuxRender's 683 lm/W.
fn xyz_weights() -> Vec<(f64, [f64; 3])> {
    (380..=720)
        .map(|nm| {
            let l = nm as f32;
            let white = smits::sample(&smits::WHITE, l) as f64 * smits::ILLUM_SCALE as f64;
            let refl = smits::sample(&smits::REFL_WHITE, l) as f64 * smits::REFL_SCALE as f64;
            let c = cmf(l);
            let w = 683.0 * white * refl;
            (
                nm as f64,
                [w * c[0] as f64, w * c[1] as f64, w * c[2] as f64],
            )
        })
        .collect()
}

/// The RGB reflectance of the interference spectrum `cos²(4π d / λ + π)`.
fn spectral_factor(d: f64, weights: &[(f64, [f64; 3])]) -> Rgb {
    let mut xyz = [0.0f64; 3];
    for (l, w) in weights {
        let f = (4.0 * PI * d / l + PI).cos().powi(2);
        for k in 0..3 {
            xyz[k] += f * w[k];
        }
    }
    xyz_to_rgb([xyz[0] as f32, xyz[1] as f32, xyz[2] as f32]).map(|v| v.max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_film_thickness_leaves_white_and_thick_films_average_half() {
        // d = 0: cos²(π) = 1 at every wavelength.
        let w = path_factor(0.0);
        for i in 0..3 {
            assert!((w[i] - 1.0).abs() < 0.01, "{w:?}");
        }
        // Fine fringes average to one half.
        let h = path_factor(2900.0);
        for i in 0..3 {
            assert!((h[i] - 0.5).abs() < 0.08, "{h:?}");
        }
        assert!(ThinFilm::new(0.0, 1.5).is_none());
    }

    #[test]
    fn interference_maxima_and_minima_follow_the_optical_path() {
        // cos²(4π d/λ) at λ = 550 nm: a maximum for d = 137.5 nm (red and blue lower), a
        // minimum for d = 68.75 nm (all of the visible range dim, green darkest).
        let max = path_factor(137.5);
        assert!(
            max.g > 0.95 && max.b < max.g - 0.3 && max.r < max.g,
            "{max:?}"
        );
        let min = path_factor(68.75);
        assert!(min.g < 0.1 && min.max_component() < 0.35, "{min:?}");
        // The optical path grows with the film index and shrinks with the angle.
        let film = ThinFilm::new(100.0, 1.375).unwrap();
        let at_normal = film.factor(1.0);
        assert!((at_normal.g - max.g).abs() < 1e-5);
        let grazing = film.factor(0.0);
        let expect = path_factor(100.0 * (1.375f32 * 1.375 - 1.0).sqrt());
        assert!((grazing.r - expect.r).abs() < 1e-5);
    }
}
