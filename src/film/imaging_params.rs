//! The Film statement's imaging parameters: the tonemapping kernel and its settings, false
//! colours, the colour space, the clamp method and the image effects, read into `imaging.rs`'s
//! types. It also holds the small helpers both files read and refuse values with (`choice`,
//! `bad`, `loc_of`); `params.rs` builds the whole `FilmParams` and calls in here.

use super::imaging::{
    ClampMethod, ColorSpaceParams, Effects, FalseColors, FalseMethod, FalseScale, Kernel,
    TonemapParams,
};
use super::FilmError;
use crate::lxs::{Loc, ParamSet};

pub(super) fn bad(loc: &Loc, name: &str, msg: impl std::fmt::Display) -> FilmError {
    FilmError::Param {
        loc: loc.clone(),
        message: format!("Film parameter \"{name}\": {msg}"),
    }
}

pub(super) fn loc_of(ps: &ParamSet, name: &str, fallback: &Loc) -> Loc {
    ps.params
        .iter()
        .rev()
        .find(|p| p.name == name)
        .map(|p| p.loc.clone())
        .unwrap_or_else(|| fallback.clone())
}

/// An enumerated string option: the default when absent, an error naming the place when
/// the value is unknown.
pub(super) fn choice<T>(
    ps: &ParamSet,
    loc: &Loc,
    name: &str,
    default: &str,
    parse: impl Fn(&str) -> Option<T>,
) -> Result<T, FilmError> {
    let v = ps.string_or(name, default);
    parse(v).ok_or_else(|| {
        bad(
            &loc_of(ps, name, loc),
            name,
            format!("unknown value \"{v}\""),
        )
    })
}
/// Two floats (a chromaticity); LuxRender ignores a parameter of another length.
fn xy(ps: &ParamSet, name: &str, default: [f32; 2]) -> [f32; 2] {
    match ps.floats(name) {
        Some([a, b]) => [*a, *b],
        _ => default,
    }
}
/// The tonemapping kernel's parameter name: `tonemapkernel`, or the legacy `multiimage`
/// film's `tonemapper` when that film gives it and no `tonemapkernel`.
fn kernel_key(ps: &ParamSet, kind: &str) -> &'static str {
    if kind == "multiimage"
        && ps.string("tonemapper").is_some()
        && ps.string("tonemapkernel").is_none()
    {
        "tonemapper"
    } else {
        "tonemapkernel"
    }
}

pub(super) fn tonemap_params(
    ps: &ParamSet,
    loc: &Loc,
    kind: &str,
) -> Result<TonemapParams, FilmError> {
    let d = TonemapParams::default();
    let cs = ColorSpaceParams::default();
    let kernel = choice(
        ps,
        loc,
        kernel_key(ps, kind),
        "autolinear",
        Kernel::from_name,
    )?;
    Ok(TonemapParams {
        kernel,
        reinhard_prescale: ps.float_or("reinhard_prescale", d.reinhard_prescale),
        reinhard_postscale: ps.float_or("reinhard_postscale", d.reinhard_postscale),
        reinhard_burn: ps.float_or("reinhard_burn", d.reinhard_burn),
        linear_sensitivity: ps.float_or("linear_sensitivity", d.linear_sensitivity),
        linear_exposure: ps.float_or("linear_exposure", d.linear_exposure),
        linear_fstop: ps.float_or("linear_fstop", d.linear_fstop),
        linear_gamma: ps.float_or("linear_gamma", d.linear_gamma),
        contrast_ywa: ps.float_or("contrast_ywa", d.contrast_ywa),
        false_colors: false_colors(ps, loc, kernel)?,
        gamma: ps.float_or("gamma", d.gamma),
        colorspace: ColorSpaceParams {
            white: xy(ps, "colorspace_white", cs.white),
            red: xy(ps, "colorspace_red", cs.red),
            green: xy(ps, "colorspace_green", cs.green),
            blue: xy(ps, "colorspace_blue", cs.blue),
        },
        clamp_method: choice(ps, loc, "ldr_clamp_method", "cut", ClampMethod::from_name)?,
        groups: Vec::new(),
        flavour: d.flavour,
        effects: Effects::default(),
    })
}

/// The falsecolors kernel's `false_*` parameters (LuxRender's defaults: linear, std, 0, 0).
/// An unknown method or scale name is an error where LuxRender warned and used linear or std.
/// With the falsecolors kernel, a range other than finite `false_min < false_max` is an error
/// naming `false_max` (or `false_min`, or the Film statement): LuxRender checks nothing and
/// shows every pixel in one colour (its defaults, 0 and 0, do that).
fn false_colors(ps: &ParamSet, loc: &Loc, kernel: Kernel) -> Result<FalseColors, FilmError> {
    let d = FalseColors::default();
    let fc = FalseColors {
        method: choice(ps, loc, "false_method", "linear", FalseMethod::from_name)?,
        scale: choice(ps, loc, "false_colorscale", "std", FalseScale::from_name)?,
        max: ps.float_or("false_max", d.max),
        min: ps.float_or("false_min", d.min),
    };
    let ordered = fc.min.is_finite() && fc.max.is_finite() && fc.min < fc.max;
    if kernel != Kernel::FalseColors || ordered {
        return Ok(fc);
    }
    let name = match (ps.float("false_max"), ps.float("false_min")) {
        (None, Some(_)) => "false_min",
        _ => "false_max",
    };
    Err(bad(
        &loc_of(ps, name, loc),
        name,
        format!(
            "the falsecolors kernel needs finite false_min < false_max (the luminance range \
             it colours), got false_min {} and false_max {}",
            fc.min, fc.max
        ),
    ))
}

/// The image effects; LuxRender's `abberation_*` spelling, and the correct one as an alias.
pub(super) fn effects(ps: &ParamSet) -> Effects {
    let d = Effects::default();
    let aberration_enabled = ps.bool_or("aberration_enabled", false);
    let aberration_amount = ps.float_or("aberration_amount", d.aberration_amount);
    Effects {
        bloom_enabled: ps.bool_or("bloom_enabled", d.bloom_enabled),
        bloom_radius: ps.float_or("bloom_radius", d.bloom_radius),
        bloom_weight: ps.float_or("bloom_weight", d.bloom_weight),
        glare_enabled: ps.bool_or("glare_enabled", d.glare_enabled),
        glare_amount: ps.float_or("glare_amount", d.glare_amount),
        glare_radius: ps.float_or("glare_radius", d.glare_radius),
        glare_blades: ps.int_or("glare_blades", 3).max(0) as u32,
        glare_threshold: ps.float_or("glare_threshold", d.glare_threshold),
        vignetting_enabled: ps.bool_or("vignetting_enabled", d.vignetting_enabled),
        vignetting_scale: ps.float_or("vignetting_scale", d.vignetting_scale),
        aberration_enabled: ps.bool_or("abberation_enabled", aberration_enabled),
        aberration_amount: ps.float_or("abberation_amount", aberration_amount),
        camera_response: ps.string_or("cameraresponse", "").to_string(),
        response: None,
    }
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::params::tests::film;
    use crate::film::params::FilmParams;
    use crate::lxs::{Entity, ParamValue};
    #[test]
    fn multiimage_tonemapper_is_honoured() {
        let mut ps = ParamSet::new();
        ps.add("tonemapper", ParamValue::String(vec!["reinhard".into()]));
        ps.add("reinhard_burn", ParamValue::Float(vec![3.0]));
        let mut e = Entity {
            kind: "multiimage".into(),
            params: ps,
            loc: Loc::default(),
        };
        let p = FilmParams::from_entity(Some(&e)).unwrap();
        assert_eq!(p.tonemap.kernel, Kernel::Reinhard);
        assert_eq!(p.tonemap.reinhard_burn, 3.0);
        // fleximage has no such key; tonemapkernel wins when both are given
        e.kind = "fleximage".into();
        let p = FilmParams::from_entity(Some(&e)).unwrap();
        assert_eq!(p.tonemap.kernel, Kernel::AutoLinear);
        e.kind = "multiimage".into();
        e.params
            .add("tonemapkernel", ParamValue::String(vec!["linear".into()]));
        let p = FilmParams::from_entity(Some(&e)).unwrap();
        assert_eq!(p.tonemap.kernel, Kernel::Linear);
        e.params = ParamSet::new();
        e.params
            .add("tonemapper", ParamValue::String(vec!["nonesuch".into()]));
        assert!(FilmParams::from_entity(Some(&e)).is_err());
    }

    #[test]
    fn false_colors_parameters() {
        let s = |v: &str| ParamValue::String(vec![v.into()]);
        let f = |v: f32| ParamValue::Float(vec![v]);
        let p = film(&[
            ("tonemapkernel", s("falsecolors")),
            ("false_method", s("log3")),
            ("false_colorscale", s("speos")),
            ("false_max", f(20.0)),
            ("false_min", f(0.5)),
        ])
        .unwrap();
        assert_eq!(p.tonemap.kernel, Kernel::FalseColors);
        let fc = p.tonemap.false_colors;
        assert_eq!(
            (fc.method, fc.scale),
            (FalseMethod::Log3, FalseScale::Speos)
        );
        assert_eq!((fc.min, fc.max), (0.5, 20.0));
        for m in FalseMethod::ALL {
            assert_eq!(FalseMethod::from_name(m.name()), Some(m));
            assert_eq!(FalseMethod::from_id(m as i32 as f64), m);
        }
        for c in FalseScale::ALL {
            assert_eq!(FalseScale::from_name(c.name()), Some(c));
            assert_eq!(FalseScale::from_id(c as i32 as f64), c);
        }
        // defaults: linear, std; the range only matters to the falsecolors kernel
        let d = FilmParams::default().tonemap.false_colors;
        assert_eq!(d, FalseColors::default());
        assert_eq!(
            (d.method, d.scale, d.min, d.max),
            (FalseMethod::Linear, FalseScale::Std, 0.0, 0.0)
        );
    }

    #[test]
    fn bad_false_colors_parameters_are_located_errors() {
        let at = |line| Loc {
            file: "scene.lxs".into(),
            line,
            col: 3,
        };
        // (name, value, line)
        type Given<'a> = Vec<(&'a str, ParamValue, u32)>;
        let with = |params: Given| {
            let mut ps = ParamSet::new();
            for (n, v, line) in params {
                ps.push(crate::lxs::Param::new(n, v, at(line)));
            }
            FilmParams::from_entity(Some(&Entity {
                kind: "fleximage".into(),
                params: ps,
                loc: at(1),
            }))
        };
        let s = |v: &str| ParamValue::String(vec![v.into()]);
        let f = |v: f32| ParamValue::Float(vec![v]);
        let k = || ("tonemapkernel", s("falsecolors"), 2);
        let cases: Vec<(Given, u32, &str)> = vec![
            (vec![k(), ("false_method", s("log2"), 5)], 5, "false_method"),
            (
                vec![k(), ("false_colorscale", s("jet"), 6)],
                6,
                "false_colorscale",
            ),
            (
                vec![k(), ("false_max", f(1.0), 7), ("false_min", f(1.0), 8)],
                7,
                "false_max",
            ),
            (
                vec![k(), ("false_max", f(1.0), 7), ("false_min", f(2.0), 8)],
                7,
                "false_max",
            ),
            (vec![k(), ("false_min", f(2.0), 8)], 8, "false_min"),
            (vec![k()], 1, "false_max"),
        ];
        for (params, line, name) in cases {
            let e = with(params).unwrap_err().to_string();
            assert!(e.contains(&format!("scene.lxs:{line}:")), "{e}");
            assert!(e.contains(name), "{e}");
        }
        // an unknown name is refused whatever the kernel; the range only with falsecolors
        assert!(with(vec![("false_method", s("log2"), 5)]).is_err());
        assert!(with(vec![("false_max", f(-1.0), 5)]).is_ok());
    }

    #[test]
    fn effects_are_read_with_luxrenders_spelling() {
        let p = film(&[
            ("bloom_enabled", ParamValue::Bool(vec![true])),
            ("bloom_radius", ParamValue::Float(vec![0.1])),
            ("glare_enabled", ParamValue::Bool(vec![true])),
            ("glare_blades", ParamValue::Integer(vec![6])),
            ("vignetting_enabled", ParamValue::Bool(vec![true])),
            ("abberation_enabled", ParamValue::Bool(vec![true])),
            ("abberation_amount", ParamValue::Float(vec![0.02])),
        ])
        .unwrap();
        let e = &p.tonemap.effects;
        assert!(e.bloom_applies() && e.glare_applies());
        assert!(e.vignetting_applies() && e.aberration_applies());
        assert_eq!((e.bloom_radius, e.bloom_weight), (0.1, 0.25));
        assert_eq!(e.glare_blades, 6);
        assert_eq!(e.aberration_amount, 0.02);
        let d = FilmParams::default();
        let e = &d.tonemap.effects;
        assert!(!e.bloom_applies() && !e.glare_applies());
        assert!(!e.vignetting_applies() && !e.aberration_applies());
    }
}
