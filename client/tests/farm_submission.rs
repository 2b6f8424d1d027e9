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

/// Admission control: a film beyond the master's memory budget is refused naming the figure,
/// too many light groups are refused at submission (not delta by delta later), a scene
/// without a camera or without anything to see is refused with its location, halt rules
/// beyond the limits are refused, and a job without a halt rule gets the master's default
/// and says so.
#[test]
fn admission_control_refuses_what_cannot_render_or_fit() {
    let dir = tempfile::tempdir().unwrap();
    let s = server(&dir.path().join("data"), &["--max-job-memory", "100000000"]);
    let small = std::fs::read_to_string(small_scene(dir.path(), "a", (8, 6), "")).unwrap();
    let post = |text: String, query: &str| post_job(&s, text.into_bytes(), query);
    // 16384 x 16384: allowed by the parser, far beyond a 100 MB budget
    let big = small.replace(
        "[8] \"integer yresolution\" [6]",
        "[16384] \"integer yresolution\" [16384]",
    );
    assert_ne!(big, small);
    let (st, body) = post(big, "?filename=big.lxs&haltspp=4");
    assert_eq!(st, 413, "{body}");
    let detail = body["detail"].as_str().unwrap_or("");
    assert!(
        detail.contains("--max-job-memory") && detail.contains("16384x16384"),
        "{detail}"
    );
    // 1,100 light groups
    let mut many = String::new();
    for i in 0..1100 {
        many.push_str(&format!(
            "LightGroup \"g{i}\"\nAttributeBegin\nAreaLightSource \"area\" \"color L\" [1 1 1]\n\
             Shape \"trianglemesh\" \"integer indices\" [0 1 2] \"point P\" [0 0 1 1 0 1 0 1 1]\n\
             AttributeEnd\n"
        ));
    }
    let groups = small.replace("WorldEnd", &format!("{many}WorldEnd"));
    let (st, body) = post(groups, "?filename=g.lxs&haltspp=4");
    assert!((400..500).contains(&st), "{st} {body}");
    assert!(
        body["detail"]
            .as_str()
            .unwrap_or("")
            .contains("light groups"),
        "{body}"
    );
    // no camera; nothing to see
    let no_camera = small.replace("Camera \"perspective\" \"float fov\" [45]\n", "");
    let (st, body) = post(no_camera, "?filename=nc.lxs&haltspp=4");
    assert_eq!(st, 400, "{body}");
    assert!(
        body["detail"].as_str().unwrap_or("").contains("nc.lxs:"),
        "{body}"
    );
    let start = small.find("WorldBegin").unwrap() + "WorldBegin\n".len();
    let end = small.find("WorldEnd").unwrap();
    let empty = format!("{}{}", &small[..start], &small[end..]);
    let (st, body) = post(empty, "?filename=e.lxs&haltspp=4");
    assert_eq!(st, 400, "{body}");
    assert!(
        body["detail"].as_str().unwrap_or("").contains("e.lxs:"),
        "{body}"
    );
    // halt rules that never end
    for q in [
        "haltspp=1e308",
        "haltspp=inf",
        "haltspp=-1",
        "halttime=1e300",
    ] {
        let (st, body) = post(small.clone(), &format!("?filename=h.lxs&{q}"));
        assert_eq!(st, 400, "{q}: {body}");
    }
    assert_eq!(get_json(&s.api("/jobs")).as_array().map(Vec::len), Some(0));
    // no halt rule: the default, noted on the job
    let (st, job) = post(small, "?filename=d.lxs");
    assert_eq!(st, 201, "{job}");
    assert!(job["haltspp"].as_f64().is_some_and(|v| v > 0.0), "{job}");
    let notes = job["notes"].to_string();
    assert!(notes.contains("--default-haltspp"), "{job}");
}
