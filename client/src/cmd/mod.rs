//! One module per subcommand.

pub mod bench_bvh;
pub mod compare_image;
pub mod parse;
pub mod render;
