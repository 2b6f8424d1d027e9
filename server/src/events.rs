//! Push updates: Server-Sent Events at `GET /api/v1/events` (and `/api/events`).
//!
//! ```text
//! Farm::touch (a job, lease, merge or worker changed) --watch channel--> each open stream
//!   --at most every 250 ms--> `jobs`, `workers` and `sequences` events (JSON, the same
//!   views as the REST lists) --EventSource--> the dashboard
//! ```
//!
//! A stream starts with the current state, so a client needs no first poll. It ends when the
//! master drains (the client reconnects to the next master). Comments every 15 s keep proxies
//! from closing a quiet stream.

use crate::farm::Farm;
use crate::views;
use axum::response::sse::{Event, KeepAlive, Sse};
use futures_util::stream::{self, Stream, StreamExt};
use std::convert::Infallible;
use std::sync::Arc;
use std::time::Duration;

/// Shortest time between two updates of one stream (merges can touch the farm many times a
/// second; a dashboard needs no more).
const MIN_GAP: Duration = Duration::from_millis(250);

/// The state as events: jobs, workers, sequences (an `error` event when the store fails).
fn snapshot(farm: &Farm) -> Vec<Event> {
    let json = |name: &str, v: crate::error::Result<serde_json::Value>| match v {
        Ok(v) => Event::default().event(name).data(v.to_string()),
        Err(e) => Event::default().event("error").data(e.to_string()),
    };
    vec![
        json("jobs", views::job_views(farm).and_then(to_json)),
        json("workers", views::worker_views(farm).and_then(to_json)),
        json("sequences", farm.sequence_views().and_then(to_json)),
    ]
}

fn to_json<T: serde::Serialize>(v: T) -> crate::error::Result<serde_json::Value> {
    serde_json::to_value(v).map_err(crate::error::ServerError::internal)
}

/// Waits for the next change; false when the stream should end (the master drains or the
/// farm is gone).
async fn next_change(farm: &Farm, rx: &mut tokio::sync::watch::Receiver<u64>) -> bool {
    loop {
        if farm.is_draining() {
            return false;
        }
        match tokio::time::timeout(Duration::from_secs(1), rx.changed()).await {
            Ok(Ok(())) => {
                tokio::time::sleep(MIN_GAP).await;
                rx.borrow_and_update();
                return !farm.is_draining();
            }
            Ok(Err(_)) => return false,
            Err(_) => continue,
        }
    }
}

/// The event stream of one client.
pub fn stream(farm: Arc<Farm>) -> Sse<impl Stream<Item = Result<Event, Infallible>>> {
    let rx = farm.changed.subscribe();
    let updates = stream::unfold((farm, rx, true), |(farm, mut rx, first)| async move {
        if !first && !next_change(&farm, &mut rx).await {
            return None;
        }
        let f = farm.clone();
        let events = tokio::task::spawn_blocking(move || snapshot(&f))
            .await
            .unwrap_or_else(|e| vec![Event::default().event("error").data(e.to_string())]);
        Some((events, (farm, rx, false)))
    })
    .flat_map(|events| stream::iter(events.into_iter().map(Ok)));
    Sse::new(updates).keep_alive(KeepAlive::new().interval(Duration::from_secs(15)))
}
