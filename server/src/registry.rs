//! Worker registration: protocol versions compared, a credential issued (or proved again by a
//! worker coming back), and the master's record of when each worker was last seen.
//!
//! ```text
//! RegisterRequest (protocol, build, old id + credential) --register--> RegisterReply
//!   protocol differs            -> FailedPrecondition naming both versions (the worker exits)
//!   old id + its credential     -> same id, same credential (after a master restart)
//!   otherwise                   -> a new id and a new credential (stored hashed)
//! ```
//!
//! The worker also declares what it offers: tags (cleaned by `admission::clean_tags`: lowercase
//! letters, digits, `-`, `_`, `.`; at most `admission::MAX_TAGS`), its memory and its build; the
//! scheduler matches them against what jobs ask for (`lease`).

use crate::auth::{hash_token, WORKER_PREFIX};
use crate::db::WorkerRow;
use crate::error::{Result, ServerError};
use crate::farm::{lock, new_id, now_ms, secret, Farm, WorkerRt};
use luxfarm_proto as pb;
use std::time::Instant;

/// Longest worker name kept.
const MAX_NAME: usize = 128;

/// The refusal of a worker speaking another protocol version.
pub fn protocol_mismatch(worker_protocol: u32, worker_build: &str) -> ServerError {
    let build = if worker_build.is_empty() {
        "an older luxfarm"
    } else {
        worker_build
    };
    ServerError::Conflict(format!(
        "protocol mismatch: the worker ({build}) speaks worker protocol {worker_protocol}, this \
         master (luxfarm {}) speaks protocol {}: run the same luxfarm release on the workers and \
         the master",
        pb::BUILD,
        pb::PROTOCOL_VERSION
    ))
}

impl Farm {
    /// Registers a worker (see the module docs).
    pub fn register(&self, r: &pb::RegisterRequest) -> Result<pb::RegisterReply> {
        if r.protocol != pb::PROTOCOL_VERSION {
            return Err(protocol_mismatch(r.protocol, &r.build));
        }
        let name: String = r
            .name
            .chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .take(MAX_NAME)
            .collect();
        let known = if r.worker_id.is_empty() || r.worker_token.is_empty() {
            None
        } else {
            lock(&self.db)
                .worker(&r.worker_id)?
                .filter(|w| !w.token_hash.is_empty() && w.token_hash == hash_token(&r.worker_token))
        };
        let (id, token) = match known {
            Some(w) => (w.id, r.worker_token.clone()),
            None => (new_id("w"), secret(WORKER_PREFIX)?),
        };
        let now = now_ms();
        let tags = crate::admission::clean_tags(&r.tags)?;
        let build: String = r
            .build
            .chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .take(MAX_NAME)
            .collect();
        lock(&self.db).upsert_worker(&WorkerRow {
            id: id.clone(),
            name: name.clone(),
            threads: r.threads,
            last_seen_ms: now,
            token_hash: hash_token(&token),
            tags: tags.clone(),
            memory_mb: r.memory_mb,
            build: build.clone(),
        })?;
        let mut workers = lock(&self.workers);
        let lease = workers.get(&id).and_then(|w| w.lease.clone());
        workers.insert(
            id.clone(),
            WorkerRt {
                id: id.clone(),
                name: name.clone(),
                threads: r.threads,
                last_seen: Instant::now(),
                last_seen_ms: now,
                lease,
                lost: false,
                samples: 0.0,
                tags,
                memory_mb: r.memory_mb,
                build,
            },
        );
        drop(workers);
        tracing::info!(worker = %id, %name, threads = r.threads, "worker registered");
        self.touch();
        Ok(pb::RegisterReply {
            worker_id: id,
            heartbeat_interval: (self.cfg.worker_timeout / 6.0).clamp(0.2, 5.0),
            worker_token: token,
            protocol: pb::PROTOCOL_VERSION,
            build: pb::BUILD.to_string(),
            master_instance: self.instance.clone(),
        })
    }

    /// Marks a worker as seen; false when the master does not know it (it must register).
    /// A worker known to the store but not in memory (after a restart) is taken back.
    pub fn seen(&self, worker_id: &str) -> bool {
        {
            let mut workers = lock(&self.workers);
            if let Some(w) = workers.get_mut(worker_id) {
                w.last_seen = Instant::now();
                w.last_seen_ms = now_ms();
                w.lost = false;
                return true;
            }
        }
        let Ok(Some(row)) = lock(&self.db).worker(worker_id) else {
            return false;
        };
        lock(&self.workers).insert(
            row.id.clone(),
            WorkerRt {
                id: row.id,
                name: row.name,
                threads: row.threads,
                last_seen: Instant::now(),
                last_seen_ms: now_ms(),
                lease: None,
                lost: false,
                samples: 0.0,
                tags: row.tags,
                memory_mb: row.memory_mb,
                build: row.build,
            },
        );
        true
    }
}
