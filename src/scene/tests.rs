//! World-level facts of light sampling: which scenes draw the light pick sample `u_pick`
//! ([`World::lights_read_pick`]), checked against what each light's sampling really reads.

use super::*;
use crate::fileio::SceneFiles;
use crate::light::strategy::LightStrategy;
use crate::lxs::{parse_str, ParseOptions};
use glam::{Vec2, Vec3A};

fn world(body: &str) -> World {
    let text = format!("WorldBegin\n{body}\nWorldEnd\n");
    let desc = parse_str(&text, "scene.lxs", &ParseOptions::default()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let files = SceneFiles::confined(dir.path(), dir.path()).unwrap();
    let opts = WorldOptions {
        light_strategy: LightStrategy::Auto,
        media: false,
    };
    World::build(&desc, &files, opts, &mut Vec::new()).unwrap()
}

/// A trianglemesh statement of an n × n grid of quads over [-1, 1]² at height z, facing down.
fn grid(n: usize, z: f32) -> String {
    let mut p = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (
                2.0 * i as f32 / n as f32 - 1.0,
                2.0 * j as f32 / n as f32 - 1.0,
            );
            p.push(format!("{x} {y} {z}"));
        }
    }
    let mut idx = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            let q = [a, a + n + 2, a + 1, a, a + n + 1, a + n + 2];
            idx.extend(q.map(|k| k.to_string()));
        }
    }
    format!(
        "Shape \"trianglemesh\" \"integer indices\" [{}] \"point P\" [{}]",
        idx.join(" "),
        p.join(" ")
    )
}

/// How many of 100 light samples from a point below z = 1 change when `u_pick` does.
fn pick_changes(w: &World, light: &Light) -> usize {
    let r = Interaction {
        p: Vec3A::new(0.1, -0.2, 0.0),
        n: Vec3A::Z,
        ..Default::default()
    };
    (0..100)
        .filter(|&k| {
            let u = Vec2::new((k % 10) as f32 / 10.0 + 0.05, (k / 10) as f32 / 10.0 + 0.05);
            let up = (k as f32 * 0.618_034).fract();
            let a = light.sample_li(&r, u, up, w);
            let b = light.sample_li(&r, u, 1.0 - up, w);
            format!("{a:?}") != format!("{b:?}")
        })
        .count()
}

#[test]
fn u_pick_is_drawn_exactly_when_some_light_reads_it() {
    let lamp = format!(
        "AttributeBegin\nAreaLightSource \"area\" \"color L\" [1 1 1]\n{}\nAttributeEnd",
        grid(1, 1.0)
    );
    let unread = [
        "LightSource \"point\" \"point from\" [0 0 1]".to_string(),
        "LightSource \"spot\" \"point from\" [0 0 1] \"point to\" [0 0 0]".to_string(),
        "LightSource \"distant\" \"point from\" [0 0 1] \"point to\" [0 0 0]".to_string(),
        "LightSource \"infinite\" \"color L\" [1 1 1]".to_string(),
        "LightSource \"sunsky2\" \"vector sundir\" [0.6 0.1 0.5]".to_string(),
        lamp,
    ];
    let w = world(&unread.join("\n"));
    assert!(w.lights().len() >= unread.len());
    assert!(!w.lights_read_pick(), "no light here reads u_pick");
    for (i, l) in w.lights().iter().enumerate() {
        assert!(!l.reads_pick(&w), "light {i}");
        assert_eq!(pick_changes(&w, l), 0, "light {i} reads u_pick");
    }
    // A light at infinity with a portal picks with it; so does an area light on a mesh of
    // more than 1024 triangles.
    let portal = format!(
        "AttributeBegin\nLightSource \"infinite\" \"color L\" [1 1 1]\nPortalShape {}\nAttributeEnd",
        grid(1, 1.0).trim_start_matches("Shape ")
    );
    let big = format!(
        "AttributeBegin\nAreaLightSource \"area\" \"color L\" [1 1 1]\n{}\nAttributeEnd",
        grid(24, 1.0)
    );
    for body in [portal, big] {
        let w = world(&body);
        assert!(w.lights_read_pick(), "{}", &body[..60]);
        let l = &w.lights()[0];
        assert!(l.reads_pick(&w));
        let changed = pick_changes(&w, l);
        assert!(
            changed > 20,
            "{}: {changed} of 100 samples moved with u_pick",
            &body[..60]
        );
    }
}
