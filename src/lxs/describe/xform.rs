//! Transform math for the graphics state, with LuxRender's conventions: every statement
//! post-multiplies the current transformation matrix (CTM), `Transform`/`ConcatTransform`
//! take 16 numbers column by column, `Rotate` takes degrees, and `LookAt` builds the
//! world-to-camera matrix whose inverse has columns (right, up, dir, eye) with
//! `right = normalize(dir x up)` and `up' = right x dir`.

use crate::lxs::description::Xform;
use crate::lxs::error::{LxsError, LxsErrorKind, LxsResult};
use crate::lxs::params::Loc;
use glam::{DMat4, DVec3, DVec4};

fn invalid(loc: &Loc, msg: impl Into<String>) -> LxsError {
    LxsError::new(LxsErrorKind::InvalidValue, loc.clone(), msg)
}

/// The matrix of a 16-number `Transform` (values are columns).
pub fn from_columns(m: [f64; 16], loc: &Loc) -> LxsResult<DMat4> {
    if m.iter().any(|v| !v.is_finite()) {
        return Err(invalid(loc, "matrix has a non-finite value"));
    }
    Ok(DMat4::from_cols_array(&m))
}

pub fn rotate(angle_deg: f64, axis: [f64; 3], loc: &Loc) -> LxsResult<DMat4> {
    let a = DVec3::from(axis);
    let len = a.length();
    if !(len > 0.0 && len.is_finite()) {
        return Err(invalid(loc, "Rotate axis must be a non-zero vector"));
    }
    Ok(DMat4::from_axis_angle(a / len, angle_deg.to_radians()))
}

pub fn scale(s: [f64; 3]) -> DMat4 {
    DMat4::from_scale(DVec3::from(s))
}

pub fn translate(d: [f64; 3]) -> DMat4 {
    DMat4::from_translation(DVec3::from(d))
}

/// LuxRender's LookAt: the world-to-camera transform.
pub fn look_at(eye: [f64; 3], target: [f64; 3], up: [f64; 3], loc: &Loc) -> LxsResult<DMat4> {
    let eye = DVec3::from(eye);
    let dir = DVec3::from(target) - eye;
    if dir.length_squared() == 0.0 {
        return Err(invalid(loc, "LookAt eye and target are the same point"));
    }
    let dir = dir.normalize();
    let right = dir.cross(DVec3::from(up));
    let len2 = right.length_squared();
    if len2 == 0.0 || len2.is_nan() {
        return Err(invalid(
            loc,
            "LookAt up vector is zero or parallel to the view direction",
        ));
    }
    let right = right.normalize();
    let new_up = right.cross(dir);
    let cam_to_world = DMat4::from_cols(
        right.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        DVec4::new(eye.x, eye.y, eye.z, 1.0),
    );
    Ok(cam_to_world.inverse())
}

/// The inverse of a transform (every key), refusing singular matrices.
pub fn inverse(x: &Xform, loc: &Loc, what: &str) -> LxsResult<Xform> {
    let mut keys = Vec::with_capacity(x.keys.len());
    for &(t, m) in &x.keys {
        let det = m.determinant();
        if !(det.abs() > 0.0 && det.is_finite()) {
            return Err(invalid(
                loc,
                format!("{what} is singular (cannot be inverted)"),
            ));
        }
        keys.push((t, m.inverse()));
    }
    Ok(Xform { keys })
}

/// `a * b` for possibly animated transforms: keywise when the key times agree, or when one
/// side is static.
pub fn mul(a: &Xform, b: &Xform, loc: &Loc) -> LxsResult<Xform> {
    let keys = match (a.keys.len(), b.keys.len()) {
        (1, _) => b.keys.iter().map(|&(t, m)| (t, a.keys[0].1 * m)).collect(),
        (_, 1) => a.keys.iter().map(|&(t, m)| (t, m * b.keys[0].1)).collect(),
        (n, k) if n == k && a.keys.iter().zip(&b.keys).all(|(x, y)| x.0 == y.0) => a
            .keys
            .iter()
            .zip(&b.keys)
            .map(|(x, y)| (x.0, x.1 * y.1))
            .collect(),
        _ => {
            return Err(LxsError::new(
                LxsErrorKind::Unsupported,
                loc.clone(),
                "combining two motion transforms with different key times is not supported",
            ))
        }
    };
    Ok(Xform { keys })
}

/// `ctm * m` for a static `m`.
pub fn post(ctm: &Xform, m: DMat4) -> Xform {
    Xform {
        keys: ctm.keys.iter().map(|&(t, k)| (t, k * m)).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn loc() -> Loc {
        Loc::default()
    }

    #[test]
    fn transform_values_are_columns() {
        // A translation by (1, 2, 3) written as LuxRender exporters write it.
        let m = from_columns(
            [
                1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 1., 2., 3., 1.,
            ],
            &loc(),
        )
        .unwrap();
        assert_eq!(m.transform_point3(DVec3::ZERO), DVec3::new(1., 2., 3.));
    }

    #[test]
    fn rotate_is_counter_clockwise_in_degrees() {
        let m = rotate(90.0, [0., 0., 1.], &loc()).unwrap();
        let p = m.transform_point3(DVec3::X);
        assert!((p - DVec3::Y).length() < 1e-12);
        assert!(rotate(10.0, [0., 0., 0.], &loc()).is_err());
    }

    #[test]
    fn look_at_maps_eye_to_origin_and_target_to_plus_z() {
        let m = look_at([0., -3.9, 1.], [0., 0., 1.], [0., 0., 1.], &loc()).unwrap();
        assert!(m.transform_point3(DVec3::new(0., -3.9, 1.)).length() < 1e-12);
        let t = m.transform_point3(DVec3::new(0., 0., 1.));
        assert!((t - DVec3::new(0., 0., 3.9)).length() < 1e-12);
        // Up maps to +y, and right = dir x up (world +x here) is camera +x.
        let u = m.transform_vector3(DVec3::Z);
        assert!((u - DVec3::Y).length() < 1e-12);
        let r = m.transform_vector3(DVec3::X);
        assert!((r - DVec3::X).length() < 1e-12);
        assert!(look_at([0.; 3], [0., 0., 1.], [0., 0., 1.], &loc()).is_err());
    }
}
