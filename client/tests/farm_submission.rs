//! What the master refuses at submission, before any worker sees a job: scenes naming files
//! outside their bundle (image maps, meshes, environment maps, nk files: absolute paths, `..`,
//! devices), each a 400 naming the scene location and no host path.

mod farm_common;

use farm_common::*;

/// The small scene with `extra` statements added before WorldEnd.
fn scene_with(dir: &std::path::Path, name: &str, extra: &str) -> Vec<u8> {
    let text = std::fs::read_to_string(small_scene(dir, name, (8, 6), "")).unwrap();
    text.replace("WorldEnd", &format!("{extra}\nWorldEnd"))
        .into_bytes()
}

#[test]
fn files_outside_the_bundle_are_refused_with_their_location() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let s = server(&data, &[]);
    let secret = dir.path().join("secret.png");
    std::fs::write(&secret, b"not really a png").unwrap();
    let cases = [
        format!(
            "Texture \"t\" \"color\" \"imagemap\" \"string filename\" [\"{}\"]",
            secret.display()
        ),
        "Shape \"plymesh\" \"string filename\" [\"/etc/passwd\"]".into(),
        "Shape \"plymesh\" \"string filename\" [\"/root/.ssh/id_rsa\"]".into(),
        "Shape \"plymesh\" \"string filename\" [\"/dev/zero\"]".into(),
        "Shape \"stlmesh\" \"string filename\" [\"../../secret.png\"]".into(),
        "LightSource \"infinite\" \"string mapname\" [\"../secret.png\"]".into(),
        "Material \"metal\" \"string name\" [\"/etc/hostname\"]".into(),
    ];
    for extra in &cases {
        let (st, body) = post_job(&s, scene_with(dir.path(), "c", extra), "?filename=c.lxs");
        assert_eq!(st, 400, "{extra}: {body}");
        let detail = body["detail"].as_str().unwrap_or("");
        // The statement is the 15th line of the small scene.
        assert!(detail.contains("c.lxs:15:"), "{extra}: {detail}");
        assert!(
            detail.contains("absolute path") || detail.contains("leaves the scene's directory"),
            "{extra}: {detail}"
        );
        assert!(!detail.contains(data.to_str().unwrap()), "{detail}");
    }
    let jobs = get_json(&s.api("/jobs"));
    assert_eq!(jobs.as_array().map(Vec::len), Some(0), "{jobs}");
}
