//! The float/colour texture tree: [`TexNode`] and its two evaluations, the value at a hit
//! ([`TexNode::eval`]) and the derivatives with respect to the surface (u, v) that bump
//! mapping reads ([`TexNode::duv`], LuxRender's `GetDuv`). Each variant is implemented in the
//! file of its texture; arithmetic nodes (scale, add, subtract) are evaluated here.
//!
//! Derivatives follow LuxRender texture by texture: exact ones for image maps, mappings and
//! the arithmetic and blending nodes; for procedural 3D patterns LuxRender's generic finite
//! difference ([`generic_duv`]): the hit is moved `delta` world units along the shading
//! tangent `dpdu` (so `delta / |dpdu|` in u) and the change divided by that step in u. The
//! derivatives are of the texture's float value (its first channel).

use super::{
    band, bilerp, blender, brick, checkerboard, cloud, colordepth, dots, fbm, harlequin,
    hitpointalpha, hitpointcolor, hitpointgrey, imagemap, marble, mix, multimix, normalmap,
    spectral, uv, uvmask, windy, wrinkled,
};
use crate::geometry::SurfaceInteraction;
use crate::spectrum::Rgb;
use glam::Vec2;
use std::sync::Arc;

/// One node of a float or colour texture tree.
#[derive(Debug)]
pub enum TexNode {
    Const(Rgb),
    Image(imagemap::ImageTex),
    NormalMap(normalmap::NormalMapTex),
    Scale(Arc<TexNode>, Arc<TexNode>),
    Mix(mix::MixTex),
    Add(Arc<TexNode>, Arc<TexNode>),
    Subtract(Arc<TexNode>, Arc<TexNode>),
    Band(band::BandTex),
    Bilerp(bilerp::BilerpTex),
    MultiMix(multimix::MultiMixTex),
    Checker2D(checkerboard::Checker2D),
    Checker3D(checkerboard::Checker3D),
    Dots(dots::DotsTex),
    Brick(Box<brick::BrickTex>),
    UvMask(uvmask::UvMaskTex),
    Uv(uv::UvTex),
    Fbm(fbm::FbmTex),
    Wrinkled(wrinkled::WrinkledTex),
    Windy(windy::WindyTex),
    Marble(marble::MarbleTex),
    Cloud(Box<cloud::CloudTex>),
    Harlequin(harlequin::HarlequinTex),
    HitpointColor(hitpointcolor::HitpointColor),
    HitpointAlpha(hitpointalpha::HitpointAlpha),
    HitpointGrey(hitpointgrey::HitpointGrey),
    ColorDepth(colordepth::ColorDepthTex),
    /// A colour converted from spectral data at build time; the data is kept.
    Spectral(spectral::SpectralTex),
    Blender(Box<blender::BlenderTex>),
}

impl TexNode {
    /// The value at a hit (three equal channels for float textures).
    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        match self {
            TexNode::Const(c) => *c,
            TexNode::Image(t) => t.eval(si),
            TexNode::NormalMap(t) => t.eval(si),
            TexNode::Scale(a, b) => a.eval(si) * b.eval(si),
            TexNode::Mix(m) => m.eval(si),
            TexNode::Add(a, b) => a.eval(si) + b.eval(si),
            TexNode::Subtract(a, b) => a.eval(si) - b.eval(si),
            TexNode::Band(t) => t.eval(si),
            TexNode::Bilerp(t) => t.eval(si),
            TexNode::MultiMix(t) => t.eval(si),
            TexNode::Checker2D(c) => c.eval(si),
            TexNode::Checker3D(c) => c.eval(si),
            TexNode::Dots(t) => t.eval(si),
            TexNode::Brick(t) => t.eval(si),
            TexNode::UvMask(t) => t.eval(si),
            TexNode::Uv(u) => u.eval(si),
            TexNode::Fbm(t) => Rgb::splat(t.value(si)),
            TexNode::Wrinkled(t) => Rgb::splat(t.value(si)),
            TexNode::Windy(t) => Rgb::splat(t.value(si)),
            TexNode::Marble(t) => t.eval(si),
            TexNode::Cloud(t) => Rgb::splat(t.value(si)),
            TexNode::Harlequin(t) => t.eval(si),
            TexNode::HitpointColor(t) => t.eval(si),
            TexNode::HitpointAlpha(t) => Rgb::splat(t.value(si)),
            TexNode::HitpointGrey(t) => Rgb::splat(t.value(si)),
            TexNode::ColorDepth(t) => t.eval(si),
            TexNode::Spectral(t) => t.rgb,
            TexNode::Blender(t) => Rgb::splat(t.value(si)),
        }
    }

    /// The float value at a hit (the first channel).
    #[inline]
    pub fn value(&self, si: &SurfaceInteraction) -> f32 {
        match self {
            TexNode::Const(c) => c.r,
            other => other.eval(si).r,
        }
    }

    /// The constant value when the node does not vary.
    pub fn as_const(&self) -> Option<Rgb> {
        match self {
            TexNode::Const(c) => Some(*c),
            TexNode::Spectral(t) => Some(t.rgb),
            _ => None,
        }
    }

    /// Derivatives of the float value with respect to the surface (u, v), LuxRender's
    /// `GetDuv` with sample distance `delta` (see the module documentation).
    pub fn duv(&self, si: &SurfaceInteraction, delta: f32) -> Vec2 {
        match self {
            TexNode::Const(_)
            | TexNode::Harlequin(_)
            | TexNode::HitpointColor(_)
            | TexNode::HitpointAlpha(_)
            | TexNode::HitpointGrey(_)
            | TexNode::ColorDepth(_)
            | TexNode::Spectral(_) => Vec2::ZERO,
            TexNode::Image(t) => t.duv(si),
            TexNode::NormalMap(t) => t.duv(si),
            TexNode::Scale(a, b) => a.duv(si, delta) * b.value(si) + a.value(si) * b.duv(si, delta),
            TexNode::Mix(m) => m.duv(si, delta),
            TexNode::Add(a, b) => a.duv(si, delta) + b.duv(si, delta),
            TexNode::Subtract(a, b) => a.duv(si, delta) - b.duv(si, delta),
            TexNode::Band(t) => t.duv(si, delta),
            TexNode::Bilerp(t) => t.duv(si),
            TexNode::MultiMix(t) => t.duv(si, delta),
            TexNode::Checker2D(c) => c.duv(si, delta),
            TexNode::Checker3D(c) => c.duv(si, delta),
            TexNode::UvMask(t) => t.duv(si, delta),
            TexNode::Blender(t) => t.duv(si, delta),
            TexNode::Dots(_)
            | TexNode::Brick(_)
            | TexNode::Uv(_)
            | TexNode::Fbm(_)
            | TexNode::Wrinkled(_)
            | TexNode::Windy(_)
            | TexNode::Marble(_)
            | TexNode::Cloud(_) => generic_duv(self, si, delta),
        }
    }
}

/// LuxRender's generic texture derivative: finite differences of the float value over
/// `delta` world units along the shading tangents, with (u, v) moved accordingly.
pub fn generic_duv(node: &TexNode, si: &SurfaceInteraction, delta: f32) -> Vec2 {
    let base = node.value(si);
    let step = |dir: glam::Vec3A, axis: Vec2| -> f32 {
        let len = dir.length();
        if !(len > 0.0 && delta > 0.0) {
            return 0.0;
        }
        let h = delta / len;
        let mut moved = *si;
        moved.it.p += dir * h;
        moved.uv += axis * h;
        let d = (node.value(&moved) - base) / h;
        if d.is_finite() {
            d
        } else {
            0.0
        }
    };
    Vec2::new(
        step(si.shading.dpdu, Vec2::X),
        step(si.shading.dpdv, Vec2::Y),
    )
}
