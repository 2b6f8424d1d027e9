//! The camera's placement: camera-to-world, fixed or interpolated between motion keys.
//!
//! `CameraDesc.world_to_camera` is the CTM at the `Camera` statement (LuxRender and pbrt
//! convention: camera space looks down +z, +y up; LuxRender's `LookAt` puts +x to the right,
//! `right = normalize(dir x up)`). Animated cameras (`MotionBegin` around the camera
//! transform) are interpolated like LuxRender's motion system ([`MotionTransform`], shared
//! with moving shapes and instances): translation and scale linearly, rotation by quaternion
//! slerp, between the keys around the ray's time.

use crate::geometry::motion::MotionTransform;
use crate::lxs::Xform;
use glam::{DAffine3, DMat4};

#[derive(Clone, Debug, PartialEq)]
pub enum CameraMotion {
    Fixed(DAffine3),
    /// Camera-to-world interpolated between its keys.
    Keys(MotionTransform),
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
        if MotionTransform::loses_shear(&keys) {
            tracing::warn!("a camera motion key is sheared: it is interpolated without its shear");
        }
        MotionTransform::new(&keys)
            .map(CameraMotion::Keys)
            .ok_or_else(|| "camera motion keys are not finite".to_string())
    }

    /// Camera-to-world at `time`.
    pub fn at(&self, time: f32) -> DAffine3 {
        match self {
            CameraMotion::Fixed(a) => *a,
            CameraMotion::Keys(m) => m.at(time),
        }
    }
}
