//! LightWave's coordinates and rotations, and their conversion to luxfarm's.
//!
//! LightWave is left-handed with +Y up (+X right, +Z forward, into the screen). An item's
//! rotation is heading (about Y), pitch (about X), bank (about Z), combined as M = B·P·H with the
//! matrices of the LWSC specification; the rows of M are the item's +X, +Y, +Z axes in its
//! parent's space. Its local transform is `T(position) · Mᵀ · S(scale) · T(−pivot)` (column
//! vectors), and a child's transform is relative to its parent's (pivot excluded).
//!
//! luxfarm (LuxRender) is right-handed with +Z up. Swapping Y and Z ([`swap_yz`]) maps one onto
//! the other: LightWave's (x, y, z) is luxfarm's (x, z, y). The swap is a mirror, so it also
//! turns LightWave's clockwise polygons (seen from their front) into counter-clockwise ones:
//! triangles keep their front when their winding is reversed ([`super::triangulate`] callers
//! emit (a, c, b)). A LightWave item matrix W becomes `C · W · C` with C the swap.

use glam::{DMat3, DMat4, DVec3, DVec4};

/// Heading, pitch and bank (radians) as LightWave's rotation matrix M = B·P·H, whose rows are
/// the rotated +X, +Y, +Z axes.
pub fn hpb_matrix(h: f64, p: f64, b: f64) -> DMat3 {
    let (sh, ch) = h.sin_cos();
    let (sp, cp) = p.sin_cos();
    let (sb, cb) = b.sin_cos();
    // Row-major literals of the specification's H, P, B.
    let hm = rows([[ch, 0.0, -sh], [0.0, 1.0, 0.0], [sh, 0.0, ch]]);
    let pm = rows([[1.0, 0.0, 0.0], [0.0, cp, sp], [0.0, -sp, cp]]);
    let bm = rows([[cb, sb, 0.0], [-sb, cb, 0.0], [0.0, 0.0, 1.0]]);
    bm * pm * hm
}

/// A 3x3 matrix from its rows.
fn rows(r: [[f64; 3]; 3]) -> DMat3 {
    DMat3::from_cols_array_2d(&r).transpose()
}

/// The rotation taking an item's local vectors to its parent's space (column vectors):
/// Mᵀ, whose columns are the item's axes.
pub fn rotation(h: f64, p: f64, b: f64) -> DMat3 {
    hpb_matrix(h, p, b).transpose()
}

/// The frame children are placed in: position, rotation and scale, without the pivot offset.
pub fn frame_transform(pos: DVec3, hpb: DVec3, scale: DVec3) -> DMat4 {
    let r = rotation(hpb.x, hpb.y, hpb.z);
    DMat4::from_translation(pos) * DMat4::from_mat3(r) * DMat4::from_scale(scale)
}

/// Heading and pitch that point an item's +Z along `dir` (LightWave space; bank unchanged).
pub fn aim(dir: DVec3) -> Option<(f64, f64)> {
    let horizontal = (dir.x * dir.x + dir.z * dir.z).sqrt();
    if horizontal == 0.0 && dir.y == 0.0 {
        return None;
    }
    Some((dir.x.atan2(dir.z), (-dir.y).atan2(horizontal)))
}

/// LightWave (x, y, z) to luxfarm (x, z, y).
pub fn swap_yz(v: DVec3) -> DVec3 {
    DVec3::new(v.x, v.z, v.y)
}

/// The swap as a matrix (its own inverse).
pub fn swap_matrix() -> DMat4 {
    DMat4::from_cols(DVec4::X, DVec4::Z, DVec4::Y, DVec4::W)
}

/// A LightWave transform expressed in luxfarm space: C·W·C.
pub fn to_lux(w: DMat4) -> DMat4 {
    let c = swap_matrix();
    c * w * c
}

/// A point of an object file in luxfarm space (f32 as meshes store them).
pub fn point_to_lux(p: [f32; 3]) -> [f32; 3] {
    [p[0], p[2], p[1]]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) {
        assert!((a - b).length() < 1e-12, "{a} != {b}");
    }

    #[test]
    fn heading_plus_90_turns_plus_z_into_plus_x() {
        let r = rotation(std::f64::consts::FRAC_PI_2, 0.0, 0.0);
        close(r * DVec3::Z, DVec3::X);
        // and +X into -Z: heading turns clockwise seen from +Y in a left-handed frame
        close(r * DVec3::X, -DVec3::Z);
    }

    #[test]
    fn positive_pitch_points_down_and_bank_rolls() {
        let r = rotation(0.0, std::f64::consts::FRAC_PI_2, 0.0);
        close(r * DVec3::Z, -DVec3::Y);
        let b = rotation(0.0, 0.0, std::f64::consts::FRAC_PI_2);
        // bank +90: the item's +X axis (row 0 of B) is world +Y
        close(b * DVec3::X, DVec3::Y);
    }

    #[test]
    fn rows_of_m_are_the_item_axes() {
        let (h, p, b) = (0.3, -0.7, 1.1);
        let m = hpb_matrix(h, p, b);
        let r = rotation(h, p, b);
        close(r * DVec3::X, m.row(0));
        close(r * DVec3::Y, m.row(1));
        close(r * DVec3::Z, m.row(2));
    }

    #[test]
    fn aim_inverts_the_forward_axis() {
        for dir in [
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(-1.0, -0.5, 0.2),
            DVec3::new(0.0, 0.0, -1.0),
        ] {
            let (h, p) = aim(dir).unwrap();
            close(rotation(h, p, 0.0) * DVec3::Z, dir.normalize());
        }
        assert!(aim(DVec3::ZERO).is_none());
    }

    #[test]
    fn pivot_is_the_rotation_centre() {
        let pivot = DVec3::new(1.0, 0.0, 0.0);
        let m = frame_transform(
            DVec3::new(5.0, 0.0, 0.0),
            DVec3::new(std::f64::consts::FRAC_PI_2, 0.0, 0.0),
            DVec3::ONE,
        ) * DMat4::from_translation(-pivot);
        // the pivot lands on the item's position
        close(m.transform_point3(pivot), DVec3::new(5.0, 0.0, 0.0));
    }

    #[test]
    fn conversion_swaps_y_and_z() {
        let w = DMat4::from_translation(DVec3::new(1.0, 2.0, 3.0));
        let l = to_lux(w);
        close(l.transform_point3(DVec3::ZERO), DVec3::new(1.0, 3.0, 2.0));
        assert_eq!(point_to_lux([1.0, 2.0, 3.0]), [1.0, 3.0, 2.0]);
        close(
            swap_yz(DVec3::new(1.0, 2.0, 3.0)),
            DVec3::new(1.0, 3.0, 2.0),
        );
    }
}
