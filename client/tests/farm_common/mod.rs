//! Helpers of the farm end-to-end tests: real `luxfarm server` / `luxfarm worker` processes on
//! loopback (killed when dropped), small scenes, and a REST client. Everything waits with a
//! bound so a broken build fails instead of hanging.

#![allow(dead_code)]

/// The CLI tests' helpers (the scene builder, running the binary): a test that uses both
/// takes them from here.
#[path = "../cli_common/mod.rs"]
pub mod cli_common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// The shared material (`../shared` beside the repository, else /work/shared).
pub fn shared() -> PathBuf {
    let beside = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared"));
    if beside.exists() {
        return beside.to_path_buf();
    }
    PathBuf::from("/work/shared")
}

/// The luxfarm binary under test.
pub fn exe() -> &'static str {
    env!("CARGO_BIN_EXE_luxfarm")
}

/// A child process killed (SIGKILL) and reaped on drop.
pub struct Proc(pub Child);

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

impl Proc {
    /// Sends SIGTERM.
    pub fn term(&self) {
        if let Ok(pid) = i32::try_from(self.0.id()) {
            // SAFETY: signalling our own child process.
            unsafe {
                libc::kill(pid, libc::SIGTERM);
            }
        }
    }

    /// Waits for the process to exit, at most `secs`.
    pub fn wait_exit(&mut self, secs: u64) -> Option<std::process::ExitStatus> {
        let end = Instant::now() + Duration::from_secs(secs);
        while Instant::now() < end {
            if let Ok(Some(s)) = self.0.try_wait() {
                return Some(s);
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        None
    }
}

/// A running master.
pub struct Server {
    pub proc: Proc,
    pub addr: String,
    pub data: PathBuf,
}

impl Server {
    pub fn url(&self) -> String {
        format!("http://{}", self.addr)
    }
    pub fn api(&self, path: &str) -> String {
        format!("http://{}/api/v1{path}", self.addr)
    }
}

/// Starts `luxfarm server` on a free loopback port with `data` as data dir.
pub fn server(data: &Path, extra: &[&str]) -> Server {
    server_on(data, "127.0.0.1:0", extra)
}

/// Starts `luxfarm server` on `listen`.
pub fn server_on(data: &Path, listen: &str, extra: &[&str]) -> Server {
    let mut child = Command::new(exe())
        .args(["server", "--listen", listen, "--data-dir"])
        .arg(data)
        .args(extra)
        .env_remove("LUXFARM_TOKEN")
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("spawn server");
    let stdout = child.stdout.take().expect("stdout");
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if let Some(a) = line.strip_prefix("listening on ") {
                let _ = tx.send(a.trim().to_string());
            }
        }
    });
    let proc = Proc(child);
    let addr = rx
        .recv_timeout(Duration::from_secs(60))
        .expect("server did not report its address");
    Server {
        proc,
        addr,
        data: data.to_path_buf(),
    }
}

/// Starts `luxfarm worker` for a master.
pub fn worker(url: &str, threads: usize, extra: &[&str]) -> Proc {
    let child = Command::new(exe())
        .args(["worker", "--master", url, "--threads", &threads.to_string()])
        .args(extra)
        .env_remove("LUXFARM_TOKEN")
        .stdout(Stdio::null())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("spawn worker");
    Proc(child)
}

/// Stops workers with SIGTERM and waits until each has exited successfully. A worker records
/// an acknowledgement (`--keep-deltas`) a moment after the master sent it, so a test that
/// compares a finished job with the kept deltas stops its workers first: the last delta of a
/// job may be acknowledged just as the job ends.
#[allow(dead_code)]
pub fn stop_workers(workers: &mut [Proc]) {
    for w in workers.iter() {
        w.term();
    }
    for w in workers.iter_mut() {
        let status = w.wait_exit(120).expect("a worker exits after SIGTERM");
        assert!(status.success(), "{status:?}");
    }
}

/// A small scene at `dir/name.lxs` (the shared builder of the CLI tests' scenes): seen from
/// (0, −3, 1), an area light just under the top of a 2×2 floor and back wall; `film_extra`
/// ends the Film statement.
pub fn small_scene(dir: &Path, name: &str, res: (u32, u32), film_extra: &str) -> PathBuf {
    let film = format!(
        r#"Film "fleximage" "integer xresolution" [{}] "integer yresolution" [{}] {film_extra}"#,
        res.0, res.1
    );
    let text = cli_common::SceneSpec {
        look_at: "0 -3 1 0 0 1 0 0 1",
        fov: 45.0,
        film: &film,
        maxdepth: 3,
        light_group: None,
        lamp_l: 4.0,
        lamp: r#""integer indices" [0 1 2 0 2 3] "point P" [-0.5 -0.5 1.99 0.5 -0.5 1.99 0.5 0.5 1.99 -0.5 0.5 1.99]"#,
        kd: 0.7,
        surfaces: &[
            r#""integer indices" [0 1 2 0 2 3] "point P" [-1 -1 0 1 -1 0 1 1 0 -1 1 0]"#,
            r#""integer indices" [0 1 2 0 2 3] "point P" [-1 1 0 1 1 0 1 1 2 -1 1 2]"#,
        ],
    }
    .text();
    let path = dir.join(format!("{name}.lxs"));
    std::fs::write(&path, text).expect("write scene");
    path
}

/// Runs `luxfarm submit --master URL EXTRA... SCENE` against `s`; returns the job id it prints.
pub fn submit_scene(s: &Server, scene: &Path, extra: &[&str]) -> String {
    let out = run_ok(
        Command::new(exe())
            .args(["submit", "--master", &s.url()])
            .args(extra)
            .arg(scene)
            .env_remove("LUXFARM_TOKEN"),
    );
    let id = String::from_utf8_lossy(&out.stdout).trim().to_string();
    assert!(!id.is_empty(), "luxfarm submit printed no job id");
    id
}

/// A blocking REST client.
pub fn http() -> reqwest::blocking::Client {
    reqwest::blocking::Client::builder()
        .timeout(Duration::from_secs(60))
        .build()
        .expect("client")
}

/// POSTs bytes as a job; returns (status, JSON body).
pub fn post_job(s: &Server, bytes: Vec<u8>, query: &str) -> (u16, serde_json::Value) {
    let r = http()
        .post(format!("{}{query}", s.api("/jobs")))
        .body(bytes)
        .send()
        .expect("POST /jobs");
    let status = r.status().as_u16();
    (status, r.json().unwrap_or(serde_json::Value::Null))
}

/// GETs JSON.
pub fn get_json(url: &str) -> serde_json::Value {
    http().get(url).send().expect("GET").json().expect("JSON")
}

/// Polls a job until `pred` holds or `secs` pass; returns the last view.
pub fn wait_job(
    s: &Server,
    id: &str,
    secs: u64,
    pred: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    wait_view(s, &format!("/jobs/{id}"), secs, pred)
}

/// Polls the API resource at `path` (e.g. `/jobs/ID`) until `pred` holds or `secs` pass;
/// returns the last view.
pub fn wait_view(
    s: &Server,
    path: &str,
    secs: u64,
    pred: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    let end = Instant::now() + Duration::from_secs(secs);
    loop {
        let v = get_json(&s.api(path));
        if pred(&v) || Instant::now() > end {
            return v;
        }
        std::thread::sleep(Duration::from_millis(200));
    }
}

/// Every file under `dir` (recursively).
pub fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let Ok(rd) = std::fs::read_dir(dir) else {
        return out;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(files_under(&p));
        } else {
            out.push(p);
        }
    }
    out
}

/// The sum of the deltas workers kept (`--keep-deltas`) that the master merged, and their
/// number.
pub fn sum_kept(dirs: &[&Path]) -> (luxfarm::film::Film, usize) {
    let mut sum: Option<luxfarm::film::Film> = None;
    let mut n = 0;
    for d in dirs {
        for p in files_under(d) {
            let name = p.file_name().unwrap().to_string_lossy().to_string();
            if !name.ends_with(".merged.lxd") {
                continue;
            }
            let f = luxfarm_wire::codec::decode(&std::fs::read(&p).unwrap()).unwrap();
            n += 1;
            match &mut sum {
                Some(s) => s.merge(&f).unwrap(),
                None => sum = Some(f),
            }
        }
    }
    (sum.expect("some deltas"), n)
}

/// The deltas kept as sent whose acknowledgement no worker recorded (`--keep-deltas` keeps
/// `LEASE-SEQ.sent.lxd` until `LEASE-SEQ.STATUS.lxd` replaces it).
pub fn sent_only(dirs: &[&Path]) -> Vec<luxfarm::film::Film> {
    let mut out = Vec::new();
    for d in dirs {
        for p in files_under(d) {
            let name = p.file_name().unwrap().to_string_lossy().to_string();
            if name.ends_with(".sent.lxd") {
                out.push(luxfarm_wire::codec::decode(&std::fs::read(&p).unwrap()).unwrap());
            }
        }
    }
    out
}

/// The films hold the same sums: sample counts exactly, pixel sums up to the rounding of f64
/// additions done in another order (the master adds deltas in arrival order).
pub fn assert_same_sums(a: &luxfarm::film::Film, b: &luxfarm::film::Film) {
    a.check_layout(b).unwrap();
    for g in 0..a.groups().len() {
        assert_eq!(
            a.sample_count(g),
            b.sample_count(g),
            "group {g} sample count"
        );
        for k in 0..a.buffer_types().len() {
            let (x, y) = (a.buffer(g, k).unwrap(), b.buffer(g, k).unwrap());
            for (i, (p, q)) in x.iter().zip(y).enumerate() {
                assert!(
                    (p - q).abs() <= 1e-12 * p.abs().max(1.0),
                    "value {i}: {p} vs {q}"
                );
            }
        }
    }
}

/// The job's committed checkpoint once it holds every sample the master reports merged: the
/// store's generation leads the job's `film_version`, and files of other generations may
/// remain beside it (a master killed between committing a checkpoint and removing the one
/// before keeps the older file). Waits up to a minute for that checkpoint to be written.
pub fn final_checkpoint(s: &Server, id: &str) -> luxfarm::film::Film {
    let end = Instant::now() + Duration::from_secs(60);
    loop {
        let v = get_json(&s.api(&format!("/jobs/{id}")));
        let generation = v["film_version"]
            .as_str()
            .and_then(|f| f.split('-').next())
            .and_then(|g| g.parse::<u64>().ok())
            .unwrap_or(0);
        let path = s
            .data
            .join("jobs")
            .join(id)
            .join(format!("checkpoint-{generation}.lxd"));
        let film = std::fs::read(&path)
            .ok()
            .and_then(|b| luxfarm_wire::codec::decode(&b).ok());
        let late = Instant::now() > end;
        match film {
            Some(f) if late || Some(f.total_samples()) == v["samples"].as_f64() => return f,
            None if late => panic!("no committed checkpoint {}: {v}", path.display()),
            _ => std::thread::sleep(Duration::from_millis(200)),
        }
    }
}

/// Runs a command to completion; panics with its standard error when it fails.
pub fn run_ok(cmd: &mut Command) -> std::process::Output {
    let out = cmd.output().expect("run command");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}
