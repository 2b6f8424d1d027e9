//! `velvet`: asperity scattering (see [`super::bxdf::asperity`]) with LuxRender 1.x's
//! parameters: `Kd` (default 0.3, clamped to [0, 1]), the phase polynomial `p1` (-2), `p2`
//! (20), `p3` (2), each clamped to [-100, 100], and the fuzz `thickness` (0.1, clamped to
//! [0, 1]). (LuxRender's scene-format page gives Kd 1; its sources use 0.3.)

use super::bsdf::Lobes;
use super::bxdf::asperity::Asperity;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{ColorTex, FloatTex};

#[derive(Debug)]
pub struct Velvet {
    pub kd: ColorTex,
    pub p1: FloatTex,
    pub p2: FloatTex,
    pub p3: FloatTex,
    pub thickness: FloatTex,
}

impl Velvet {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Velvet, MaterialError> {
        let p = &e.params;
        let t = &mut b.textures;
        Ok(Velvet {
            kd: t.color_param(p, "Kd", Rgb::splat(0.3))?,
            p1: t.float_param(p, "p1", -2.0)?,
            p2: t.float_param(p, "p2", 20.0)?,
            p3: t.float_param(p, "p3", 2.0)?,
            thickness: t.float_param(p, "thickness", 0.1)?,
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let c = |v: f32| v.clamp(-100.0, 100.0);
        Lobes::Velvet(Asperity {
            r: self.kd.eval(si).map(|v| v.clamp(0.0, 1.0)),
            a1: c(self.p1.eval(si)),
            a2: c(self.p2.eval(si)),
            a3: c(self.p3.eval(si)),
            thickness: self.thickness.eval(si).clamp(0.0, 1.0),
        })
    }
}
