//! Memory reused by uploads, so receiving and merging a delta touches no fresh pages: the
//! buffers deltas are received into ([`BytePool`]) and the films they are decoded into
//! ([`ScratchPool`]).
//!
//! ```text
//! upload body --BytePool::take(announced size)--> a kept buffer, filled chunk by chunk
//! upload --ScratchPool::take(job layout)--> a kept film of that layout (or a new one)
//!   --codec::decode_as_into--> every value, count and rejection overwritten by the delta
//!   --merge into the job's film--> both given back --> kept for the next upload
//! job ends --retain(layouts of the loaded jobs)--> films no job can use are freed
//! ```
//!
//! A 1080p delta decodes into about 83 MB of f64 sums and arrives in tens of MB. Allocated
//! afresh for every upload, those pages were mapped and zeroed by the kernel before being
//! overwritten (the page faults showed in the master's profile). The film pool keeps at most
//! one film per merge slot (uploads decoded at once), the figure admission control already
//! counts per job; the byte pool as many buffers, freed when no job is left rendering. Contents between uses are
//! unspecified: decoding overwrites a whole film, and a buffer is cleared before it is filled.

use crate::scene::{self, Film, SceneInfo};
use std::sync::{Mutex, MutexGuard};

/// Films kept for decoding, of any layout, oldest first.
pub struct ScratchPool {
    films: Mutex<Vec<Film>>,
    keep: usize,
}

/// Whether `film` has the layout of the job's films (resolution, groups, buffers).
fn fits(film: &Film, info: &SceneInfo) -> bool {
    film.width() == info.width
        && film.height() == info.height
        && film.groups().len() == info.groups.len()
        && film.buffer_types() == info.buffers.as_slice()
}

impl ScratchPool {
    /// A pool keeping at most `keep` films.
    pub fn new(keep: usize) -> ScratchPool {
        ScratchPool {
            films: Mutex::new(Vec::new()),
            keep,
        }
    }

    fn films(&self) -> MutexGuard<'_, Vec<Film>> {
        self.films.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// A film of the job's layout to decode a delta into: a kept one when there is one, else
    /// a new one. Its values are unspecified.
    pub fn take(&self, info: &SceneInfo) -> Film {
        let kept = {
            let mut films = self.films();
            let at = films.iter().rposition(|f| fits(f, info));
            at.map(|i| films.remove(i))
        };
        kept.unwrap_or_else(|| scene::new_film(info))
    }

    /// Keeps a film for the next upload, dropping the oldest kept one when the pool is full.
    pub fn give_back(&self, film: Film) {
        if self.keep == 0 {
            return;
        }
        let mut films = self.films();
        if films.len() >= self.keep {
            films.remove(0);
        }
        films.push(film);
    }

    /// Frees the kept films that none of `layouts` (the loaded jobs) can use.
    pub fn retain(&self, layouts: &[&SceneInfo]) {
        self.films()
            .retain(|f| layouts.iter().any(|info| fits(f, info)));
    }

    /// Films kept now.
    #[cfg(test)]
    pub fn kept(&self) -> usize {
        self.films().len()
    }
}

/// Buffers uploads are received into, largest kept first.
pub struct BytePool {
    buffers: Mutex<Vec<Vec<u8>>>,
    keep: usize,
}

impl BytePool {
    /// A pool keeping at most `keep` buffers.
    pub fn new(keep: usize) -> BytePool {
        BytePool {
            buffers: Mutex::new(Vec::new()),
            keep,
        }
    }

    fn buffers(&self) -> MutexGuard<'_, Vec<Vec<u8>>> {
        self.buffers.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// An empty buffer able to hold `size` bytes: the smallest kept one that can, else a new
    /// one (the caller bounded `size` before asking).
    pub fn take(&self, size: usize) -> Vec<u8> {
        let kept = {
            let mut buffers = self.buffers();
            let fit = buffers
                .iter()
                .enumerate()
                .filter(|(_, b)| b.capacity() >= size)
                .min_by_key(|(_, b)| b.capacity())
                .map(|(i, _)| i);
            fit.map(|i| buffers.swap_remove(i))
        };
        let mut b = kept.unwrap_or_else(|| Vec::with_capacity(size));
        b.clear();
        b
    }

    /// Keeps a buffer for a later upload; when the pool is full the smallest one goes.
    pub fn give_back(&self, buffer: Vec<u8>) {
        if self.keep == 0 {
            return;
        }
        let mut buffers = self.buffers();
        buffers.push(buffer);
        if buffers.len() > self.keep {
            if let Some(i) = (0..buffers.len()).min_by_key(|&i| buffers[i].capacity()) {
                buffers.swap_remove(i);
            }
        }
    }

    /// Frees every kept buffer (no job is rendering).
    pub fn clear(&self) {
        self.buffers().clear();
    }

    /// Bytes held by the kept buffers.
    #[cfg(test)]
    pub fn held(&self) -> usize {
        self.buffers().iter().map(Vec::capacity).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use luxfarm::film::BufferType;

    fn info(width: u32, height: u32, groups: usize) -> SceneInfo {
        SceneInfo {
            params: Default::default(),
            width,
            height,
            pixels: u64::from(width) * u64::from(height),
            pass_pixels: u64::from(width) * u64::from(height),
            groups: (0..groups).map(|g| format!("g{g}")).collect(),
            buffers: vec![BufferType::PerPixel],
            haltspp: None,
            halttime: None,
            haltthreshold: None,
            convergence_step: 32.0,
            noise_aware: false,
            map_refusal: None,
            basename: "b".into(),
            name: "n".into(),
            scene: "s.lxs".into(),
            has_camera: true,
            shapes: 1,
            lights: 1,
        }
    }

    #[test]
    fn films_come_back_by_layout_and_the_pool_stays_bounded() {
        let pool = ScratchPool::new(2);
        let (a, b) = (info(4, 3, 1), info(4, 3, 2));
        let mut f = pool.take(&a);
        f.add_sample_count(5.0);
        pool.give_back(f);
        // Another layout does not get it.
        assert_eq!(pool.take(&b).groups().len(), 2);
        // The same layout gets the kept film back (its contents as left).
        let f = pool.take(&a);
        assert_eq!(f.total_samples(), 5.0);
        assert_eq!(pool.kept(), 0);
        pool.give_back(f);
        pool.give_back(pool.take(&b));
        pool.give_back(scene::new_film(&a));
        assert_eq!(pool.kept(), 2, "the oldest was dropped");
        pool.retain(&[&b]);
        assert_eq!(
            pool.kept(),
            1,
            "only the 2-group film is of a loaded layout"
        );
        assert_eq!(pool.take(&b).groups().len(), 2);
        pool.retain(&[]);
        assert_eq!(pool.kept(), 0);
        let none = ScratchPool::new(0);
        none.give_back(scene::new_film(&a));
        assert_eq!(none.kept(), 0);
    }

    #[test]
    fn buffers_come_back_empty_and_big_enough() {
        let pool = BytePool::new(2);
        let mut a = pool.take(100);
        a.extend_from_slice(&[7; 100]);
        pool.give_back(a);
        let b = pool.take(50);
        assert!(
            b.is_empty() && b.capacity() >= 100,
            "the kept buffer, cleared"
        );
        assert_eq!(pool.held(), 0);
        pool.give_back(b);
        let c = pool.take(1000);
        assert!(c.capacity() >= 1000);
        pool.give_back(c);
        pool.give_back(Vec::with_capacity(10));
        assert!(pool.held() >= 1100);
        // Full: the smallest goes.
        pool.give_back(Vec::with_capacity(5000));
        assert!(pool.held() >= 6000 && pool.take(4000).capacity() >= 5000);
        assert!(pool.take(1).capacity() >= 1000);
        assert_eq!(pool.held(), 0);
    }
}
