//! The gRPC contract between luxfarm clients, the master and workers (filled by the farm issue).
