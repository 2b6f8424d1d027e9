//! Cameras: perspective, orthographic, environment (one file per plugin).
