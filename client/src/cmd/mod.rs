//! One module per subcommand.

pub mod bench_bvh;
pub mod bench_parse;
pub mod parse;
