//! The `falsecolors` kernel: a luminance map. Each pixel's film luminance Y is bounded to
//! the Film's [`false_min`, `false_max`], normalised to [0, 1], shaped by `false_method`
//! (linear, log, log3) and looked up in the `false_colorscale` (std, lmk, red, white, yellow,
//! speos); the pixel becomes that colour, whatever its own chromaticity.
//!
//! Data flow, as LuxRender 1.x's `FalseColorsOp` runs it: XYZ in (after the negative clamp,
//! bloom and glare of [`super::apply_kernel`]); per pixel Y -> normalised value -> shaped
//! value -> 8-bit-step scale colour as RGB in [0, 1] -> XYZ through Adobe RGB (1998)
//! primaries with a D65 white, which LuxRender's kernel uses whatever the Film's colour
//! space. The pipeline then converts that XYZ to the Film's colour space, clamps and applies
//! the gamma like any other kernel's output, so a scale colour reaches a PNG unchanged only
//! when the Film's colour space is Adobe RGB and its gamma 1.
//!
//! Values outside [min, max] take the colour of the nearest end (the scale saturates: no
//! special "under" or "over" colour). LuxRender bounds Y with `y > min ? min(y, max) : min`,
//! so a NaN luminance reads as `min`; when `max <= min` (only reachable from an FLM written
//! by LuxRender, whose header omits the range: the Film statement refuses it, see
//! [`crate::film::FilmParams`]) every pixel gets the scale's colour at 0 (at 1 above `min`
//! when `min > max`), as LuxRender shows it. The output is always finite.
//!
//! LuxRender's GUI draws a legend beside the image (its `falseDrawLegend`); the Film has no
//! legend parameter and no output file carries one, so neither does luxfarm's.

use super::colorspace::ColorSystem;
use crate::film::imaging::{ColorSpaceParams, FalseColors, FalseMethod, FalseScale};

/// The colour space LuxRender converts the scale colours from: Adobe RGB (1998), D65 white.
pub fn scale_space() -> ColorSpaceParams {
    ColorSpaceParams {
        white: [0.3127, 0.3290],
        red: [0.64, 0.33],
        green: [0.21, 0.71],
        blue: [0.15, 0.06],
    }
}

/// Replaces every pixel (XYZ, in place) by its false colour.
pub fn map(xyz: &mut [[f32; 3]], p: &FalseColors) {
    let cs = ColorSystem::new(&scale_space());
    for px in xyz.iter_mut() {
        let v = shape(p.method, normalise(px[1], p.min, p.max));
        *px = cs.to_xyz(scale_rgb(p.scale, v));
    }
}

/// Y bounded to [min, max] and mapped to [0, 1] (NaN when `max == min`; read as 0 later).
pub fn normalise(y: f32, min: f32, max: f32) -> f32 {
    let bounded = if y > min {
        if y < max {
            y
        } else {
            max
        }
    } else {
        min
    };
    (bounded - min) / (max - min)
}

/// The value the colour scale is read at: `false_method` applied to a normalised luminance.
pub fn shape(method: FalseMethod, v: f32) -> f32 {
    match method {
        FalseMethod::Linear => v,
        FalseMethod::Log => (1.0 + 9.0 * v).log10(),
        FalseMethod::Log3 => (1.0 + 9.0 * v).log10().powf(1.0 / 3.0),
    }
}

/// `v` limited to [0, 1], NaN to 0 (LuxRender's `Clamp`).
fn unit(v: f32) -> f32 {
    if v > 0.0 {
        v.min(1.0)
    } else {
        0.0
    }
}

/// One stretch of a stepped scale: the 8-bit colour at its first step and the change per
/// step along it.
type Segment = ([i32; 3], [i32; 3]);

/// `std`: 8 stretches of 128 steps (1024 in all), dark blue (0, 0, 128) to dark red
/// (128, 0, 0) through blue, cyan, light green, yellow and orange.
const STD: [Segment; 8] = [
    ([0, 0, 128], [0, 0, 1]),
    ([0, 0, 255], [0, 1, 0]),
    ([0, 127, 255], [0, 1, 0]),
    ([0, 255, 255], [1, 0, -1]),
    ([127, 255, 127], [1, 0, -1]),
    ([255, 255, 0], [0, -1, 0]),
    ([255, 128, 0], [0, -1, 0]),
    ([255, 0, 0], [-1, 0, 0]),
];

/// `lmk`: 5 stretches of 256 steps, black, blue, green, red, yellow, white.
const LMK: [Segment; 5] = [
    ([0, 0, 0], [0, 0, 1]),
    ([0, 0, 255], [0, 1, -1]),
    ([0, 255, 0], [1, -1, 0]),
    ([255, 0, 0], [0, 1, 0]),
    ([255, 255, 0], [0, 0, 1]),
];

/// `speos`: 6 stretches of 256 steps, black, blue, cyan, green, yellow, red, white.
const SPEOS: [Segment; 6] = [
    ([0, 0, 0], [0, 0, 1]),
    ([0, 0, 255], [0, 1, 0]),
    ([0, 255, 255], [0, 0, -1]),
    ([0, 255, 0], [1, 0, 0]),
    ([255, 255, 0], [0, -1, 0]),
    ([255, 0, 0], [0, 1, 1]),
];

/// A stepped scale read at `v`: the step is `trunc(v * (steps - 1))`, as LuxRender's integer
/// conversion, over stretches of `len` steps.
fn stepped(segments: &[Segment], len: i32, v: f32) -> [f32; 3] {
    let steps = segments.len() as i32 * len;
    let step = (unit(v) * (steps - 1) as f32) as i32;
    let (i, k) = ((step / len) as usize, step % len);
    let (base, slope) = segments.get(i).copied().unwrap_or(([0; 3], [0; 3]));
    [0, 1, 2].map(|c| (base[c] + slope[c] * k) as f32 / 255.0)
}

/// The colour (RGB in [0, 1], Adobe RGB primaries) of `scale` at `v` (limited to [0, 1]).
pub fn scale_rgb(scale: FalseScale, v: f32) -> [f32; 3] {
    let v = unit(v);
    match scale {
        FalseScale::Std => stepped(&STD, 128, v),
        FalseScale::Lmk => stepped(&LMK, 256, v),
        FalseScale::Speos => stepped(&SPEOS, 256, v),
        FalseScale::Red => [v, 0.0, 0.0],
        FalseScale::White => [v, v, v],
        FalseScale::Yellow => [v, 0.287_245_17 * v, 0.0],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rgb8(scale: FalseScale, v: f32) -> [i32; 3] {
        scale_rgb(scale, v).map(|c| (c * 255.0).round() as i32)
    }

    fn close(a: [f32; 3], b: [f32; 3], tol: f32) -> bool {
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= tol)
    }

    #[test]
    fn std_scale_control_points() {
        use FalseScale::Std;
        // step = trunc(v * 1023); stretch = step / 128, position = step % 128
        assert_eq!(rgb8(Std, 0.0), [0, 0, 128]);
        assert_eq!(rgb8(Std, 1.0), [128, 0, 0]); // step 1023: stretch 7, 127 in
        assert_eq!(rgb8(Std, 0.5), [127, 255, 128]); // step 511: stretch 3, 127 in
        assert_eq!(rgb8(Std, 0.25), [0, 127, 255]); // step 255: stretch 1, 127 in
        assert_eq!(rgb8(Std, 0.75), [255, 128, 0]); // step 767: stretch 5, 127 in
        assert_eq!(rgb8(Std, -1.0), [0, 0, 128]);
        assert_eq!(rgb8(Std, 2.0), [128, 0, 0]);
        assert_eq!(rgb8(Std, f32::NAN), [0, 0, 128]);
    }

    #[test]
    fn every_scale_at_its_ends_and_middle() {
        // (scale, v, expected 8-bit colour), hand-computed from the stretch tables
        let cases = [
            (FalseScale::Lmk, 0.0, [0, 0, 0]),
            (FalseScale::Lmk, 1.0, [255, 255, 255]), // step 1279: stretch 4, 255 in
            (FalseScale::Lmk, 0.5, [127, 128, 0]),   // step 639: stretch 2, 127 in
            (FalseScale::Speos, 0.0, [0, 0, 0]),
            (FalseScale::Speos, 1.0, [255, 255, 255]), // step 1535: stretch 5, 255 in
            (FalseScale::Speos, 0.5, [0, 255, 0]),     // step 767: stretch 2, 255 in
            (FalseScale::Red, 0.5, [128, 0, 0]),
            (FalseScale::White, 0.25, [64, 64, 64]),
            (FalseScale::Yellow, 1.0, [255, 73, 0]),
        ];
        for (s, v, want) in cases {
            assert_eq!(rgb8(s, v), want, "{s:?} at {v}");
        }
    }

    #[test]
    fn values_outside_the_range_take_the_ends_colours() {
        let p = |y| scale_rgb(FalseScale::Std, normalise(y, 2.0, 10.0));
        assert_eq!(p(0.5), p(2.0));
        assert_eq!(p(-3.0), p(2.0));
        assert_eq!(p(1e30), p(10.0));
        assert_eq!(p(f32::INFINITY), p(10.0));
        assert_eq!(p(f32::NAN), p(2.0));
        assert_eq!(normalise(6.0, 2.0, 10.0), 0.5);
    }

    #[test]
    fn methods_shape_the_normalised_value() {
        for m in FalseMethod::ALL {
            assert_eq!(shape(m, 0.0), 0.0, "{m:?}");
            assert!((shape(m, 1.0) - 1.0).abs() < 1e-6, "{m:?}");
        }
        // log: log10(1 + 9 * 0.5) = log10(5.5)
        assert!((shape(FalseMethod::Log, 0.5) - 0.740_362_7).abs() < 1e-6);
        assert!((shape(FalseMethod::Log3, 0.5) - 0.740_362_7f32.cbrt()).abs() < 1e-6);
        assert_eq!(shape(FalseMethod::Linear, 0.3), 0.3);
        // log at v = 1/9 reads the scale at log10(2)
        assert!((shape(FalseMethod::Log, 1.0 / 9.0) - 2f32.log10()).abs() < 1e-6);
    }

    #[test]
    fn log_reads_the_middle_of_the_scale_at_the_geometric_middle_of_1_plus_9v() {
        // LuxRender's log is log10(1 + 9 v): 1 + 9 v runs over [1, 10], and its geometric
        // middle sqrt(10) reads the scale at 0.5. With min 0 and max 9, v = Y / 9, so
        // Y = sqrt(10) - 1 is that point: std's colour at 0.5, (127, 255, 128).
        let y = 10f32.sqrt() - 1.0;
        let v = shape(FalseMethod::Log, normalise(y, 0.0, 9.0));
        assert!((v - 0.5).abs() < 1e-6, "{v}");
        assert_eq!(rgb8(FalseScale::Std, v), [127, 255, 128]);
        // the plain geometric middle of [1, 100] (10) is not the middle under log
        let v = shape(FalseMethod::Log, normalise(10.0, 1.0, 100.0));
        assert!((v - (20f32 / 11.0).log10()).abs() < 1e-6, "{v}");
    }

    #[test]
    fn degenerate_ranges_stay_finite_as_luxrender_shows_them() {
        for (min, max) in [(0.0, 0.0), (5.0, 5.0), (f32::NEG_INFINITY, f32::INFINITY)] {
            let mut px = vec![[1.0, 3.0, 1.0], [0.0; 3], [f32::NAN; 3]];
            map(
                &mut px,
                &FalseColors {
                    min,
                    max,
                    ..FalseColors::default()
                },
            );
            assert!(px.iter().flatten().all(|c| c.is_finite()), "{min} {max}");
        }
        // min > max: at or below min -> 0, above -> 1
        assert_eq!(normalise(3.0, 5.0, 1.0), 0.0);
        assert_eq!(normalise(7.0, 5.0, 1.0), 1.0);
    }

    #[test]
    fn map_converts_the_scale_colour_through_adobe_rgb() {
        let cs = ColorSystem::new(&scale_space());
        let p = FalseColors {
            method: FalseMethod::Linear,
            scale: FalseScale::Std,
            min: 0.0,
            max: 4.0,
        };
        let mut px = vec![[9.0, 0.0, 1.0], [0.0, 4.0, 0.0], [5.0, 8.0, 0.0]];
        map(&mut px, &p);
        let want = [[0.0, 0.0, 128.0 / 255.0], [128.0 / 255.0, 0.0, 0.0]];
        assert!(
            close(cs.to_rgb(px[0]), want[0], 1e-5),
            "{:?}",
            cs.to_rgb(px[0])
        );
        assert!(
            close(cs.to_rgb(px[1]), want[1], 1e-5),
            "{:?}",
            cs.to_rgb(px[1])
        );
        assert_eq!(px[2], px[1], "above max: the colour of max");
        // D65 white of Adobe RGB: RGB (1, 1, 1) has Y = 1
        assert!((cs.to_xyz([1.0; 3])[1] - 1.0).abs() < 1e-5);
    }
}
