//! luxfarm master: accepts jobs, leases sample streams to workers and merges their film
//! deltas (filled by the farm issue).
