//! Render sessions: seeded sample streams over the frame, splatting into the film, halt rules.
