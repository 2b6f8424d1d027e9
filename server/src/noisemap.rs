//! Sampling maps on the master: for a job whose sampler has `"bool noiseaware"`, the map is
//! built from the merged film (the render core's `luxfarm::render::noise`, the same builder a
//! local render uses: each pixel's spread of contributions, which the workers' deltas carry,
//! over its visibility threshold, at `convergencestep` spp and then at doubling steps); a job
//! may also have a user sampling map (`crate::usermap`). The map the workers get is their pixel by pixel
//! product when both exist, else the one that does (LuxRender's `Film::UpdateSamplingMap`;
//! a cleared user map without a noise-aware map gives the uniform map), handed to every
//! worker with its acknowledgements, as LuxRender's master pushed its maps to the slaves.
//!
//! ```text
//! merge (lease), then the tick (crate::analysis): due? --> copy of the merged film --MapBuilder-->
//!   noise-aware SamplingMap --\
//! REST PUT/DELETE (crate::usermap) --> user map --+--> combined --to_wire (at most
//!   MAX_WIRE_CELLS cells, f32 little endian)--> pb::SamplingMap (version), in the job's run state
//! ack of a worker whose header says it takes maps at version v --for_worker: newer?-->
//!   UploadAck.sampling_map
//! ```
//!
//! Versions only grow: a new combined map takes the larger of its candidate (the merged
//! film's sample count for a noise-aware rebuild, the stored version for a user map) and one
//! more than the last. A worker reporting a version this master never issued (it took a map
//! from the master before a restart) raises the counter past it, and gets the current map
//! again at the new version, so no worker keeps a map this master no longer holds. Workers
//! that do not say which version they have (older builds) never get a map.

use luxfarm::film::Film;
use luxfarm::render::noise::MapBuilder;
use luxfarm::sampler::map::SamplingMap;
use luxfarm::tonemap::TonemapParams;
use luxfarm_proto as pb;
use std::sync::Arc;

/// Most map cells sent to a worker (256 KiB of f32): larger films are downsampled.
pub const MAX_WIRE_CELLS: u64 = 1 << 16;

/// A job's user sampling map as the master holds it.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum UserMap {
    /// The job never had one.
    #[default]
    None,
    /// It had one and it was cleared: sampling goes back to uniform (or noise-aware) over
    /// the job's `width` × `height` film.
    Cleared {
        width: u32,
        height: u32,
    },
    Set(Arc<SamplingMap>),
}

/// A job's map state: the builder (created when the first map is due), the last noise-aware
/// map, the user map, and the last combined map with its version.
#[derive(Default)]
pub struct NoiseMapState {
    builder: Option<MapBuilder>,
    noise: Option<Arc<SamplingMap>>,
    user: UserMap,
    /// The last version issued (or seen from a worker).
    version: u64,
    current: Option<Arc<pb::SamplingMap>>,
}

impl NoiseMapState {
    /// Whether the merged film at `spp` is due for a new map.
    pub fn due(&self, spp: f64) -> bool {
        self.builder.as_ref().is_none_or(|b| b.due(spp))
    }

    /// Takes the builder out (at the first call a new one, its first map due at `step` spp),
    /// to run it without holding the job's state; [`Self::put_back`] returns it.
    pub fn take_builder(&mut self, step: f64) -> MapBuilder {
        self.builder.take().unwrap_or_else(|| MapBuilder::new(step))
    }

    /// Returns the builder and, when one was built, the new noise-aware map (with its
    /// candidate version, the film's sample count).
    pub fn put_back(&mut self, builder: MapBuilder, built: Option<(SamplingMap, u64)>) {
        self.builder = Some(builder);
        if let Some((m, candidate)) = built {
            self.noise = Some(Arc::new(m));
            self.refresh(candidate);
        }
    }

    /// Sets the user map, its version at least `candidate`; returns the version of the
    /// combined map the workers will get.
    pub fn set_user(&mut self, user: UserMap, candidate: u64) -> u64 {
        self.user = user;
        self.refresh(candidate);
        self.version
    }

    /// The last version issued.
    pub fn version(&self) -> u64 {
        self.version
    }

    /// Recombines the maps into the current wire map, at a new version (at least
    /// `candidate`, above the last).
    fn refresh(&mut self, candidate: u64) {
        let combined = match (&self.noise, &self.user) {
            (Some(n), UserMap::Set(u)) => match n.product(u) {
                Ok(m) => Some(Arc::new(m)),
                Err(e) => {
                    // Both are checked against the job's film: sizes always match.
                    tracing::error!(error = %e, "sampling maps not combined");
                    Some(u.clone())
                }
            },
            (None, UserMap::Set(u)) => Some(u.clone()),
            (Some(n), _) => Some(n.clone()),
            (None, UserMap::Cleared { width, height }) => {
                SamplingMap::uniform(*width, *height).ok().map(Arc::new)
            }
            (None, UserMap::None) => None,
        };
        let Some(m) = combined else {
            self.current = None;
            return;
        };
        self.version = candidate.max(self.version.saturating_add(1));
        self.current = Some(Arc::new(to_wire(&m, self.version)));
    }
}

/// Runs `builder` on (a copy of) the merged film when it is due: the new map and its
/// candidate version, the film's sample count.
pub fn build(
    builder: &mut MapBuilder,
    film: &Film,
    tonemap: &TonemapParams,
) -> Option<(SamplingMap, u64)> {
    if !builder.due(film.spp()) {
        return None;
    }
    let map = builder.update(film, tonemap)?;
    let version = film.total_samples().max(1.0) as u64;
    Some((map, version))
}

impl NoiseMapState {
    /// The map to send with an acknowledgement: the current one when the worker takes maps
    /// (`have` is the version it renders with) and it is newer. A version above any this
    /// master issued (from before a restart) raises the counter and reissues the current map.
    pub fn for_worker(&mut self, have: Option<u64>) -> Option<pb::SamplingMap> {
        let have = have?;
        if have > self.version {
            self.version = have;
            if let Some(c) = self.current.as_mut() {
                self.version = self.version.saturating_add(1);
                let mut again = (**c).clone();
                again.version = self.version;
                *c = Arc::new(again);
            }
        }
        let m = self.current.as_ref()?;
        (m.version > have).then(|| (**m).clone())
    }
}

/// The wire form of a map, at version `version`.
pub fn to_wire(map: &SamplingMap, version: u64) -> pb::SamplingMap {
    let cell = map.cell_size_for(MAX_WIRE_CELLS);
    let (w, h, values) = map.to_cells(cell);
    let mut densities = Vec::with_capacity(values.len() * 4);
    for v in values {
        densities.extend_from_slice(&v.to_le_bytes());
    }
    pb::SamplingMap {
        version,
        cell,
        width: w,
        height: h,
        densities,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn values(m: &pb::SamplingMap) -> Vec<f32> {
        m.densities
            .chunks(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    }

    fn user(w: &[f32], width: u32) -> UserMap {
        let h = w.len() as u32 / width;
        UserMap::Set(Arc::new(SamplingMap::from_weights(w, width, h).unwrap()))
    }

    #[test]
    fn maps_go_only_to_workers_that_take_them_and_only_when_newer() {
        let mut st = NoiseMapState::default();
        assert!(st.due(0.0));
        assert!(st.for_worker(Some(0)).is_none());
        let b = st.take_builder(4.0);
        st.put_back(b, Some((SamplingMap::uniform(4, 2).unwrap(), 10)));
        assert_eq!(st.for_worker(Some(0)).map(|m| m.version), Some(10));
        assert!(st.for_worker(Some(10)).is_none());
        assert!(st.for_worker(None).is_none());
    }

    #[test]
    fn the_user_map_alone_times_the_noise_map_and_cleared() {
        let mut st = NoiseMapState::default();
        // the user map alone, at its candidate version
        assert_eq!(st.set_user(user(&[9.0, 1.0], 2), 5), 5);
        let m = st.for_worker(Some(0)).unwrap();
        assert_eq!((m.version, values(&m)), (5, vec![1.8, 0.2]));
        // a noise-aware map multiplies in, at a version above the last even when the film's
        // count is lower
        let noise = SamplingMap::from_cells(2, 1, 1, 2, 1, &[1.0, 3.0]).unwrap();
        let b = st.take_builder(4.0);
        st.put_back(b, Some((noise, 3)));
        let m = st.for_worker(Some(5)).unwrap();
        assert_eq!(m.version, 6);
        let v = values(&m);
        assert!((v[0] / v[1] - 3.0).abs() < 1e-5, "{v:?}");
        // cleared: the noise-aware map alone
        st.set_user(
            UserMap::Cleared {
                width: 2,
                height: 1,
            },
            0,
        );
        let m = st.for_worker(Some(6)).unwrap();
        assert_eq!(m.version, 7);
        let v = values(&m);
        assert!((v[1] / v[0] - 3.0).abs() < 1e-5, "{v:?}");
        // without a noise-aware map, cleared is uniform
        let mut st = NoiseMapState::default();
        st.set_user(user(&[0.0, 1.0], 2), 1);
        st.set_user(
            UserMap::Cleared {
                width: 2,
                height: 1,
            },
            0,
        );
        let m = st.for_worker(Some(1)).unwrap();
        assert_eq!((m.version, values(&m)), (2, vec![1.0, 1.0]));
        // a job that never had a user map and has no noise-aware map sends nothing
        let mut st = NoiseMapState::default();
        st.set_user(UserMap::None, 4);
        assert!(st.for_worker(Some(0)).is_none());
    }

    #[test]
    fn a_worker_ahead_of_a_restarted_master_gets_the_map_again() {
        // The restarted master holds the stored user map at version 4; a worker took a
        // noise-aware product at version 900 from the master before the restart.
        let mut st = NoiseMapState::default();
        st.set_user(user(&[1.0, 3.0], 2), 4);
        let m = st.for_worker(Some(900)).expect("reissued");
        assert_eq!(m.version, 901);
        assert!(st.for_worker(Some(901)).is_none());
        // a fresh worker gets the same
        assert_eq!(st.for_worker(Some(0)).map(|m| m.version), Some(901));
        // a later map goes above it
        assert_eq!(st.set_user(user(&[1.0, 1.0], 2), 5), 902);
        // with no map at all, the counter still moves past what workers have
        let mut st = NoiseMapState::default();
        assert!(st.for_worker(Some(70)).is_none());
        let b = st.take_builder(4.0);
        st.put_back(b, Some((SamplingMap::uniform(2, 1).unwrap(), 10)));
        assert_eq!(st.for_worker(Some(70)).map(|m| m.version), Some(71));
    }

    #[test]
    fn wire_maps_are_bounded_and_round_trip() {
        let weights: Vec<f32> = (0..600 * 400).map(|i| (i % 600) as f32 / 100.0).collect();
        let m = SamplingMap::from_weights(&weights, 600, 400).unwrap();
        let w = to_wire(&m, 7);
        assert!(u64::from(w.width * w.height) <= MAX_WIRE_CELLS);
        assert_eq!(w.densities.len() as u32, 4 * w.width * w.height);
        assert_eq!(w.width, 600u32.div_ceil(w.cell));
        let values: Vec<f32> = w
            .densities
            .chunks(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        let back = SamplingMap::from_cells(600, 400, w.cell, w.width, w.height, &values).unwrap();
        assert!(back.density(599, 0) > 2.0 * back.density(0, 0));
        // a small film travels at full resolution
        let s = SamplingMap::uniform(32, 16).unwrap();
        let w = to_wire(&s, 1);
        assert_eq!((w.cell, w.width, w.height), (1, 32, 16));
    }
}
