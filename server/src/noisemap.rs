//! Noise-aware sampling maps on the master: for a job whose sampler has `"bool noiseaware"`,
//! the map is built from the merged film (the render core's `luxfarm::render::noise`, the
//! same builder a local render uses: the convergence test every `convergencestep` spp) and
//! handed to every worker with its acknowledgements, as LuxRender's master pushed its map to
//! the slaves.
//!
//! ```text
//! merge (lease), then the tick (crate::analysis): due? --> copy of the merged film --MapBuilder-->
//!   SamplingMap --to_cells (at most MAX_WIRE_CELLS cells, f32 little endian)-->
//!   pb::SamplingMap (version), kept in the job's run state
//! ack of a worker whose header says it takes maps at version v --for_worker: newer?-->
//!   UploadAck.sampling_map
//! ```
//!
//! A map's version is the merged film's sample count when it was built: it grows with every
//! map and survives a master restart (the film comes back from its checkpoint), so a worker
//! never takes an older map for a newer one. Workers that do not say which version they have
//! (older builds) never get a map.

use luxfarm::film::Film;
use luxfarm::render::noise::MapBuilder;
use luxfarm::sampler::map::SamplingMap;
use luxfarm::tonemap::TonemapParams;
use luxfarm_proto as pb;
use std::sync::Arc;

/// Most map cells sent to a worker (256 KiB of f32): larger films are downsampled.
pub const MAX_WIRE_CELLS: u64 = 1 << 16;

/// A job's map state: the builder (created at the first test) and the last map built.
#[derive(Default)]
pub struct NoiseMapState {
    builder: Option<MapBuilder>,
    current: Option<Arc<pb::SamplingMap>>,
}

impl NoiseMapState {
    /// Whether the merged film at `spp` is due for a new map.
    pub fn due(&self, spp: f64) -> bool {
        self.builder.as_ref().is_none_or(|b| b.due(spp))
    }

    /// Takes the builder out (a new one testing every `step` spp at the first call), to run
    /// it without holding the job's state; [`Self::put_back`] returns it.
    pub fn take_builder(&mut self, step: f64) -> MapBuilder {
        self.builder.take().unwrap_or_else(|| MapBuilder::new(step))
    }

    /// Returns the builder and, when one was built, the new current map.
    pub fn put_back(&mut self, builder: MapBuilder, built: Option<pb::SamplingMap>) {
        self.builder = Some(builder);
        if let Some(m) = built {
            self.current = Some(Arc::new(m));
        }
    }
}

/// Runs `builder` on (a copy of) the merged film when it is due: the new map in its wire
/// form, its version the film's sample count.
pub fn build(
    builder: &mut MapBuilder,
    film: &Film,
    tonemap: &TonemapParams,
) -> Option<pb::SamplingMap> {
    if !builder.due(film.spp()) {
        return None;
    }
    let map = builder.update(film, tonemap)?;
    let version = film.total_samples().max(1.0) as u64;
    Some(to_wire(&map, version))
}

impl NoiseMapState {
    /// The map to send with an acknowledgement: the current one when the worker takes maps
    /// (`have` is the version it renders with) and it is newer.
    pub fn for_worker(&self, have: Option<u64>) -> Option<pb::SamplingMap> {
        let have = have?;
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

    #[test]
    fn maps_go_only_to_workers_that_take_them_and_only_when_newer() {
        let mut st = NoiseMapState::default();
        assert!(st.due(0.0));
        assert!(st.for_worker(Some(0)).is_none());
        st.current = Some(Arc::new(to_wire(&SamplingMap::uniform(4, 2).unwrap(), 10)));
        assert_eq!(st.for_worker(Some(0)).map(|m| m.version), Some(10));
        assert!(st.for_worker(Some(10)).is_none());
        assert!(st.for_worker(None).is_none());
    }

    #[test]
    fn wire_maps_are_bounded_and_round_trip() {
        let noise: Vec<f32> = (0..600 * 400).map(|i| (i % 600) as f32 / 100.0).collect();
        let m = SamplingMap::from_noise(&noise, 600, 400).unwrap();
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
