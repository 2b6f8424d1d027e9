//! How an infinite light's map covers the sphere of directions (`mapping`): LuxRender 1.x's
//! `latlong` (default), `angular` (a light probe) and `vcross` (a cube map as a vertical
//! cross), each as light-space direction ↔ image coordinates (s, t) ∈ [0, 1]² (t = 0 the top
//! row) with the Jacobian dω/(ds dt) that importance sampling divides by.
//!
//! - **latlong**: s = φ/2π (φ = atan2(y, x)), t = θ/π (θ from +z); dω = 2π² sin θ ds dt.
//! - **angular**: the image's inscribed disc; the centre looks along −x, the radius
//!   r = acos(−x)/2π from it grows with the angle from −x (the rim, r = ½, is +x), and the
//!   point is at (s, t) = (½, ½) − r·(y, z)/√(y² + z²); dω = 2π sin θ / r ds dt. Outside the
//!   disc there is no direction.
//! - **vcross**: a 3 × 4 grid of cube faces (column, row): (1, 0) +z, (0, 1) +y, (1, 1) −x,
//!   (2, 1) −y, (1, 2) −z, (1, 3) +x; the other six cells are unused. On a face with major
//!   axis coordinate 1 and in-face coordinates (a, b) ∈ [−1, 1]², dω = 48 ds dt / |(a, b, 1)|³.
//!   The in-face orientation of each face is LuxRender's.

use glam::Vec3A;
use std::f32::consts::PI;

/// The `mapping` of an infinite light's map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnvMapping {
    LatLong,
    Angular,
    VerticalCross,
}

impl EnvMapping {
    /// The mapping a `mapping` parameter names.
    pub fn from_name(name: &str) -> Option<EnvMapping> {
        match name {
            "latlong" => Some(EnvMapping::LatLong),
            "angular" => Some(EnvMapping::Angular),
            "vcross" => Some(EnvMapping::VerticalCross),
            _ => None,
        }
    }

    /// Image coordinates of the unit light-space direction `d`.
    pub fn to_st(self, d: Vec3A) -> (f32, f32) {
        match self {
            EnvMapping::LatLong => {
                let (s, t, _) = super::latlong::dir_to_st(d);
                (s, t)
            }
            EnvMapping::Angular => angular_st(d),
            EnvMapping::VerticalCross => vcross_st(d),
        }
    }

    /// The unit direction at image coordinates (s, t) with dω/(ds dt), or None where the
    /// image holds no direction.
    pub fn to_dir(self, s: f32, t: f32) -> Option<(Vec3A, f32)> {
        let (d, jac) = match self {
            EnvMapping::LatLong => {
                let (d, sin_t) = super::latlong::st_to_dir(s, t);
                (d, 2.0 * PI * PI * sin_t)
            }
            EnvMapping::Angular => angular_dir(s, t)?,
            EnvMapping::VerticalCross => vcross_dir(s, t)?,
        };
        (jac > 0.0 && jac.is_finite()).then_some((d, jac))
    }
}

fn angular_st(d: Vec3A) -> (f32, f32) {
    let sin_t = (d.y * d.y + d.z * d.z).sqrt();
    let r = (-d.x).clamp(-1.0, 1.0).acos() / (2.0 * PI);
    if sin_t > 1e-9 {
        let k = r / sin_t;
        (0.5 - d.y * k, 0.5 - d.z * k)
    } else if d.x < 0.0 {
        (0.5, 0.5)
    } else {
        // Straight along +x: the rim (any point of it); take the right edge's middle.
        (0.0, 0.5)
    }
}

fn angular_dir(s: f32, t: f32) -> Option<(Vec3A, f32)> {
    let (a, b) = (s - 0.5, t - 0.5);
    let r = (a * a + b * b).sqrt();
    if r > 0.5 || r <= 1e-7 {
        return None;
    }
    let theta = 2.0 * PI * r;
    let sin_t = theta.sin();
    let d = Vec3A::new(-theta.cos(), -sin_t * a / r, -sin_t * b / r);
    Some((d, 2.0 * PI * sin_t / r))
}

/// Face (column, row), in-face (a, b) and the direction for each of the six faces.
fn vcross_st(d: Vec3A) -> (f32, f32) {
    let (ax, ay, az) = (d.x.abs(), d.y.abs(), d.z.abs());
    let (sc, tc, so, to, m) = if ax >= ay && ax >= az {
        if d.x > 0.0 {
            (-d.y, d.z, 1.0, 3.0, ax)
        } else {
            (-d.y, -d.z, 1.0, 1.0, ax)
        }
    } else if ay >= az {
        if d.y > 0.0 {
            (-d.x, -d.z, 0.0, 1.0, ay)
        } else {
            (d.x, -d.z, 2.0, 1.0, ay)
        }
    } else if d.z > 0.0 {
        (-d.y, -d.x, 1.0, 0.0, az)
    } else {
        (-d.y, d.x, 1.0, 2.0, az)
    };
    let m = m.max(1e-9);
    let s = ((sc / m + 1.0) * 0.5).clamp(0.0, 1.0);
    let t = ((tc / m + 1.0) * 0.5).clamp(0.0, 1.0);
    ((s + so) / 3.0, (t + to) / 4.0)
}

fn vcross_dir(s: f32, t: f32) -> Option<(Vec3A, f32)> {
    let so = ((3.0 * s).floor().max(0.0) as u32).min(2);
    let to = ((4.0 * t).floor().max(0.0) as u32).min(3);
    let sc = (3.0 * s - so as f32) * 2.0 - 1.0;
    let tc = (4.0 * t - to as f32) * 2.0 - 1.0;
    // The inverse of vcross_st on each used face.
    let v = match (so, to) {
        (1, 3) => Vec3A::new(1.0, -sc, tc),
        (1, 1) => Vec3A::new(-1.0, -sc, -tc),
        (0, 1) => Vec3A::new(-sc, 1.0, -tc),
        (2, 1) => Vec3A::new(sc, -1.0, -tc),
        (1, 0) => Vec3A::new(-tc, -sc, 1.0),
        (1, 2) => Vec3A::new(tc, -sc, -1.0),
        _ => return None,
    };
    let len = v.length();
    Some((v / len, 48.0 / (len * len * len)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dirs() -> Vec<Vec3A> {
        (0..200)
            .map(|i| {
                let u = (i as f32 + 0.5) / 200.0;
                let z = 1.0 - 2.0 * u;
                let phi = 2.399_963 * i as f32;
                let r = (1.0 - z * z).max(0.0).sqrt();
                Vec3A::new(r * phi.cos(), r * phi.sin(), z)
            })
            .collect()
    }

    #[test]
    fn mappings_round_trip() {
        for m in [
            EnvMapping::LatLong,
            EnvMapping::Angular,
            EnvMapping::VerticalCross,
        ] {
            for d in dirs() {
                let (s, t) = m.to_st(d);
                let (back, jac) = m.to_dir(s, t).unwrap_or_else(|| panic!("{m:?} {d:?}"));
                assert!(
                    (back - d).length() < 2e-3,
                    "{m:?}: {d:?} -> ({s}, {t}) -> {back:?}"
                );
                assert!(jac > 0.0);
            }
        }
    }

    #[test]
    fn jacobians_cover_the_sphere() {
        // ∫ dω/(ds dt) over the image = 4π for every mapping (midpoint rule).
        for m in [
            EnvMapping::LatLong,
            EnvMapping::Angular,
            EnvMapping::VerticalCross,
        ] {
            let n = 600;
            let mut sum = 0.0f64;
            for i in 0..n {
                for j in 0..n {
                    let (s, t) = ((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    if let Some((_, jac)) = m.to_dir(s, t) {
                        sum += f64::from(jac);
                    }
                }
            }
            let area = sum / (n * n) as f64;
            let want = 4.0 * std::f64::consts::PI;
            assert!((area - want).abs() < 0.01 * want, "{m:?}: {area}");
        }
    }

    #[test]
    fn angular_and_vcross_landmarks() {
        // Angular: −x at the centre, +y left of it halfway to the rim... (s = ½ − r).
        let (s, t) = EnvMapping::Angular.to_st(-Vec3A::X);
        assert!((s - 0.5).abs() < 1e-6 && (t - 0.5).abs() < 1e-6);
        let (s, t) = EnvMapping::Angular.to_st(Vec3A::Y);
        assert!((s - 0.25).abs() < 1e-6 && (t - 0.5).abs() < 1e-6);
        // Vcross: face centres.
        for (d, st) in [
            (Vec3A::Z, (0.5, 0.125)),
            (Vec3A::Y, (1.0 / 6.0, 0.375)),
            (-Vec3A::X, (0.5, 0.375)),
            (-Vec3A::Y, (5.0 / 6.0, 0.375)),
            (-Vec3A::Z, (0.5, 0.625)),
            (Vec3A::X, (0.5, 0.875)),
        ] {
            let (s, t) = EnvMapping::VerticalCross.to_st(d);
            assert!(
                (s - st.0).abs() < 1e-6 && (t - st.1).abs() < 1e-6,
                "{d:?}: ({s}, {t})"
            );
        }
        assert!(EnvMapping::VerticalCross.to_dir(0.1, 0.1).is_none());
        assert!(EnvMapping::Angular.to_dir(0.02, 0.02).is_none());
    }
}
