//! The sample dimensions of one bidirectional sample: the camera's five, then a fixed block
//! per eye vertex (its distance sampling, scattering, roulette and direct-lighting draws),
//! then one block per light subpath (its origin, then a fixed block per vertex). With fixed
//! blocks a vertex draws from the same dimensions in every sample, whatever the lengths of
//! the subpaths before it.

/// Which sample dimensions each vertex draws (the camera's five come first).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Light samples per eye vertex (direct lighting).
    pub direct_count: u32,
    eye_stride: u32,
    light_base: u32,
    light_stride: u32,
}

impl Layout {
    pub fn new(max_eye: u32, max_light: u32, direct_count: u32) -> Layout {
        let eye_stride = 7 + 4 * direct_count;
        Layout {
            direct_count,
            eye_stride,
            light_base: 5 + max_eye.saturating_sub(1) * eye_stride,
            light_stride: 6 + max_light.saturating_sub(1) * 7,
        }
    }

    /// First dimension of eye vertex `i` (1 = the first hit): distance sampling (2, for the
    /// segment reaching it), component, lobe, direction (2D), roulette, then per light
    /// sample: choice, position (2D), mesh triangle.
    pub fn eye(&self, i: usize) -> u32 {
        5 + (i as u32).saturating_sub(1) * self.eye_stride
    }

    /// First dimension of light sample `d` at eye vertex `i`.
    pub fn direct(&self, i: usize, d: u32) -> u32 {
        self.eye(i) + 7 + 4 * d
    }

    /// First dimension of light subpath `p`: choice, position (2D), direction (2D), mesh
    /// triangle.
    pub fn light_origin(&self, p: u32) -> u32 {
        self.light_base + p * self.light_stride
    }

    /// First dimension of vertex `i` >= 1 of light subpath `p`: distance sampling (2),
    /// component, lobe, direction (2D), roulette.
    pub fn light_vertex(&self, p: u32, i: usize) -> u32 {
        self.light_origin(p) + 6 + (i as u32).saturating_sub(1) * 7
    }

    /// Dimensions a sample uses with `paths` light subpaths.
    pub fn total(&self, paths: u32) -> u32 {
        self.light_base + paths * self.light_stride
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_blocks_do_not_overlap() {
        let l = Layout::new(8, 6, 2);
        assert_eq!(l.eye(1), 5);
        assert_eq!(l.direct(1, 0), 12);
        assert_eq!(l.direct(1, 1) + 4, l.eye(2));
        assert_eq!(l.eye(7) + 15, l.light_origin(0));
        assert_eq!(l.light_vertex(0, 1), l.light_origin(0) + 6);
        assert_eq!(l.light_vertex(0, 5) + 7, l.light_origin(1));
        assert_eq!(l.total(2), l.light_origin(2));
    }
}
