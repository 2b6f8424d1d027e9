//! `blender_voronoi`: Worley/Voronoi noise, |w1·F1 + w2·F2 + w3·F3 + w4·F4| scaled by
//! `outscale`/(|w1| + |w2| + |w3| + |w4|), with `distmetric` (`actual_distance`,
//! `distance_squared`, `manhattan`, `chebychev`, `minkovsky_half`, `minkovsky_four`,
//! `minkovsky` with exponent `minkovsky_exp` 2.5), the point divided by `noisesize` (0.25);
//! weights `w1` 1, `w2`..`w4` 0. `coltype` 1–3 colours the cells (Blender's position,
//! position-outline and position-outline-intensity modes). `nabla` (0.025) is read.

use super::noiselib::{cell_noise_v, voronoi, Distance};
use super::{BriCont, Params, TexResult};
use crate::texture::TextureError;

#[derive(Debug)]
pub struct Voronoi {
    pub metric: Distance,
    pub exponent: f32,
    pub weights: [f32; 4],
    pub size: f32,
    pub outscale: f32,
    pub coltype: i32,
}

impl Voronoi {
    pub fn eval(&self, p: [f32; 3], bc: &BriCont) -> TexResult {
        let q = p.map(|c| c / self.size);
        let aw = self.weights.map(f32::abs);
        let mut sc = aw.iter().sum::<f32>();
        if sc != 0.0 {
            sc = self.outscale / sc;
        }
        let (da, pa) = voronoi(q[0], q[1], q[2], self.exponent, self.metric);
        let w = self.weights;
        let tin = sc * (w[0] * da[0] + w[1] * da[1] + w[2] * da[2] + w[3] * da[3]).abs();
        if self.coltype == 0 {
            return TexResult::int(bc.int(tin));
        }
        let mut rgb = [0.0f32; 3];
        for (k, point) in pa.iter().enumerate() {
            let c = cell_noise_v(point[0], point[1], point[2]);
            for ch in 0..3 {
                rgb[ch] += aw[k] * c[ch];
            }
        }
        let factor = if self.coltype >= 2 {
            let t1 = ((da[1] - da[0]) * 10.0).min(1.0);
            if self.coltype == 3 {
                t1 * tin
            } else {
                t1 * sc
            }
        } else {
            sc
        };
        TexResult {
            tin,
            rgb: Some(bc.rgb(rgb.map(|c| c * factor))),
        }
    }
}

pub fn build(p: &mut Params) -> Result<Voronoi, TextureError> {
    let metric = p.choice(
        "distmetric",
        None,
        ("actual_distance", Distance::Actual),
        Distance::from_name,
    );
    let exponent = match p.t.entity.params.float("minkowsky_exp") {
        Some(v) if !p.t.entity.params.contains("minkovsky_exp") => v,
        _ => p.float("minkovsky_exp", None, 2.5)?,
    };
    let _nabla = p.float("nabla", None, 0.025)?;
    Ok(Voronoi {
        metric,
        exponent,
        weights: [
            p.float("w1", None, 1.0)?,
            p.float("w2", None, 0.0)?,
            p.float("w3", None, 0.0)?,
            p.float("w4", None, 0.0)?,
        ],
        size: p.noise_size()?,
        outscale: p.float("outscale", None, 1.0)?,
        coltype: p.int("coltype", None, 0).clamp(0, 3),
    })
}
