//! Identities and roles: who is calling, and what they may do.
//!
//! ```text
//! bearer token --identify--> Identity
//!   lfw_...          a registered worker's credential (hash in `workers`)  -> Worker(id)
//!   --token value    the operator's admin token (compared in constant time) -> User(admin)
//!   lfu_...          a user token (hash in `tokens`, not revoked)          -> User(name, role)
//!   none             on an open farm (no --token, no user token): anonymous admin
//! ```
//!
//! Roles: `admin` (everything, tokens included), `submitter` (submit, read, cancel its own
//! jobs), `viewer` (read), `worker` (register workers only). A registered worker's calls are
//! bound to it: a lease and its uploads, heartbeats and failure reports are accepted only from
//! the worker holding the lease, so worker and lease ids are not secrets. Tokens are stored as
//! their sha256 and shown once, when made.

use crate::db::TokenRow;
use crate::error::{Result, ServerError};
use crate::farm::{lock, new_id, now_ms, secret, Farm};
use sha2::{Digest, Sha256};

/// Prefix of worker credentials.
pub const WORKER_PREFIX: &str = "lfw_";
/// Prefix of user tokens.
pub const USER_PREFIX: &str = "lfu_";

/// A user's role.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    Admin,
    Submitter,
    Viewer,
    Worker,
}

impl Role {
    /// Parses a role name.
    pub fn parse(s: &str) -> Option<Role> {
        Some(match s {
            "admin" => Role::Admin,
            "submitter" => Role::Submitter,
            "viewer" => Role::Viewer,
            "worker" => Role::Worker,
            _ => return None,
        })
    }

    pub fn as_str(self) -> &'static str {
        match self {
            Role::Admin => "admin",
            Role::Submitter => "submitter",
            Role::Viewer => "viewer",
            Role::Worker => "worker",
        }
    }
}

/// Who is calling.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Identity {
    /// A user: the token's name (empty on an open farm) and role.
    User { name: String, role: Role },
    /// A registered worker, by id.
    Worker(String),
}

impl Identity {
    fn role(&self) -> Option<Role> {
        match self {
            Identity::User { role, .. } => Some(*role),
            Identity::Worker(_) => None,
        }
    }

    /// May read jobs, outputs and workers.
    pub fn can_read(&self) -> bool {
        matches!(
            self.role(),
            Some(Role::Admin | Role::Submitter | Role::Viewer)
        )
    }

    /// May submit jobs.
    pub fn can_submit(&self) -> bool {
        matches!(self.role(), Some(Role::Admin | Role::Submitter))
    }

    /// May register a worker.
    pub fn can_register(&self) -> bool {
        matches!(self.role(), Some(Role::Admin | Role::Worker))
    }

    pub fn is_admin(&self) -> bool {
        self.role() == Some(Role::Admin)
    }

    /// The name jobs submitted under this identity are owned by.
    pub fn owner(&self) -> String {
        match self {
            Identity::User { name, .. } => name.clone(),
            Identity::Worker(id) => id.clone(),
        }
    }

    /// Refuses unless this identity may cancel a job owned by `owner`.
    pub fn check_manage(&self, owner: &str) -> Result<()> {
        if self.is_admin() || (self.can_submit() && self.owner() == owner) {
            return Ok(());
        }
        Err(ServerError::Forbidden(format!(
            "this job belongs to {}: only its submitter or an admin may change it",
            if owner.is_empty() { "nobody" } else { owner }
        )))
    }

    /// The worker id of a worker identity, or Forbidden.
    pub fn worker(&self) -> Result<&str> {
        match self {
            Identity::Worker(id) => Ok(id),
            Identity::User { .. } => Err(ServerError::Forbidden(
                "worker calls need the worker's own credential (register first)".into(),
            )),
        }
    }
}

/// Hex sha256 of a token (what the store keeps).
pub fn hash_token(token: &str) -> String {
    luxfarm_wire::bundle::hex(&Sha256::digest(token.as_bytes()))
}

/// Constant-time comparison of two byte strings.
fn same(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

impl Farm {
    /// True when calls need a token (an admin token is configured or a user token exists).
    pub fn auth_required(&self) -> Result<bool> {
        let configured = self.cfg.token.as_deref().is_some_and(|t| !t.is_empty());
        Ok(configured || lock(&self.db).has_tokens()?)
    }

    /// Resolves a bearer token (None when none was given). An unknown or revoked token is
    /// Unauthorized.
    pub fn identify(&self, token: Option<&str>) -> Result<Option<Identity>> {
        let Some(token) = token.filter(|t| !t.is_empty()) else {
            return Ok(None);
        };
        if token.starts_with(WORKER_PREFIX) {
            return match lock(&self.db).worker_by_token(&hash_token(token))? {
                Some(w) => Ok(Some(Identity::Worker(w.id))),
                None => Err(ServerError::Unauthorized),
            };
        }
        if let Some(admin) = self.cfg.token.as_deref().filter(|t| !t.is_empty()) {
            if same(token.as_bytes(), admin.as_bytes()) {
                return Ok(Some(Identity::User {
                    name: "admin".into(),
                    role: Role::Admin,
                }));
            }
        }
        match lock(&self.db).token_by_hash(&hash_token(token))? {
            Some(t) => Ok(Some(Identity::User {
                role: Role::parse(&t.role).unwrap_or(Role::Viewer),
                name: t.name,
            })),
            None => Err(ServerError::Unauthorized),
        }
    }

    /// The identity of a call without a token: an anonymous admin on an open farm.
    pub fn anonymous(&self) -> Result<Identity> {
        if self.auth_required()? {
            return Err(ServerError::Unauthorized);
        }
        Ok(Identity::User {
            name: String::new(),
            role: Role::Admin,
        })
    }

    /// Makes a user token; returns its row and the token (shown once).
    pub fn add_token(&self, name: &str, role: &str) -> Result<(TokenRow, String)> {
        let role = Role::parse(role)
            .ok_or_else(|| {
                ServerError::BadRequest(format!(
                    "unknown role {role:?} (admin, submitter, viewer or worker)"
                ))
            })?
            .as_str();
        let name = name.trim();
        if name.is_empty() || name.len() > 64 || name.chars().any(char::is_control) {
            return Err(ServerError::BadRequest(
                "a token needs a name of 1 to 64 printable characters".into(),
            ));
        }
        let token = secret(USER_PREFIX)?;
        let row = TokenRow {
            id: new_id("t"),
            name: name.to_string(),
            role: role.to_string(),
            hash: hash_token(&token),
            created_ms: now_ms(),
            revoked_ms: None,
        };
        lock(&self.db).insert_token(&row)?;
        tracing::info!(id = %row.id, name = %row.name, role, "token added");
        Ok((row, token))
    }

    /// Every user token (hashes, never tokens).
    pub fn tokens(&self) -> Result<Vec<TokenRow>> {
        lock(&self.db).tokens()
    }

    /// Revokes a user token at once.
    pub fn revoke_token(&self, id: &str) -> Result<TokenRow> {
        let row = lock(&self.db)
            .revoke_token(id, now_ms())?
            .ok_or_else(|| ServerError::NotFound(format!("no token {id:?}")))?;
        tracing::info!(id, name = %row.name, "token revoked");
        Ok(row)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn user(name: &str, role: Role) -> Identity {
        Identity::User {
            name: name.into(),
            role,
        }
    }

    #[test]
    fn roles_allow_what_they_say() {
        let admin = user("root", Role::Admin);
        let alice = user("alice", Role::Submitter);
        let viewer = user("v", Role::Viewer);
        let worker_token = user("w", Role::Worker);
        let worker = Identity::Worker("w1".into());
        assert!(admin.can_read() && admin.can_submit() && admin.can_register());
        assert!(alice.can_read() && alice.can_submit() && !alice.can_register());
        assert!(viewer.can_read() && !viewer.can_submit());
        assert!(!worker_token.can_read() && worker_token.can_register());
        assert!(!worker.can_read() && !worker.can_submit() && !worker.can_register());
        assert!(alice.check_manage("alice").is_ok());
        assert!(alice.check_manage("bob").is_err());
        assert!(admin.check_manage("bob").is_ok());
        assert!(viewer.check_manage("v").is_err());
        assert_eq!(worker.worker().unwrap(), "w1");
        assert!(alice.worker().is_err());
    }

    #[test]
    fn hashes_are_stable_hex() {
        assert_eq!(hash_token("abc").len(), 64);
        assert_eq!(hash_token("abc"), hash_token("abc"));
        assert_ne!(hash_token("abc"), hash_token("abd"));
    }
}
