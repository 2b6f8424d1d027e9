//! Complex refractive indices over wavelength: LuxRender's named metal presets (`amorphous
//! carbon`, `silver`, `gold`, `copper`, `aluminium`: the `metal` material's `name` and the
//! `fresnelname` texture) with their wavelengths in nm, n and k (SOPRA data as shipped with
//! LuxRender, its digits as published), and the readers of `.nk` files: SOPRA (header `unit
//! first last count`, then `n k` lines) and luxpop (lines of Ångström, n, k; `;` comments).
//! [`NkTable::to_rgb`] is the RGB renderer's reading of a table (for a metal, fitted to its
//! reflectance in [`super::nk_rgb`]).
//!
//! This is the one home of these tables: the `metal` material and the fresnel textures read them.
#![allow(clippy::excessive_precision, clippy::approx_constant)]

#[rustfmt::skip]
pub const SOPRA_WL: [f32; 56] = [
    298.7570554, 302.4004341, 306.1337728, 309.960445, 313.8839949, 317.9081487, 322.036826,
    326.2741526, 330.6244747, 335.092373, 339.6826795, 344.4004944, 349.2512056, 354.2405086,
    359.374429, 364.6593471, 370.1020239, 375.7096303, 381.4897785, 387.4505563, 393.6005651,
    399.9489613, 406.5055016, 413.2805933, 420.2853492, 427.5316483, 435.0322035, 442.8006357,
    450.8515564, 459.2006593, 467.8648226, 476.8622231, 486.2124627, 495.936712, 506.0578694,
    516.6007417, 527.5922468, 539.0616435, 551.0407911, 563.5644455, 576.6705953, 590.4008476,
    604.8008683, 619.92089, 635.8162974, 652.5483053, 670.1847459, 688.8009889, 708.4810171,
    729.3186941, 751.4192606, 774.9011125, 799.8979226, 826.5611867, 855.0632966, 885.6012714,
];

#[rustfmt::skip]
pub const CARBON_WL: [f32; 15] = [
    247.96, 309.95, 326.263, 344.389, 364.647, 387.438, 413.267, 442.786, 476.846, 516.583,
    563.545, 619.9, 688.778, 774.875, 885.571,
];
#[rustfmt::skip]
pub const CARBON_N: [f32; 15] = [
    1.73, 1.84, 1.9, 1.94, 2.0, 2.06, 2.11, 2.17, 2.24, 2.3, 2.38, 2.43, 2.43, 2.33, 2.24,
];
/// LuxRender's table has 14 k values for 15 wavelengths; the last is repeated.
#[rustfmt::skip]
pub const CARBON_K: [f32; 15] = [
    0.712, 0.808, 0.91, 0.92, 0.92, 0.91, 0.9, 0.89, 0.88, 0.87, 0.82, 0.75, 0.7, 0.71, 0.71,
];

#[rustfmt::skip]
pub const SILVER_N: [f32; 56] = [
    1.519, 1.496, 1.4325, 1.323, 1.142062, 0.932, 0.719062, 0.526, 0.388125, 0.294, 0.253313,
    0.238, 0.221438, 0.209, 0.194813, 0.186, 0.192063, 0.2, 0.198063, 0.192, 0.182, 0.173, 0.172625,
    0.173, 0.166688, 0.16, 0.1585, 0.157, 0.151063, 0.144, 0.137313, 0.132, 0.13025, 0.13, 0.129938,
    0.13, 0.130063, 0.129, 0.124375, 0.12, 0.119313, 0.121, 0.1255, 0.131, 0.136125, 0.14, 0.140063,
    0.14, 0.144313, 0.148, 0.145875, 0.143, 0.142563, 0.145, 0.151938, 0.163,
];
#[rustfmt::skip]
pub const SILVER_K: [f32; 56] = [
    1.08, 0.882, 0.761063, 0.647, 0.550875, 0.504, 0.554375, 0.663, 0.818563, 0.986, 1.120687,
    1.24, 1.34525, 1.44, 1.53375, 1.61, 1.641875, 1.67, 1.735, 1.81, 1.87875, 1.95, 2.029375, 2.11,
    2.18625, 2.26, 2.329375, 2.4, 2.47875, 2.56, 2.64, 2.72, 2.798125, 2.88, 2.97375, 3.07, 3.159375,
    3.25, 3.348125, 3.45, 3.55375, 3.66, 3.76625, 3.88, 4.010625, 4.15, 4.293125, 4.44, 4.58625, 4.74,
    4.908125, 5.09, 5.28875, 5.5, 5.720624, 5.95,
];
#[rustfmt::skip]
pub const GOLD_N: [f32; 56] = [
    1.795, 1.812, 1.822625, 1.83, 1.837125, 1.84, 1.83425, 1.824, 1.812, 1.798, 1.782,
    1.766, 1.7525, 1.74, 1.727625, 1.716, 1.705875, 1.696, 1.68475, 1.674, 1.666, 1.658, 1.64725,
    1.636, 1.628, 1.616, 1.59625, 1.562, 1.502125, 1.426, 1.345875, 1.242, 1.08675, 0.916, 0.7545,
    0.608, 0.49175, 0.402, 0.3455, 0.306, 0.267625, 0.236, 0.212375, 0.194, 0.17775, 0.166, 0.161,
    0.16, 0.160875, 0.164, 0.1695, 0.176, 0.181375, 0.188, 0.198125, 0.21,
];
#[rustfmt::skip]
pub const GOLD_K: [f32; 56] = [
    1.920375, 1.92, 1.918875, 1.916, 1.911375, 1.904, 1.891375, 1.878, 1.86825, 1.86,
    1.85175, 1.846, 1.84525, 1.848, 1.852375, 1.862, 1.883, 1.906, 1.9225, 1.936, 1.94775, 1.956,
    1.959375, 1.958, 1.951375, 1.94, 1.9245, 1.904, 1.875875, 1.846, 1.814625, 1.796, 1.797375,
    1.84, 1.9565, 2.12, 2.32625, 2.54, 2.730625, 2.88, 2.940625, 2.97, 3.015, 3.06, 3.07, 3.15,
    3.445812, 3.8, 4.087687, 4.357, 4.610188, 4.86, 5.125813, 5.39, 5.63125, 5.88,
];
#[rustfmt::skip]
pub const COPPER_N: [f32; 56] = [
    1.400313, 1.38, 1.358438, 1.34, 1.329063, 1.325, 1.3325, 1.34, 1.334375, 1.325,
    1.317812, 1.31, 1.300313, 1.29, 1.281563, 1.27, 1.249062, 1.225, 1.2, 1.18, 1.174375, 1.175,
    1.1775, 1.18, 1.178125, 1.175, 1.172812, 1.17, 1.165312, 1.16, 1.155312, 1.15, 1.142812, 1.135,
    1.131562, 1.12, 1.092437, 1.04, 0.950375, 0.826, 0.645875, 0.468, 0.35125, 0.272, 0.230813, 0.214,
    0.20925, 0.213, 0.21625, 0.223, 0.2365, 0.25, 0.254188, 0.26, 0.28, 0.3,
];
#[rustfmt::skip]
pub const COPPER_K: [f32; 56] = [
    1.662125, 1.687, 1.703313, 1.72, 1.744563, 1.77, 1.791625, 1.81, 1.822125, 1.834,
    1.85175, 1.872, 1.89425, 1.916, 1.931688, 1.95, 1.972438, 2.015, 2.121562, 2.21, 2.177188, 2.13,
    2.160063, 2.21, 2.249938, 2.289, 2.326, 2.362, 2.397625, 2.433, 2.469187, 2.504, 2.535875, 2.564,
    2.589625, 2.605, 2.595562, 2.583, 2.5765, 2.599, 2.678062, 2.809, 3.01075, 3.24, 3.458187, 3.67,
    3.863125, 4.05, 4.239563, 4.43, 4.619563, 4.817, 5.034125, 5.26, 5.485625, 5.717,
];
#[rustfmt::skip]
pub const ALUMINIUM_N: [f32; 56] = [
    0.273375, 0.28, 0.286813, 0.294, 0.301875, 0.31, 0.317875, 0.326, 0.33475, 0.344,
    0.353813, 0.364, 0.374375, 0.385, 0.39575, 0.407, 0.419125, 0.432, 0.445688, 0.46, 0.474688, 0.49,
    0.506188, 0.523, 0.540063, 0.558, 0.577313, 0.598, 0.620313, 0.644, 0.668625, 0.695, 0.72375, 0.755,
    0.789, 0.826, 0.867, 0.912, 0.963, 1.02, 1.08, 1.15, 1.22, 1.3, 1.39, 1.49, 1.6, 1.74, 1.91, 2.14,
    2.41, 2.63, 2.8, 2.74, 2.58, 2.24,
];
#[rustfmt::skip]
pub const ALUMINIUM_K: [f32; 56] = [
    3.59375, 3.64, 3.689375, 3.74, 3.789375, 3.84, 3.894375, 3.95, 4.005, 4.06, 4.11375,
    4.17, 4.23375, 4.3, 4.365, 4.43, 4.49375, 4.56, 4.63375, 4.71, 4.784375, 4.86, 4.938125, 5.02,
    5.10875, 5.2, 5.29, 5.38, 5.48, 5.58, 5.69, 5.8, 5.915, 6.03, 6.15, 6.28, 6.42, 6.55, 6.7, 6.85,
    7.0, 7.15, 7.31, 7.48, 7.65, 7.82, 8.01, 8.21, 8.39, 8.57, 8.62, 8.6, 8.45, 8.31, 8.21, 8.21,
];

/// The wavelength bands averaged into the red, green and blue channels (nm, inclusive).
pub const BANDS: [(u32, u32); 3] = [(580, 700), (490, 580), (400, 490)];

/// Averages of (n, k) given by `at` (per wavelength in nm) over each of [`BANDS`], 1 nm
/// steps: red, green, blue.
pub fn band_averages(at: impl Fn(f32) -> (f32, f32)) -> ([f32; 3], [f32; 3]) {
    let mut n = [0.0f32; 3];
    let mut k = [0.0f32; 3];
    for (ch, (a, b)) in BANDS.iter().enumerate() {
        let (mut sn, mut sk) = (0.0f64, 0.0f64);
        for nm in *a..=*b {
            let (ni, ki) = at(nm as f32);
            sn += f64::from(ni);
            sk += f64::from(ki);
        }
        let count = f64::from(b - a + 1);
        n[ch] = (sn / count) as f32;
        k[ch] = (sk / count) as f32;
    }
    (n, k)
}

/// Band-average extinction above which a table is read as a metal (its RGB n, k fitted to
/// its reflectance) rather than a dielectric.
pub const ABSORBING_K: f32 = 0.01;

/// Tabulated n and k over wavelength (nm, ascending).
#[derive(Clone, Debug, PartialEq)]
pub struct NkTable {
    pub wl: Vec<f32>,
    pub n: Vec<f32>,
    pub k: Vec<f32>,
}

impl NkTable {
    fn from_slices(wl: &[f32], n: &[f32], k: &[f32]) -> NkTable {
        NkTable {
            wl: wl.to_vec(),
            n: n.to_vec(),
            k: k.to_vec(),
        }
    }

    /// A named preset; `None` for unknown names.
    pub fn preset(name: &str) -> Option<NkTable> {
        Some(match name {
            "amorphous carbon" => NkTable::from_slices(&CARBON_WL, &CARBON_N, &CARBON_K),
            "silver" => NkTable::from_slices(&SOPRA_WL, &SILVER_N, &SILVER_K),
            "gold" => NkTable::from_slices(&SOPRA_WL, &GOLD_N, &GOLD_K),
            "copper" => NkTable::from_slices(&SOPRA_WL, &COPPER_N, &COPPER_K),
            "aluminium" => NkTable::from_slices(&SOPRA_WL, &ALUMINIUM_N, &ALUMINIUM_K),
            _ => return None,
        })
    }

    /// Linear interpolation (clamped at the ends) of (n, k) at `nm`.
    pub fn at(&self, nm: f32) -> (f32, f32) {
        let len = self.wl.len().min(self.n.len()).min(self.k.len());
        if len == 0 {
            return (1.0, 0.0);
        }
        if nm <= self.wl[0] {
            return (self.n[0], self.k[0]);
        }
        // The first sample at or beyond nm (the table is sorted), 1 ≤ i.
        let i = self.wl[..len].partition_point(|&w| w < nm);
        if i >= len {
            return (self.n[len - 1], self.k[len - 1]);
        }
        let span = self.wl[i] - self.wl[i - 1];
        let t = if span > 0.0 {
            (nm - self.wl[i - 1]) / span
        } else {
            1.0
        };
        let lerp = |a: &[f32]| a[i - 1] * (1.0 - t) + a[i] * t;
        (lerp(&self.n), lerp(&self.k))
    }

    /// RGB (n, k), the RGB renderer's reading of the table: for an absorbing table (a metal:
    /// k above [`ABSORBING_K`] in a band), the (n, k) fitted to its spectral reflectance
    /// ([`super::nk_rgb::fit`]); otherwise (a dielectric, whose n is an index of refraction)
    /// the band averages of [`Self::band_averages`].
    pub fn to_rgb(&self) -> ([f32; 3], [f32; 3]) {
        let avg = self.band_averages();
        if avg.1.iter().any(|&v| v > ABSORBING_K) {
            super::nk_rgb::fit(|nm| self.at(nm), avg)
        } else {
            avg
        }
    }

    /// Averages of n and k over [`BANDS`] (see [`band_averages`]).
    pub fn band_averages(&self) -> ([f32; 3], [f32; 3]) {
        band_averages(|nm| self.at(nm))
    }

    /// Parses an `.nk` file: SOPRA (header `unit first last count`, then `n k` lines) or luxpop
    /// (`wavelength_Å n k` lines, `;` comments).
    pub fn parse(text: &str) -> Result<NkTable, String> {
        parse_sopra(text).or_else(|_| parse_luxpop(text))
    }

    /// Parses a SOPRA file only.
    pub fn parse_sopra(text: &str) -> Result<NkTable, String> {
        parse_sopra(text)
    }

    /// Parses a luxpop file only.
    pub fn parse_luxpop(text: &str) -> Result<NkTable, String> {
        parse_luxpop(text)
    }
}

fn nums(line: &str) -> Vec<f32> {
    line.split_whitespace()
        .map_while(|t| t.parse::<f32>().ok())
        .collect()
}

fn parse_sopra(text: &str) -> Result<NkTable, String> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let head = nums(lines.next().ok_or("empty file")?);
    if head.len() < 4 {
        return Err("not a SOPRA header".into());
    }
    let (unit, a, b, count) = (head[0] as i32, head[1], head[2], head[3] as usize);
    let conv = |x: f32| -> f32 {
        match unit {
            1 => 4.135667e-15 * 299_792_458.0 * 1e9 / x,
            2 => x * 1000.0,
            3 => 1e7 / x,
            _ => x,
        }
    };
    if !(1..=4).contains(&unit) || count == 0 || count > 100_000 {
        return Err("bad SOPRA header".into());
    }
    // eV and cm^-1 run from high to low wavelength: the file's first value is the last one.
    let (first, last) = if unit == 1 || unit == 3 {
        (b, a)
    } else {
        (a, b)
    };
    let mut rows = Vec::with_capacity(count);
    for _ in 0..count {
        let v = nums(lines.next().ok_or("truncated SOPRA data")?);
        if v.len() < 2 {
            return Err("bad SOPRA line".into());
        }
        rows.push((v[0], v[1]));
    }
    let mut t = NkTable {
        wl: vec![],
        n: vec![],
        k: vec![],
    };
    for i in (0..count).rev() {
        let x = first + (last - first) * i as f32 / count as f32;
        let (n, k) = rows[count - 1 - i];
        t.wl.push(conv(x));
        t.n.push(n);
        t.k.push(k);
    }
    sort(t)
}

fn parse_luxpop(text: &str) -> Result<NkTable, String> {
    let mut t = NkTable {
        wl: vec![],
        n: vec![],
        k: vec![],
    };
    for line in text.lines() {
        let l = line.trim();
        if l.is_empty() || l.starts_with(';') {
            continue;
        }
        let v = nums(l);
        if v.len() < 3 {
            return Err(format!("bad nk line \"{l}\""));
        }
        t.wl.push(v[0] * 0.1);
        t.n.push(v[1]);
        t.k.push(v[2]);
    }
    if t.wl.is_empty() {
        return Err("no nk data".into());
    }
    sort(t)
}

fn sort(t: NkTable) -> Result<NkTable, String> {
    let mut idx: Vec<usize> = (0..t.wl.len()).collect();
    idx.sort_by(|&a, &b| t.wl[a].total_cmp(&t.wl[b]));
    if t.wl.iter().any(|w| !w.is_finite()) {
        return Err("non-finite wavelength".into());
    }
    let bad = |(n, k): (&f32, &f32)| !(n.is_finite() && k.is_finite() && *n > 0.0 && *k >= 0.0);
    if let Some((n, k)) = t.n.iter().zip(&t.k).find(|p| bad(*p)) {
        return Err(format!(
            "n {n}, k {k}: the optical constants must be finite, n above 0 and k not negative"
        ));
    }
    Ok(NkTable {
        wl: idx.iter().map(|&i| t.wl[i]).collect(),
        n: idx.iter().map(|&i| t.n[i]).collect(),
        k: idx.iter().map(|&i| t.k[i]).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_interpolation_and_file_formats() {
        let gold = NkTable::preset("gold").unwrap();
        let (n, k) = gold.band_averages();
        // Gold: low n and high k in the red, n above 1 in the blue.
        assert!(n[0] < 0.3 && n[2] > 1.0, "{n:?}");
        assert!(k[0] > k[2], "{k:?}");
        assert!(NkTable::preset("unobtainium").is_none());
        let t = NkTable::parse("; comment\n5000 1.5 0.1\n4000 1.4 0.2\n").unwrap();
        assert_eq!(t.wl, vec![400.0, 500.0]);
        assert_eq!(t.at(450.0), (1.45, 0.15000001));
        assert_eq!(t.at(300.0), (1.4, 0.2));
        // SOPRA in nm (unit 2 is µm: 0.4 to 0.5 in 2 steps).
        let s = NkTable::parse_sopra("2 0.4 0.5 2\n1.0 2.0\n3.0 4.0\n").unwrap();
        assert_eq!(s.wl.len(), 2);
        assert!(NkTable::parse_sopra("; x\n5000 1.5 0.1\n").is_err());
        for bad in [
            "5000 nan 0.1\n",
            "5000 1.5 inf\n",
            "5000 0 1\n",
            "5000 1.5 -0.1\n",
        ] {
            let e = NkTable::parse(bad).expect_err(bad);
            assert!(e.contains("optical constants"), "{bad}: {e}");
        }
    }
}

#[cfg(test)]
mod preset_tests {
    use super::*;
    use crate::spectrum::nk_rgb::{rgb_reflectance, spectral_rgb_reflectance, COSINES};

    /// RMS over the channels and [`COSINES`] of (reflectance of (n, k) − the table's own),
    /// each angle weighted by its cosine (what it contributes to reflected irradiance).
    fn weighted_rms(t: &NkTable, n: [f32; 3], k: [f32; 3]) -> f32 {
        let (mut se, mut w) = (0.0f32, 0.0f32);
        for c in COSINES {
            // A saturated colour can leave the gamut (gold's red is 1.01): a Fresnel
            // reflectance stops just below 1.
            let want = spectral_rgb_reflectance(&|nm| t.at(nm), c).map(|v| v.min(0.999));
            let got = rgb_reflectance(n, k, c);
            for ch in 0..3 {
                se += c * (got[ch] - want[ch]).powi(2);
                w += c;
            }
        }
        (se / w).sqrt()
    }

    /// The metal presets: the RGB (n, k) reflect the table's spectral RGB colour within 0.01
    /// RMS over the angles, never further than band averages of n and k, which miss gold's and copper's colour by 0.05 and 0.02 RMS.
    #[test]
    fn presets_reflect_their_spectral_colour() {
        for name in ["gold", "copper", "silver", "aluminium", "amorphous carbon"] {
            let t = NkTable::preset(name).unwrap();
            let (n, k) = t.to_rgb();
            let (an, ak) = t.band_averages();
            if name == "gold" {
                // Gold's colour at normal incidence, integrated from its table (red beyond
                // the gamut, 1.01, clamped).
                let got = rgb_reflectance(n, k, 1.0);
                let want = [0.999, 0.786, 0.332];
                assert!((0..3).all(|c| (got[c] - want[c]).abs() < 0.002), "{got:?}");
            }
            if name == "gold" || name == "copper" {
                // Fitted: exact at normal incidence.
                let want = spectral_rgb_reflectance(&|nm| t.at(nm), 1.0).map(|v| v.min(0.999));
                let got = rgb_reflectance(n, k, 1.0);
                for ch in 0..3 {
                    assert!(
                        (got[ch] - want[ch]).abs() < 1e-3,
                        "{name}: {got:?} vs {want:?}"
                    );
                }
            }
            let (fitted, averaged) = (weighted_rms(&t, n, k), weighted_rms(&t, an, ak));
            eprintln!("{name}: weighted RMS fitted {fitted:.4}, band averages {averaged:.4}");
            assert!(
                fitted < 0.01 && fitted <= averaged,
                "{name}: {fitted} vs {averaged}"
            );
            if name == "gold" || name == "copper" {
                assert!(averaged > 0.015, "{name}: band averages off by {averaged}");
            }
        }
    }
}
