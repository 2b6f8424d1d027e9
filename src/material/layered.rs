//! `layered`: up to four named materials stacked as separate surfaces, `namedmaterial1` (the
//! base, facing the side of the geometric normal first) to `namedmaterial4`, each optional,
//! with `opacity1`–`opacity4` (float textures, default 1, clamped to [0, 1]): a layer lets
//! `1 - opacity` of the light through unchanged, and a layer of opacity 0 is left out. A stack
//! without layers is a null surface. See [`super::bsdf::composite::layered`] for the stochastic
//! estimator LuxRender uses (LuxRender calls the material experimental).

use super::bsdf::composite::{layered, Composite};
use super::bsdf::{Bsdf, Lobes};
use super::{Builder, Material, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::texture::FloatTex;
use std::sync::Arc;

#[derive(Debug)]
pub struct Layered {
    pub layers: Vec<(Arc<Material>, FloatTex)>,
}

/// A 64-bit seed from the hit (its uv and the per-hit random number).
fn hit_seed(si: &SurfaceInteraction, u: f32) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for x in [u, si.uv.x, si.uv.y, si.it.p.x, si.it.p.y, si.it.p.z] {
        h = (h ^ x.to_bits() as u64).wrapping_mul(0x100_0000_01b3);
    }
    h
}

impl Layered {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Layered, MaterialError> {
        let mut layers = Vec::new();
        for i in 1..=4 {
            let m = b.optional_named(e, &format!("namedmaterial{i}"))?;
            let op = b
                .textures
                .float_param(&e.params, &format!("opacity{i}"), 1.0)?;
            if let Some(m) = m {
                layers.push((m, op));
            }
        }
        Ok(Layered { layers })
    }

    pub fn lobes(&self, si: &SurfaceInteraction, u_select: f32) -> Lobes {
        let seed = hit_seed(si, u_select);
        let mut bsdfs: Vec<Bsdf> = Vec::with_capacity(self.layers.len());
        for (i, (m, op)) in self.layers.iter().enumerate() {
            let op = op.eval(si).clamp(0.0, 1.0);
            if op <= 0.0 {
                continue;
            }
            // Each layer gets its own selector for mix components.
            let u = ((seed >> (8 * i)) & 0xff_ffff) as f32 / (1u32 << 24) as f32;
            let b = m.bsdf(si, u);
            bsdfs.push(if op < 1.0 {
                Bsdf::new(
                    si,
                    Lobes::Composite(Box::new(Composite::Opacity {
                        bsdf: b,
                        opacity: op,
                    })),
                )
            } else {
                b
            });
        }
        if bsdfs.is_empty() {
            return Lobes::Null;
        }
        Lobes::Composite(Box::new(Composite::Layered(layered::Layered {
            layers: bsdfs,
            seed,
        })))
    }
}
