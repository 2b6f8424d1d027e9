//! `velvet`: asperity scattering with `Kd` (default 0.3, clamped), `p1` (2), `p2` (10), `p3`
//! and `thickness` (0.1, clamped to [0, 1]); p1–p3 are clamped to [0, 100]. LuxRender reads
//! the third coefficient from the parameter named `p2` (default 2), and so do we, for
//! identical renders: a `p3` parameter is reported unused, as LuxRender does.

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
            p1: t.float_param(p, "p1", 2.0)?,
            p2: t.float_param(p, "p2", 10.0)?,
            p3: if p.contains("p2") {
                t.float_param(p, "p2", 2.0)?
            } else {
                FloatTex::constant(2.0)
            },
            thickness: t.float_param(p, "thickness", 0.1)?,
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        let c = |v: f32| v.clamp(0.0, 100.0);
        Lobes::Velvet(Asperity {
            r: self.kd.eval(si).map(|v| v.clamp(0.0, 1.0)),
            a1: c(self.p1.eval(si)),
            a2: c(self.p2.eval(si)),
            a3: c(self.p3.eval(si)),
            thickness: self.thickness.eval(si).clamp(0.0, 1.0),
        })
    }
}
