//! One module per subcommand (farm commands share `farm_remote`; scenes are bundled by
//! `luxfarm_wire::bundle`). `luxfarm bench` lives in the `luxfarm-bench` crate.

pub mod cancel;
pub mod certs;
pub mod compare_image;
pub mod farm_remote;
pub mod farm_render;
pub mod fetch;
pub mod flm;
pub mod frames;
pub mod jobs;
pub mod parse;
pub mod regress;
pub mod render;
pub mod server;
pub mod status;
pub mod study;
pub mod submit;
pub mod token;
pub mod watch;
pub mod worker;
pub mod workers;
