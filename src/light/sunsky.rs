//! The `sun`, `sky`, `sunsky`, `sky2` and `sunsky2` LightSource plugins of LuxRender 1.x.
//! `sunsky` (`sunsky2`) is both the sun and the Preetham `sky` (the Hosek–Wilkie `sky2`) built
//! from the same parameters (so they share `sundir`, `turbidity`, `gain` and
//! `nsamples`, and the light group), the sun first, as LuxRender's API does it. Note that
//! LuxRender's defaults for a missing `sundir` differ: (0, 0, −1) for the sun (below the
//! horizon: it emits nothing) and (0, 0, 1) for the sky. `L` is not a parameter of these
//! lights (0.x exporters wrote it; it is reported unused).
//!
//! `sunsky2`'s sun is LuxRender's `sun` plugin, as in LuxRender 1.x.

use super::{Light, LightCommon, Sky2Light, SkyLight, SunLight};
use crate::lxs::{Loc, ParamSet};
use crate::plugin::BuildError;
use glam::Mat4;

/// The plugin names handled here.
pub const KINDS: [&str; 5] = ["sun", "sky", "sunsky", "sky2", "sunsky2"];

/// Builds the light(s) of a daylight LightSource (see [`KINDS`]); `None` for other kinds.
pub fn build(
    kind: &str,
    params: &ParamSet,
    l2w: Mat4,
    common: LightCommon,
    loc: &Loc,
) -> Option<Result<Vec<Light>, BuildError>> {
    let err = |m: String| BuildError::new(loc, m);
    let sun = || SunLight::new(params, l2w, common).map(Light::Sun);
    let sky = || SkyLight::new(params, l2w, common).map(|s| Light::Sky(Box::new(s)));
    let sky2 = || Sky2Light::new(params, l2w, common).map(|s| Light::Sky2(Box::new(s)));
    let built = match kind {
        "sun" => sun().map(|l| vec![l]),
        "sky" => sky().map(|l| vec![l]),
        "sunsky" => sun().and_then(|a| Ok(vec![a, sky()?])),
        "sky2" => sky2().map(|l| vec![l]),
        "sunsky2" => sun().and_then(|a| Ok(vec![a, sky2()?])),
        _ => return None,
    };
    Some(built.map_err(err))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lxs::ParamValue;

    fn common() -> LightCommon {
        LightCommon {
            nsamples: 3,
            low_nsamples: 3,
            ..LightCommon::single(2)
        }
    }

    #[test]
    fn sunsky_is_a_sun_and_a_sky_sharing_parameters() {
        let mut ps = ParamSet::new();
        ps.add("sundir", ParamValue::Vector(vec![[0.3, 0.2, 0.8]]));
        ps.add("gain", ParamValue::Float(vec![0.01]));
        ps.add("L", ParamValue::Color(vec![[1.0; 3]]));
        let lights = build("sunsky", &ps, Mat4::IDENTITY, common(), &Loc::default())
            .unwrap()
            .unwrap();
        assert_eq!(lights.len(), 2);
        let (Light::Sun(sun), Light::Sky(sky)) = (&lights[0], &lights[1]) else {
            panic!("expected a sun then a sky");
        };
        assert!((sun.to_light - sky.model.sun).length() < 1e-6);
        assert_eq!(sky.gain(), 0.01);
        for l in &lights {
            assert_eq!(l.group(), 2);
            assert_eq!(l.nsamples(), 3);
            assert!(!l.is_delta() && l.is_infinite());
        }
        assert_eq!(ps.unused().count(), 1, "L is not a sun/sky parameter");
        assert!(build("sky3", &ps, Mat4::IDENTITY, common(), &Loc::default()).is_none());
    }

    #[test]
    fn sunsky2_is_the_sun_and_a_hosek_wilkie_sky() {
        let mut ps = ParamSet::new();
        ps.add("sundir", ParamValue::Vector(vec![[0.0, 0.6, 0.8]]));
        ps.add("turbidity", ParamValue::Float(vec![4.0]));
        let lights = build("sunsky2", &ps, Mat4::IDENTITY, common(), &Loc::default())
            .unwrap()
            .unwrap();
        let (Light::Sun(sun), Light::Sky2(sky)) = (&lights[0], &lights[1]) else {
            panic!("expected a sun then a sky2");
        };
        assert!((sun.to_light - sky.model.sun).length() < 1e-6);
        assert_eq!(ps.unused().count(), 0);
        let sky2 = build("sky2", &ps, Mat4::IDENTITY, common(), &Loc::default())
            .unwrap()
            .unwrap();
        assert!(matches!(sky2.as_slice(), [Light::Sky2(_)]));
    }

    #[test]
    fn bad_parameters_are_located_errors() {
        let mut ps = ParamSet::new();
        ps.add("relsize", ParamValue::Float(vec![0.0]));
        let loc = Loc::default();
        let e = match build("sun", &ps, Mat4::IDENTITY, common(), &loc) {
            Some(Err(e)) => e,
            _ => panic!("relsize 0 must be refused"),
        };
        assert!(e.to_string().contains("relsize"), "{e}");
        let mut ps = ParamSet::new();
        ps.add("sundir", ParamValue::Vector(vec![[0.0; 3]]));
        assert!(matches!(
            build("sky", &ps, Mat4::IDENTITY, common(), &loc),
            Some(Err(_))
        ));
    }
}
