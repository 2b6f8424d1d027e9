//! Outlier ("firefly") rejection as LuxRender's `outlierrejection_k`.
//!
//! Samples are points (x, y, ln(1 + Y)) with x and y in units of cells about two filter radii
//! wide. A sample is kept when the k previously rejected points nearest to it lie on average
//! within distance 1 (squared distances summed over at most k points, compared with their
//! count); otherwise it is recorded in its cell and the neighbouring cells, and rejected.
//! Isolated bright samples therefore never reach the film, while a feature that keeps
//! producing similar samples soon builds the cluster that lets its samples through.

/// The k-nearest outlier test over the film's sample extent.
#[derive(Clone, Debug)]
pub struct OutlierRejector {
    k: usize,
    inv_cell: [f32; 2],
    offset: [f32; 2],
    cols: usize,
    rows: usize,
    cells: Vec<Vec<[f32; 3]>>,
}

impl OutlierRejector {
    /// `k` nearest points; film buffer size and pixel start (crop window) and the filter
    /// radius define the grid. `None` when k is 0 (rejection disabled).
    pub fn new(k: u32, width: u32, height: u32, start: [u32; 2], radius: [f32; 2]) -> Option<Self> {
        if k == 0 {
            return None;
        }
        let cell = radius.map(|r| (2.0 * r).floor().max(1.0));
        let real = [
            width as f32 + 2.0 * radius[0] + 1.0,
            height as f32 + 2.0 * radius[1] + 1.0,
        ];
        let cols = ((real[0] / cell[0]) as usize).max(1);
        let rows = ((real[1] / cell[1]) as usize).max(1);
        Some(OutlierRejector {
            k: k as usize,
            inv_cell: cell.map(|c| 1.0 / c),
            offset: [
                radius[0] - 0.5 - start[0] as f32,
                radius[1] - 0.5 - start[1] as f32,
            ],
            cols,
            rows,
            cells: vec![Vec::new(); cols * rows],
        })
    }

    /// Whether a sample at raster position (x, y) of the full image with luminance `y_lum`
    /// goes to the film (`false`: it is an outlier and is recorded).
    pub fn accept(&mut self, image_x: f32, image_y: f32, y_lum: f32) -> bool {
        let p = [
            (image_x + self.offset[0]) * self.inv_cell[0],
            (image_y + self.offset[1]) * self.inv_cell[1],
            (1.0 + y_lum.max(0.0)).ln(),
        ];
        if !p.iter().all(|v| v.is_finite()) {
            return false;
        }
        let cx = (p[0].floor().max(0.0) as usize).min(self.cols - 1);
        let cy = (p[1].floor().max(0.0) as usize).min(self.rows - 1);
        let (found, sum) = self.nearest(cy * self.cols + cx, p);
        if found > 0 && sum <= found as f32 {
            return true;
        }
        for y in cy.saturating_sub(1)..=(cy + 1).min(self.rows - 1) {
            for x in cx.saturating_sub(1)..=(cx + 1).min(self.cols - 1) {
                if let Some(c) = self.cells.get_mut(y * self.cols + x) {
                    c.push(p);
                }
            }
        }
        false
    }

    /// Number of the k nearest points found in a cell and the sum of their squared distances.
    fn nearest(&self, cell: usize, p: [f32; 3]) -> (usize, f32) {
        let Some(points) = self.cells.get(cell) else {
            return (0, 0.0);
        };
        let mut best: Vec<f32> = Vec::with_capacity(self.k + 1);
        for q in points {
            let d = (0..3).map(|i| (q[i] - p[i]) * (q[i] - p[i])).sum::<f32>();
            if best.len() < self.k || d < best[best.len() - 1] {
                let pos = best.partition_point(|&b| b <= d);
                best.insert(pos, d);
                best.truncate(self.k);
            }
        }
        (best.len(), best.iter().sum())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isolated_samples_are_rejected_and_clusters_accepted() {
        let mut r = OutlierRejector::new(2, 16, 16, [0, 0], [2.0, 2.0]).unwrap();
        // The first sample of a kind is an outlier; similar ones then pass.
        assert!(!r.accept(5.5, 5.5, 1.0));
        assert!(r.accept(5.6, 5.4, 1.05));
        // A very bright sample far in luminance is rejected.
        assert!(!r.accept(5.5, 5.5, 1e6));
        assert!(OutlierRejector::new(0, 16, 16, [0, 0], [2.0, 2.0]).is_none());
        assert!(!r.accept(f32::NAN, 1.0, 1.0));
    }
}
