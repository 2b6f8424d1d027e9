//! Options and helpers shared by the farm commands: where the master is, its token, and the
//! gRPC clients.

use luxfarm_proto as pb;
use luxfarm_proto::connect::{self, AuthChannel};
use std::path::PathBuf;

/// How to reach the master.
#[derive(Clone, Debug, clap::Args)]
pub struct Remote {
    /// URL of the master (https:// for TLS).
    #[arg(long, env = "LUXFARM_MASTER", default_value = "http://127.0.0.1:7878")]
    pub master: String,
    /// Bearer token of the master.
    #[arg(long, env = "LUXFARM_TOKEN")]
    pub token: Option<String>,
    /// Extra CA certificate (PEM) to trust for an https:// master.
    #[arg(long)]
    pub ca_cert: Option<PathBuf>,
}

impl Remote {
    /// An Admin client (user tokens).
    pub fn admin(&self) -> anyhow::Result<pb::admin_client::AdminClient<AuthChannel>> {
        let ch = connect::channel(&self.master, self.token.as_deref(), self.ca_cert.as_deref())?;
        Ok(pb::admin_client::AdminClient::new(ch))
    }

    /// A Jobs client.
    pub fn jobs(&self) -> anyhow::Result<pb::jobs_client::JobsClient<AuthChannel>> {
        let ch = connect::channel(&self.master, self.token.as_deref(), self.ca_cert.as_deref())?;
        Ok(connect::jobs_client(ch))
    }
}

/// A tokio runtime for a command.
pub fn runtime() -> anyhow::Result<tokio::runtime::Runtime> {
    Ok(tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()?)
}

/// gRPC status as a readable error (certificate errors say what to do).
pub fn status(s: tonic::Status) -> anyhow::Error {
    anyhow::anyhow!("{}: {}", code_name(s.code()), connect::explain(&s))
}

fn code_name(c: tonic::Code) -> &'static str {
    use tonic::Code::*;
    match c {
        InvalidArgument => "refused",
        NotFound => "not found",
        Unauthenticated => "unauthorized",
        FailedPrecondition => "conflict",
        ResourceExhausted => "too large",
        Unavailable => "master unavailable",
        _ => "error",
    }
}

/// One line about a job.
pub fn job_line(j: &pb::JobInfo) -> String {
    let halt = match (j.haltspp, j.halttime, j.haltthreshold) {
        (Some(s), _, _) => format!("{:.1}/{s} spp", j.spp),
        (None, Some(t), _) => format!("{:.1} spp, {:.0}/{t} s", j.spp, j.elapsed),
        (None, None, Some(th)) => format!("{:.1} spp, threshold {th}", j.spp),
        _ => format!("{:.1} spp", j.spp),
    };
    let reason = if j.reason.is_empty() {
        String::new()
    } else {
        format!("  ({})", printable(&j.reason))
    };
    format!(
        "{:<18} {:<10} {:<24} {:>3}  {halt}  {} leases{reason}",
        j.id,
        j.state,
        printable(&j.name),
        j.priority,
        j.active_leases
    )
}

/// Text from the master as it may be shown on a terminal: control characters (escape
/// sequences included) become U+FFFD.
pub fn printable(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { '\u{fffd}' } else { c })
        .collect()
}

/// True for done, cancelled and failed.
pub fn is_final(state: &str) -> bool {
    matches!(state, "done" | "cancelled" | "failed")
}

#[cfg(test)]
mod tests {
    #[test]
    fn control_characters_are_not_printed() {
        assert_eq!(
            super::printable("a\x1b[2Jb\nc\u{7}"),
            "a\u{fffd}[2Jb\u{fffd}c\u{fffd}"
        );
        assert_eq!(super::printable("plain name é"), "plain name é");
    }
}
