//! luxfarm worker: renders leased sample streams with the full render core and uploads film
//! deltas to the master (filled by the farm issue).
