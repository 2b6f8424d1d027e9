//! The density grid of LuxRender's `volumegrid` region volume: `nx`×`ny`×`nz` values
//! (`density`, x fastest, then y, then z) spread over the box `p0`–`p1` of the volume's own
//! space, each value at its voxel's centre, trilinearly interpolated between centres and
//! held constant (the nearest value) in the half voxel next to each face; 0 outside the box.

use glam::{Affine3A, Vec3A};

/// Most cells a grid may have (checked before its values are copied).
pub const MAX_CELLS: u64 = 1 << 24;

#[derive(Debug)]
pub struct Grid {
    dims: [usize; 3],
    data: Vec<f32>,
    /// World space to the volume's space.
    to_volume: Affine3A,
    lo: Vec3A,
    hi: Vec3A,
}

/// Why a grid cannot be made.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum GridError {
    #[error("{0}×{1}×{2} cells is more than the {MAX_CELLS} allowed")]
    TooLarge(u32, u32, u32),
    #[error("{got} density values for nx×ny×nz = {want}")]
    Count { got: usize, want: u64 },
    #[error("density value {0} is negative or not finite")]
    Value(f32),
}

impl Grid {
    /// A grid of `dims` cells from `data`, over the box `lo`–`hi` of the space `to_volume`
    /// maps world points into.
    pub fn new(
        dims: [u32; 3],
        data: &[f32],
        to_volume: Affine3A,
        lo: Vec3A,
        hi: Vec3A,
    ) -> Result<Grid, GridError> {
        let [nx, ny, nz] = dims;
        let want = (nx as u64)
            .checked_mul(ny as u64)
            .and_then(|n| n.checked_mul(nz as u64))
            .filter(|&n| n <= MAX_CELLS)
            .ok_or(GridError::TooLarge(nx, ny, nz))?;
        if data.len() as u64 != want {
            return Err(GridError::Count {
                got: data.len(),
                want,
            });
        }
        if let Some(&bad) = data.iter().find(|v| !v.is_finite() || **v < 0.0) {
            return Err(GridError::Value(bad));
        }
        Ok(Grid {
            dims: dims.map(|d| d as usize),
            data: data.to_vec(),
            to_volume,
            lo,
            hi,
        })
    }

    /// The value of cell (x, y, z), indices clamped into the grid.
    fn cell(&self, x: i64, y: i64, z: i64) -> f32 {
        let [nx, ny, nz] = self.dims;
        let c = |v: i64, n: usize| v.clamp(0, n as i64 - 1) as usize;
        let i = c(z, nz) * nx * ny + c(y, ny) * nx + c(x, nx);
        self.data.get(i).copied().unwrap_or(0.0)
    }

    /// The density at world point `p`.
    pub fn density(&self, p: Vec3A) -> f32 {
        let q = self.to_volume.transform_point3a(p);
        if q.cmplt(self.lo).any() || q.cmpgt(self.hi).any() {
            return 0.0;
        }
        let ext = self.hi - self.lo;
        let n = Vec3A::new(
            self.dims[0] as f32,
            self.dims[1] as f32,
            self.dims[2] as f32,
        );
        let v = (q - self.lo) / ext.max(Vec3A::splat(f32::MIN_POSITIVE)) * n - 0.5;
        let f = v.floor();
        let d = v - f;
        let (x, y, z) = (f.x as i64, f.y as i64, f.z as i64);
        let lerp = |t: f32, a: f32, b: f32| a + t * (b - a);
        let d00 = lerp(d.x, self.cell(x, y, z), self.cell(x + 1, y, z));
        let d10 = lerp(d.x, self.cell(x, y + 1, z), self.cell(x + 1, y + 1, z));
        let d01 = lerp(d.x, self.cell(x, y, z + 1), self.cell(x + 1, y, z + 1));
        let d11 = lerp(
            d.x,
            self.cell(x, y + 1, z + 1),
            self.cell(x + 1, y + 1, z + 1),
        );
        lerp(d.z, lerp(d.y, d00, d10), lerp(d.y, d01, d11))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(dims: [u32; 3], data: &[f32]) -> Grid {
        Grid::new(dims, data, Affine3A::IDENTITY, Vec3A::ZERO, Vec3A::ONE).unwrap()
    }

    #[test]
    fn values_sit_at_voxel_centres_and_interpolate_between_them() {
        let g = unit([2, 1, 1], &[1.0, 3.0]);
        assert_eq!(g.density(Vec3A::new(0.25, 0.5, 0.5)), 1.0);
        assert_eq!(g.density(Vec3A::new(0.75, 0.5, 0.5)), 3.0);
        assert_eq!(g.density(Vec3A::new(0.5, 0.5, 0.5)), 2.0);
        // Held in the outer half voxel, zero outside the box.
        assert_eq!(g.density(Vec3A::new(0.05, 0.5, 0.5)), 1.0);
        assert_eq!(g.density(Vec3A::new(1.5, 0.5, 0.5)), 0.0);
        // z varies slowest: cell (0, 0, 1) is the third value of a 1×2×2 grid.
        let g = unit([1, 2, 2], &[0.0, 0.0, 5.0, 0.0]);
        assert_eq!(g.density(Vec3A::new(0.5, 0.25, 0.75)), 5.0);
    }

    #[test]
    fn the_box_follows_the_volume_transform() {
        let to_volume = Affine3A::from_translation(glam::Vec3::new(-10.0, 0.0, 0.0));
        let g = Grid::new([1, 1, 1], &[2.0], to_volume, Vec3A::ZERO, Vec3A::ONE).unwrap();
        assert_eq!(g.density(Vec3A::new(10.5, 0.5, 0.5)), 2.0);
        assert_eq!(g.density(Vec3A::new(0.5, 0.5, 0.5)), 0.0);
    }

    #[test]
    fn sizes_and_values_are_checked_before_copying() {
        let id = Affine3A::IDENTITY;
        let e = Grid::new(
            [1 << 20, 1 << 20, 1 << 20],
            &[1.0],
            id,
            Vec3A::ZERO,
            Vec3A::ONE,
        );
        assert!(matches!(e, Err(GridError::TooLarge(..))));
        let e = Grid::new([2, 2, 2], &[1.0; 7], id, Vec3A::ZERO, Vec3A::ONE);
        assert_eq!(e.unwrap_err(), GridError::Count { got: 7, want: 8 });
        let e = Grid::new([1, 1, 1], &[f32::NAN], id, Vec3A::ZERO, Vec3A::ONE);
        assert!(matches!(e, Err(GridError::Value(_))));
    }
}
