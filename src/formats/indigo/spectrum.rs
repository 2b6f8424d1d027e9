//! Indigo spectra (`uniform`, `rgb`, `blackbody`, `peak`, `regular_tabulated`, `xyz`) turned
//! into the RGB values LuxRender parameters take, once, at import.
//!
//! ```text
//! <spectrum element> --S(λ) sampled 360..830 nm--> Σ S(λ) w_c(λ) / Σ w_c(λ) --> [r, g, b]
//! ```
//!
//! `w_c` are the linear-sRGB colour matching functions (the CIE 1931 observer through the
//! XYZ→sRGB matrix). Dividing by their sums makes the map exact for flat spectra: `uniform v`
//! gives `(v, v, v)` whatever the scale, so reflectances stay reflectances and emitters keep
//! Indigo's spectral radiance unit (W m⁻³ sr⁻¹) as the LuxRender `L` value; a saturated
//! spectrum can fall outside the sRGB gamut, and its negative channels are clamped to 0.
//!
//! `rgb` values are raised to `gamma` (Indigo's rule; 2.2 when not given, the value its
//! reference recommends). `blackbody` is Planck's law in W m⁻³ sr⁻¹ times `gain`; `peak` is
//! `peak_value` over [peak_min, peak_min + peak_width) nm and `base_value` elsewhere;
//! `regular_tabulated` interpolates its values linearly between `start_wavelength` and
//! `end_wavelength` (metres) and is 0 outside. `xyz` (light layer scales) is its triple times
//! `gain`, kept as a per-channel scale.

use super::ctx::{err, Ctx};
use super::node::Elem;
use crate::lxs::{LxsError, LxsErrorKind};
use crate::spectrum::cie;
use std::sync::OnceLock;

/// Element names that hold a spectrum.
pub const KINDS: [&str; 6] = [
    "uniform",
    "rgb",
    "blackbody",
    "peak",
    "regular_tabulated",
    "xyz",
];

/// XYZ → linear sRGB (D65 primaries).
const XYZ_TO_SRGB: [[f64; 3]; 3] = [
    [3.2406, -1.5372, -0.4986],
    [-0.9689, 1.8758, 0.0415],
    [0.0557, -0.2040, 1.0570],
];

const LAMBDA_MIN: u32 = 360;
const LAMBDA_MAX: u32 = 830;

/// (λ in nm, [w_r, w_g, w_b]) at 1 nm steps, and the sums of each w.
type Weights = (Vec<(f64, [f64; 3])>, [f64; 3]);

fn weights() -> &'static Weights {
    static W: OnceLock<Weights> = OnceLock::new();
    W.get_or_init(|| {
        let mut v = Vec::new();
        let mut sum = [0.0; 3];
        for nm in LAMBDA_MIN..=LAMBDA_MAX {
            let c = cie::cmf(nm as f32).map(f64::from);
            let mut w = [0.0; 3];
            for (k, wk) in w.iter_mut().enumerate() {
                *wk =
                    XYZ_TO_SRGB[k][0] * c[0] + XYZ_TO_SRGB[k][1] * c[1] + XYZ_TO_SRGB[k][2] * c[2];
                sum[k] += *wk;
            }
            v.push((nm as f64, w));
        }
        (v, sum)
    })
}

/// The RGB of a spectrum given as a function of the wavelength in nm.
pub fn project(s: impl Fn(f64) -> f64) -> [f64; 3] {
    let (w, sum) = weights();
    let mut acc = [0.0; 3];
    for (nm, wc) in w {
        let v = s(*nm);
        for k in 0..3 {
            acc[k] += v * wc[k];
        }
    }
    [0, 1, 2].map(|k| (acc[k] / sum[k]).max(0.0))
}

/// Planck's law: spectral radiance in W m⁻³ sr⁻¹ at `nm` nanometres, `t` kelvin.
pub fn planck(nm: f64, t: f64) -> f64 {
    const H: f64 = 6.626_070_15e-34;
    const C: f64 = 2.997_924_58e8;
    const K: f64 = 1.380_649e-23;
    let l = nm * 1e-9;
    let x = H * C / (l * K * t);
    if x > 700.0 {
        return 0.0;
    }
    2.0 * H * C * C / l.powi(5) / x.exp_m1()
}

/// A number child, `default` when absent (required when `default` is None).
fn value(e: &Elem, ctx: &Ctx, name: &str, default: Option<f64>) -> Result<f64, LxsError> {
    match (e.child_num(ctx, name)?, default) {
        (Some(v), _) => Ok(v),
        (None, Some(d)) => Ok(d),
        (None, None) => e.need(ctx, name)?.num(ctx),
    }
}

/// Reads the spectrum element `e` (one of [`KINDS`]).
pub fn read(e: &Elem, ctx: &Ctx) -> Result<[f64; 3], LxsError> {
    e.mark_used();
    match e.name.as_str() {
        "uniform" => {
            let v = e.need(ctx, "value")?.num(ctx)?;
            Ok([v; 3])
        }
        "rgb" => {
            let c = e.need(ctx, "rgb")?.vec3(ctx)?;
            let gamma = e.child_num_or(ctx, "gamma", 2.2)?;
            if gamma <= 0.0 {
                return Err(err(
                    LxsErrorKind::InvalidValue,
                    &e.loc,
                    format!("rgb gamma must be > 0, got {gamma}"),
                ));
            }
            Ok(c.map(|v| v.signum() * v.abs().powf(gamma)))
        }
        "blackbody" => {
            let t = e.need(ctx, "temperature")?.positive(ctx)?;
            let gain = value(e, ctx, "gain", Some(1.0))?;
            Ok(project(|nm| planck(nm, t)).map(|v| v * gain))
        }
        "peak" => {
            let min = value(e, ctx, "peak_min", None)?;
            let width = e.need(ctx, "peak_width")?.positive(ctx)?;
            let base = value(e, ctx, "base_value", Some(0.0))?;
            let peak = value(e, ctx, "peak_value", None)?;
            Ok(project(|nm| {
                if nm >= min && nm < min + width {
                    peak
                } else {
                    base
                }
            }))
        }
        "regular_tabulated" => tabulated(e, ctx),
        "xyz" => {
            // Used for light layer scales: the triple times gain, as a per-channel scale.
            let xyz = e.need(ctx, "xyz")?.vec3(ctx)?;
            let gain = e.child_num_or(ctx, "gain", 1.0)?;
            Ok(xyz.map(|v| v * gain))
        }
        other => Err(err(
            LxsErrorKind::Unsupported,
            &e.loc,
            format!("unknown spectrum <{other}> (known: {})", KINDS.join(", ")),
        )),
    }
}

fn tabulated(e: &Elem, ctx: &Ctx) -> Result<[f64; 3], LxsError> {
    let start = e.need(ctx, "start_wavelength")?.positive(ctx)? * 1e9;
    let end = e.need(ctx, "end_wavelength")?.positive(ctx)? * 1e9;
    let values_elem = e.need(ctx, "values")?;
    let values = values_elem.nums(ctx)?;
    if let Some(n) = e.child_int(ctx, "num_values")? {
        if n < 0 || n as usize != values.len() {
            return Err(err(
                LxsErrorKind::WrongValueCount,
                &values_elem.loc,
                format!("num_values is {n} but {} values are given", values.len()),
            ));
        }
    }
    if values.len() < 2 || end <= start {
        return Err(err(
            LxsErrorKind::InvalidValue,
            &e.loc,
            "regular_tabulated needs at least 2 values and end_wavelength > start_wavelength",
        ));
    }
    let step = (end - start) / (values.len() - 1) as f64;
    Ok(project(|nm| {
        if nm < start || nm > end {
            return 0.0;
        }
        let x = (nm - start) / step;
        let i = (x.floor() as usize).min(values.len() - 2);
        let t = x - i as f64;
        values[i] * (1.0 - t) + values[i + 1] * t
    }))
}

/// The spectrum held by `parent`: its first child named in [`KINDS`] (also inside a
/// `<spectrum>` wrapper). None when there is none.
pub fn find<'a>(parent: &'a Elem, ctx: &Ctx) -> Option<&'a Elem> {
    if let Some(s) = parent.child(ctx, "spectrum") {
        return find(s, ctx);
    }
    parent
        .children
        .iter()
        .find(|c| KINDS.contains(&c.name.as_str()))
}

/// The RGB of the spectrum `parent` holds (an error naming `parent` when it holds none).
pub fn of(parent: &Elem, ctx: &Ctx) -> Result<[f64; 3], LxsError> {
    match find(parent, ctx) {
        Some(s) => read(s, ctx),
        None => Err(err(
            LxsErrorKind::WrongValueCount,
            &parent.loc,
            format!("<{}> needs a spectrum ({})", parent.name, KINDS.join(", ")),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::indigo::xml;
    use crate::lxs::ParseOptions;
    use std::path::Path;

    fn rgb_of(text: &str) -> Result<[f64; 3], LxsError> {
        let ctx = Ctx::new(Path::new("t.igs"), &ParseOptions::default());
        let p = xml::parse(text.as_bytes(), &"t.igs".into()).unwrap();
        of(&p.root, &ctx)
    }

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() <= tol * b[k].abs().max(1e-12))
    }

    #[test]
    fn flat_spectra_are_exact_grey() {
        assert_eq!(
            rgb_of("<c><uniform><value>0.3</value></uniform></c>").unwrap(),
            [0.3; 3]
        );
        let peak = rgb_of(
            "<c><peak><peak_min>300</peak_min><peak_width>600</peak_width><base_value>0</base_value><peak_value>7</peak_value></peak></c>",
        )
        .unwrap();
        assert!(close(peak, [7.0; 3], 1e-9), "{peak:?}");
        let tab = rgb_of(
            "<c><regular_tabulated><start_wavelength>3e-7</start_wavelength><end_wavelength>9e-7</end_wavelength><num_values>3</num_values><values>2 2 2</values></regular_tabulated></c>",
        )
        .unwrap();
        assert!(close(tab, [2.0; 3], 1e-9), "{tab:?}");
    }

    #[test]
    fn rgb_applies_gamma_and_spectra_have_the_expected_hue() {
        let c = rgb_of("<c><rgb><rgb>0.5 1 0</rgb><gamma>2</gamma></rgb></c>").unwrap();
        assert_eq!(c, [0.25, 1.0, 0.0]);
        // A red-only table is red; a 2000 K blackbody is orange, a 10000 K one bluish.
        let red = rgb_of(
            "<c><regular_tabulated><start_wavelength>6.2e-7</start_wavelength><end_wavelength>7e-7</end_wavelength><num_values>2</num_values><values>1 1</values></regular_tabulated></c>",
        )
        .unwrap();
        assert!(red[0] > 5.0 * red[1].max(red[2]), "{red:?}");
        let warm =
            rgb_of("<c><blackbody><temperature>2000</temperature><gain>1</gain></blackbody></c>")
                .unwrap();
        assert!(warm[0] > warm[1] && warm[1] > warm[2], "{warm:?}");
        let cold = rgb_of(
            "<c><spectrum><blackbody><temperature>10000</temperature></blackbody></spectrum></c>",
        )
        .unwrap();
        assert!(cold[2] > cold[0], "{cold:?}");
        // Planck at 6500 K, 500 nm: 2hc²/λ⁵ / (e^(hc/λkT) - 1) = 3.81e15 / 83.0 = 4.59e13 W m^-3 sr^-1.
        assert!((planck(500.0, 6500.0) / 4.59e13 - 1.0).abs() < 0.01);
    }

    #[test]
    fn malformed_spectra_are_located_errors() {
        for bad in [
            "<c/>",
            "<c><rgb><rgb>1 2</rgb></rgb></c>",
            "<c><blackbody><temperature>-5</temperature></blackbody></c>",
            "<c><regular_tabulated><start_wavelength>4e-7</start_wavelength><end_wavelength>7e-7</end_wavelength><num_values>3</num_values><values>1 2</values></regular_tabulated></c>",
            "<c><uniform><value>x</value></uniform></c>",
        ] {
            let e = rgb_of(bad).unwrap_err();
            assert_eq!(e.loc.file.as_ref(), "t.igs", "{bad}");
            assert!(e.loc.line >= 1);
        }
    }
}
