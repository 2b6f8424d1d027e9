//! Camera response functions (the Film's `cameraresponse`): a film or sensor's measured
//! response curves, either one of LuxRender 1.x's built-in presets ([`super::crf_presets`]) or
//! a CRF file in the DoRF text format as LuxRender 1.x reads it, applied to the RGB image after
//! the colour space conversion.
//!
//! Resolution, as LuxRender 1.x's CameraResponse does it: a preset name first (exact,
//! case-sensitive), then a file through the scene's files (confined to the bundle on the farm).
//! A name that is neither is an error naming both failures and the closest preset, except
//! `"None"` (LuxBlend's "no preset" value; LuxRender too finds neither and applies nothing).
//! An empty name means no response.
//!
//! File format: for each channel a block
//! `<name>Red` (or `Green`, `Blue`; the name glued to the channel word), a line starting with
//! `graph`, a line `I = <inputs>` and a line `B = <outputs>` (the numbers may also start on the
//! line after the `=`). The first complete Red, Green and Blue blocks of the first name are
//! used; a file with only Red is monochrome (applied to the luminance), as are the Agfapan
//! presets. For presets and files alike, as LuxRender does, the gamma the curves have built in
//! is estimated (a Gauss-Newton fit of B = I^γ over the luminance of the grey inputs, each
//! distinct input once) and taken out (B^(1/γ)), so that the film's `gamma` is not applied
//! twice. Mapping interpolates linearly and holds the end values outside the inputs.

use super::crf_presets;
use crate::fileio::{FileError, SceneFiles};

/// Largest CRF file read (bytes) and points per curve.
pub const MAX_CRF_FILE: u64 = 4 << 20;
pub const MAX_POINTS: usize = 1 << 16;

/// Response curves: inputs I and outputs B per channel (one curve: monochrome).
#[derive(Clone, Debug, PartialEq)]
pub struct CameraResponse {
    pub name: String,
    /// Red, green, blue curves, or only the first for a monochrome response.
    pub curves: Vec<(Vec<f32>, Vec<f32>)>,
}

use crf_presets::Curve;

const LUM: [f32; 3] = [0.212_671, 0.715_160, 0.072_169];

impl CameraResponse {
    /// Parses a CRF file's text.
    pub fn parse(text: &str) -> Result<CameraResponse, String> {
        let lines: Vec<&str> = text.lines().map(str::trim).collect();
        let mut name: Option<String> = None;
        let mut found: [Option<(Vec<f32>, Vec<f32>)>; 3] = [None, None, None];
        let mut i = 0;
        while i < lines.len() {
            let Some((n, ch)) = channel_header(lines[i]) else {
                i += 1;
                continue;
            };
            let Some((curve, next)) = block(&lines, i + 1) else {
                i += 1;
                continue;
            };
            i = next;
            match &name {
                None => name = Some(n.to_string()),
                Some(first) if first != n => break,
                _ => {}
            }
            if found[ch].is_none() {
                found[ch] = Some(curve);
            }
            if found.iter().all(Option::is_some) {
                break;
            }
        }
        let [Some(r), g, b] = found else {
            return Err("no valid Red response curve".into());
        };
        let curves = match (g, b) {
            (Some(g), Some(b)) => vec![r, g, b],
            _ => vec![r],
        };
        Ok(CameraResponse::from_curves(
            name.unwrap_or_default(),
            curves,
        ))
    }

    /// A response from measured curves (Red, Green, Blue or Red alone), built-in gamma taken out.
    pub fn from_curves(name: String, curves: Vec<Curve>) -> CameraResponse {
        let mut crf = CameraResponse { name, curves };
        crf.remove_gamma();
        crf
    }

    /// LuxRender's built-in preset `name` (`Ok(None)` when `name` is no preset).
    pub fn preset(name: &str) -> Result<Option<CameraResponse>, String> {
        let curves = crf_presets::curves(name)?;
        Ok(curves.map(|c| CameraResponse::from_curves(name.to_string(), c)))
    }

    /// Resolves a `cameraresponse` value as LuxRender 1.x does: a built-in preset by name, else
    /// a CRF file through the scene's files. `Ok(None)`: no response (`""`, or `"None"` when no
    /// file has that name).
    pub fn resolve(files: &SceneFiles, name: &str) -> Result<Option<CameraResponse>, String> {
        if name.is_empty() {
            return Ok(None);
        }
        if let Some(crf) = CameraResponse::preset(name)? {
            return Ok(Some(crf));
        }
        match CameraResponse::read(files, name) {
            Ok(crf) => Ok(Some(crf)),
            Err(Unread::File(e @ FileError::NotFound { .. })) if name == "None" => {
                tracing::debug!("camera response \"None\": {e}; no response applied");
                Ok(None)
            }
            Err(Unread::File(e)) => Err(unknown(name, &e)),
            Err(Unread::Parse(e)) => Err(e),
        }
    }

    /// Reads a CRF file through the scene's files (confined to the bundle on the farm).
    pub fn read(files: &SceneFiles, name: &str) -> Result<CameraResponse, Unread> {
        let text = files
            .read_small_text(name, MAX_CRF_FILE)
            .map_err(Unread::File)?;
        CameraResponse::parse(&text)
            .map_err(|e| Unread::Parse(format!("camera response \"{name}\": {e}")))
    }

    /// Maps a linear RGB colour through the response.
    pub fn map(&self, rgb: [f32; 3]) -> [f32; 3] {
        match &self.curves[..] {
            [r, g, b] => [apply(rgb[0], r), apply(rgb[1], g), apply(rgb[2], b)],
            [m, ..] => {
                let y = rgb[0] * LUM[0] + rgb[1] * LUM[1] + rgb[2] * LUM[2];
                [apply(y, m); 3]
            }
            [] => rgb,
        }
    }

    fn remove_gamma(&mut self) {
        let mut inputs: Vec<f32> = self
            .curves
            .iter()
            .flat_map(|c| c.0.iter().copied())
            .collect();
        inputs.sort_by(f32::total_cmp);
        inputs.dedup();
        let outputs: Vec<f32> = inputs
            .iter()
            .map(|&x| {
                let c = self.map([x; 3]);
                c[0] * LUM[0] + c[1] * LUM[1] + c[2] * LUM[2]
            })
            .collect();
        let gamma = estimate_gamma(&inputs, &outputs);
        if gamma.is_finite() && gamma > 0.0 {
            for (_, b) in &mut self.curves {
                b.iter_mut().for_each(|v| *v = v.max(0.0).powf(1.0 / gamma));
            }
        }
    }
}

/// Why a CRF file gave no response: it could not be read, or its text is no response.
#[derive(Debug)]
pub enum Unread {
    File(FileError),
    Parse(String),
}

impl std::fmt::Display for Unread {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Unread::File(e) => write!(f, "camera response {e}"),
            Unread::Parse(e) => f.write_str(e),
        }
    }
}

/// The error for a name that is neither a preset nor a readable file.
fn unknown(name: &str, file: &FileError) -> String {
    let hint = crf_presets::closest(name)
        .map(|p| format!("; did you mean the preset \"{p}\"?"))
        .unwrap_or_else(|| "; presets are LuxRender's film names, e.g. \"Advantix_100CD\"".into());
    format!(
        "camera response \"{name}\" is neither one of LuxRender's built-in presets nor a \
         readable file ({file}){hint}"
    )
}

/// `<name>Red|Green|Blue` with a non-empty name: the name and the channel index.
fn channel_header(line: &str) -> Option<(&str, usize)> {
    let last = line.split_whitespace().last()?;
    ["Red", "Green", "Blue"]
        .iter()
        .enumerate()
        .find_map(|(i, ch)| {
            last.strip_suffix(ch)
                .filter(|n| !n.is_empty())
                .map(|n| (n, i))
        })
}

/// A `graph` line, then `I = ...` and `B = ...` from line `at`: the curve (same non-zero
/// length, at most MAX_POINTS) and the line after it.
fn block(lines: &[&str], at: usize) -> Option<(Curve, usize)> {
    let graph = lines.get(at)?;
    if !graph.starts_with("graph") || graph.len() <= "graph".len() {
        return None;
    }
    let (i, next) = values(lines, at + 1, 'I')?;
    let (b, next) = values(lines, next, 'B')?;
    (i.len() == b.len() && !i.is_empty() && i.len() <= MAX_POINTS).then_some(((i, b), next))
}

/// `<key> = numbers` at line `at` (numbers possibly on the next non-empty line).
fn values(lines: &[&str], at: usize, key: char) -> Option<(Vec<f32>, usize)> {
    let rest = lines
        .get(at)?
        .strip_prefix(key)?
        .trim_start()
        .strip_prefix('=')?
        .trim();
    let (text, next) = if rest.is_empty() {
        let j = (at + 1..lines.len()).find(|&j| !lines[j].is_empty())?;
        (lines[j], j + 1)
    } else {
        (rest, at + 1)
    };
    let v: Vec<f32> = text
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|w| !w.is_empty())
        .map(|w| w.parse::<f32>().ok().filter(|x| x.is_finite()))
        .collect::<Option<_>>()?;
    Some((v, next))
}

/// Piecewise linear lookup with the ends held.
fn apply(x: f32, (from, to): &(Vec<f32>, Vec<f32>)) -> f32 {
    let (Some(&f0), Some(&f1), Some(&t0), Some(&t1)) =
        (from.first(), from.last(), to.first(), to.last())
    else {
        return x;
    };
    if x.is_nan() || x <= f0 {
        return t0;
    }
    if x >= f1 {
        return t1;
    }
    let k = from.partition_point(|&v| v <= x).clamp(1, from.len() - 1);
    let (x1, x2, y1, y2) = (from[k - 1], from[k], to[k - 1], to[k]);
    if x2 > x1 {
        y1 + (x - x1) / (x2 - x1) * (y2 - y1)
    } else {
        y2
    }
}

/// γ of y = x^γ by Gauss-Newton from γ = 1 (inputs below 1e-12 skipped).
fn estimate_gamma(x: &[f32], y: &[f32]) -> f32 {
    let mut gamma = 1.0f64;
    let mut last_ssr = 1e30f64;
    for _ in 0..100 {
        let (mut ssr, mut jtr, mut jtj) = (0.0f64, 0.0f64, 0.0f64);
        for (&xi, &yi) in x.iter().zip(y) {
            if xi < 1e-12 {
                continue;
            }
            let lx = f64::from(xi).ln();
            let xg = (gamma * lx).exp();
            let r = f64::from(yi) - xg;
            let j = lx * xg;
            ssr += r * r;
            jtr += j * r;
            jtj += j * j;
        }
        if (ssr - last_ssr).abs() < 1e-6 || jtj == 0.0 {
            break;
        }
        let delta = jtr / jtj;
        if !delta.is_finite() || delta.abs() < 1e-9 {
            break;
        }
        gamma += delta;
        last_ssr = ssr;
    }
    gamma as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Curves B = I^(1/2.2) sampled at 0, 0.25, 0.5, 1 (a pure gamma film) and a distinct blue.
    fn gamma_file() -> String {
        let i = "0 0.25 0.5 1";
        let b: Vec<String> = [0.0f32, 0.25, 0.5, 1.0]
            .iter()
            .map(|x| format!("{}", x.powf(1.0 / 2.2)))
            .collect();
        let b = b.join(" ");
        format!(
            "TestfilmRed\ngraph: #1\nI = {i}\nB = {b}\n\nTestfilmGreen\ngraph: #2\nI =\n{i}\nB = {b}\n\
             TestfilmBlue\ngraph: #3\nI = {i}\nB = 0 0.5 0.75 1\n"
        )
    }

    #[test]
    fn parses_and_removes_the_built_in_gamma() {
        let crf = CameraResponse::parse(&gamma_file()).unwrap();
        assert_eq!(crf.name, "Testfilm");
        assert_eq!(crf.curves.len(), 3);
        // The red curve is x^(1/2.2): once its gamma is taken out it is close to linear.
        let m = crf.map([0.5, 0.25, 0.0]);
        assert!((m[0] - 0.5).abs() < 0.06, "{m:?}");
        assert!((m[1] - 0.25).abs() < 0.06, "{m:?}");
        // ends held: below the first input and above the last
        assert_eq!(crf.map([-1.0, 2.0, 0.0])[0], 0.0);
        assert!((crf.map([-1.0, 2.0, 0.0])[1] - 1.0).abs() < 1e-6);
    }

    #[test]
    fn linear_response_maps_at_chosen_values() {
        // A linear film keeps its curves (γ = 1): 0.3 -> 0.3 on red, and blue's own curve
        // 0 -> 0, 0.5 -> 0.25, 1 -> 1 interpolated: 0.75 -> 0.625.
        let text = "LinRed\ngraph x\nI = 0 0.5 1\nB = 0 0.5 1\n\
                    LinGreen\ngraph x\nI = 0 0.5 1\nB = 0 0.5 1\n\
                    LinBlue\ngraph x\nI = 0 0.5 1\nB = 0 0.25 1\n";
        let crf = CameraResponse::parse(text).unwrap();
        let m = crf.map([0.3, 0.5, 0.75]);
        assert!((m[0] - 0.3).abs() < 0.02, "{m:?}");
        assert!(m[2] < 0.75, "{m:?}");
    }

    #[test]
    fn monochrome_and_bad_files() {
        let mono = CameraResponse::parse("BwRed\ngraph x\nI = 0 1\nB = 0 1\n").unwrap();
        assert_eq!(mono.curves.len(), 1);
        let m = mono.map([1.0, 0.0, 0.0]);
        assert!((m[0] - 0.212_671).abs() < 1e-4 && m[0] == m[2], "{m:?}");
        assert!(CameraResponse::parse("nothing here").is_err());
        assert!(CameraResponse::parse("XRed\ngraph x\nI = 0 1\nB = 0\n").is_err());
        let dir = tempfile::tempdir().unwrap();
        let files = SceneFiles::confined(dir.path(), dir.path()).unwrap();
        assert!(CameraResponse::read(&files, "../x.crf").is_err());
        assert!(CameraResponse::read(&files, "/etc/passwd").is_err());
    }

    /// Inputs 3/1023 and 10/1023 of every preset, and Advantix_100CD's red outputs there, as
    /// cameraresponsefunctions.h writes them.
    const I3: f32 = 2.932551e-3;
    const I4: f32 = 3.910068e-3;
    const I10: f32 = 9.775171e-3;
    const ADVANTIX_RED_B3: f32 = 2.818739e-2;
    const ADVANTIX_RED_B10: f32 = 7.222205e-2;

    #[test]
    fn preset_maps_its_table_with_the_gamma_taken_out() {
        let crf = CameraResponse::preset("Advantix_100CD").unwrap().unwrap();
        assert_eq!(crf.curves.len(), 3);
        let m3 = crf.map([I3, 0.0, 0.0])[0];
        let m10 = crf.map([I10, 0.0, 0.0])[0];
        // at grid inputs the output is the table's B^(1/γ), one γ for all points
        let inv3 = m3.ln() / ADVANTIX_RED_B3.ln();
        let inv10 = m10.ln() / ADVANTIX_RED_B10.ln();
        assert!((inv3 - inv10).abs() < 1e-4, "{inv3} {inv10}");
        // a film's curve has a built-in gamma near 1/2 (B = 0.072 at I = 0.0098)
        assert!((1.5..3.0).contains(&inv3), "1/γ = {inv3}");
        // linear between grid points
        let m4 = crf.map([I4, 0.0, 0.0])[0];
        let mid = crf.map([0.5 * (I3 + I4), 0.0, 0.0])[0];
        assert!((mid - 0.5 * (m3 + m4)).abs() < 1e-6, "{mid} {m3} {m4}");
        // channels differ: the green curve is not the red one
        assert_ne!(crf.map([I10; 3])[0], crf.map([I10; 3])[1]);
    }

    #[test]
    fn monochrome_preset_maps_luminance() {
        let crf = CameraResponse::preset("Agfapan_apx_100CD")
            .unwrap()
            .unwrap();
        assert_eq!(crf.curves.len(), 1);
        let m = crf.map([0.4, 0.1, 0.2]);
        assert!(m[0] == m[1] && m[1] == m[2], "{m:?}");
        let y = 0.4 * LUM[0] + 0.1 * LUM[1] + 0.2 * LUM[2];
        assert_eq!(m[0], crf.map([y; 3])[0]);
    }

    #[test]
    fn every_preset_resolves() {
        let dir = tempfile::tempdir().unwrap();
        let files = SceneFiles::confined(dir.path(), dir.path()).unwrap();
        for name in crf_presets::NAMES {
            let crf = CameraResponse::resolve(&files, name).unwrap().unwrap();
            assert_eq!(crf.name, name);
            let m = crf.map([0.18; 3]);
            assert!(
                m.iter().all(|v| v.is_finite() && *v > 0.0 && *v < 1.0),
                "{name} {m:?}"
            );
        }
    }

    #[test]
    fn presets_come_before_files_as_in_luxrender() {
        let dir = tempfile::tempdir().unwrap();
        let linear = "LinRed\ngraph x\nI = 0 1\nB = 0 1\n";
        std::fs::write(dir.path().join("Gold_200CD"), linear).unwrap();
        std::fs::write(dir.path().join("None"), linear).unwrap();
        std::fs::write(dir.path().join("lin.crf"), linear).unwrap();
        let files = SceneFiles::confined(dir.path(), dir.path()).unwrap();
        let resolved = |n: &str| CameraResponse::resolve(&files, n).unwrap();
        // a preset's name is the preset even when a file has that name
        let gold = resolved("Gold_200CD").unwrap();
        assert_eq!(gold, CameraResponse::preset("Gold_200CD").unwrap().unwrap());
        assert_eq!(gold.curves.len(), 3);
        // other names are files; "None" too when such a file exists
        assert_eq!(resolved("lin.crf").unwrap().name, "Lin");
        assert_eq!(resolved("None").unwrap().name, "Lin");
        assert_eq!(resolved(""), None);
        // without the file, "None" (LuxBlend's value for no preset) is no response
        let empty = tempfile::tempdir().unwrap();
        let nothing = SceneFiles::confined(empty.path(), empty.path()).unwrap();
        assert_eq!(CameraResponse::resolve(&nothing, "None").unwrap(), None);
    }

    #[test]
    fn unknown_names_are_errors_that_suggest_a_preset() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("bad.crf"), "no curves").unwrap();
        let files = SceneFiles::confined(dir.path(), dir.path()).unwrap();
        let e = CameraResponse::resolve(&files, "advantix_100cd").unwrap_err();
        assert!(e.contains("neither") && e.contains("not found"), "{e}");
        assert!(
            e.contains("did you mean the preset \"Advantix_100CD\""),
            "{e}"
        );
        let e = CameraResponse::resolve(&files, "film.crf").unwrap_err();
        assert!(e.contains("\"film.crf\"") && e.contains("e.g."), "{e}");
        // outside the bundle: still neither
        let e = CameraResponse::resolve(&files, "../Portra_800.crf").unwrap_err();
        assert!(e.contains("leaves the scene's directory"), "{e}");
        // a readable file that is no response says so
        let e = CameraResponse::resolve(&files, "bad.crf").unwrap_err();
        assert!(e.contains("no valid Red response curve"), "{e}");
    }
}
