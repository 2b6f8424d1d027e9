//! `brick` texture: masonry over a 3D mapping, LuxRender's pattern. `brickbond` (`stacked`,
//! the default, `running`, `flemish`, `english`, `herringbone`, `basket`, `chain link`),
//! `brickwidth` 0.3, `brickheight` 0.1, `brickdepth` 0.15, `mortarsize` 0.01, `brickrun` 0.75
//! (the row offset of running bonds; stacked uses 0, english 0.25, chain link 1.25),
//! `brickbevel` 0 (read; LuxRender does not draw bevels either), `bricktex` (default 1) times
//! `brickmodtex` (default 1, evaluated at the brick's index, so each brick can get its own
//! value) on the bricks, `mortartex` (default 0.2) in the joints. Herringbone and basket use
//! square cells of `brickwidth` split in ⌊width/height⌋ strips.

use super::mapping::Mapping3D;
use super::{param_loc, TexNode, TextureError, TextureSet};
use crate::geometry::SurfaceInteraction;
use crate::lxs::TextureDesc;
use crate::spectrum::Rgb;
use glam::Vec3A;
use std::sync::Arc;

pub const DEFAULT_BOND: &str = "stacked";
const EPSILON: f32 = 1e-3;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bond {
    Running,
    Flemish,
    English,
    Herringbone,
    Basket,
    ChainLink,
}

#[derive(Debug)]
pub struct BrickTex {
    pub mapping: Mapping3D,
    pub bond: Bond,
    /// Added to the normalised point (LuxRender's per-bond `offset`).
    pub offset: Vec3A,
    pub size: Vec3A,
    pub mortar_size: f32,
    pub run: f32,
    /// Mortar width relative to the brick: x, y (depth), z (height).
    pub mortar: Vec3A,
    pub proportion: f32,
    pub inv_proportion: f32,
    pub brick: Arc<TexNode>,
    pub mortar_tex: Arc<TexNode>,
    pub modulation: Arc<TexNode>,
}

/// LuxRender's `fmodf` (the sign of the dividend).
fn fmod(a: f32, b: f32) -> f32 {
    a % b
}

impl BrickTex {
    /// Whether normalised point `p` is on a brick, and the brick's index.
    pub fn locate(&self, p: Vec3A) -> (bool, Vec3A) {
        match self.bond {
            Bond::Running => self.running(p),
            Bond::Flemish => self.running_alternate(p, 1.0),
            Bond::ChainLink => self.running_alternate(p, 2.0),
            Bond::English => self.english(p),
            Bond::Herringbone => self.herringbone(p),
            Bond::Basket => self.basket(p),
        }
    }

    fn on_brick(&self, b: Vec3A) -> bool {
        b.z > self.mortar.z && b.y > self.mortar.y && b.x > self.mortar.x
    }

    fn running(&self, p: Vec3A) -> (bool, Vec3A) {
        let iz = p.z.floor();
        let bx = p.x + iz * self.run;
        let by = p.y - iz * self.run;
        let i = Vec3A::new(bx.floor(), by.floor(), iz);
        let b = Vec3A::new(bx - i.x, by - i.y, p.z - iz);
        (self.on_brick(b), i)
    }

    fn running_alternate(&self, p: Vec3A, whole: f32) -> (bool, Vec3A) {
        let sub = whole + 0.5;
        let rsub = sub.ceil();
        let iz = p.z.floor();
        let mut bx = (p.x + iz * self.run) / sub;
        let mut by = (p.y + iz * self.run) / sub;
        let mut i = Vec3A::new(bx.floor(), by.floor(), iz);
        bx = (bx - i.x) * sub;
        by = (by - i.y) * sub;
        let bz = (p.z - iz) * sub;
        i.x += bx.floor() / rsub;
        i.y += by.floor() / rsub;
        bx -= bx.floor();
        by -= by.floor();
        (self.on_brick(Vec3A::new(bx, by, bz)), i)
    }

    fn english(&self, p: Vec3A) -> (bool, Vec3A) {
        let iz = p.z.floor();
        let bx = p.x + iz * self.run;
        let by = p.y - iz * self.run;
        let i = Vec3A::new(bx.floor(), by.floor(), iz);
        let bz = p.z - iz;
        let divider = fmod(iz.abs(), 2.0).floor() + 1.0;
        let bx = (divider * bx - (divider * bx).floor()) / divider;
        let by = (divider * by - (divider * by).floor()) / divider;
        (self.on_brick(Vec3A::new(bx, by, bz)), i)
    }

    fn herringbone(&self, p: Vec3A) -> (bool, Vec3A) {
        let (prop, inv) = (self.proportion, self.inv_proportion);
        let mut iy = (prop * p.y).floor();
        let px = p.x + iy * inv;
        let ix = px.floor();
        let mut bx = 2.0 * (0.5 * px - (px * 0.5).floor());
        let mut by = (prop * p.y - (prop * p.y).floor()) * inv;
        if bx > 1.0 + inv {
            bx = prop * (bx - 1.0);
            iy -= (bx - 1.0).floor();
            bx -= bx.floor();
            bx *= inv;
            by = 1.0;
        } else if bx > 1.0 {
            bx = prop * (bx - 1.0);
            iy -= (bx - 1.0).floor();
            bx -= bx.floor();
            bx *= inv;
        }
        let on = by > self.mortar.z && bx > self.mortar.x;
        (on, Vec3A::new(ix, iy, 0.0))
    }

    fn basket(&self, p: Vec3A) -> (bool, Vec3A) {
        let mut i = Vec3A::new(p.x.floor(), p.y.floor(), 0.0);
        let mut bx = p.x - i.x;
        let mut by = p.y - i.y;
        i.x += i.y - 2.0 * (0.5 * i.y).floor();
        let split = (i.x - 2.0 * (0.5 * i.x).floor()) < 1.0;
        if split {
            bx = fmod(bx, self.inv_proportion);
            i.x = (self.proportion * p.x).floor() * self.inv_proportion;
        } else {
            by = fmod(by, self.inv_proportion);
            i.y = (self.proportion * p.y).floor() * self.inv_proportion;
        }
        (by > self.mortar.y && bx > self.mortar.x, i)
    }

    pub fn eval(&self, si: &SurfaceInteraction) -> Rgb {
        let p = self.mapping.map(si);
        let offs = EPSILON + self.mortar_size;
        let bp = (p + Vec3A::splat(offs)) / self.size + self.offset;
        let (on, index) = self.locate(bp);
        if on {
            let mut at = *si;
            at.it.p = index;
            self.brick.eval(si) * self.modulation.eval(&at)
        } else {
            self.mortar_tex.eval(si)
        }
    }
}

pub fn build(set: &mut TextureSet, t: &TextureDesc) -> Result<TexNode, TextureError> {
    let p = &t.entity.params;
    let bond_name = p.string_or("brickbond", DEFAULT_BOND).to_string();
    let mut run = p.float_or("brickrun", 0.75);
    let mut offset = Vec3A::ZERO;
    let bond = match bond_name.as_str() {
        "stacked" => {
            run = 0.0;
            Bond::Running
        }
        "running" => {
            offset = Vec3A::new(0.0, -0.5, 0.0);
            Bond::Running
        }
        "flemish" => Bond::Flemish,
        "english" => {
            run = 0.25;
            Bond::English
        }
        "herringbone" => Bond::Herringbone,
        "basket" => Bond::Basket,
        "chain link" => {
            run = 1.25;
            offset = Vec3A::new(0.25, -1.0, 0.0);
            Bond::ChainLink
        }
        other => {
            set.warn(
                &param_loc(p, "brickbond", &t.entity.loc),
                format!("unknown brickbond \"{other}\": running bond, as LuxRender uses"),
            );
            offset = Vec3A::new(0.0, -0.5, 0.0);
            Bond::Running
        }
    };
    let mut w = p.float_or("brickwidth", 0.3);
    let mut h = p.float_or("brickheight", 0.1);
    let mut d = p.float_or("brickdepth", 0.15);
    let mortar_size = p.float_or("mortarsize", 0.01);
    let _bevel = p.float_or("brickbevel", 0.0);
    for (name, v) in [("brickwidth", w), ("brickheight", h), ("brickdepth", d)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(TextureError::param(
                t,
                name,
                format!("brick {name} must be positive, got {v}"),
            ));
        }
    }
    if !(mortar_size.is_finite() && run.is_finite()) {
        return Err(TextureError::param(
            t,
            "mortarsize",
            "mortarsize and brickrun must be finite",
        ));
    }
    let (mut proportion, mut inv_proportion) = (1.0, 1.0);
    if matches!(bond, Bond::Herringbone | Bond::Basket) {
        proportion = (w / h).floor().max(1.0);
        inv_proportion = 1.0 / proportion;
        d = w;
        h = w;
    }
    let brick = set.same_type(t, "bricktex", 1.0)?;
    let mortar_tex = set.same_type(t, "mortartex", 0.2)?;
    let modulation = set.same_type(t, "brickmodtex", 1.0)?;
    let mapping = set.mapping3d(t);
    w = w.max(f32::MIN_POSITIVE);
    Ok(TexNode::Brick(Box::new(BrickTex {
        mapping,
        bond,
        offset,
        size: Vec3A::new(w, d, h),
        mortar_size,
        run,
        mortar: Vec3A::new(mortar_size / w, mortar_size / d, mortar_size / h),
        proportion,
        inv_proportion,
        brick,
        mortar_tex,
        modulation,
    })))
}
