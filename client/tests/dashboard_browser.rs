//! End-to-end test of the web dashboard in a real browser: a `luxfarm server` and a worker on
//! loopback render the Cornell box while headless Chromium (driven over W3C WebDriver by
//! chromedriver, started here on a free port) opens the dashboard, finds the job, watches the
//! preview load and change, switches the tonemapping (the preview is refetched with the new
//! query and gets brighter), cancels the job and sees it cancelled. The browser console must
//! stay free of errors; screenshots are saved to `target/dashboard*.png`. A second test shows a
//! frame sequence as a strip that fills in over Server-Sent Events, without poll requests. A
//! third watches a job's speed/accuracy trade: the error-over-time chart, the projection to a
//! typed target relative error, and the convergence map toggled over the preview. A fourth
//! submits a mental ray `.mi` through the form, whose file input accepts every scene format.
//!
//! The WebDriver client is a few JSON calls over the `reqwest` already used by the farm tests.
//! Without `/usr/bin/chromium` and `chromedriver` the test fails and says how to install them
//! (`.ci/run` does it).

mod farm_common;

use farm_common::*;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const CHROMIUM: &str = "/usr/bin/chromium";

fn chromedriver() -> PathBuf {
    ["/usr/bin/chromedriver", "/usr/lib/chromium/chromedriver"]
        .iter()
        .map(PathBuf::from)
        .find(|p| p.exists())
        .unwrap_or_else(|| {
            panic!(
                "chromedriver not found: install Debian's browser with \
                 `apt-get update && apt-get install -y chromium chromium-driver` (.ci/run does)"
            )
        })
}

/// A WebDriver session (deleted on drop) on a chromedriver process (killed on drop).
struct Browser {
    base: String,
    http: reqwest::blocking::Client,
    _driver: Proc,
    _profile: tempfile::TempDir,
}

impl Browser {
    fn start() -> Browser {
        assert!(
            Path::new(CHROMIUM).exists(),
            "{CHROMIUM} not found: install it with \
             `apt-get update && apt-get install -y chromium chromium-driver` (.ci/run does)"
        );
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .expect("free port")
            .port();
        let driver = Proc(
            Command::new(chromedriver())
                .arg(format!("--port={port}"))
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .expect("spawn chromedriver"),
        );
        let http = http();
        let base = format!("http://127.0.0.1:{port}");
        let ready = wait_for(30, || {
            http.get(format!("{base}/status"))
                .send()
                .ok()
                .and_then(|r| r.json::<Value>().ok())
                .filter(|v| v["value"]["ready"] == true)
        });
        assert!(ready.is_some(), "chromedriver did not become ready");
        let profile = tempfile::tempdir().expect("profile dir");
        let caps = json!({"capabilities": {"alwaysMatch": {
            "browserName": "chrome",
            "goog:loggingPrefs": {"browser": "ALL"},
            "goog:chromeOptions": {"binary": CHROMIUM, "args": [
                "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                "--disable-background-networking", "--disable-component-update", "--disable-sync",
                "--disable-dev-shm-usage", "--window-size=1280,800",
                format!("--user-data-dir={}", profile.path().display()),
            ]},
        }}});
        let resp: Value = http
            .post(format!("{base}/session"))
            .json(&caps)
            .send()
            .expect("new session")
            .json()
            .expect("session JSON");
        let id = resp["value"]["sessionId"]
            .as_str()
            .unwrap_or_else(|| panic!("no WebDriver session: {resp}"))
            .to_string();
        Browser {
            base: format!("{base}/session/{id}"),
            http,
            _driver: driver,
            _profile: profile,
        }
    }

    fn call(&self, method: reqwest::Method, path: &str, body: Value) -> Value {
        let req = self.http.request(method, format!("{}{path}", self.base));
        let req = if body.is_null() { req } else { req.json(&body) };
        let v: Value = req.send().expect("WebDriver call").json().expect("JSON");
        if v["value"]["error"].is_string() {
            panic!("WebDriver {path}: {}", v["value"]);
        }
        v["value"].clone()
    }

    fn goto(&self, url: &str) {
        self.call(reqwest::Method::POST, "/url", json!({ "url": url }));
    }

    fn js(&self, script: &str) -> Value {
        self.call(
            reqwest::Method::POST,
            "/execute/sync",
            json!({"script": script, "args": []}),
        )
    }

    /// Types `text` into the element matching a CSS selector (a file input takes a path).
    fn type_into(&self, css: &str, text: &str) {
        let e = self.call(
            reqwest::Method::POST,
            "/element",
            json!({"using": "css selector", "value": css}),
        );
        let id = e["element-6066-11e4-a52e-4f735466cecf"]
            .as_str()
            .unwrap_or_else(|| panic!("no element {css}: {e}"))
            .to_string();
        self.call(
            reqwest::Method::POST,
            &format!("/element/{id}/value"),
            json!({ "text": text }),
        );
    }

    /// Accepts an open dialog; false when there is none (yet).
    fn accept_alert(&self) -> bool {
        self.http
            .post(format!("{}/alert/accept", self.base))
            .json(&json!({}))
            .send()
            .ok()
            .and_then(|r| r.json::<Value>().ok())
            .is_some_and(|v| !v["value"]["error"].is_string())
    }

    fn resize(&self, w: u32, h: u32) {
        self.call(
            reqwest::Method::POST,
            "/window/rect",
            json!({"width": w, "height": h}),
        );
    }

    fn screenshot(&self, path: &Path) {
        let v = self.call(reqwest::Method::GET, "/screenshot", Value::Null);
        let png = base64_decode(v.as_str().expect("screenshot base64"));
        std::fs::write(path, png).expect("write screenshot");
    }

    /// Chromium's console log entries (chromedriver's legacy log endpoint).
    fn console(&self) -> Vec<Value> {
        self.call(reqwest::Method::POST, "/se/log", json!({"type": "browser"}))
            .as_array()
            .cloned()
            .unwrap_or_default()
    }

    /// Waits until an element matching a CSS selector is in the page.
    fn wait_element(&self, secs: u64, what: &str, css: &str) {
        let css = Value::from(css);
        self.wait_js(
            secs,
            what,
            &format!("return document.querySelector({css}) ? true : null;"),
        );
    }

    /// Sets the value of the element with id `id` and fires `event` on it, as typing into a
    /// field (`input`) or choosing in a list (`change`) does.
    fn set_value(&self, id: &str, value: &str, event: &str) {
        let (id, value, event) = (Value::from(id), Value::from(value), Value::from(event));
        self.js(&format!(
            "const e = document.getElementById({id}); e.value = {value};
            e.dispatchEvent(new Event({event})); return true;"
        ));
    }

    /// Asserts that Chromium's console holds no error (level SEVERE).
    fn assert_no_console_errors(&self) {
        let severe: Vec<Value> = self
            .console()
            .into_iter()
            .filter(|e| e["level"] == "SEVERE")
            .collect();
        assert!(severe.is_empty(), "browser console errors: {severe:?}");
    }

    /// Asserts that the page shows no error banner, recorded no error since [`CAPTURE`] ran,
    /// and that the console holds none.
    fn assert_page_clean(&self) {
        let banner = self
            .js("return getComputedStyle(document.getElementById('error')).display === 'none';");
        assert_eq!(
            banner,
            true,
            "error banner shown: {}",
            self.js("return document.getElementById('error-text').textContent;")
        );
        assert_eq!(
            self.js("return window.__errors;"),
            json!([]),
            "errors in the page"
        );
        self.assert_no_console_errors();
    }

    /// Polls a JS expression (the body of a function) until it returns non-null/false.
    fn wait_js(&self, secs: u64, what: &str, script: &str) -> Value {
        wait_for(secs, || {
            let v = self.js(script);
            (!v.is_null() && v != false).then_some(v)
        })
        .unwrap_or_else(|| panic!("timed out after {secs} s waiting for {what}"))
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.http.delete(&self.base).send();
    }
}

fn wait_for<T>(secs: u64, mut f: impl FnMut() -> Option<T>) -> Option<T> {
    let end = Instant::now() + Duration::from_secs(secs);
    loop {
        if let Some(v) = f() {
            return Some(v);
        }
        if Instant::now() > end {
            return None;
        }
        std::thread::sleep(Duration::from_millis(250));
    }
}

/// Standard base64 decoding (the screenshot), without another dependency.
fn base64_decode(s: &str) -> Vec<u8> {
    let val = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let digits: Vec<u8> = s.bytes().filter_map(val).collect();
    let mut out = Vec::with_capacity(digits.len() * 3 / 4);
    for chunk in digits.chunks(4) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |acc, (i, d)| acc | (u32::from(*d) << (18 - 6 * i)));
        let bytes = n.to_be_bytes();
        out.extend_from_slice(&bytes[1..chunk.len()]);
    }
    out
}

/// Records console errors and uncaught exceptions of the current document into
/// `window.__errors`.
const CAPTURE: &str = "if (!window.__errors) { window.__errors = [];
  const e = console.error.bind(console);
  console.error = (...a) => { window.__errors.push(a.map(String).join(' ')); e(...a); };
  window.addEventListener('error', (ev) => window.__errors.push(String(ev.message)));
  window.addEventListener('unhandledrejection', (ev) => window.__errors.push(String(ev.reason)));
} return true;";

#[test]
fn dashboard_watches_and_cancels_a_job_in_chromium() {
    let browser = Browser::start();
    let dir = tempfile::tempdir().expect("tempdir");
    let s = server(&dir.path().join("data"), &["--upload-interval", "1"]);
    let _w = worker(&s.url(), 1, &[]);
    // Chromium's file input takes only canonical paths (no `..`).
    let scene = shared()
        .join("scenes/cornell/cornell.lxs")
        .canonicalize()
        .expect("cornell.lxs exists");
    let bytes = std::fs::read(&scene).expect("read cornell.lxs");
    let (status, job) = post_job(&s, bytes, "?filename=cornell.lxs&haltspp=100000");
    assert_eq!(status, 201, "{job}");
    let id = job["id"].as_str().expect("job id").to_string();

    browser.goto(&format!("{}/", s.url()));
    browser.js(CAPTURE);
    let row = format!("#jobs tr[data-id=\"{id}\"]");
    browser.wait_element(30, "the job row", &row);
    browser.js(&format!(
        "document.querySelector('#jobs tr[data-id=\"{id}\"] a').click(); return true;"
    ));
    browser.wait_element(10, "the job page", "#preview");

    // The preview loads once samples arrive, then changes (a new ETag and new pixels).
    let probe = "const i = document.getElementById('preview');
      if (!i || !i.complete || !i.naturalWidth || !i.dataset.etag) return null;
      const c = document.createElement('canvas'); c.width = i.naturalWidth; c.height = i.naturalHeight;
      const g = c.getContext('2d'); g.drawImage(i, 0, 0);
      const d = g.getImageData(0, 0, c.width, c.height).data; let h = 0, sum = 0;
      for (let k = 0; k < d.length; k++) { h = (h * 31 + d[k]) >>> 0; if (k % 4 !== 3) sum += d[k]; }
      return [i.dataset.etag, i.naturalWidth, h, sum / (d.length * 0.75), i.dataset.query || ''];";
    let first = browser.wait_js(120, "the preview to load", probe);
    assert_eq!(first[1], 256, "preview width: {first}");
    let changed = wait_for(120, || {
        let v = browser.js(probe);
        (!v.is_null() && v[0] != first[0] && v[2] != first[2]).then_some(v)
    });
    assert!(changed.is_some(), "the preview never changed from {first}");

    // Tonemapping panel: the linear kernel with a long exposure refetches the preview with that
    // query (debounced), and the picture gets brighter; "Scene default" goes back.
    browser.wait_element(10, "the tonemapping panel", "#tm-kernel");
    let before = browser.js(probe);
    browser.set_value("tm-kernel", "linear", "change");
    browser.wait_element(10, "the linear kernel's controls", "#tm-linear_exposure");
    browser.set_value("tm-linear_exposure", "1000", "input");
    let toned = browser.wait_js(
        30,
        "the preview with the linear kernel",
        &format!(
            "const v = (() => {{ {probe} }})();
         return v && v[4].includes('kernel=linear') && v[4].includes('linear_exposure=1000')
           ? v : null;"
        ),
    );
    assert!(
        toned[3].as_f64() > before[3].as_f64().map(|b| b + 10.0),
        "exposure 1000 s did not brighten the preview: {before} -> {toned}"
    );
    let requested = browser.js(
        "return performance.getEntriesByType('resource').map((e) => e.name)
           .filter((n) => n.includes('/preview.png?') && n.includes('kernel=linear')
             && n.includes('linear_exposure=1000')).length;",
    );
    assert!(
        requested.as_u64() >= Some(1),
        "no preview request with the query"
    );
    // The periodic poll keeps the query (a 304 or a newer film with the same setting).
    std::thread::sleep(Duration::from_secs(3));
    let later = browser.js(probe);
    assert_eq!(later[4], toned[4], "the poll dropped the tonemapping query");

    // The job's worker row shows the master's samples/s for the worker.
    browser.wait_js(
        30,
        "the worker's samples/s on the job page",
        "const c = document.querySelector('#job-workers tr[data-worker] td:nth-child(3)');
         return c && parseFloat(c.textContent) > 0 ? c.textContent : null;",
    );

    browser.resize(390, 844);
    browser.js("document.getElementById('tonemap').scrollIntoView(); return true;");
    browser.screenshot(&target_dir().join("dashboard-narrow-tonemap.png"));
    browser.js("window.scrollTo(0, 0); return true;");
    browser.resize(1280, 800);
    browser.screenshot(&target_dir().join("dashboard-tonemap.png"));

    browser.js("document.getElementById('tm-reset').click(); return true;");
    browser.wait_js(
        30,
        "the scene's tonemapping back",
        &format!("const v = (() => {{ {probe} }})(); return v && v[4] === '' ? v : null;"),
    );
    let select = browser.js("return document.getElementById('tm-kernel').value;");
    assert_eq!(select, "autolinear");

    browser.resize(390, 844);
    browser.screenshot(&target_dir().join("dashboard-narrow.png"));
    browser.resize(1280, 800);
    browser.screenshot(&target_dir().join("dashboard.png"));

    // Cancel through the page (confirm dialog accepted) and see the state change.
    browser.js("setTimeout(() => document.getElementById('cancel').click(), 0); return true;");
    wait_for(10, || browser.accept_alert().then_some(())).expect("the cancel confirmation dialog");
    browser.wait_js(
        60,
        "the state to become cancelled",
        "return document.getElementById('job-info').dataset.state === 'cancelled' ? true : null;",
    );
    let api_state = get_json(&s.api(&format!("/jobs/{id}")))["state"].clone();
    assert_eq!(api_state, "cancelled");

    // Jobs list filtered by state, the workers page, and a submission through the form.
    browser.js("location.hash = '#/jobs'; return true;");
    browser.wait_element(10, "the jobs list", &row);
    browser.set_value("state-filter", "rendering", "change");
    let css = Value::from(row.as_str());
    browser.wait_js(
        10,
        "the cancelled job filtered out",
        &format!("return document.querySelector({css}) ? null : true;"),
    );
    browser.js("location.hash = '#/workers'; return true;");
    browser.wait_element(10, "a worker row", "#workers tr[data-id]");
    browser.js("location.hash = '#/submit'; return true;");
    browser.wait_element(10, "the submit form", "#submit-form");
    browser.type_into("#f-file", &scene.display().to_string());
    browser.type_into("#f-haltspp", "1");
    browser.type_into("#f-priority", "3");
    browser.js("document.querySelector('#submit-form button[type=submit]').click(); return true;");
    let hash = browser.wait_js(
        30,
        "the new job's page",
        &format!("const h = location.hash; return h.startsWith('#/job/') && h !== '#/job/{id}' ? h : null;"),
    );
    let new_id = hash
        .as_str()
        .and_then(|h| h.strip_prefix("#/job/"))
        .expect("job id")
        .to_string();
    let new_job = get_json(&s.api(&format!("/jobs/{new_id}")));
    assert_eq!(new_job["haltspp"], 1.0, "{new_job}");
    assert_eq!(new_job["priority"], 3, "{new_job}");

    browser.assert_page_clean();
}

/// The workspace's target directory.
fn target_dir() -> PathBuf {
    let exe = Path::new(exe());
    exe.ancestors()
        .find(|p| p.file_name().is_some_and(|n| n == "target"))
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../target")))
}

#[test]
fn dashboard_asks_for_the_token_and_sends_it() {
    let browser = Browser::start();
    let dir = tempfile::tempdir().expect("tempdir");
    let s = server(&dir.path().join("data"), &["--token", "s3cret"]);
    browser.goto(&format!("{}/", s.url()));
    // The page itself loads without a token; its API call is refused and the token form opens.
    browser.wait_js(
        20,
        "the token form and the 401 in the banner",
        "return !document.getElementById('token-form').hidden
            && document.getElementById('error-text').textContent.includes('401') ? true : null;",
    );
    browser.type_into("#token-input", "s3cret");
    browser.js("document.querySelector('#token-form button').click(); return true;");
    browser.wait_js(
        20,
        "the job list with the token",
        "const t = document.getElementById('jobs');
         return t && t.textContent.includes('no jobs')
            && getComputedStyle(document.getElementById('error')).display === 'none' ? true : null;",
    );
}

/// A frame sequence on the dashboard: the job list shows it as a strip of frames that fill
/// in as the two workers render them, with thumbnails, while the page takes its updates from
/// the Server-Sent Events stream and sends no poll request.
#[test]
fn dashboard_strip_follows_a_sequence_over_server_sent_events() {
    let browser = Browser::start();
    let dir = tempfile::tempdir().expect("tempdir");
    let s = server(&dir.path().join("data"), &["--upload-interval", "0.5"]);
    let cornell = std::fs::read_to_string(shared().join("scenes/cornell/cornell.lxs"))
        .expect("read cornell.lxs");
    browser.goto(&format!("{}/", s.url()));
    browser.wait_js(
        30,
        "the event stream to open",
        "return document.body.dataset.live === 'sse' ? true : null;",
    );
    let seq = http()
        .post(s.api("/sequences"))
        .json(&json!({"name": "strip", "policy": "earliest"}))
        .send()
        .expect("POST /sequences")
        .json::<Value>()
        .expect("JSON");
    let seq = seq["id"].as_str().expect("sequence id").to_string();
    // The baseline: what the page fetched before the sequence existed.
    let fetches = "return performance.getEntriesByType('resource')
        .filter((e) => ['fetch', 'xmlhttprequest'].includes(e.initiatorType)
          && /\\/api\\/v1\\/(jobs|sequences|workers)/.test(e.name)).length;";
    let before = browser.js(fetches);
    for f in 1..=4 {
        let x = -0.3 + 0.2 * f64::from(f);
        let scene = cornell
            .replace("LookAt 0 -3.9 1", &format!("LookAt {x:.2} -3.9 1"))
            .replace(
                "[256] \"integer yresolution\" [256]",
                "[32] \"integer yresolution\" [32]",
            );
        let (st, job) = post_job(
            &s,
            scene.into_bytes(),
            &format!("?filename=c.lxs&haltspp=32&sequence={seq}&sequence_frame={f}"),
        );
        assert_eq!(st, 201, "{job}");
        assert_eq!(job["name"], format!("strip_{f:04}"));
    }
    let strip = format!("document.querySelector('.sequence[data-id=\"{seq}\"]')");
    browser.wait_js(
        30,
        "the strip",
        &format!("const q = {strip}; return q && q.querySelectorAll('.frame').length === 4 ? true : null;"),
    );
    let _w1 = worker(&s.url(), 1, &[]);
    let _w2 = worker(&s.url(), 1, &[]);
    let done = browser.wait_js(
        600,
        "every frame done with a thumbnail",
        &format!(
            "const q = {strip}; if (!q || q.dataset.state !== 'done') return null;
            const f = [...q.querySelectorAll('.frame')];
            if (f.some((x) => x.dataset.state !== 'done')) return null;
            const imgs = [...q.querySelectorAll('.frame img')];
            if (imgs.length !== 4 || imgs.some((i) => !i.complete || !i.naturalWidth)) return null;
            return f.map((x) => x.dataset.number);"
        ),
    );
    assert_eq!(done, json!(["1", "2", "3", "4"]));
    assert_eq!(
        browser.js(fetches),
        before,
        "the job list polled while the event stream was open"
    );
    browser.screenshot(&target_dir().join("dashboard-strip.png"));
    browser.assert_no_console_errors();
}

/// The job page's "Error over time" panel on a small scene: the log–log chart draws the
/// relative error and the failing fraction as they come, a typed target relative error is
/// projected (the text and the dashed projection line; the REST API projects too when it
/// sees the page's history),
/// the toggle lays the convergence map over the preview, and a cancelled job keeps its chart.
#[test]
fn dashboard_charts_the_error_trade_and_overlays_the_convergence_map() {
    let browser = Browser::start();
    let dir = tempfile::tempdir().expect("tempdir");
    let s = server(&dir.path().join("data"), &["--upload-interval", "0.5"]);
    let scene = small_scene(dir.path(), "t", (96, 96), "\"float convergencestep\" [4]");
    let bytes = std::fs::read(scene).expect("read scene");
    let (status, job) = post_job(&s, bytes, "?filename=t.lxs&haltspp=100000");
    assert_eq!(status, 201, "{job}");
    let id = job["id"].as_str().expect("job id").to_string();
    let _w = worker(&s.url(), 1, &[]);
    browser.goto(&format!("{}/#/job/{id}", s.url()));
    browser.js(CAPTURE);

    // The chart fills in: both series drawn once there are points.
    browser.wait_js(
        120,
        "the error-over-time chart",
        "const c = document.getElementById('trade-chart');
         return c && Number(c.dataset.points) >= 2
           && c.querySelector('polyline[data-metric=relative_error]')
           && c.querySelector('polyline[data-metric=failing_fraction]') ? c.dataset.points : null;",
    );
    let untargeted = browser.js("return document.getElementById('trade-projection').textContent;");
    assert!(
        untargeted
            .as_str()
            .is_some_and(|t| t.contains("type a target")),
        "{untargeted}"
    );

    // A typed target is projected: the text, the dashed line, and the REST API's time.
    browser.type_into("#trade-target", "0.05");
    let text = browser.wait_js(
        120,
        "the projection to the typed target",
        "const p = document.getElementById('trade-target-text');
         return p && p.dataset.status === 'projected'
           && document.querySelector('#trade-chart .trade-projection[data-metric=relative_error]')
           && document.querySelector('#trade-chart .trade-target[data-metric=relative_error]')
           ? p.textContent : null;",
    );
    let text = text.as_str().expect("projection text").to_string();
    assert!(text.contains("relative error 0.05: projected at"), "{text}");
    // The page and the API agree on the same history, and project on it. A point arriving
    // between the two reads can change the fit (seen in CI: projected on 6 points, "noisy"
    // on 7), so both are read until they show the same number of points (a history thinned
    // past 200 points keeps its length; this job stays far below that) and the page projects.
    let end = Instant::now() + Duration::from_secs(90);
    loop {
        let page = browser.js("const p = document.getElementById('trade-target-text'),
                   c = document.getElementById('trade-chart');
             return p && c ? [p.dataset.status, Number(c.dataset.points)] : null;");
        let t = get_json(&s.api(&format!("/jobs/{id}/trade?target=0.05")));
        let n = t["history"].as_array().map_or(0, Vec::len) as u64;
        if page[1].as_u64() == Some(n) {
            let p = &t["target_projection"];
            assert_eq!(
                p["status"], page[0],
                "page {page} and API differ on one history: {t}"
            );
            if p["status"] == "projected" {
                assert!(
                    p["at_secs"].as_f64().is_some_and(f64::is_finite),
                    "the API projects no finite time: {t}"
                );
                break;
            }
        }
        assert!(
            Instant::now() < end,
            "no projection on a history the page and the API both saw; last: page {page}, API {t}"
        );
        std::thread::sleep(Duration::from_millis(200));
    }
    let requested = browser.js(
        "return performance.getEntriesByType('resource').map((e) => e.name)
           .filter((n) => n.includes('/trade?target=0.05')).length;",
    );
    assert!(
        requested.as_u64() >= Some(1),
        "no /trade request with the target"
    );

    // The convergence map over the preview, the preview's size.
    browser.js("document.getElementById('overlay-toggle').click(); return true;");
    let sizes = browser.wait_js(
        60,
        "the convergence map overlay",
        "const o = document.getElementById('overlay'), i = document.getElementById('preview');
         return o && !o.hidden && o.complete && o.naturalWidth && Number(o.dataset.loads) >= 1
           && i && i.naturalWidth && getComputedStyle(o).display !== 'none'
           ? [o.naturalWidth, o.naturalHeight, i.naturalWidth, i.naturalHeight] : null;",
    );
    assert_eq!(sizes, json!([96, 96, 96, 96]));
    browser.js("document.getElementById('trade').scrollIntoView(); return true;");
    browser.screenshot(&target_dir().join("dashboard-trade.png"));
    browser.js("window.scrollTo(0, 0); return true;");
    browser.screenshot(&target_dir().join("dashboard-trade-overlay.png"));
    browser.js("document.getElementById('overlay-toggle').click(); return true;");
    let hidden = browser.js("return document.getElementById('overlay').hidden;");
    assert_eq!(hidden, true);

    browser.assert_page_clean();
    // Cancelled, the page keeps the chart: the history saved with the final checkpoint.
    let r = http()
        .delete(s.api(&format!("/jobs/{id}")))
        .send()
        .expect("cancel");
    assert_eq!(r.status(), 200);
    browser.wait_js(
        30,
        "the ended job's saved history on the chart",
        "const c = document.getElementById('trade-chart');
         return document.getElementById('job-info').dataset.state === 'cancelled'
           && c && Number(c.dataset.points) >= 2 ? c.dataset.points : null;",
    );
    assert_eq!(browser.js("return window.__errors;"), json!([]));
}

/// The submit form takes every scene format the master reads: its file input accepts each
/// scene extension, and a mental ray `.mi` chosen in it is queued and rendered to its halt.
#[test]
fn dashboard_submits_a_mental_ray_scene() {
    let browser = Browser::start();
    let dir = tempfile::tempdir().expect("tempdir");
    let s = server(&dir.path().join("data"), &["--upload-interval", "0.5"]);
    let _w = worker(&s.url(), 1, &[]);
    let text = std::fs::read_to_string(shared().join("scenes/formats/cornell_box/cornell_box.mi"))
        .expect("read cornell_box.mi");
    let scene = dir.path().join("box.mi");
    std::fs::write(
        &scene,
        text.replace("resolution 500 500", "resolution 24 24"),
    )
    .expect("write box.mi");
    let scene = scene.canonicalize().expect("canonical path");

    browser.goto(&format!("{}/#/submit", s.url()));
    browser.js(CAPTURE);
    browser.wait_element(10, "the submit form", "#submit-form");
    let accept = browser.js("return document.getElementById('f-file').accept;");
    let accept: Vec<&str> = accept
        .as_str()
        .expect("accept attribute")
        .split(',')
        .collect();
    for ext in luxfarm::formats::SCENE_EXTENSIONS {
        assert!(
            accept.contains(&format!(".{ext}").as_str()),
            ".{ext} not in {accept:?}"
        );
    }
    browser.type_into("#f-file", &scene.display().to_string());
    browser.type_into("#f-haltspp", "2");
    browser.js("document.querySelector('#submit-form button[type=submit]').click(); return true;");
    let hash = browser.wait_js(
        30,
        "the new job's page",
        "const h = location.hash; return h.startsWith('#/job/') ? h : null;",
    );
    let id = hash
        .as_str()
        .and_then(|h| h.strip_prefix("#/job/"))
        .expect("job id")
        .to_string();
    let v = wait_job(&s, &id, 300, |v| {
        v["state"] != "queued" && v["state"] != "rendering"
    });
    assert_eq!(v["state"], "done", "{v}");
    // Named after the Film's file name: the .mi's primary framebuffer, mental_ray.exr.
    assert_eq!(v["name"], "mental_ray", "{v}");
    assert_eq!(v["width"], 24, "{v}");
    assert!(v["spp"].as_f64().is_some_and(|spp| spp >= 2.0), "{v}");
    browser.assert_page_clean();
}
