//! `band` texture: a gradient. `offsets` (ascending floats, one per input) place the inputs
//! `tex1`..`texN` (same type as the texture, default 0) along `amount` (a float texture,
//! default 0); below the first offset the first input, from the last one on the last, between
//! two offsets the linear blend of their inputs. Fresnel textures blend n and k. The bump
//! derivative is LuxRender's (which blends the inputs' derivatives by `amount` itself rather
//! than by the position between the two offsets).

use super::{Fresnel, FresnelNode, TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;
use glam::Vec2;
use std::sync::Arc;

/// Where `a` falls: `Err(i)` on input `i` alone, `Ok((i, t))` between inputs `i` and `i + 1`.
fn locate(offsets: &[f32], a: f32) -> Result<(usize, f32), usize> {
    let last = offsets.len().saturating_sub(1);
    if offsets.is_empty() || a < offsets[0] {
        return Err(0);
    }
    if a >= offsets[last] {
        return Err(last);
    }
    let p = offsets.partition_point(|&o| o <= a).clamp(1, last);
    let span = offsets[p] - offsets[p - 1];
    let t = if span > 0.0 {
        (a - offsets[p - 1]) / span
    } else {
        0.0
    };
    Ok((p - 1, t))
}

#[derive(Debug)]
pub struct BandTex {
    pub offsets: Vec<f32>,
    pub tex: Vec<Arc<TexNode>>,
    pub amount: Arc<TexNode>,
}

impl BandTex {
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        match locate(&self.offsets, self.amount.value(si)) {
            Err(i) => self.tex.get(i).map_or(Rgb::BLACK, |t| t.eval(si)),
            Ok((i, t)) => match (self.tex.get(i), self.tex.get(i + 1)) {
                (Some(a), Some(b)) => a.eval(si) * (1.0 - t) + b.eval(si) * t,
                _ => Rgb::BLACK,
            },
        }
    }

    pub fn duv(&self, si: &SurfaceInteraction, delta: f32) -> Vec2 {
        let a = self.amount.value(si);
        match locate(&self.offsets, a) {
            Err(i) => self.tex.get(i).map_or(Vec2::ZERO, |t| t.duv(si, delta)),
            Ok((i, _)) => match (self.tex.get(i), self.tex.get(i + 1)) {
                (Some(t1), Some(t2)) => {
                    let (d1, d2) = (t1.duv(si, delta), t2.duv(si, delta));
                    let d = t2.value(si) - t1.value(si);
                    d1 * (1.0 - a) + d2 * a + self.amount.duv(si, delta) * d
                }
                _ => Vec2::ZERO,
            },
        }
    }
}

/// The offsets, checked: present, finite, ascending (LuxRender only logs a disorder).
fn offsets(set: &mut TextureSet, t: &TextureDesc) -> Result<Vec<f32>, TextureError> {
    let Some(o) = t.entity.params.floats("offsets") else {
        return Err(TextureError::param(
            t,
            "offsets",
            "band needs \"float offsets\" (one per input texture)",
        ));
    };
    if o.is_empty() || o.iter().any(|x| !x.is_finite()) {
        return Err(TextureError::param(
            t,
            "offsets",
            "band offsets must be finite numbers",
        ));
    }
    if o.windows(2).any(|w| w[0] > w[1]) {
        set.warn(
            &super::param_loc(&t.entity.params, "offsets", &t.entity.loc),
            "band offsets are not in ascending order".into(),
        );
    }
    Ok(o.to_vec())
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let offsets = offsets(set, t)?;
    let tex = (1..=offsets.len())
        .map(|i| set.same_type(t, &format!("tex{i}"), 0.0))
        .collect::<Result<Vec<_>, _>>()?;
    let amount = set.float_of(t, "amount", 0.0)?;
    Ok(TexNode::Band(BandTex {
        offsets,
        tex,
        amount,
    }))
}

#[derive(Debug)]
pub struct BandFresnel {
    pub offsets: Vec<f32>,
    pub tex: Vec<Arc<FresnelNode>>,
    pub amount: Arc<TexNode>,
}

impl BandFresnel {
    pub fn eval(&self, si: &SurfaceInteraction) -> Fresnel {
        let zero = Fresnel::dielectric(0.0);
        match locate(&self.offsets, self.amount.value(si)) {
            Err(i) => self.tex.get(i).map_or(zero, |t| t.eval(si)),
            Ok((i, t)) => match (self.tex.get(i), self.tex.get(i + 1)) {
                (Some(a), Some(b)) => Fresnel::lerp(t, a.eval(si), b.eval(si)),
                _ => zero,
            },
        }
    }

    /// The real index at wavelength `nm` (see [`FresnelNode::index_at`]).
    pub fn index_at(&self, si: &SurfaceInteraction, nm: f32) -> f32 {
        match locate(&self.offsets, self.amount.value(si)) {
            Err(i) => self.tex.get(i).map_or(0.0, |t| t.index_at(si, nm)),
            Ok((i, t)) => match (self.tex.get(i), self.tex.get(i + 1)) {
                (Some(a), Some(b)) => a.index_at(si, nm) * (1.0 - t) + b.index_at(si, nm) * t,
                _ => 0.0,
            },
        }
    }
}

pub fn build_fresnel(set: &mut TextureSet, t: &TextureDesc) -> Result<FresnelNode, TextureError> {
    let offsets = offsets(set, t)?;
    let tex = (1..=offsets.len())
        .map(|i| set.fresnel_node_param(&t.entity.params, &format!("tex{i}"), 0.0))
        .collect::<Result<Vec<_>, _>>()?;
    let amount = set.float_of(t, "amount", 0.0)?;
    Ok(FresnelNode::Band(BandFresnel {
        offsets,
        tex,
        amount,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locate_between_offsets() {
        let o = [0.0, 0.33, 0.66, 1.0];
        assert_eq!(locate(&o, -0.1), Err(0));
        assert_eq!(locate(&o, 1.0), Err(3));
        let (i, t) = locate(&o, 0.5).unwrap();
        assert_eq!(i, 1);
        assert!((t - 0.17 / 0.33).abs() < 1e-6);
        assert_eq!(locate(&o, 0.0), Ok((0, 0.0)));
        assert_eq!(locate(&[0.5], 0.7), Err(0));
    }
}
