//! The volume integrator (`VolumeIntegrator`): how much of the participating media a path
//! tracer renders, with LuxRender's names and default (`emission` when the scene has no
//! statement):
//!
//! - `none`: media are ignored (the world is built without them);
//! - `emission`: rays are attenuated by the media they cross, never scattered (with every
//!   integrator other than `none`, region volumes' emission `Le` is added along the path
//!   segments that cross them: path's every segment, directlighting's eye ray and specular
//!   continuations, as in LuxRender 1.x; bidirectional's every eye subpath segment, which
//!   LuxRender 1.x's bidirectional does not render);
//! - `single`: as emission, plus one scattering event in a medium per path;
//! - `multi`: as many scattering events as the path's depth allows.
//!
//! `stepsize` (default 1) is read for LuxRender's region volumes; heterogeneous media carry
//! their own step. The path integrator asks [`VolumeIntegrator::max_scatters`] per path,
//! bidirectional per subpath (and its weights drop the strategies that would need more),
//! directlighting whether its eye ray may scatter (once, whatever the limit above one).

use crate::lxs::{Diagnostic, Entity};
use crate::plugin::Stmt;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum VolumeIntegrator {
    None,
    #[default]
    Emission,
    Single,
    Multi,
}

impl VolumeIntegrator {
    /// Reads the scene's `VolumeIntegrator` statement; an unknown name warns (located) and
    /// renders as `multi`.
    pub fn build(e: Option<&Entity>, warnings: &mut Vec<Diagnostic>) -> VolumeIntegrator {
        let Some(e) = e else {
            return VolumeIntegrator::Emission;
        };
        let mut s = Stmt::new("VolumeIntegrator", e, warnings);
        s.params().float_or("stepsize", 1.0);
        match e.kind.as_str() {
            "none" => VolumeIntegrator::None,
            "emission" => VolumeIntegrator::Emission,
            "single" => VolumeIntegrator::Single,
            "multi" => VolumeIntegrator::Multi,
            other => {
                s.warn(format!(
                    "unknown VolumeIntegrator \"{other}\" (none, emission, single, multi); \
                     rendering with \"multi\""
                ));
                VolumeIntegrator::Multi
            }
        }
    }

    /// Whether media are rendered at all.
    pub fn renders_media(self) -> bool {
        self != VolumeIntegrator::None
    }

    /// How many times one path may scatter in media.
    pub fn max_scatters(self) -> u32 {
        match self {
            VolumeIntegrator::None | VolumeIntegrator::Emission => 0,
            VolumeIntegrator::Single => 1,
            VolumeIntegrator::Multi => u32::MAX,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn build(kind: &str) -> (VolumeIntegrator, usize) {
        let e = Entity {
            kind: kind.into(),
            ..Default::default()
        };
        let mut w = Vec::new();
        (VolumeIntegrator::build(Some(&e), &mut w), w.len())
    }

    #[test]
    fn names_and_default() {
        assert_eq!(
            VolumeIntegrator::build(None, &mut Vec::new()),
            VolumeIntegrator::Emission
        );
        assert_eq!(build("none"), (VolumeIntegrator::None, 0));
        assert_eq!(build("single").0.max_scatters(), 1);
        assert_eq!(build("multi").0.max_scatters(), u32::MAX);
        assert_eq!(build("emission").0.max_scatters(), 0);
        assert_eq!(build("bogus"), (VolumeIntegrator::Multi, 1));
        assert!(!VolumeIntegrator::None.renders_media());
    }
}
