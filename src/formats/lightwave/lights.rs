//! LightWave lights as LuxRender lights, and the backdrop and ambient light as an environment.
//!
//! ```text
//! LightItem + its frame at the evaluated time
//!   distant -> LightSource "distant" (from, to)        point -> "point" (from)
//!   spot    -> "spot" (from, to, coneangle, conedeltaangle)
//!   area    -> a square AreaLightSource mesh (1 m, scaled by the item, facing its +Z)
//!   linear  -> a thin area light along the item's X axis (with a warning)
//! Globals (backdrop, ambient) -> LightSource "infinite" L
//! ```
//!
//! Brightness: LightWave lights a white diffuse surface facing a 100% light at full white,
//! without LuxRender's 1/π of a Lambertian surface, so every light's colour × intensity is
//! multiplied by π. LightWave lights do not fall off unless asked: falloff types map onto
//! luxfarm's `falloffexponent` k (intensity / d^k) exactly for none (k = 0), inverse distance
//! (k = 1, × range) and inverse square (k = 2, × range²); linear falloff ((r − d)/r inside
//! the range) has no exact counterpart and is approximated by inverse distance matched at half
//! the range, with a warning. Area and linear lights emit radiance π·I/area so that, seen from
//! afar along their axis, they match a point light of the same intensity with inverse-square
//! falloff at 1 m (approximate, warned once).

use super::coords::swap_yz;
use super::items::{Globals, LightItem, LightKind};
use super::material::{color, float};
use crate::lxs::{Loc, ParamSet, ParamValue};
use glam::{DMat4, DVec3};
use std::f64::consts::PI;

/// A light to declare.
#[derive(Clone, Debug, PartialEq)]
pub enum LightOut {
    /// `LightSource kind params` in world space.
    Delta {
        kind: &'static str,
        params: ParamSet,
    },
    /// An emitting mesh: `AreaLightSource "area" area`, then `Shape "trianglemesh" mesh`
    /// (world space), once per emitting side.
    Area {
        area: ParamSet,
        meshes: Vec<ParamSet>,
    },
}

/// The light `l` placed by `frame` (LightWave space) at `time`.
pub fn light(
    l: &LightItem,
    frame: &DMat4,
    time: f64,
    double_sided_area: bool,
    warnings: &mut Vec<(Loc, String)>,
) -> Option<LightOut> {
    let rgb = [0, 1, 2].map(|i| l.color[i].at(time));
    let intensity = l.intensity.at(time);
    let scaled = rgb.map(|c| (c * intensity * PI) as f32);
    if scaled.iter().all(|&c| c == 0.0) {
        return None;
    }
    let at = l.kind.1.clone().unwrap_or_else(|| l.common.loc.clone());
    let pos = frame.transform_point3(DVec3::ZERO);
    let fwd = frame.transform_vector3(DVec3::Z).normalize_or(DVec3::Z);
    let from = swap_yz(pos).to_array().map(|v| v as f32);
    let to = swap_yz(pos + fwd).to_array().map(|v| v as f32);
    let mut ps = ParamSet::new();
    match l.kind.0 {
        LightKind::Distant => {
            ps.add("L", color(scaled));
            ps.add("from", ParamValue::Point(vec![from]));
            ps.add("to", ParamValue::Point(vec![to]));
            Some(LightOut::Delta {
                kind: "distant",
                params: ps,
            })
        }
        LightKind::Point | LightKind::Spot => {
            let (k, gain) = falloff(l, time, warnings);
            ps.add("L", color(scaled));
            ps.add("gain", float(gain as f32));
            ps.add("falloffexponent", float(k));
            ps.add("from", ParamValue::Point(vec![from]));
            if l.kind.0 == LightKind::Point {
                return Some(LightOut::Delta {
                    kind: "point",
                    params: ps,
                });
            }
            let cone = l.cone_deg.at(time).clamp(0.0, 90.0);
            let edge = l.edge_deg.at(time).clamp(0.0, cone);
            ps.add("to", ParamValue::Point(vec![to]));
            ps.add("coneangle", float(cone as f32));
            ps.add("conedeltaangle", float(edge as f32));
            Some(LightOut::Delta {
                kind: "spot",
                params: ps,
            })
        }
        LightKind::Area | LightKind::Linear => {
            if l.kind.0 == LightKind::Linear {
                warnings.push((
                    at.clone(),
                    format!(
                        "light \"{}\": a linear light is rendered as a thin area light",
                        l.common.name
                    ),
                ));
            }
            warnings.push((
                at,
                format!(
                    "light \"{}\": area light brightness is approximate",
                    l.common.name
                ),
            ));
            let half_h = if l.kind.0 == LightKind::Linear {
                0.005
            } else {
                0.5
            };
            let corners = [
                [-0.5, -half_h],
                [0.5, -half_h],
                [0.5, half_h],
                [-0.5, half_h],
            ]
            .map(|[x, y]| frame.transform_point3(DVec3::new(x, y, 0.0)));
            let area = (corners[1] - corners[0])
                .cross(corners[3] - corners[0])
                .length();
            if area <= 0.0 || !area.is_finite() {
                return None;
            }
            let mut a = ParamSet::new();
            a.add("L", color(scaled.map(|c| c / area as f32)));
            a.add("power", float(0.0));
            a.add("efficacy", float(0.0));
            let p: Vec<[f32; 3]> = corners
                .iter()
                .map(|c| swap_yz(*c).to_array().map(|v| v as f32))
                .collect();
            // Emits towards the light's +Z: LightWave clockwise order reversed by the swap.
            let front = quad(&p, [0, 3, 2, 0, 2, 1]);
            let mut meshes = vec![front];
            if double_sided_area {
                meshes.push(quad(&p, [0, 1, 2, 0, 2, 3]));
            }
            Some(LightOut::Area { area: a, meshes })
        }
    }
}

fn quad(p: &[[f32; 3]], idx: [i32; 6]) -> ParamSet {
    let mut m = ParamSet::new();
    m.add("P", ParamValue::Point(p.to_vec()));
    m.add("indices", ParamValue::Integer(idx.to_vec()));
    m
}

/// (falloff exponent, gain) of a point or spot light.
fn falloff(l: &LightItem, time: f64, warnings: &mut Vec<(Loc, String)>) -> (f32, f64) {
    let r = l.range.at(time).abs().max(1e-9);
    let at = l.falloff.1.clone().unwrap_or_else(|| l.common.loc.clone());
    match l.falloff.0 {
        0 => (0.0, 1.0),
        1 => {
            warnings.push((
                at,
                format!(
                    "light \"{}\": linear falloff is approximated by inverse-distance falloff matching it at half the range (no cut-off at the range)",
                    l.common.name
                ),
            ));
            (1.0, r / 4.0)
        }
        2 => (1.0, r),
        3 => (2.0, r * r),
        other => {
            warnings.push((
                at,
                format!(
                    "light \"{}\": unknown falloff type {other}: no falloff",
                    l.common.name
                ),
            ));
            (0.0, 1.0)
        }
    }
}

/// The environment light of the backdrop and the ambient light, if either is not black.
pub fn environment(
    g: &Globals,
    time: f64,
    loc: &Loc,
    warnings: &mut Vec<(Loc, String)>,
) -> Option<ParamSet> {
    let backdrop = if g.solid_backdrop {
        g.backdrop_color
    } else {
        let mean = [0, 1, 2].map(|i| g.gradient.iter().map(|c| c[i]).sum::<f64>() / 4.0);
        if mean.iter().any(|&c| c > 0.0) {
            warnings.push((
                loc.clone(),
                "the gradient backdrop is rendered as its mean colour".into(),
            ));
        }
        mean
    };
    let ambient = g.ambient_intensity.at(time);
    let amb = g.ambient_color.map(|c| c * ambient);
    if amb.iter().any(|&c| c > 0.0) {
        warnings.push((
            loc.clone(),
            "ambient light is rendered as part of an environment light (shadowed, and seen behind objects), unlike LightWave's flat ambient term".into(),
        ));
    }
    if backdrop.iter().any(|&c| c > 0.0) && !g.radiosity {
        warnings.push((
            loc.clone(),
            "the backdrop lights the scene as an environment light, as LightWave does only with radiosity".into(),
        ));
    }
    let l = [0, 1, 2].map(|i| (backdrop[i] + amb[i]) as f32);
    if l.iter().all(|&c| c <= 0.0) {
        return None;
    }
    let mut ps = ParamSet::new();
    ps.add("L", color(l));
    Some(ps)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::lightwave::envelope::Animated;
    use crate::formats::lightwave::items::ItemCommon;

    fn light_item(kind: LightKind) -> LightItem {
        LightItem {
            common: ItemCommon::new(0x2000_0000, "L".into(), Loc::default()),
            color: [
                Animated::Const(1.0),
                Animated::Const(0.5),
                Animated::Const(0.0),
            ],
            intensity: Animated::Const(2.0),
            kind: (kind, None),
            falloff: (0, None),
            range: Animated::Const(4.0),
            cone_deg: Animated::Const(30.0),
            edge_deg: Animated::Const(5.0),
        }
    }

    #[test]
    fn distant_light_is_scaled_by_pi_and_points_along_plus_z() {
        let mut w = Vec::new();
        let out = light(
            &light_item(LightKind::Distant),
            &DMat4::IDENTITY,
            0.0,
            false,
            &mut w,
        )
        .unwrap();
        let LightOut::Delta { kind, params } = out else {
            panic!()
        };
        assert_eq!(kind, "distant");
        let l = params.color("L").unwrap();
        assert!((l[0] - 2.0 * std::f32::consts::PI).abs() < 1e-5);
        // LightWave +Z is luxfarm +Y
        assert_eq!(params.point("to"), Some([0.0, 1.0, 0.0]));
    }

    #[test]
    fn falloff_types_map_onto_the_exponent() {
        let mut w = Vec::new();
        for (ty, k, gain) in [(0, 0.0, 1.0), (2, 1.0, 4.0), (3, 2.0, 16.0), (1, 1.0, 1.0)] {
            let mut l = light_item(LightKind::Point);
            l.falloff = (ty, None);
            let LightOut::Delta { params, .. } =
                light(&l, &DMat4::IDENTITY, 0.0, false, &mut w).unwrap()
            else {
                panic!()
            };
            assert_eq!(params.float("falloffexponent"), Some(k));
            assert_eq!(params.float("gain"), Some(gain));
        }
        assert_eq!(w.len(), 1, "only linear falloff is approximate");
    }

    #[test]
    fn area_light_faces_plus_z_with_radiance_per_area() {
        let mut w = Vec::new();
        let frame = DMat4::from_scale(DVec3::new(2.0, 2.0, 1.0));
        let LightOut::Area { area, meshes } =
            light(&light_item(LightKind::Area), &frame, 0.0, true, &mut w).unwrap()
        else {
            panic!()
        };
        assert_eq!(meshes.len(), 2);
        let l = area.color("L").unwrap();
        assert!((l[0] - 2.0 * std::f32::consts::PI / 4.0).abs() < 1e-5);
        let p = meshes[0].points("P").unwrap();
        let i = meshes[0].ints("indices").unwrap();
        let v = |k: usize| DVec3::from(p[i[k] as usize].map(f64::from));
        let n = (v(1) - v(0)).cross(v(2) - v(0));
        assert!(n.y > 0.0, "front faces luxfarm +Y (LightWave +Z): {n}");
    }

    #[test]
    fn environment_from_backdrop_and_ambient() {
        let mut w = Vec::new();
        let g = Globals {
            ambient_intensity: Animated::Const(0.0),
            ..Globals::default()
        };
        assert!(environment(&g, 0.0, &Loc::default(), &mut w).is_none());
        let g = Globals {
            backdrop_color: [0.2, 0.2, 0.2],
            ambient_intensity: Animated::Const(0.1),
            ..Globals::default()
        };
        let ps = environment(&g, 0.0, &Loc::default(), &mut w).unwrap();
        let l = ps.color("L").unwrap();
        assert!((l[0] - 0.3).abs() < 1e-6);
    }
}
