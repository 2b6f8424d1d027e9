//! `mirror`: perfect specular reflection of `Kr` (default 1, clamped to [0, 1]) with an
//! optional thin film: `film` (thickness in nm, float texture, default 0 = none) of index
//! `filmindex` (default 1.5); see [`super::bxdf::thin_film`]. [`FilmParams`] is shared with
//! glass and shinymetal.

use super::bsdf::Lobes;
use super::bxdf::specular::SpecularReflection;
use super::bxdf::thin_film::ThinFilm;
use super::{Builder, MaterialError};
use crate::geometry::SurfaceInteraction;
use crate::lxs::Entity;
use crate::spectrum::Rgb;
use crate::texture::{ColorTex, FloatTex};

/// The `film` and `filmindex` parameters.
#[derive(Debug)]
pub struct FilmParams {
    pub thickness: FloatTex,
    pub index: FloatTex,
}

impl FilmParams {
    pub fn read(b: &mut Builder, e: &Entity) -> Result<FilmParams, MaterialError> {
        Ok(FilmParams {
            thickness: b.textures.float_param(&e.params, "film", 0.0)?,
            index: b.textures.float_param(&e.params, "filmindex", 1.5)?,
        })
    }

    /// The film at a hit (`None` when its thickness is 0).
    pub fn eval(&self, si: &SurfaceInteraction) -> Option<ThinFilm> {
        if self.thickness.as_const() == Some(0.0) {
            return None;
        }
        ThinFilm::new(self.thickness.eval(si), self.index.eval(si))
    }
}

#[derive(Debug)]
pub struct Mirror {
    pub kr: ColorTex,
    pub film: FilmParams,
}

impl Mirror {
    pub fn build(b: &mut Builder, e: &Entity) -> Result<Mirror, MaterialError> {
        Ok(Mirror {
            kr: b.textures.color_param(&e.params, "Kr", Rgb::WHITE)?,
            film: FilmParams::read(b, e)?,
        })
    }

    pub fn lobes(&self, si: &SurfaceInteraction) -> Lobes {
        Lobes::Mirror(SpecularReflection {
            kr: self.kr.eval(si).map(|v| v.clamp(0.0, 1.0)),
            fresnel: None,
            film: self.film.eval(si),
        })
    }
}
