//! Shapes: meshes, PLY, quadrics, heightfield (one file per shape).
