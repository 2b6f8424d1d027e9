//! Colour systems as LuxRender builds them: XYZ <-> RGB matrices from the chromaticities of
//! the primaries and the white point, gamut constraining of negative RGB, the LDR clamp
//! methods, and Bradford chromatic adaptation (light group RGB scale and temperature).

use crate::film::imaging::{ClampMethod, ColorSpaceParams};

type M3 = [[f64; 3]; 3];

fn mul(a: &M3, b: &M3) -> M3 {
    let mut r = [[0.0; 3]; 3];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    r
}

fn apply(m: &M3, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

fn invert(m: &M3) -> M3 {
    let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    let inv = if det.abs() > 1e-300 { 1.0 / det } else { 0.0 };
    [
        [
            (m[1][1] * m[2][2] - m[1][2] * m[2][1]) * inv,
            (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * inv,
            (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * inv,
        ],
        [
            (m[1][2] * m[2][0] - m[1][0] * m[2][2]) * inv,
            (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * inv,
            (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * inv,
        ],
        [
            (m[1][0] * m[2][1] - m[1][1] * m[2][0]) * inv,
            (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * inv,
            (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * inv,
        ],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// An RGB colour system (primaries, white point, white luminance 1).
#[derive(Clone, Debug)]
pub struct ColorSystem {
    p: ColorSpaceParams,
    xyz_to_rgb: M3,
    rgb_to_xyz: M3,
}

impl ColorSystem {
    /// Builds the matrices the way LuxRender does: the RGB primaries are fitted so that RGB
    /// (1, 1, 1) maps to the white point, through a least-squares system around the white.
    pub fn new(p: &ColorSpaceParams) -> ColorSystem {
        let xy = |c: [f32; 2]| {
            let (x, y) = (f64::from(c[0]), f64::from(c[1]));
            [x / y, 1.0, (1.0 - x - y) / y]
        };
        let (red, green, blue, white) = (xy(p.red), xy(p.green), xy(p.blue), xy(p.white));
        let prim = [
            [red[0], green[0], blue[0]],
            [red[1], green[1], blue[1]],
            [red[2], green[2], blue[2]],
        ];
        let y = apply(&invert(&prim), white);
        let x = [y[0] * red[0], y[1] * green[0], y[2] * blue[0]];
        let z = [y[0] * red[2], y[1] * green[2], y[2] * blue[2]];
        let rgb = [
            [x[0] + white[0], y[0] + white[1], z[0] + white[2]],
            [x[1] + white[0], y[1] + white[1], z[1] + white[2]],
            [x[2] + white[0], y[2] + white[1], z[2] + white[2]],
        ];
        let rows = [x, y, z];
        let mut m = [[0.0; 3]; 3];
        for (i, row) in m.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = dot(rows[j], rows[i]) + white[i] * white[j];
            }
        }
        let xyz_to_rgb = mul(&rgb, &invert(&m));
        ColorSystem {
            p: p.clone(),
            rgb_to_xyz: invert(&xyz_to_rgb),
            xyz_to_rgb,
        }
    }

    pub fn to_rgb(&self, xyz: [f32; 3]) -> [f32; 3] {
        apply(&self.xyz_to_rgb, xyz.map(f64::from)).map(|v| v as f32)
    }

    pub fn to_xyz(&self, rgb: [f32; 3]) -> [f32; 3] {
        apply(&self.rgb_to_xyz, rgb.map(f64::from)).map(|v| v as f32)
    }

    /// Luminance (Y) of a linear RGB colour.
    pub fn luminance(&self, rgb: [f32; 3]) -> f32 {
        let r = &self.rgb_to_xyz[1];
        (r[0] * f64::from(rgb[0]) + r[1] * f64::from(rgb[1]) + r[2] * f64::from(rgb[2])) as f32
    }

    /// XYZ to RGB, desaturating colours outside the gamut (a negative primary) towards the
    /// gamut boundary at constant luminance, as LuxRender's `ToRGBConstrained`.
    pub fn to_rgb_constrained(&self, xyz: [f32; 3]) -> [f32; 3] {
        let rgb = self.to_rgb(xyz);
        if rgb.iter().all(|&c| c >= 0.0) {
            return rgb;
        }
        self.constrain(xyz)
    }

    fn constrain(&self, xyz: [f32; 3]) -> [f32; 3] {
        let yc = xyz[1];
        if yc.is_nan() || yc <= 0.0 {
            return [0.0; 3];
        }
        let sum = xyz[0] + xyz[1] + xyz[2];
        let (mut xc, mut ycc) = (xyz[0] / sum, xyz[1] / sum);
        let [xr, yr] = self.p.red;
        let [xg, yg] = self.p.green;
        let [xb, yb] = self.p.blue;
        let line = |x0: f32, y0: f32, x1: f32, y1: f32| {
            let a = (y1 - y0) / (x1 - x0);
            (a, y0 - a * x0)
        };
        let project = |a: f32, b: f32, x: f32, y: f32| {
            let ao = -1.0 / a;
            let bo = -ao * x + y;
            let px = (bo - b) / (a - ao);
            (px, a * px + b)
        };
        let (a_br, b_br) = line(xb, yb, xr, yr);
        let (a_bg, b_bg) = line(xb, yb, xg, yg);
        let (a_gr, b_gr) = line(xg, yg, xr, yr);
        if ycc < a_br * xc + b_br {
            (xc, ycc) = project(a_br, b_br, xc, ycc);
            (xc, ycc) = clamp_to(xc, ycc, (xb, yb), (xr, yr));
        } else if ycc > a_bg * xc + b_bg {
            (xc, ycc) = project(a_bg, b_bg, xc, ycc);
            (xc, ycc) = clamp_to(xc, ycc, (xb, yb), (xg, yg));
        } else if ycc > a_gr * xc + b_gr {
            (xc, ycc) = project(a_gr, b_gr, xc, ycc);
            (xc, ycc) = clamp_to(xc, ycc, (xg, yg), (xr, yr));
        }
        let disp = [xc * yc / ycc, yc, (1.0 - xc - ycc) * yc / ycc];
        self.to_rgb(disp)
    }

    /// Brings an RGB colour with a component above 1 back into [0, 1] by the LDR clamp
    /// method (LuxRender's `ColorSystem::Limit`); colours already inside are unchanged.
    pub fn limit(&self, rgb: [f32; 3], method: ClampMethod) -> [f32; 3] {
        if !rgb.iter().any(|&c| c > 1.0) {
            return rgb;
        }
        match method {
            ClampMethod::Cut => rgb.map(|c| c.clamp(0.0, 1.0)),
            ClampMethod::Darken => {
                let m = rgb[0].max(rgb[1]).max(rgb[2]);
                rgb.map(|c| c / m)
            }
            ClampMethod::Lum | ClampMethod::Hue => {
                let lum = match method {
                    ClampMethod::Lum => self.luminance(rgb),
                    _ => 1.0 / 3.0,
                };
                if lum > 1.0 {
                    return [1.0; 3];
                }
                let l = lum;
                let top = if rgb[0] > rgb[1] && rgb[0] > rgb[2] {
                    rgb[0]
                } else if rgb[1] > rgb[2] {
                    rgb[1]
                } else {
                    rgb[2]
                };
                let t = (1.0 - l) / (top - l);
                rgb.map(|c| l + t * (c - l))
            }
        }
    }
}

fn clamp_to(x: f32, y: f32, lo: (f32, f32), hi: (f32, f32)) -> (f32, f32) {
    if x < lo.0 {
        lo
    } else if x > hi.0 {
        hi
    } else {
        (x, y)
    }
}

const BRADFORD: M3 = [
    [0.8951, 0.2664, -0.1614],
    [-0.7502, 1.7135, 0.0367],
    [0.0389, -0.0685, 1.0296],
];
const INV_BRADFORD: M3 = [
    [0.9869929, -0.1470543, 0.1599627],
    [0.4323053, 0.5183603, 0.0492912],
    [-0.0085287, 0.0400428, 0.9684867],
];

/// A chromatic adaptation (Bradford) from one white to another, possibly scaled.
#[derive(Clone, Debug, PartialEq)]
pub struct ColorAdaptation {
    m: M3,
}

impl ColorAdaptation {
    pub fn identity() -> ColorAdaptation {
        ColorAdaptation {
            m: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
    }

    /// Adapts colours from white `from` to white `to` (both XYZ).
    pub fn new(from: [f32; 3], to: [f32; 3]) -> ColorAdaptation {
        let d = |i: usize| {
            if from[i] != 0.0 {
                f64::from(to[i]) / f64::from(from[i])
            } else {
                0.0
            }
        };
        let diag = [[d(0), 0.0, 0.0], [0.0, d(1), 0.0], [0.0, 0.0, d(2)]];
        ColorAdaptation {
            m: mul(&INV_BRADFORD, &mul(&diag, &BRADFORD)),
        }
    }

    pub fn then(&self, other: &ColorAdaptation) -> ColorAdaptation {
        ColorAdaptation {
            m: mul(&self.m, &other.m),
        }
    }

    pub fn scaled(mut self, s: f64) -> ColorAdaptation {
        self.m.iter_mut().flatten().for_each(|v| *v *= s);
        self
    }

    pub fn adapt(&self, xyz: [f64; 3]) -> [f64; 3] {
        apply(&self.m, xyz)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_maps_to_rgb_one() {
        let cs = ColorSystem::new(&ColorSpaceParams::default());
        let w = ColorSpaceParams::default().white;
        let xyz = [w[0] / w[1], 1.0, (1.0 - w[0] - w[1]) / w[1]];
        let rgb = cs.to_rgb(xyz);
        for c in rgb {
            assert!((c - 1.0).abs() < 1e-4, "{rgb:?}");
        }
        let back = cs.to_xyz(rgb);
        assert!((back[1] - 1.0).abs() < 1e-5);
    }

    #[test]
    fn constrained_has_no_negative_primary() {
        let cs = ColorSystem::new(&ColorSpaceParams::default());
        let rgb = cs.to_rgb_constrained([0.1, 0.5, 0.05]);
        assert!(rgb.iter().all(|&c| c >= -1e-5), "{rgb:?}");
    }

    #[test]
    fn limit_methods_bring_values_into_range() {
        let cs = ColorSystem::new(&ColorSpaceParams::default());
        for m in [
            ClampMethod::Lum,
            ClampMethod::Hue,
            ClampMethod::Cut,
            ClampMethod::Darken,
        ] {
            let r = cs.limit([1.5, 0.2, 0.1], m);
            assert!(r.iter().all(|&c| c <= 1.0 + 1e-5), "{m:?} {r:?}");
        }
        assert_eq!(cs.limit([0.5, 0.2, 0.1], ClampMethod::Lum), [0.5, 0.2, 0.1]);
    }
}
