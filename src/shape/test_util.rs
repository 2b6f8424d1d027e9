//! Helpers for shape and accelerator tests: shape descriptions built in code.

use crate::lxs::{Entity, Loc, ParamSet, ParamValue, ShapeDesc, Xform};
use glam::DMat4;

/// A `ShapeDesc` of `kind` with `params`, transform `m`, at a recognisable location.
pub fn shape(kind: &str, params: Vec<(&str, ParamValue)>, m: DMat4, reverse: bool) -> ShapeDesc {
    let mut ps = ParamSet::new();
    for (name, v) in params {
        ps.add(name, v);
    }
    ShapeDesc {
        entity: Entity {
            kind: kind.to_string(),
            params: ps,
            loc: Loc {
                file: "test.lxs".into(),
                line: 7,
                col: 3,
            },
        },
        object_to_world: Xform::fixed(m),
        material: None,
        area_light: None,
        reverse_orientation: reverse,
        interior: None,
        exterior: None,
        portal: false,
        portal_light: None,
    }
}

pub fn floats(v: &[f32]) -> ParamValue {
    ParamValue::Float(v.to_vec())
}

pub fn ints(v: &[i32]) -> ParamValue {
    ParamValue::Integer(v.to_vec())
}

pub fn points(v: &[[f32; 3]]) -> ParamValue {
    ParamValue::Point(v.to_vec())
}

/// A unit quad in the z = 0 plane ([-1,1]²), normal +z, as a trianglemesh.
pub fn quad(m: DMat4, reverse: bool) -> ShapeDesc {
    shape(
        "trianglemesh",
        vec![
            ("indices", ints(&[0, 1, 2, 0, 2, 3])),
            (
                "P",
                points(&[
                    [-1.0, -1.0, 0.0],
                    [1.0, -1.0, 0.0],
                    [1.0, 1.0, 0.0],
                    [-1.0, 1.0, 0.0],
                ]),
            ),
        ],
        m,
        reverse,
    )
}
