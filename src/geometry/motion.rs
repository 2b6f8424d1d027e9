//! Animated transforms: LuxRender's interpolation between motion keys, and the bound of a box
//! carried along the motion.
//!
//! A `MotionBegin [t0 t1 ...] ... MotionEnd` block gives one affine matrix per time. Each key
//! is decomposed once into scale, rotation (a quaternion) and translation; at a ray's time the
//! two keys around it are blended as LuxRender does (translation and scale linearly, rotation
//! by quaternion slerp, the shortest way), and before the first or after the last key the end
//! key holds. Key times are compared with the ray's time as they are (the camera's shutter
//! times, `shutteropen`..`shutterclose`, are on the same axis). The camera and moving shapes
//! and instances share this one implementation.

use super::Transform;
use glam::{DAffine3, DMat4, DQuat, DVec3};

/// One decomposed key: time, scale, rotation, translation (`M = T · R · S`).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Key {
    time: f32,
    scale: DVec3,
    rotation: DQuat,
    translation: DVec3,
}

impl Key {
    fn affine(&self) -> DAffine3 {
        DAffine3::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// A transform interpolated between two or more keys, sorted by time.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionTransform {
    keys: Vec<Key>,
}

/// Relative size above which a key's decomposition does not give its matrix back (shear,
/// which the scale/rotation/translation decomposition cannot hold).
const SHEAR_TOLERANCE: f64 = 1e-6;

impl MotionTransform {
    /// Decomposes the keys (any order; sorted here). `None` with fewer than two keys or when
    /// a key is not finite.
    pub fn new(keys: &[(f32, DAffine3)]) -> Option<MotionTransform> {
        if keys.len() < 2 {
            return None;
        }
        let mut out: Vec<Key> = Vec::with_capacity(keys.len());
        for (time, a) in keys {
            if !time.is_finite() || !a.is_finite() {
                return None;
            }
            let (scale, rotation, translation) = a.to_scale_rotation_translation();
            out.push(Key {
                time: *time,
                scale,
                rotation: rotation.normalize(),
                translation,
            });
        }
        out.sort_by(|a, b| a.time.total_cmp(&b.time));
        Some(MotionTransform { keys: out })
    }

    /// As [`Self::new`] from 4×4 matrices (a projective last row is ignored).
    pub fn from_matrices(keys: &[(f32, DMat4)]) -> Option<MotionTransform> {
        let affine: Vec<(f32, DAffine3)> = keys
            .iter()
            .map(|(t, m)| (*t, DAffine3::from_mat4(*m)))
            .collect();
        MotionTransform::new(&affine)
    }

    /// Whether some key's matrix is not what its decomposition gives back (a sheared key:
    /// interpolated without its shear). `keys` as given to [`Self::new`].
    pub fn loses_shear(keys: &[(f32, DAffine3)]) -> bool {
        keys.iter().any(|(_, a)| {
            let (s, r, t) = a.to_scale_rotation_translation();
            let back = DAffine3::from_scale_rotation_translation(s, r.normalize(), t);
            let size = a
                .matrix3
                .abs()
                .to_cols_array()
                .into_iter()
                .fold(0.0, f64::max);
            let diff = (back.matrix3 - a.matrix3)
                .abs()
                .to_cols_array()
                .into_iter()
                .fold(0.0, f64::max);
            diff > SHEAR_TOLERANCE * size.max(f64::MIN_POSITIVE)
        })
    }

    /// The factor areas are multiplied by, when every key is a similarity (the same |scale|
    /// on all three axes) of one scale: then it holds at every time. `None` otherwise.
    pub fn area_scale(&self) -> Option<f64> {
        let s = self.keys.first()?.scale.abs().x;
        let same = |v: f64| (v - s).abs() <= 1e-9 * s.max(f64::MIN_POSITIVE);
        self.keys
            .iter()
            .all(|k| k.scale.abs().to_array().into_iter().all(same))
            .then_some(s * s)
    }

    /// The first key's area factor for a similarity, |det|^(2/3) (what
    /// [`Self::area_scale`] falls back to).
    pub fn first_key_area_scale(&self) -> f64 {
        self.keys.first().map_or(1.0, |k| {
            let s = k.scale;
            (s.x * s.y * s.z).abs().powf(2.0 / 3.0)
        })
    }

    /// Times of the first and last key.
    pub fn time_range(&self) -> (f32, f32) {
        match (self.keys.first(), self.keys.last()) {
            (Some(a), Some(b)) => (a.time, b.time),
            _ => (0.0, 0.0),
        }
    }

    /// The two keys around `time` and the blend factor between them; the end key (factor 0)
    /// before the first or after the last key.
    fn around(&self, time: f32) -> Option<(&Key, &Key, f64)> {
        let (first, last) = (self.keys.first()?, self.keys.last()?);
        if time.is_nan() || time <= first.time {
            return Some((first, first, 0.0));
        }
        if time >= last.time {
            return Some((last, last, 0.0));
        }
        let i = self
            .keys
            .partition_point(|k| k.time <= time)
            .clamp(1, self.keys.len() - 1);
        let (a, b) = (self.keys.get(i - 1)?, self.keys.get(i)?);
        let span = (b.time - a.time) as f64;
        let f = if span > 0.0 {
            (time - a.time) as f64 / span
        } else {
            0.0
        };
        Some((a, b, f))
    }

    /// The interpolated affine transform at `time`.
    pub fn at(&self, time: f32) -> DAffine3 {
        match self.around(time) {
            Some((a, b, f)) => blend(a, b, f).affine(),
            None => DAffine3::IDENTITY,
        }
    }

    /// [`Self::at`] with its inverse; `None` where the interpolated matrix is singular (keys
    /// whose scales change sign pass through zero).
    pub fn transform_at(&self, time: f32) -> Option<Transform> {
        let a = self.at(time);
        let inv = a.inverse();
        if !inv.is_finite() || a.matrix3.determinant() == 0.0 {
            return None;
        }
        Some(Transform {
            m: DMat4::from(a),
            inv: DMat4::from(inv),
        })
    }

    /// A box containing the box `lo..hi` (in the moving space) at every time, in the target
    /// space. Conservative: each key interval is cut into steps of at most π/256 of rotation
    /// (1 to 1024 steps); the transformed box at every step is exact, and the sweep between
    /// two steps, where translation and scale move linearly and the rotation turns by at most
    /// the step's angle θ, stays within those two boxes grown by 2·θ·s·r (s the largest
    /// |scale| of the interval, r the farthest corner of the box from the moving space's
    /// origin), because |(R(t) − Rᵢ)v| ≤ θ|v|.
    pub fn bound(&self, lo: DVec3, hi: DVec3) -> (DVec3, DVec3) {
        let corners = box_corners(lo, hi);
        let r = corners.iter().map(|c| c.length()).fold(0.0, f64::max);
        let mut out = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        let mut add = |b: (DVec3, DVec3), pad: f64| {
            out.0 = out.0.min(b.0 - DVec3::splat(pad));
            out.1 = out.1.max(b.1 + DVec3::splat(pad));
        };
        for pair in self.keys.windows(2) {
            let [a, b] = pair else { continue };
            let steps = rotation_steps(a.rotation, b.rotation);
            let smax = a.scale.abs().max_element().max(b.scale.abs().max_element());
            let mut prev = *a;
            for i in 1..=steps {
                let next = blend(a, b, i as f64 / steps as f64);
                let theta = angle_between(prev.rotation, next.rotation);
                let pad = 2.0 * theta * smax * r;
                add(affine_box(&prev.affine(), &corners), pad);
                add(affine_box(&next.affine(), &corners), pad);
                prev = next;
            }
        }
        out
    }
}

/// Keys `a` and `b` blended at factor `f`.
fn blend(a: &Key, b: &Key, f: f64) -> Key {
    if f <= 0.0 {
        return *a;
    }
    Key {
        time: a.time,
        scale: a.scale.lerp(b.scale, f),
        rotation: a.rotation.slerp(b.rotation, f),
        translation: a.translation.lerp(b.translation, f),
    }
}

/// Rotation angle between two unit quaternions (the shorter way), in radians.
fn angle_between(a: DQuat, b: DQuat) -> f64 {
    2.0 * a.dot(b).abs().min(1.0).acos()
}

/// Steps a key interval is cut into for [`MotionTransform::bound`].
fn rotation_steps(a: DQuat, b: DQuat) -> u32 {
    let steps = (angle_between(a, b) / (std::f64::consts::PI / 256.0)).ceil();
    if steps.is_finite() {
        (steps as u32).clamp(1, 1024)
    } else {
        1
    }
}

fn box_corners(lo: DVec3, hi: DVec3) -> [DVec3; 8] {
    std::array::from_fn(|i| {
        DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

fn affine_box(a: &DAffine3, corners: &[DVec3; 8]) -> (DVec3, DVec3) {
    corners.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), c| {
            let w = a.transform_point3(*c);
            (lo.min(w), hi.max(w))
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn keys(a: DAffine3, b: DAffine3) -> MotionTransform {
        MotionTransform::new(&[(0.0, a), (1.0, b)]).expect("two keys")
    }

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-9
    }

    #[test]
    fn translation_and_scale_are_linear_and_ends_hold() {
        let m = keys(
            DAffine3::from_translation(DVec3::new(-1.0, 0.0, 0.0)),
            DAffine3::from_scale_rotation_translation(
                DVec3::splat(3.0),
                DQuat::IDENTITY,
                DVec3::new(1.0, 2.0, 0.0),
            ),
        );
        let p = DVec3::new(1.0, 0.0, 0.0);
        assert!(close(
            m.at(0.5).transform_point3(p),
            DVec3::new(2.0, 1.0, 0.0)
        ));
        assert!(close(
            m.at(0.25).transform_point3(DVec3::ZERO),
            DVec3::new(-0.5, 0.5, 0.0)
        ));
        assert!(close(m.at(-3.0).transform_point3(p), DVec3::ZERO));
        assert!(close(
            m.at(7.0).transform_point3(p),
            DVec3::new(4.0, 2.0, 0.0)
        ));
        assert!(close(m.at(f32::NAN).transform_point3(p), DVec3::ZERO));
    }

    #[test]
    fn rotation_is_slerped_the_short_way() {
        let m = keys(
            DAffine3::IDENTITY,
            DAffine3::from_quat(DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2)),
        );
        let half = std::f64::consts::FRAC_PI_4;
        assert!(close(
            m.at(0.5).transform_point3(DVec3::X),
            DVec3::new(half.cos(), half.sin(), 0.0)
        ));
        // 270° one way is 90° the other: the slerp takes the short way.
        let m = keys(
            DAffine3::IDENTITY,
            DAffine3::from_quat(DQuat::from_rotation_z(1.5 * std::f64::consts::PI)),
        );
        assert!(close(
            m.at(0.5).transform_point3(DVec3::X),
            DVec3::new(half.cos(), -half.sin(), 0.0)
        ));
    }

    #[test]
    fn several_keys_pick_the_interval_around_the_time() {
        let at = |x: f64| DAffine3::from_translation(DVec3::new(x, 0.0, 0.0));
        let m =
            MotionTransform::new(&[(2.0, at(10.0)), (0.0, at(0.0)), (1.0, at(4.0))]).expect("keys");
        assert_eq!(m.time_range(), (0.0, 2.0));
        let x = |t: f32| m.at(t).translation.x;
        assert!((x(0.5) - 2.0).abs() < 1e-12);
        assert!((x(1.5) - 7.0).abs() < 1e-12);
        assert!((x(1.0) - 4.0).abs() < 1e-12);
    }

    #[test]
    fn transform_at_inverts_and_rejects_singular() {
        let m = keys(
            DAffine3::from_rotation_y(0.4),
            DAffine3::from_scale_rotation_translation(
                DVec3::new(2.0, 1.0, 1.0),
                DQuat::from_rotation_x(1.0),
                DVec3::new(0.0, 5.0, 0.0),
            ),
        );
        let t = m.transform_at(0.3).expect("invertible");
        let p = DVec3::new(0.3, -2.0, 4.0);
        assert!(close(t.inverse().point(t.point(p)), p));
        // Scale x from 1 to -1 passes through 0 halfway.
        let flip = keys(
            DAffine3::IDENTITY,
            DAffine3::from_scale(DVec3::new(-1.0, 1.0, 1.0)),
        );
        assert!(flip.transform_at(0.5).is_none());
        assert!(MotionTransform::new(&[(0.0, DAffine3::IDENTITY)]).is_none());
    }

    #[test]
    fn shear_is_detected() {
        let shear = DAffine3::from_cols_array(&[
            1.0, 0.0, 0.0, 0.7, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0,
        ]);
        assert!(MotionTransform::loses_shear(&[
            (0.0, DAffine3::IDENTITY),
            (1.0, shear)
        ]));
        let rigid = DAffine3::from_rotation_z(2.0);
        assert!(!MotionTransform::loses_shear(&[
            (0.0, DAffine3::IDENTITY),
            (1.0, rigid)
        ]));
    }

    /// Every corner, edge midpoint and face centre of the box, at many times, lies in the
    /// bound, for rotations up to a half turn and beyond.
    #[test]
    fn bound_contains_the_sweep() {
        let (lo, hi) = (DVec3::new(1.0, -0.5, 0.2), DVec3::new(3.0, 0.5, 0.4));
        for angle in [0.0, 0.3, 1.5, 3.0, 6.0] {
            let m = MotionTransform::new(&[
                (0.0, DAffine3::from_translation(DVec3::new(0.0, 1.0, 0.0))),
                (
                    0.5,
                    DAffine3::from_scale_rotation_translation(
                        DVec3::new(1.5, 0.5, 1.0),
                        DQuat::from_axis_angle(DVec3::new(0.2, 0.3, 1.0).normalize(), angle),
                        DVec3::new(2.0, 0.0, -1.0),
                    ),
                ),
                (1.0, DAffine3::from_rotation_x(angle)),
            ])
            .expect("keys");
            let (blo, bhi) = m.bound(lo, hi);
            for i in 0..=400 {
                let a = m.at(i as f32 / 400.0);
                for x in 0..3 {
                    for y in 0..3 {
                        for z in 0..3 {
                            let f = DVec3::new(x as f64, y as f64, z as f64) * 0.5;
                            let p = a.transform_point3(lo + (hi - lo) * f);
                            assert!(
                                p.cmpge(blo - 1e-12).all() && p.cmple(bhi + 1e-12).all(),
                                "angle {angle}: {p} outside {blo}..{bhi}"
                            );
                        }
                    }
                }
            }
            // Not wildly loose: within 20% of the box's own reach.
            let sampled = (0..=400).fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(l, h), i| {
                    let b = affine_box(&m.at(i as f32 / 400.0), &box_corners(lo, hi));
                    (l.min(b.0), h.max(b.1))
                },
            );
            assert!((sampled.0 - blo).max_element() < 0.2 * 3.2);
            assert!((bhi - sampled.1).max_element() < 0.2 * 3.2);
        }
    }
}
