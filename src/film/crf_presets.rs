//! LuxRender 1.x's built-in camera response presets: the 50 film names its `cameraresponse`
//! accepts besides CRF files ("Advantix_100CD", "Portra_800CD", ...), with their measured
//! curves.
//!
//! LuxRender compiles them in (lux/film/data/cameraresponsefunctions.h, used by
//! CameraResponse::loadPreset in lux/core/cameraresponse.cpp). They come from Columbia
//! University's DoRF database: per film 1024 points I = k/1023 with outputs B per channel; 47
//! colour films have Red, Green and Blue curves, the three Agfapan films only Red (monochrome).
//! Names are matched exactly, case included, as LuxRender does.
//!
//! The curves are committed as `data/crf_presets.txt.gz`, written by
//! `scripts/extract_crf_presets.py` (which says where the numbers come from and how they were
//! checked, and describes the format), and decoded on first use.

use std::io::Read;
use std::sync::OnceLock;

/// A response curve: inputs and outputs.
pub type Curve = (Vec<f32>, Vec<f32>);

/// The preset names, in LuxRender's (alphabetical) order.
pub const NAMES: [&str; 50] = [
    "Advantix_100CD",
    "Advantix_200CD",
    "Advantix_400CD",
    "Agfachrome_ctpecisa_200CD",
    "Agfachrome_ctprecisa_100CD",
    "Agfachrome_rsx2_050CD",
    "Agfachrome_rsx2_100CD",
    "Agfachrome_rsx2_200CD",
    "Agfacolor_futura_100CD",
    "Agfacolor_futura_200CD",
    "Agfacolor_futura_400CD",
    "Agfacolor_futuraII_100CD",
    "Agfacolor_futuraII_200CD",
    "Agfacolor_futuraII_400CD",
    "Agfacolor_hdc_100_plusCD",
    "Agfacolor_hdc_200_plusCD",
    "Agfacolor_hdc_400_plusCD",
    "Agfacolor_optimaII_100CD",
    "Agfacolor_optimaII_200CD",
    "Agfacolor_ultra_050_CD",
    "Agfacolor_vista_100CD",
    "Agfacolor_vista_200CD",
    "Agfacolor_vista_400CD",
    "Agfacolor_vista_800CD",
    "Agfapan_apx_025CD",
    "Agfapan_apx_100CD",
    "Agfapan_apx_400CD",
    "Ektachrome_100_plusCD",
    "Ektachrome_100CD",
    "Ektachrome_320TCD",
    "Ektachrome_400XCD",
    "Ektachrome_64CD",
    "Ektachrome_64TCD",
    "Ektachrome_E100SCD",
    "F125CD",
    "F250CD",
    "F400CD",
    "FCICD",
    "Gold_100CD",
    "Gold_200CD",
    "Kodachrome_200CD",
    "Kodachrome_25CD",
    "Kodachrome_64CD",
    "Max_Zoom_800CD",
    "Portra_100TCD",
    "Portra_160NCCD",
    "Portra_160VCCD",
    "Portra_400NCCD",
    "Portra_400VCCD",
    "Portra_800CD",
];

/// Points per curve.
pub const POINTS: usize = 1024;

const DATA: &[u8] = include_bytes!("data/crf_presets.txt.gz");

/// Per preset (in [`NAMES`] order) its curves: Red, Green, Blue, or Red alone.
type Table = Vec<Vec<Curve>>;

/// Whether `name` is one of LuxRender's presets (exact, case-sensitive match).
pub fn is_preset(name: &str) -> bool {
    NAMES.contains(&name)
}

/// The measured curves of preset `name` as LuxRender's table has them (built-in gamma not yet
/// taken out): `Ok(None)` when `name` is no preset.
pub fn curves(name: &str) -> Result<Option<Vec<Curve>>, String> {
    let Some(index) = NAMES.iter().position(|&n| n == name) else {
        return Ok(None);
    };
    let table = table()?;
    Ok(table.get(index).cloned())
}

/// The preset name closest to `name` (ignoring case; a small edit distance), if one is close.
pub fn closest(name: &str) -> Option<&'static str> {
    let lower = name.to_lowercase();
    NAMES
        .iter()
        .map(|&n| (edit_distance(&lower, &n.to_lowercase()), n))
        .filter(|&(d, n)| d <= (n.len() / 4).max(2))
        .min_by_key(|&(d, _)| d)
        .map(|(_, n)| n)
}

/// The decoded table (decoded once).
fn table() -> Result<&'static Table, String> {
    static TABLE: OnceLock<Result<Table, String>> = OnceLock::new();
    TABLE
        .get_or_init(|| decode(DATA))
        .as_ref()
        .map_err(|e| format!("built-in camera response presets: {e}"))
}

/// Gunzips and parses the committed data.
fn decode(gz: &[u8]) -> Result<Table, String> {
    let mut text = String::new();
    flate2::read::GzDecoder::new(gz)
        .read_to_string(&mut text)
        .map_err(|e| format!("data unreadable: {e}"))?;
    let mut inputs: Option<Vec<f32>> = None;
    let mut table: Table = vec![Vec::new(); NAMES.len()];
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.is_empty())
    {
        let mut words = line.split(' ');
        let head = words.next().unwrap_or_default();
        if head == "I" {
            inputs = Some(running_sum(words)?);
            continue;
        }
        let index = NAMES
            .iter()
            .position(|&n| n == head)
            .ok_or_else(|| format!("unknown film \"{head}\""))?;
        let _channel = words.next();
        let i = inputs.clone().ok_or("outputs before inputs")?;
        table[index].push((i, running_sum(words)?));
    }
    match table.iter().position(|c| c.len() != 3 && c.len() != 1) {
        Some(k) => Err(format!("{} has {} curves", NAMES[k], table[k].len())),
        None => Ok(table),
    }
}

/// Values from their differences in units of 1e-10 (the data file's encoding).
fn running_sum<'a>(words: impl Iterator<Item = &'a str>) -> Result<Vec<f32>, String> {
    let mut sum = 0i64;
    let v: Vec<f32> = words
        .map(|w| {
            let d: i64 = w.parse().map_err(|_| format!("bad number \"{w}\""))?;
            sum = sum.checked_add(d).ok_or("overflow")?;
            Ok((sum as f64 * 1e-10) as f32)
        })
        .collect::<Result<_, String>>()?;
    if v.len() == POINTS {
        Ok(v)
    } else {
        Err(format!(
            "a curve has {} points instead of {POINTS}",
            v.len()
        ))
    }
}

/// Levenshtein distance over characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diag = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let next = (diag + usize::from(ca != cb))
                .min(row[j] + 1)
                .min(row[j + 1] + 1);
            diag = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Output of preset `name`, channel `ch` (0 red) at point `k`, as in the table.
    fn b(name: &str, ch: usize, k: usize) -> f32 {
        curves(name).unwrap().unwrap()[ch].1[k]
    }

    #[test]
    fn table_values_are_luxrenders() {
        // Numbers copied from cameraresponsefunctions.h (as LuxRender and LuxCore ship it).
        assert_eq!(b("Advantix_100CD", 0, 0), 0.0);
        assert_eq!(b("Advantix_100CD", 0, 1), 9.97592e-3); // 9.975920e-003
        assert_eq!(b("Advantix_100CD", 0, 3), 2.818739e-2);
        assert_eq!(b("Advantix_100CD", 0, 10), 7.222205e-2);
        assert_eq!(b("Agfapan_apx_025CD", 0, 1005), 9.985421e-1);
        assert_eq!(b("Agfapan_apx_025CD", 0, 1012), 9.991252e-1);
        assert_eq!(b("Portra_800CD", 2, 1006), 9.944175e-1);
        assert_eq!(b("Portra_800CD", 2, 1008), 9.951048e-1);
        assert_eq!(b("Portra_800CD", 2, 1023), 1.0);
        // the shared inputs: k/1023 with 7 significant digits
        let i = &curves("F125CD").unwrap().unwrap()[1].0;
        assert_eq!(
            (i[0], i[1], i[2], i[1023]),
            (0.0, 9.775171e-4, 1.955034e-3, 1.0)
        );
        assert_eq!(i[511], 4.995112e-1);
    }

    #[test]
    fn every_name_has_curves_and_only_agfapan_is_monochrome() {
        for name in NAMES {
            let c = curves(name).unwrap().unwrap();
            let mono = name.starts_with("Agfapan");
            assert_eq!(c.len(), if mono { 1 } else { 3 }, "{name}");
            for (i, o) in &c {
                assert_eq!((i.len(), o.len()), (POINTS, POINTS), "{name}");
                assert!(o.windows(2).all(|w| w[0] <= w[1]), "{name} rises");
                assert_eq!((o[0], o[POINTS - 1]), (0.0, 1.0), "{name}");
            }
        }
        // distinct films have distinct curves
        assert_ne!(b("Gold_100CD", 1, 300), b("Gold_200CD", 1, 300));
    }

    #[test]
    fn names_are_case_sensitive_and_close_ones_are_suggested() {
        assert!(is_preset("Portra_160VCCD"));
        assert!(!is_preset("portra_160vccd"));
        assert_eq!(curves("None").unwrap(), None);
        assert_eq!(closest("portra_160vccd"), Some("Portra_160VCCD"));
        assert_eq!(closest("Advantix_100"), Some("Advantix_100CD"));
        assert_eq!(closest("Kodachrome_64"), Some("Kodachrome_64CD"));
        assert_eq!(closest("my_film.crf"), None);
    }

    #[test]
    fn corrupt_data_is_an_error() {
        assert!(decode(b"not gzip").is_err());
        let gz = |s: &str| {
            let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
            std::io::Write::write_all(&mut e, s.as_bytes()).unwrap();
            e.finish().unwrap()
        };
        assert!(decode(&gz("I 0 1\nF125CD Red 0 1\n")).is_err());
        assert!(decode(&gz("Nope Red 0\n")).is_err());
    }
}
