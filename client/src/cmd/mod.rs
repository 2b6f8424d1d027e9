//! One module per subcommand (farm commands share `farm_remote` and `farm_bundle`).

pub mod bench_bvh;
pub mod bench_cornell;
pub mod bench_flm;
pub mod bench_load;
pub mod bench_master;
pub mod bench_parse;
pub mod bench_transport;
pub mod cancel;
pub mod compare_image;
pub mod farm_bundle;
pub mod farm_remote;
pub mod farm_render;
pub mod fetch;
pub mod flm;
pub mod jobs;
pub mod parse;
pub mod render;
pub mod server;
pub mod status;
pub mod submit;
pub mod watch;
pub mod worker;
pub mod workers;
