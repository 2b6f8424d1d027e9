//! The six woven fabrics of LuxRender's cloth material (`presetname`): tile layouts, yarn
//! segments and scattering parameters as LuxRender ships them (measured by Irawan;
//! Mitsuba's weave files). [`pattern`] builds one with the material's `repeat_u`/`repeat_v`.

use super::bxdf::irawan::{WeaveParams, WeavePattern, Yarn};

/// The preset names LuxRender accepts (the default first).
pub const PRESETS: [&str; 6] = [
    "denim",
    "silk_charmeuse",
    "silk_shantung",
    "cotton_twill",
    "wool_gabardine",
    "polyester_lining_cloth",
];

/// Scattering and noise parameters of a fabric: alpha, beta, ss, h_width, warp area, weft
/// area, fineness, then dWarpUmax/dWarp, dWarpUmax/dWeft, dWeftUmax/dWarp, dWeftUmax/dWeft
/// (degrees) and the noise period.
type Params = ([f32; 7], [f32; 4], f32);

/// A yarn as LuxRender lists it: psi and umax (degrees), kappa, width, length, centre u, v.
type YarnData = (f32, f32, f32, f32, f32, f32, f32);

struct Fabric {
    tile: (u32, u32),
    params: Params,
    pattern: &'static [u8],
    warp: &'static [YarnData],
    weft: &'static [YarnData],
}

#[rustfmt::skip]
const DENIM: Fabric = Fabric {
    tile: (3, 6),
    params: ([0.01, 4.0, 0.0, 0.5, 5.0, 1.0, 3.0], [0.0; 4], 0.0),
    pattern: &[1, 3, 8, 1, 3, 5, 1, 7, 5, 1, 4, 5, 6, 4, 5, 2, 4, 5],
    warp: &[
        (-30.0, 12.0, 0.0, 1.0, 5.0, 0.1667, 0.75),
        (-30.0, 12.0, 0.0, 1.0, 5.0, 0.1667, -0.25),
        (-30.0, 12.0, 0.0, 1.0, 5.0, 0.5, 1.0833),
        (-30.0, 12.0, 0.0, 1.0, 5.0, 0.5, 0.0833),
        (-30.0, 12.0, 0.0, 1.0, 5.0, 0.8333, 0.4167),
    ],
    weft: &[
        (-30.0, 38.0, 0.0, 1.0, 1.0, 0.1667, 0.25),
        (-30.0, 38.0, 0.0, 1.0, 1.0, 0.5, 0.5833),
        (-30.0, 38.0, 0.0, 1.0, 1.0, 0.8333, 0.9167),
    ],
};

#[rustfmt::skip]
const SILK_CHARMEUSE: Fabric = Fabric {
    tile: (5, 10),
    params: ([0.02, 7.3, 0.5, 0.5, 9.0, 1.0, 3.0], [0.0; 4], 0.0),
    pattern: &[
        10, 2, 4, 6, 8,
        1, 2, 4, 6, 8,
        1, 2, 4, 13, 8,
        1, 2, 4, 7, 8,
        1, 11, 4, 7, 8,
        1, 3, 4, 7, 8,
        1, 3, 4, 7, 14,
        1, 3, 4, 7, 9,
        1, 3, 12, 7, 9,
        1, 3, 5, 7, 9,
    ],
    warp: &[
        (0.0, 40.0, 2.0, 1.0, 9.0, 0.1, 0.45),
        (0.0, 40.0, 2.0, 1.0, 9.0, 0.3, 1.05),
        (0.0, 40.0, 2.0, 1.0, 9.0, 0.3, 0.05),
        (0.0, 40.0, 2.0, 1.0, 9.0, 0.5, 0.65),
        (0.0, 40.0, 2.0, 1.0, 9.0, 0.5, -0.35),
        (0.0, 40.0, 2.0, 1.0, 9.0, 0.7, 1.25),
        (0.0, 40.0, 2.0, 1.0, 9.0, 0.7, 0.25),
        (0.0, 40.0, 2.0, 1.0, 9.0, 0.9, 0.85),
        (0.0, 40.0, 2.0, 1.0, 9.0, 0.9, -0.15),
    ],
    weft: &[
        (0.0, 60.0, 0.0, 1.0, 1.0, 0.1, 0.95),
        (0.0, 60.0, 0.0, 1.0, 1.0, 0.3, 0.55),
        (0.0, 60.0, 0.0, 1.0, 1.0, 0.5, 0.15),
        (0.0, 60.0, 0.0, 1.0, 1.0, 0.7, 0.75),
        (0.0, 60.0, 0.0, 1.0, 1.0, 0.9, 0.35),
    ],
};

#[rustfmt::skip]
const COTTON_TWILL: Fabric = Fabric {
    tile: (4, 8),
    params: ([0.01, 4.0, 0.0, 0.5, 6.0, 2.0, 4.0], [0.0; 4], 0.0),
    pattern: &[
        7, 2, 4, 6,
        7, 2, 4, 6,
        1, 8, 4, 6,
        1, 8, 4, 6,
        1, 3, 9, 6,
        1, 3, 9, 6,
        1, 3, 5, 10,
        1, 3, 5, 10,
    ],
    warp: &[
        (-30.0, 24.0, 0.0, 1.0, 6.0, 0.125, 0.375),
        (-30.0, 24.0, 0.0, 1.0, 6.0, 0.375, 1.125),
        (-30.0, 24.0, 0.0, 1.0, 6.0, 0.375, 0.125),
        (-30.0, 24.0, 0.0, 1.0, 6.0, 0.625, 0.875),
        (-30.0, 24.0, 0.0, 1.0, 6.0, 0.625, -0.125),
        (-30.0, 24.0, 0.0, 1.0, 6.0, 0.875, 0.625),
    ],
    weft: &[
        (-30.0, 36.0, 0.0, 2.0, 1.0, 0.125, 0.875),
        (-30.0, 36.0, 0.0, 2.0, 1.0, 0.375, 0.625),
        (-30.0, 36.0, 0.0, 2.0, 1.0, 0.625, 0.375),
        (-30.0, 36.0, 0.0, 2.0, 1.0, 0.875, 0.125),
    ],
};

#[rustfmt::skip]
const WOOL_GABARDINE: Fabric = Fabric {
    tile: (6, 9),
    params: ([0.01, 4.0, 0.0, 0.5, 12.0, 6.0, 0.0], [0.0; 4], 0.0),
    pattern: &[
        1, 1, 2, 2, 7, 7,
        1, 1, 2, 2, 7, 7,
        1, 1, 2, 2, 7, 7,
        1, 1, 6, 6, 4, 4,
        1, 1, 6, 6, 4, 4,
        1, 1, 6, 6, 4, 4,
        5, 5, 3, 3, 4, 4,
        5, 5, 3, 3, 4, 4,
        5, 5, 3, 3, 4, 4,
    ],
    warp: &[
        (30.0, 30.0, 0.0, 2.0, 6.0, 0.167, 0.667),
        (30.0, 30.0, 0.0, 2.0, 6.0, 0.5, 1.0),
        (30.0, 30.0, 0.0, 2.0, 6.0, 0.5, 0.0),
        (30.0, 30.0, 0.0, 2.0, 6.0, 0.833, 0.333),
    ],
    weft: &[
        (30.0, 30.0, 0.0, 3.0, 2.0, 0.167, 0.167),
        (30.0, 30.0, 0.0, 3.0, 2.0, 0.5, 0.5),
        (30.0, 30.0, 0.0, 3.0, 2.0, 0.833, 0.833),
    ],
};

#[rustfmt::skip]
const POLYESTER_LINING_CLOTH: Fabric = Fabric {
    tile: (2, 2),
    params: ([0.015, 4.0, 0.5, 0.5, 1.0, 1.0, 0.0], [8.0, 8.0, 6.0, 6.0], 50.0),
    pattern: &[3, 2, 1, 4],
    warp: &[
        (0.0, 22.0, -0.7, 1.0, 1.0, 0.25, 0.25),
        (0.0, 22.0, -0.7, 1.0, 1.0, 0.75, 0.75),
    ],
    weft: &[
        (0.0, 16.0, -0.7, 1.0, 1.0, 0.25, 0.75),
        (0.0, 16.0, -0.7, 1.0, 1.0, 0.75, 0.25),
    ],
};

#[rustfmt::skip]
const SILK_SHANTUNG: Fabric = Fabric {
    tile: (6, 8),
    params: ([0.02, 1.5, 0.5, 0.5, 8.0, 16.0, 0.0], [20.0, 20.0, 10.0, 10.0], 500.0),
    pattern: &[
        3, 3, 3, 3, 2, 2,
        3, 3, 3, 3, 2, 2,
        3, 3, 3, 3, 2, 2,
        3, 3, 3, 3, 2, 2,
        4, 1, 1, 5, 5, 5,
        4, 1, 1, 5, 5, 5,
        4, 1, 1, 5, 5, 5,
        4, 1, 1, 5, 5, 5,
    ],
    warp: &[
        (0.0, 50.0, -0.5, 2.0, 4.0, 0.3333, 0.25),
        (0.0, 50.0, -0.5, 2.0, 4.0, 0.8333, 0.75),
    ],
    weft: &[
        (0.0, 23.0, -0.3, 4.0, 4.0, 0.3333, 0.75),
        (0.0, 23.0, -0.3, 4.0, 4.0, -0.1667, 0.25),
        (0.0, 23.0, -0.3, 4.0, 4.0, 0.8333, 0.25),
    ],
};

fn fabric(name: &str) -> Option<&'static Fabric> {
    Some(match name {
        "denim" => &DENIM,
        "silk_charmeuse" => &SILK_CHARMEUSE,
        "silk_shantung" => &SILK_SHANTUNG,
        "cotton_twill" => &COTTON_TWILL,
        "wool_gabardine" => &WOOL_GABARDINE,
        "polyester_lining_cloth" => &POLYESTER_LINING_CLOTH,
        _ => return None,
    })
}

/// The weave of preset `name` repeated `repeat_u × repeat_v` times over the uv square, or
/// `None` for an unknown name.
pub fn pattern(name: &str, repeat_u: f32, repeat_v: f32) -> Option<WeavePattern> {
    let f = fabric(name)?;
    let ([alpha, beta, ss, h_width, warp_area, weft_area, fineness], d, period) = f.params;
    let yarn = |y: &YarnData, weft: bool| Yarn::new([y.0, y.1], y.2, [y.3, y.4], [y.5, y.6], weft);
    let yarns = f
        .warp
        .iter()
        .map(|y| yarn(y, false))
        .chain(f.weft.iter().map(|y| yarn(y, true)))
        .collect();
    Some(WeavePattern {
        params: WeaveParams {
            alpha,
            beta,
            ss,
            h_width,
            warp_area,
            weft_area,
        },
        tile_width: f.tile.0,
        tile_height: f.tile.1,
        d_warp_umax_over_d_warp: d[0].to_radians(),
        d_warp_umax_over_d_weft: d[1].to_radians(),
        d_weft_umax_over_d_warp: d[2].to_radians(),
        d_weft_umax_over_d_weft: d[3].to_radians(),
        fineness,
        period,
        repeat_u,
        repeat_v,
        pattern: f.pattern.to_vec(),
        yarns,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_preset_is_consistent() {
        for name in PRESETS {
            let p = pattern(name, 1.0, 1.0).unwrap();
            assert_eq!(
                p.pattern.len(),
                (p.tile_width * p.tile_height) as usize,
                "{name}"
            );
            assert!(
                p.pattern
                    .iter()
                    .all(|&i| i >= 1 && (i as usize) <= p.yarns.len()),
                "{name}"
            );
            // Every yarn appears in the tile.
            for i in 1..=p.yarns.len() as u8 {
                assert!(p.pattern.contains(&i), "{name}: yarn {i} unused");
            }
        }
        assert!(pattern("tweed", 1.0, 1.0).is_none());
    }
}
