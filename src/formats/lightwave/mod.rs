//! LightWave scenes (work in progress: module list only).

mod coords;
mod envelope;
mod items;
mod keywords;
mod scene;
mod text;
mod iff;
mod lwo2;
mod lwob;
mod model;
mod motion;
mod surf2;
mod material;
mod mesh;
mod paths;
mod projection;
mod triangulate;
