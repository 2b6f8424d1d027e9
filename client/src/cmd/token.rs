//! `luxfarm token add NAME --role ROLE | list | revoke ID`: the master's user tokens, managed
//! with an admin token over the Admin gRPC service. A new token is printed once, when made;
//! the master keeps only its hash.

use super::farm_remote::{runtime, status, Remote};
use luxfarm_proto as pb;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    pub action: Action,
    #[command(flatten)]
    pub remote: Remote,
}

#[derive(clap::Subcommand)]
pub enum Action {
    /// Make a token for NAME with a role (admin, submitter, viewer or worker); prints it once.
    Add {
        name: String,
        #[arg(long, default_value = "submitter")]
        role: String,
    },
    /// List the tokens (names, roles, dates; never the tokens).
    List,
    /// Revoke a token by its id.
    Revoke { id: String },
}

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    runtime()?.block_on(async {
        let mut c = a.remote.admin()?;
        match a.action {
            Action::Add { name, role } => {
                let r = c
                    .add_token(pb::AddTokenRequest { name, role })
                    .await
                    .map_err(status)?
                    .into_inner();
                if let Some(info) = &r.info {
                    eprintln!("{}", token_line(info));
                }
                eprintln!("the token is shown only now; the master keeps its hash:");
                println!("{}", r.token);
            }
            Action::List => {
                let r = c
                    .list_tokens(pb::ListTokensRequest {})
                    .await
                    .map_err(status)?
                    .into_inner();
                for t in &r.tokens {
                    println!("{}", token_line(t));
                }
            }
            Action::Revoke { id } => {
                let t = c
                    .revoke_token(pb::RevokeTokenRequest { id })
                    .await
                    .map_err(status)?
                    .into_inner();
                println!("{}", token_line(&t));
            }
        }
        anyhow::Ok(ExitCode::SUCCESS)
    })
}

/// One line about a token: id, name, role, and when it was revoked.
fn token_line(t: &pb::TokenInfo) -> String {
    let revoked = match t.revoked_ms {
        Some(ms) => format!("  revoked at {ms} ms"),
        None => String::new(),
    };
    format!(
        "{:<18} {:<24} {:<10} created at {} ms{revoked}",
        t.id,
        super::farm_remote::printable(&t.name),
        t.role,
        t.created_ms
    )
}
