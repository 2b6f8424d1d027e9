//! Indigo scenes (`.igs`) and meshes (`.igmesh`).

pub mod ctx;
pub mod igmesh;
pub mod mesh;
pub mod node;
pub mod xml;
