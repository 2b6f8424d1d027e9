//! `tabulateddata` texture (colour): a spectrum read from `filename`, as LuxRender reads it:
//! an optional header `wavelength: <eV|um|cm-1|nm> data: <tag>` (nm when absent), then lines
//! of two numbers (wavelength, value) separated by blanks, `,` or `;`; unreadable lines before
//! the data are skipped and the first one after it ends the data. Descending wavelengths are
//! reversed. The spectrum is read as a reflectance (tabulated data describes materials). Like
//! LuxRender, a file with fewer than two samples or none in 380–720 nm gives a flat spectrum
//! of 1, with a warning; a missing or unreadable file is an error.

use super::spectral::SpectralTex;
use super::{param_loc, read_bounded, TexNode, TextureError, TextureSet};
use crate::lxs::TextureDesc;
use crate::spectrum::spd::{Spd, MAX_SAMPLES};

/// Largest data file read (bytes).
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// Wavelength units of the header, as conversions to nm.
fn unit(name: &str) -> Option<fn(f32) -> f32> {
    Some(match name {
        "eV" => |ev| 4.135667e-15 * 299_792_458.0 * 1e9 / ev,
        "um" => |um| um * 1000.0,
        "cm-1" => |k| 1e7 / k,
        "nm" => |nm| nm,
        _ => return None,
    })
}

/// The unit of a `wavelength: UNIT ... data: TAG` header line.
fn header(line: &str) -> Option<&str> {
    let rest = line.split_once("wavelength:")?.1.trim_start();
    let unit_end = rest.find(|c: char| c.is_whitespace() || c == ',' || c == ';')?;
    let (u, tail) = rest.split_at(unit_end);
    tail.contains("data:").then_some(u)
}

/// Two numbers at the start of a line.
fn sample(line: &str) -> Option<(f32, f32)> {
    let mut it = line
        .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
        .filter(|s| !s.is_empty());
    let a = it.next()?.parse::<f32>().ok()?;
    let b = it.next()?.parse::<f32>().ok()?;
    (a >= 0.0 && a.is_finite() && b.is_finite()).then_some((a, b))
}

/// Parses the text of a data file into (wavelengths in nm, values).
pub fn parse(text: &str) -> Result<(Vec<f32>, Vec<f32>), String> {
    let mut to_nm: Option<fn(f32) -> f32> = None;
    let (mut wl, mut v) = (Vec::new(), Vec::new());
    let mut in_data = false;
    for line in text.lines() {
        if !in_data {
            if let Some(u) = header(line) {
                to_nm = Some(unit(u).ok_or_else(|| format!("unknown wavelength unit \"{u}\""))?);
                in_data = true;
                continue;
            }
        }
        match sample(line) {
            Some((a, b)) => {
                in_data = true;
                if wl.len() >= MAX_SAMPLES {
                    return Err(format!("more than {MAX_SAMPLES} samples"));
                }
                let conv = to_nm.unwrap_or(|nm| nm);
                wl.push(conv(a));
                v.push(b);
            }
            None if in_data && !wl.is_empty() => break,
            None => {}
        }
    }
    if wl.len() >= 2 && wl[0] > wl[wl.len() - 1] {
        wl.reverse();
        v.reverse();
    }
    Ok((wl, v))
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let p = &t.entity.params;
    let loc = param_loc(p, "filename", &t.entity.loc);
    let name = p.string_or("filename", "").to_string();
    let io_err = |message: String| TextureError::Image {
        loc: loc.clone(),
        path: name.clone(),
        message,
    };
    let text = read_bounded(&set.ctx.files, &name, MAX_FILE_BYTES).map_err(io_err)?;
    let (wl, v) = parse(&text).map_err(io_err)?;
    let usable = wl.len() >= 2
        && wl.first().is_some_and(|&a| a <= 720.0)
        && wl.last().is_some_and(|&b| b >= 380.0);
    let spd = if usable {
        Spd::new(wl, v).map_err(io_err)?
    } else {
        set.warn(
            &loc,
            format!(
                "tabulateddata \"{}\": fewer than two samples in 380-720 nm: a flat spectrum of 1, \
                 as LuxRender uses",
                name
            ),
        );
        Spd::constant(1.0)
    };
    Ok(TexNode::Spectral(SpectralTex::reflectance(spd)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_units_separators_and_order() {
        let (wl, v) =
            parse("some title\nwavelength: um data: R\n0.7, 0.5\n0.4;0.25\n\nignored 1 2\n")
                .unwrap();
        assert_eq!(wl, vec![400.0, 700.0]);
        assert_eq!(v, vec![0.25, 0.5]);
        let (wl, _) = parse("400 1\n500 2\n").unwrap();
        assert_eq!(wl, vec![400.0, 500.0]);
        let (wl, _) = parse("wavelength: eV data: x\n2 1\n").unwrap();
        assert!((wl[0] - 619.92).abs() < 0.01, "{wl:?}");
        let (wl, _) = parse("wavelength: cm-1 data: x\n20000 1\n").unwrap();
        assert_eq!(wl, vec![500.0]);
        assert!(parse("wavelength: furlong data: x\n1 1\n").is_err());
        assert_eq!(parse("no data here\n").unwrap().0.len(), 0);
    }
}
