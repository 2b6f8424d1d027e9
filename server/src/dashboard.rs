//! The web dashboard: a static single page (HTML, CSS, plain JS modules) embedded in the binary
//! and served at `/` and `/assets/*`. It needs no token itself; the page calls the REST API and
//! sends the token the user gives it as `Authorization: Bearer`. Lists follow the event stream
//! (`events`) and poll only while it is closed.

use axum::extract::Path;
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;

/// One embedded file: its name under `/assets/`, content type and bytes.
struct Asset {
    name: &'static str,
    content_type: &'static str,
    bytes: &'static [u8],
}

const INDEX: &[u8] = include_bytes!("../assets/index.html");

const ASSETS: &[Asset] = &[
    Asset {
        name: "app.js",
        content_type: "text/javascript; charset=utf-8",
        bytes: include_bytes!("../assets/app.js"),
    },
    Asset {
        name: "style.css",
        content_type: "text/css; charset=utf-8",
        bytes: include_bytes!("../assets/style.css"),
    },
    Asset {
        name: "index.html",
        content_type: "text/html; charset=utf-8",
        bytes: INDEX,
    },
];

/// The dashboard routes (`/`, `/index.html`, `/assets/{name}`), stateless.
pub fn router<S: Clone + Send + Sync + 'static>() -> Router<S> {
    Router::new()
        .route("/", get(index))
        .route("/index.html", get(index))
        .route("/assets/{name}", get(asset))
}

async fn index() -> Response {
    serve("text/html; charset=utf-8", INDEX)
}

async fn asset(Path(name): Path<String>) -> Response {
    match ASSETS.iter().find(|a| a.name == name) {
        Some(a) => serve(a.content_type, a.bytes),
        None => crate::error::json_error(
            StatusCode::NOT_FOUND,
            "not_found",
            format!("no dashboard asset {name:?}"),
        ),
    }
}

/// The assets change only with the binary: browsers revalidate (`no-cache`) so a new build is
/// picked up at once.
fn serve(content_type: &'static str, bytes: &'static [u8]) -> Response {
    (
        [
            (header::CONTENT_TYPE, content_type),
            (header::CACHE_CONTROL, "no-cache"),
            (header::X_CONTENT_TYPE_OPTIONS, "nosniff"),
        ],
        bytes,
    )
        .into_response()
}

#[cfg(test)]
mod tests {
    use super::*;
    use axum::body::Body;
    use axum::http::Request;
    use tower::ServiceExt;

    async fn get_path(path: &str) -> (StatusCode, String, Vec<u8>) {
        let resp = router::<()>()
            .oneshot(Request::get(path).body(Body::empty()).unwrap())
            .await
            .unwrap();
        let status = resp.status();
        let ct = resp
            .headers()
            .get(header::CONTENT_TYPE)
            .map(|v| v.to_str().unwrap().to_string())
            .unwrap_or_default();
        let body = axum::body::to_bytes(resp.into_body(), 1 << 22)
            .await
            .unwrap();
        (status, ct, body.to_vec())
    }

    #[tokio::test]
    async fn index_and_assets_are_served_with_their_types() {
        let (s, ct, body) = get_path("/").await;
        assert_eq!(s, StatusCode::OK);
        assert!(ct.starts_with("text/html"));
        assert!(String::from_utf8_lossy(&body).contains("/assets/app.js"));
        let (s, ct, body) = get_path("/assets/app.js").await;
        assert_eq!(s, StatusCode::OK);
        assert!(ct.starts_with("text/javascript"));
        assert!(String::from_utf8_lossy(&body).contains("/api/v1"));
        let (s, ct, _) = get_path("/assets/style.css").await;
        assert_eq!(s, StatusCode::OK);
        assert!(ct.starts_with("text/css"));
    }

    #[tokio::test]
    async fn unknown_asset_is_a_json_404() {
        let (s, ct, body) = get_path("/assets/nope.js").await;
        assert_eq!(s, StatusCode::NOT_FOUND);
        assert!(ct.starts_with("application/json"), "{ct}");
        assert!(String::from_utf8_lossy(&body).contains("not_found"));
    }
}
