//! One module per subcommand.

pub mod bench_bvh;
pub mod bench_flm;
pub mod bench_parse;
pub mod compare_image;
pub mod flm;
pub mod parse;
pub mod render;
