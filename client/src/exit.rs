//! Exit statuses, one convention for every command:
//!
//! - 0: the command did what was asked;
//! - 1: it failed for a reason outside the input (I/O, the network, the master, a render
//!   that could not finish);
//! - 2: the input was refused — a scene error (always located: file:line:column), an invalid
//!   argument value, or a usage error (clap's own exit status for those is also 2).

use luxfarm::lxs::LxsError;
use luxfarm::plugin::BuildError;
use luxfarm::render::setup::SetupError;
use luxfarm::render::RenderError;

/// The user's input was refused: the message says what and where.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

/// The exit status for an error that ended a command.
pub fn code(e: &anyhow::Error) -> u8 {
    let input = e.chain().any(|c| {
        c.is::<InputError>()
            || c.is::<LxsError>()
            || c.is::<BuildError>()
            || c.is::<SetupError>()
            || matches!(c.downcast_ref::<RenderError>(), Some(RenderError::Setup(_)))
    });
    if input {
        2
    } else {
        1
    }
}
