//! The measured lamp spectra of LuxRender's `lampspectrum` texture (LuxRender 1.x
//! `lights/data/lamp_spect.h`: 250 samples per lamp, wavelengths in nm). The tables are kept in
//! `data/lamp_spectra.txt`, extracted from LuxCore, which ships the same tables
//! (`scripts/extract_lamp_spectra.py`). Three names are blackbodies in LuxRender 1.x rather
//! than tables ([`lamp_blackbody`]).

use super::spd::Spd;

const DATA: &str = include_str!("data/lamp_spectra.txt");

/// Names of the tabulated lamps, in file order.
pub fn lamp_names() -> impl Iterator<Item = &'static str> {
    DATA.lines().filter_map(|l| l.split(' ').next())
}

/// LuxRender 1.x renders these presets as blackbodies (the tables were poorly calibrated):
/// Candle 1020 K, Incandescent1 2750 K, Incandescent2 (and any unknown name) 2900 K.
pub fn lamp_blackbody(name: &str) -> Option<f32> {
    match name {
        "Candle" => Some(1020.0),
        "Incandescent1" => Some(2750.0),
        "Incandescent2" => Some(2900.0),
        _ => None,
    }
}

/// The spectrum of a tabulated lamp, `None` for names without a table.
pub fn lamp_spd(name: &str) -> Option<Spd> {
    let line = DATA.lines().find(|l| l.split(' ').next() == Some(name))?;
    let rest = line.split_once(" wl: ")?.1;
    let (wl, v) = rest.split_once(" v: ")?;
    let parse = |s: &str| -> Option<Vec<f32>> {
        s.split_whitespace()
            .map(|t| t.parse::<f32>().ok())
            .collect()
    };
    Spd::new(parse(wl)?, parse(v)?).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_table_parses_with_250_samples() {
        let names: Vec<&str> = lamp_names().collect();
        assert_eq!(names.len(), 64);
        for n in &names {
            let s = lamp_spd(n).unwrap_or_else(|| panic!("{n}"));
            assert_eq!(s.wavelengths().len(), 250, "{n}");
            assert!(s.values().iter().all(|v| *v >= 0.0), "{n}");
        }
        assert!(lamp_spd("Candle").is_none());
        assert_eq!(lamp_blackbody("Candle"), Some(1020.0));
        assert!(lamp_spd("nope").is_none());
    }

    #[test]
    fn sodium_lamps_are_orange_and_mercury_blue_green() {
        // Low-pressure sodium emits at 589 nm: far more red than blue.
        let lps = lamp_spd("LPS").unwrap().illuminant_rgb();
        assert!(lps.r > 5.0 * lps.b, "{lps:?}");
        let hpm = lamp_spd("HPM2").unwrap().illuminant_rgb();
        assert!(hpm.b > 0.0 && hpm.g > 0.0, "{hpm:?}");
    }
}
