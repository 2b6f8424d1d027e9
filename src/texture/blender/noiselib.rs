//! Blender's noise library as LuxRender 1.x uses it for the `blender_*` textures
//! (`blender_noiselib.cpp`): the noise bases (Blender's original gradient noise over `hash` and
//! `hashvectf`, Perlin's original noise, Perlin's improved noise, Worley/Voronoi F1–F4, F2−F1
//! and crackle with seven distance metrics, cell noise), the generic noise and turbulence
//! (`BLI_gNoise`, `BLI_gTurbulence`), and Musgrave's fractals (fBm, multifractal, ridged and
//! hybrid multifractal, heterogeneous terrain) and variable lacunarity noise. The bases
//! themselves are in [`super::noise_bases`] (re-exported here), their tables in
//! [`super::tables`].

pub use super::noise_bases::{
    cell_noise_u, cell_noise_v, new_perlin, org_blender_noise, org_perlin, voronoi, Distance,
};

/// The noise bases (`noisebasis`, `noisebasis2` of distorted noise).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoiseBasis {
    BlenderOriginal,
    OriginalPerlin,
    ImprovedPerlin,
    VoronoiF1,
    VoronoiF2,
    VoronoiF3,
    VoronoiF4,
    VoronoiF2F1,
    VoronoiCrackle,
    CellNoise,
}

impl NoiseBasis {
    pub fn from_name(name: &str) -> Option<NoiseBasis> {
        Some(match name {
            "blender_original" => NoiseBasis::BlenderOriginal,
            "original_perlin" => NoiseBasis::OriginalPerlin,
            "improved_perlin" => NoiseBasis::ImprovedPerlin,
            "voronoi_f1" => NoiseBasis::VoronoiF1,
            "voronoi_f2" => NoiseBasis::VoronoiF2,
            "voronoi_f3" => NoiseBasis::VoronoiF3,
            "voronoi_f4" => NoiseBasis::VoronoiF4,
            "voronoi_f2_f1" => NoiseBasis::VoronoiF2F1,
            "voronoi_crackle" => NoiseBasis::VoronoiCrackle,
            "cell_noise" => NoiseBasis::CellNoise,
            _ => return None,
        })
    }
}

fn voronoi_actual(x: f32, y: f32, z: f32) -> [f32; 4] {
    voronoi(x, y, z, 1.0, Distance::Actual).0
}

/// The unsigned value of a basis in about [0, 1] (what `BLI_gNoise` and `BLI_gTurbulence`
/// read for every basis, Perlin's noises as ½ + ½n), before Blender's original basis offset.
fn unsigned(basis: NoiseBasis, x: f32, y: f32, z: f32) -> f32 {
    match basis {
        NoiseBasis::BlenderOriginal => org_blender_noise(x, y, z),
        NoiseBasis::OriginalPerlin => 0.5 + 0.5 * org_perlin(x, y, z),
        NoiseBasis::ImprovedPerlin => 0.5 + 0.5 * new_perlin(x, y, z),
        NoiseBasis::CellNoise => cell_noise_u(x, y, z),
        v => voronoi_value(v, voronoi_actual(x, y, z)),
    }
}

/// The Voronoi bases from the four distances.
fn voronoi_value(basis: NoiseBasis, da: [f32; 4]) -> f32 {
    match basis {
        NoiseBasis::VoronoiF1 => da[0],
        NoiseBasis::VoronoiF2 => da[1],
        NoiseBasis::VoronoiF3 => da[2],
        NoiseBasis::VoronoiF4 => da[3],
        NoiseBasis::VoronoiF2F1 => da[1] - da[0],
        NoiseBasis::VoronoiCrackle => (10.0 * (da[1] - da[0])).min(1.0),
        _ => 0.0,
    }
}

/// The signed value of a basis (what the Musgrave functions read): Blender's original and
/// the Voronoi bases as 2v − 1, Perlin's noises as they are. Blender's signed basis for the
/// original noise works on the unshifted point; so does this.
pub fn signed(basis: NoiseBasis, x: f32, y: f32, z: f32) -> f32 {
    match basis {
        NoiseBasis::BlenderOriginal => 2.0 * org_blender_noise(x, y, z) - 1.0,
        NoiseBasis::OriginalPerlin => org_perlin(x, y, z),
        NoiseBasis::ImprovedPerlin => new_perlin(x, y, z),
        NoiseBasis::CellNoise => 2.0 * cell_noise_u(x, y, z) - 1.0,
        v => 2.0 * voronoi_value(v, voronoi_actual(x, y, z)) - 1.0,
    }
}

/// Scales by 1/size (when not 0), shifting Blender's original basis by 1 first.
fn prepare(basis: NoiseBasis, size: f32, x: f32, y: f32, z: f32) -> (f32, f32, f32) {
    let (mut x, mut y, mut z) = (x, y, z);
    if basis == NoiseBasis::BlenderOriginal {
        x += 1.0;
        y += 1.0;
        z += 1.0;
    }
    if size != 0.0 {
        let s = 1.0 / size;
        x *= s;
        y *= s;
        z *= s;
    }
    (x, y, z)
}

/// Blender's generic noise (`BLI_gNoise`); `hard` folds it to |2n − 1|.
pub fn g_noise(size: f32, x: f32, y: f32, z: f32, hard: bool, basis: NoiseBasis) -> f32 {
    let (x, y, z) = prepare(basis, size, x, y, z);
    let n = unsigned(basis, x, y, z);
    if hard {
        (2.0 * n - 1.0).abs()
    } else {
        n
    }
}

/// Most octaves of the turbulence sum (Blender caps its UI at 6; 2^24 keeps the
/// normalisation exact in f32).
pub const MAX_TURBULENCE_OCTAVES: i32 = 24;

/// Blender's generic turbulence (`BLI_gTurbulence`): octaves 0..=`oct` of halving amplitude
/// and doubling frequency, normalised.
pub fn g_turbulence(
    size: f32,
    x: f32,
    y: f32,
    z: f32,
    oct: i32,
    hard: bool,
    basis: NoiseBasis,
) -> f32 {
    let oct = oct.clamp(0, MAX_TURBULENCE_OCTAVES);
    let (x, y, z) = prepare(basis, size, x, y, z);
    let (mut sum, mut amp, mut fscale) = (0.0f32, 1.0f32, 1.0f32);
    for _ in 0..=oct {
        let mut t = unsigned(basis, fscale * x, fscale * y, fscale * z);
        if hard {
            t = (2.0 * t - 1.0).abs();
        }
        sum += t * amp;
        amp *= 0.5;
        fscale *= 2.0;
    }
    sum * ((1u32 << oct) as f32 / ((1u32 << (oct + 1)) - 1) as f32)
}

/// Most whole octaves of the Musgrave sums.
pub const MAX_MUSGRAVE_OCTAVES: f32 = 64.0;

/// Musgrave's fractal parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fractal {
    pub h: f32,
    pub lacunarity: f32,
    pub octaves: f32,
    pub offset: f32,
    pub gain: f32,
    pub basis: NoiseBasis,
}

impl Fractal {
    fn octaves(&self) -> (i32, f32) {
        let o = self.octaves.clamp(0.0, MAX_MUSGRAVE_OCTAVES);
        (o as i32, o - o.floor())
    }

    fn n(&self, p: [f32; 3]) -> f32 {
        signed(self.basis, p[0], p[1], p[2])
    }

    /// fBm (`mg_fBm`).
    pub fn fbm(&self, mut p: [f32; 3]) -> f32 {
        let pw_hl = self.lacunarity.powf(-self.h);
        let (oct, rmd) = self.octaves();
        let (mut value, mut pwr) = (0.0, 1.0);
        for _ in 0..oct {
            value += self.n(p) * pwr;
            pwr *= pw_hl;
            p = p.map(|c| c * self.lacunarity);
        }
        if rmd != 0.0 {
            value += rmd * self.n(p) * pwr;
        }
        value
    }

    /// Multifractal (`mg_MultiFractal`).
    pub fn multifractal(&self, mut p: [f32; 3]) -> f32 {
        let pw_hl = self.lacunarity.powf(-self.h);
        let (oct, rmd) = self.octaves();
        let (mut value, mut pwr) = (1.0, 1.0);
        for _ in 0..oct {
            value *= pwr * self.n(p) + 1.0;
            pwr *= pw_hl;
            p = p.map(|c| c * self.lacunarity);
        }
        if rmd != 0.0 {
            value *= rmd * self.n(p) * pwr + 1.0;
        }
        value
    }

    /// Heterogeneous terrain (`mg_HeteroTerrain`).
    pub fn hetero_terrain(&self, mut p: [f32; 3]) -> f32 {
        let pw_hl = self.lacunarity.powf(-self.h);
        let mut pwr = pw_hl;
        let (oct, rmd) = self.octaves();
        let mut value = self.offset + self.n(p);
        p = p.map(|c| c * self.lacunarity);
        for _ in 1..oct {
            let inc = (self.n(p) + self.offset) * pwr * value;
            value += inc;
            pwr *= pw_hl;
            p = p.map(|c| c * self.lacunarity);
        }
        if rmd != 0.0 {
            let inc = (self.n(p) + self.offset) * pwr * value;
            value += rmd * inc;
        }
        value
    }

    /// Hybrid multifractal (`mg_HybridMultiFractal`).
    pub fn hybrid(&self, mut p: [f32; 3]) -> f32 {
        let pw_hl = self.lacunarity.powf(-self.h);
        let mut pwr = pw_hl;
        let (oct, rmd) = self.octaves();
        let mut result = self.n(p) + self.offset;
        let mut weight = self.gain * result;
        p = p.map(|c| c * self.lacunarity);
        let mut i = 1;
        while weight > 0.001 && i < oct {
            if weight > 1.0 {
                weight = 1.0;
            }
            let signal = (self.n(p) + self.offset) * pwr;
            pwr *= pw_hl;
            result += weight * signal;
            weight *= self.gain * signal;
            p = p.map(|c| c * self.lacunarity);
            i += 1;
        }
        if rmd != 0.0 {
            result += rmd * ((self.n(p) + self.offset) * pwr);
        }
        result
    }

    /// Ridged multifractal (`mg_RidgedMultiFractal`).
    pub fn ridged(&self, mut p: [f32; 3]) -> f32 {
        let pw_hl = self.lacunarity.powf(-self.h);
        let mut pwr = pw_hl;
        let (oct, _) = self.octaves();
        let mut signal = self.offset - self.n(p).abs();
        signal *= signal;
        let mut result = signal;
        for _ in 1..oct {
            p = p.map(|c| c * self.lacunarity);
            let weight = (signal * self.gain).clamp(0.0, 1.0);
            signal = self.offset - self.n(p).abs();
            signal *= signal;
            signal *= weight;
            result += signal * pwr;
            pwr *= pw_hl;
        }
        result
    }
}

/// Variable lacunarity noise (`mg_VLNoise`): `basis2` at a point displaced by `basis1` noise
/// scaled by `distortion`.
pub fn vl_noise(p: [f32; 3], distortion: f32, basis1: NoiseBasis, basis2: NoiseBasis) -> f32 {
    let [x, y, z] = p;
    let rv = [
        signed(basis1, x + 13.5, y + 13.5, z + 13.5) * distortion,
        signed(basis1, x, y, z) * distortion,
        signed(basis1, x - 13.5, y - 13.5, z - 13.5) * distortion,
    ];
    signed(basis2, x + rv[0], y + rv[1], z + rv[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turbulence_normalisation_and_musgrave_octaves() {
        // With octave 0 only the turbulence is the unsigned noise itself (½ + ½n for Perlin's).
        let n = g_noise(0.25, 0.1, 0.2, 0.3, false, NoiseBasis::ImprovedPerlin);
        let t0 = g_turbulence(0.25, 0.1, 0.2, 0.3, 0, false, NoiseBasis::ImprovedPerlin);
        assert!((t0 - n).abs() < 1e-6, "{t0} {n}");
        assert!((n - (0.5 + 0.5 * new_perlin(0.4, 0.8, 1.2))).abs() < 1e-6);
        // Octave 1: (n(p) + ½ n(2p)) · 2/3.
        let t1 = g_turbulence(0.25, 0.1, 0.2, 0.3, 1, false, NoiseBasis::ImprovedPerlin);
        let n2 = 0.5 + 0.5 * new_perlin(0.8, 1.6, 2.4);
        assert!((t1 - (n + 0.5 * n2) * (2.0 / 3.0)).abs() < 1e-6, "{t1}");
        // fBm with H = 1, lacunarity 2, 2 octaves: n(p) + ½ n(2p).
        let f = Fractal {
            h: 1.0,
            lacunarity: 2.0,
            octaves: 2.0,
            offset: 1.0,
            gain: 1.0,
            basis: NoiseBasis::ImprovedPerlin,
        };
        let p = [0.3, 0.7, 1.1];
        let expect = new_perlin(0.3, 0.7, 1.1) + 0.5 * new_perlin(0.6, 1.4, 2.2);
        assert!((f.fbm(p) - expect).abs() < 1e-6);
        // Multifractal: (n(p) + 1)(½ n(2p) + 1).
        let expect = (new_perlin(0.3, 0.7, 1.1) + 1.0) * (0.5 * new_perlin(0.6, 1.4, 2.2) + 1.0);
        assert!((f.multifractal(p) - expect).abs() < 1e-6);
    }
}
