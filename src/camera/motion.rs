//! The camera's placement: camera-to-world, fixed or interpolated between motion keys.
//!
//! `CameraDesc.world_to_camera` is the CTM at the `Camera` statement (LuxRender and pbrt
//! convention: camera space looks down +z, +y up; LuxRender's `LookAt` puts +x to the right,
//! `right = normalize(dir x up)`). Animated cameras (`MotionBegin` around the camera
//! transform) are interpolated like LuxRender's motion system: translation and scale linearly,
//! rotation by quaternion slerp, between the keys around the ray's time.

use crate::lxs::Xform;
use glam::{DAffine3, DMat4, DQuat, DVec3};

#[derive(Clone, Debug, PartialEq)]
pub enum CameraMotion {
    Fixed(DAffine3),
    /// (time, scale, rotation, translation) of camera-to-world, by increasing time.
    Keys(Vec<(f32, DVec3, DQuat, DVec3)>),
}

/// Why a camera transform is unusable.
pub fn check_matrix(m: &DMat4) -> Result<DAffine3, String> {
    if !m.is_finite() {
        return Err("camera transform has non-finite entries".into());
    }
    let det = m.determinant();
    if det.abs() < 1e-12 {
        return Err("camera transform is singular (not invertible)".into());
    }
    if m.row(3) != glam::DVec4::new(0.0, 0.0, 0.0, 1.0) {
        return Err("camera transform is projective (last row is not 0 0 0 1)".into());
    }
    let inv = m.inverse();
    Ok(DAffine3::from_mat4(inv))
}

impl CameraMotion {
    pub fn from_xform(x: &Xform) -> Result<CameraMotion, String> {
        let mut keys: Vec<(f32, DAffine3)> = Vec::with_capacity(x.keys.len());
        for (t, m) in &x.keys {
            keys.push((*t, check_matrix(m)?));
        }
        let det = keys
            .first()
            .map(|k| k.1.matrix3.determinant())
            .unwrap_or(1.0);
        if (det.abs() - 1.0).abs() > 1e-3 {
            tracing::warn!(
                "scaling detected in the world-to-camera transformation (determinant {det:.4}); \
                 LuxRender assumes none and so may we"
            );
        }
        if !x.is_animated() {
            return Ok(CameraMotion::Fixed(
                keys.first().map(|k| k.1).unwrap_or(DAffine3::IDENTITY),
            ));
        }
        keys.sort_by(|a, b| a.0.total_cmp(&b.0));
        let keys = keys
            .into_iter()
            .map(|(t, a)| {
                let (s, r, tr) = a.to_scale_rotation_translation();
                (t, s, r, tr)
            })
            .collect();
        Ok(CameraMotion::Keys(keys))
    }

    /// Camera-to-world at `time`.
    pub fn at(&self, time: f32) -> DAffine3 {
        match self {
            CameraMotion::Fixed(a) => *a,
            CameraMotion::Keys(keys) => {
                let compose = |k: &(f32, DVec3, DQuat, DVec3)| {
                    DAffine3::from_scale_rotation_translation(k.1, k.2, k.3)
                };
                let (Some(first), Some(last)) = (keys.first(), keys.last()) else {
                    return DAffine3::IDENTITY;
                };
                if time <= first.0 {
                    return compose(first);
                }
                if time >= last.0 {
                    return compose(last);
                }
                let i = keys
                    .partition_point(|k| k.0 <= time)
                    .clamp(1, keys.len() - 1);
                let (a, b) = (&keys[i - 1], &keys[i]);
                let span = (b.0 - a.0) as f64;
                let f = if span > 0.0 {
                    (time - a.0) as f64 / span
                } else {
                    0.0
                };
                DAffine3::from_scale_rotation_translation(
                    a.1.lerp(b.1, f),
                    a.2.slerp(b.2, f),
                    a.3.lerp(b.3, f),
                )
            }
        }
    }
}
