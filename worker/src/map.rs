//! Sampling maps from the master: an acknowledgement may carry the job's newest map
//! (`pb::SamplingMap`, cells of `cell` × `cell` film pixels, f32 little endian): the
//! noise-aware map, the job's user sampling map, or their product, as the master combined
//! them (a uniform map once the user's is cleared). The render thread checks it against its
//! film and hands it to its session for the next passes (every sampler but metropolis and
//! erpt takes it).
//!
//! ```text
//! upload loop: ack.sampling_map (newer than ours) --offer--> pending (latest wins)
//! render thread, before a pass: pending --decode: size, cell count, finite, >= 0-->
//!   SamplingMap --Session::set_sampling_map--> the passes of the next delta follow it
//! ```
//!
//! A map that fails a check is logged and dropped (the session keeps its previous map); the
//! version the worker reports in its upload headers is the newest it was offered, so a bad
//! map is not sent again.

use luxfarm::sampler::map::{MapError, SamplingMap};
use luxfarm_proto as pb;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// Why a map from the master is not used.
#[derive(Debug, thiserror::Error)]
pub enum WireMapError {
    #[error("sampling map of {cells} cells for a film of {pixels} pixels")]
    TooLarge { cells: u64, pixels: u64 },
    #[error("sampling map has {got} bytes, {want} expected ({w}x{h} f32)")]
    Bytes {
        got: usize,
        want: u64,
        w: u32,
        h: u32,
    },
    #[error(transparent)]
    Map(#[from] MapError),
}

/// Checks a map from the master against a `w` × `h` film buffer and expands it.
pub fn decode(m: &pb::SamplingMap, w: u32, h: u32) -> Result<SamplingMap, WireMapError> {
    let cells = u64::from(m.width) * u64::from(m.height);
    let pixels = u64::from(w) * u64::from(h);
    if cells > pixels {
        return Err(WireMapError::TooLarge { cells, pixels });
    }
    if m.densities.len() as u64 != cells * 4 {
        return Err(WireMapError::Bytes {
            got: m.densities.len(),
            want: cells * 4,
            w: m.width,
            h: m.height,
        });
    }
    let values: Vec<f32> = m
        .densities
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    Ok(SamplingMap::from_cells(
        w, h, m.cell, m.width, m.height, &values,
    )?)
}

/// The map handed from the upload loop to the render thread.
#[derive(Default)]
pub struct MapSlot {
    /// The newest version offered (what upload headers report).
    version: AtomicU64,
    pending: Mutex<Option<pb::SamplingMap>>,
}

impl MapSlot {
    /// The version of the newest map offered (0: none).
    pub fn version(&self) -> u64 {
        self.version.load(Ordering::SeqCst)
    }

    /// Offers a map from an acknowledgement; older or equal versions are ignored.
    pub fn offer(&self, m: pb::SamplingMap) {
        if self.version.fetch_max(m.version, Ordering::SeqCst) < m.version {
            *self.pending.lock().unwrap_or_else(|p| p.into_inner()) = Some(m);
        }
    }

    /// The newest map not yet taken.
    pub fn take(&self) -> Option<pb::SamplingMap> {
        self.pending
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .take()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wire(version: u64, cell: u32, w: u32, h: u32, values: &[f32]) -> pb::SamplingMap {
        pb::SamplingMap {
            version,
            cell,
            width: w,
            height: h,
            densities: values.iter().flat_map(|v| v.to_le_bytes()).collect(),
        }
    }

    #[test]
    fn maps_are_checked_before_use() {
        let m = decode(&wire(1, 2, 2, 1, &[3.0, 1.0]), 4, 2).unwrap();
        assert_eq!(m.density(0, 0), 1.5);
        assert_eq!(m.density(3, 1), 0.5);
        // wrong cell tiling, wrong byte count, too many cells, hostile values
        assert!(decode(&wire(1, 1, 2, 1, &[3.0, 1.0]), 4, 2).is_err());
        let mut short = wire(1, 2, 2, 1, &[3.0, 1.0]);
        short.densities.pop();
        assert!(matches!(
            decode(&short, 4, 2),
            Err(WireMapError::Bytes { .. })
        ));
        assert!(matches!(
            decode(&wire(1, 1, 100_000, 100_000, &[]), 4, 2),
            Err(WireMapError::TooLarge { .. })
        ));
        assert!(decode(&wire(1, 2, 2, 1, &[f32::NAN, 1.0]), 4, 2).is_err());
        assert!(decode(&wire(1, 2, 2, 1, &[f32::INFINITY, 1.0]), 4, 2).is_err());
        assert!(decode(&wire(1, 2, 2, 1, &[-1.0, 1.0]), 4, 2).is_err());
    }

    #[test]
    fn the_slot_keeps_the_newest_map() {
        let s = MapSlot::default();
        assert_eq!(s.version(), 0);
        s.offer(wire(5, 1, 1, 1, &[1.0]));
        s.offer(wire(3, 1, 1, 1, &[1.0]));
        assert_eq!(s.version(), 5);
        assert_eq!(s.take().map(|m| m.version), Some(5));
        assert!(s.take().is_none());
        s.offer(wire(5, 1, 1, 1, &[1.0]));
        assert!(s.take().is_none());
    }
}
