//! The `compo_*` parameters every LuxRender material accepts (read by its distributedpath
//! integrator for compositing passes):
//!
//! | parameter | default | meaning |
//! | --- | --- | --- |
//! | `compo_visible_material` | true | seen directly by the camera (false: alpha 0, no light) |
//! | `compo_visible_emission` | true | its area light seen directly |
//! | `compo_visible_indirect_material` | true | seen after a bounce |
//! | `compo_visible_indirect_emission` | true | its area light seen after a bounce |
//! | `compo_override_alpha` | false | camera hits set alpha to `compo_override_alpha_value` (0) |
//!
//! [`Compositing::camera_hit`] and [`Compositing::indirect_hit`] say what a hit contributes,
//! as LuxRender's distributedpath applies the flags.

use crate::lxs::ParamSet;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Compositing {
    pub visible_material: bool,
    pub visible_emission: bool,
    pub visible_indirect_material: bool,
    pub visible_indirect_emission: bool,
    /// `compo_override_alpha_value` when `compo_override_alpha` is set.
    pub override_alpha: Option<f32>,
}

impl Default for Compositing {
    fn default() -> Compositing {
        Compositing {
            visible_material: true,
            visible_emission: true,
            visible_indirect_material: true,
            visible_indirect_emission: true,
            override_alpha: None,
        }
    }
}

/// What a hit on a material contributes to a compositing render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HitVisibility {
    /// Whether the area light of the hit (if any) is added.
    pub emission: bool,
    /// Whether the surface scatters light (false: the path ends here).
    pub material: bool,
    /// The sample's alpha when it is set by the hit.
    pub alpha: Option<f32>,
}

impl Compositing {
    pub fn read(p: &ParamSet) -> Compositing {
        let d = Compositing::default();
        let override_alpha = p.bool_or("compo_override_alpha", false);
        let value = p.float_or("compo_override_alpha_value", 0.0);
        Compositing {
            visible_material: p.bool_or("compo_visible_material", d.visible_material),
            visible_emission: p.bool_or("compo_visible_emission", d.visible_emission),
            visible_indirect_material: p.bool_or(
                "compo_visible_indirect_material",
                d.visible_indirect_material,
            ),
            visible_indirect_emission: p.bool_or(
                "compo_visible_indirect_emission",
                d.visible_indirect_emission,
            ),
            override_alpha: override_alpha.then_some(value),
        }
    }

    /// Whether every flag has its default (nothing to apply).
    pub fn is_default(&self) -> bool {
        *self == Compositing::default()
    }

    /// A hit of a camera ray: an overridden alpha wins; an invisible material gives alpha 0.
    pub fn camera_hit(&self) -> HitVisibility {
        let alpha = match (self.override_alpha, self.visible_material) {
            (Some(a), _) => Some(a),
            (None, false) => Some(0.0),
            (None, true) => None,
        };
        HitVisibility {
            emission: self.visible_emission,
            material: self.visible_material,
            alpha,
        }
    }

    /// A hit after one or more bounces.
    pub fn indirect_hit(&self) -> HitVisibility {
        HitVisibility {
            emission: self.visible_indirect_emission,
            material: self.visible_indirect_material,
            alpha: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lxs::ParamValue;

    #[test]
    fn flags_read_with_luxrender_defaults_and_apply_like_distributedpath() {
        let p = ParamSet::new();
        let c = Compositing::read(&p);
        assert!(c.is_default());
        assert_eq!(
            c.camera_hit(),
            HitVisibility {
                emission: true,
                material: true,
                alpha: None
            }
        );
        let mut p = ParamSet::new();
        p.add("compo_visible_material", ParamValue::Bool(vec![false]));
        p.add(
            "compo_visible_indirect_emission",
            ParamValue::Bool(vec![false]),
        );
        let c = Compositing::read(&p);
        assert_eq!(c.camera_hit().alpha, Some(0.0));
        assert!(!c.camera_hit().material && c.camera_hit().emission);
        assert!(c.indirect_hit().material && !c.indirect_hit().emission);
        p.add("compo_override_alpha", ParamValue::Bool(vec![true]));
        p.add("compo_override_alpha_value", ParamValue::Float(vec![0.25]));
        let c = Compositing::read(&p);
        assert_eq!(c.camera_hit().alpha, Some(0.25));
        assert!(
            p.unused().next().is_none(),
            "all compo parameters are consumed"
        );
    }
}
