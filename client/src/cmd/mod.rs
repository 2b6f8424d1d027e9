//! One module per subcommand.

pub mod bench_bvh;
pub mod parse;
