//! Acceleration structures: BVH over primitives (obvhs) and a two-level BVH for object instances.
