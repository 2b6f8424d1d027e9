//! User tokens in the store: only their sha256 is kept, with a name and a role; revoking keeps
//! the row (the list shows it) and stops the token at once.

use super::{Db, TokenRow};
use crate::error::Result;
use rusqlite::{params, OptionalExtension, Row};

const TOKEN_COLS: &str = "id, name, role, hash, created_ms, revoked_ms";

fn token_from_row(r: &Row<'_>) -> rusqlite::Result<TokenRow> {
    Ok(TokenRow {
        id: r.get(0)?,
        name: r.get(1)?,
        role: r.get(2)?,
        hash: r.get(3)?,
        created_ms: r.get(4)?,
        revoked_ms: r.get(5)?,
    })
}

impl Db {
    /// Stores a new token (by its hash).
    pub fn insert_token(&self, t: &TokenRow) -> Result<()> {
        self.conn.execute(
            "INSERT INTO tokens (id, name, role, hash, created_ms) VALUES (?1, ?2, ?3, ?4, ?5)",
            params![t.id, t.name, t.role, t.hash, t.created_ms],
        )?;
        Ok(())
    }

    /// The live (not revoked) token with this hash.
    pub fn token_by_hash(&self, hash: &str) -> Result<Option<TokenRow>> {
        let sql = format!("SELECT {TOKEN_COLS} FROM tokens WHERE hash = ?1 AND revoked_ms IS NULL");
        Ok(self
            .conn
            .query_row(&sql, [hash], token_from_row)
            .optional()?)
    }

    /// Every token, oldest first.
    pub fn tokens(&self) -> Result<Vec<TokenRow>> {
        let sql = format!("SELECT {TOKEN_COLS} FROM tokens ORDER BY created_ms, id");
        let mut st = self.conn.prepare(&sql)?;
        let rows = st.query_map([], token_from_row)?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }

    /// Revokes a token; returns it (None when unknown).
    pub fn revoke_token(&self, id: &str, now_ms: i64) -> Result<Option<TokenRow>> {
        self.conn.execute(
            "UPDATE tokens SET revoked_ms = COALESCE(revoked_ms, ?2) WHERE id = ?1",
            params![id, now_ms],
        )?;
        let sql = format!("SELECT {TOKEN_COLS} FROM tokens WHERE id = ?1");
        Ok(self.conn.query_row(&sql, [id], token_from_row).optional()?)
    }

    /// True when any user token was ever created (the farm then requires tokens).
    pub fn has_tokens(&self) -> Result<bool> {
        let n: i64 = self
            .conn
            .query_row("SELECT COUNT(*) FROM tokens", [], |r| r.get(0))?;
        Ok(n > 0)
    }
}
