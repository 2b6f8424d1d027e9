//! `doubleside`: one material on the front of a surface (the side of its geometric normal)
//! and another on the back. `frontnamedmaterial` and `backnamedmaterial` (both required);
//! `usefrontforfront` (default true) shows the front material's front face on the front,
//! false shows its back face; `usefrontforback` (default true) shows the back material's
//! front face on the back (its BSDF is built with the normals flipped), false its back face.
//! Each side is the chosen material's own BSDF, so light does not cross (as in LuxRender,
//! transmission is not supported across the two sides).

use super::bsdf::composite::Composite;
use super::bsdf::Lobes;
use super::{Builder, Material, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use std::sync::Arc;

#[derive(Debug)]
pub struct DoubleSide {
    pub front: Arc<Material>,
    pub back: Arc<Material>,
    pub front_for_front: bool,
    pub front_for_back: bool,
}

/// The hit seen from the other side: geometric and shading normals reversed.
fn flipped(si: &SurfaceInteraction) -> SurfaceInteraction {
    let mut f = *si;
    f.it.n = -f.it.n;
    f.shading.n = -f.shading.n;
    f
}

impl DoubleSide {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<DoubleSide, MaterialError> {
        let front = b.required_named(e, "frontnamedmaterial")?;
        let back = b.required_named(e, "backnamedmaterial")?;
        Ok(DoubleSide {
            front,
            back,
            front_for_front: e.params.bool_or("usefrontforfront", true),
            front_for_back: e.params.bool_or("usefrontforback", true),
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction, u_select: f32) -> Lobes {
        let front = if self.front_for_front {
            self.front.bsdf(si, u_select)
        } else {
            self.front.bsdf(&flipped(si), u_select)
        };
        let back = if self.front_for_back {
            self.back.bsdf(&flipped(si), u_select)
        } else {
            self.back.bsdf(si, u_select)
        };
        Lobes::Composite(Box::new(Composite::DoubleSide { front, back }))
    }
}
