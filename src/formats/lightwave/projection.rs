//! Image projections of LightWave texture layers: planar, cylindrical, spherical and cubic
//! mappings from an object-space point to image coordinates (s right, t down from the top row,
//! as LuxRender's image maps index them).
//!
//! ```text
//! point (object space) --centre, rotation, size of the layer--> texture space
//!   --projection along the layer's axis--> (s, t) --per polygon: seam fix--> mesh uv
//! ```
//!
//! Facts from the LWO2 specification and the SDK's texture notes: planar projections take
//! s = z + ½ along X and s = x + ½ otherwise, t = −z + ½ along Y and −y + ½ otherwise;
//! cylindrical and spherical ones measure the longitude around the axis (a full turn spans
//! the image `wrap_amount` times) and spherical ones the latitude (t = ½ − lat/π); cubic
//! ones pick, per polygon, the planar axis closest to the polygon's normal.

use super::coords::rotation;
use super::model::{Projection, TexBlock};
use glam::{DVec2, DVec3};
use std::f64::consts::{PI, TAU};

/// The layer's texture-space point for an object-space point.
fn texture_space(b: &TexBlock, p: DVec3) -> DVec3 {
    let c = DVec3::from(b.center.map(f64::from));
    let r = b.rotation.map(f64::from);
    let size = DVec3::from(b.size.map(|s| if s == 0.0 { 1.0 } else { f64::from(s) }));
    rotation(r[0], r[1], r[2]).transpose() * (p - c) / size
}

/// Heading of (x, z) as the SDK measures it, in [0, 2π).
fn heading(x: f64, z: f64) -> f64 {
    let h = if x == 0.0 && z == 0.0 {
        0.0
    } else if z == 0.0 {
        if x < 0.0 {
            PI / 2.0
        } else {
            -PI / 2.0
        }
    } else if z < 0.0 {
        -(x / z).atan() + PI
    } else {
        -(x / z).atan()
    };
    h.rem_euclid(TAU)
}

/// The axis-permuted (x, y, z) the cylindrical and spherical formulas take.
fn around_axis(q: DVec3, axis: u16) -> DVec3 {
    match axis {
        0 => DVec3::new(q.z, q.x, -q.y),
        1 => DVec3::new(-q.x, q.y, q.z),
        _ => DVec3::new(-q.x, q.z, -q.y),
    }
}

fn planar(q: DVec3, axis: u16) -> DVec2 {
    let s = if axis == 0 { q.z } else { q.x };
    let t = if axis == 1 { -q.z } else { -q.y };
    DVec2::new(s + 0.5, t + 0.5)
}

/// Image coordinates of object-space point `p` on a polygon with normal `n`; None for
/// projections that need more than the point (UV maps, front projection).
pub fn project(b: &TexBlock, p: DVec3, n: DVec3) -> Option<DVec2> {
    let q = texture_space(b, p);
    let (ww, wh) = (f64::from(b.wrap_amount.0), f64::from(b.wrap_amount.1));
    Some(match b.projection {
        Projection::Planar => planar(q, b.axis),
        Projection::Cubic => {
            let r = b.rotation.map(f64::from);
            let nt = rotation(r[0], r[1], r[2]).transpose() * n;
            let a = nt.abs();
            let axis = if a.x >= a.y && a.x >= a.z {
                0
            } else if a.y >= a.z {
                1
            } else {
                2
            };
            planar(q, axis)
        }
        Projection::Cylindrical => {
            let v = around_axis(q, b.axis);
            let lon = 1.0 - heading(v.x, v.z) / TAU;
            DVec2::new(lon * ww, 0.5 - v.y)
        }
        Projection::Spherical => {
            let v = around_axis(q, b.axis);
            let lon = 1.0 - heading(v.x, v.z) / TAU;
            let lat = v.y.atan2((v.x * v.x + v.z * v.z).sqrt());
            DVec2::new(lon * ww, (0.5 - lat / PI) * wh)
        }
        Projection::Front | Projection::Uv => return None,
    })
}

/// Keeps a polygon's longitudes on one side of the seam: corners more than half a turn
/// (`period`) below the largest are moved up by a turn.
pub fn fix_seam(uvs: &mut [DVec2], period: f64) {
    let Some(max) = uvs.iter().map(|u| u.x).reduce(f64::max) else {
        return;
    };
    for u in uvs.iter_mut() {
        if max - u.x > period / 2.0 {
            u.x += period;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn block(projection: Projection, axis: u16) -> TexBlock {
        let mut b = TexBlock::new(*b"COLR", super::super::model::BlockKind::Image, 0);
        b.projection = projection;
        b.axis = axis;
        b
    }

    #[test]
    fn planar_z_maps_the_unit_square_upright() {
        let b = block(Projection::Planar, 2);
        let tl = project(&b, DVec3::new(-0.5, 0.5, 0.0), DVec3::Z).unwrap();
        let br = project(&b, DVec3::new(0.5, -0.5, 0.0), DVec3::Z).unwrap();
        assert_eq!(tl, DVec2::new(0.0, 0.0));
        assert_eq!(br, DVec2::new(1.0, 1.0));
    }

    #[test]
    fn size_and_centre_scale_the_mapping() {
        let mut b = block(Projection::Planar, 1);
        b.size = [2.0, 2.0, 2.0];
        b.center = [1.0, 0.0, 0.0];
        let uv = project(&b, DVec3::new(2.0, 0.0, 1.0), DVec3::Y).unwrap();
        assert_eq!(uv, DVec2::new(1.0, 0.0));
    }

    #[test]
    fn cylindrical_turns_once_around_the_axis() {
        let b = block(Projection::Cylindrical, 1);
        let us: Vec<f64> = [DVec3::Z, DVec3::X, -DVec3::Z, -DVec3::X]
            .iter()
            .map(|&p| project(&b, p, p).unwrap().x)
            .collect();
        // four quarter turns, each a quarter of the image apart (modulo the seam)
        for w in us.windows(2) {
            let d = (w[1] - w[0]).rem_euclid(1.0);
            assert!(
                (d - 0.25).abs() < 1e-12 || (d - 0.75).abs() < 1e-12,
                "{us:?}"
            );
        }
        let top = block(Projection::Spherical, 1);
        assert!((project(&top, DVec3::Y, DVec3::Y).unwrap().y - 0.0).abs() < 1e-12);
        assert!((project(&top, -DVec3::Y, DVec3::Y).unwrap().y - 1.0).abs() < 1e-12);
    }

    #[test]
    fn seam_fix_keeps_polygons_together() {
        let mut uvs = [DVec2::new(0.95, 0.0), DVec2::new(0.05, 0.0)];
        fix_seam(&mut uvs, 1.0);
        assert!((uvs[1].x - 1.05).abs() < 1e-12);
    }
}
