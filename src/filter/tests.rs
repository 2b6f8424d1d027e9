//! Unit tests of the pixel filters and their splat tables.

use super::*;
use crate::lxs::{Entity, Loc, ParamSet, ParamValue};

fn entity(kind: &str, params: &[(&str, ParamValue)]) -> Entity {
    let mut ps = ParamSet::new();
    for (n, v) in params {
        ps.add(n, v.clone());
    }
    Entity {
        kind: kind.to_string(),
        params: ps,
        loc: Loc {
            file: "test.lxs".into(),
            line: 3,
            col: 1,
        },
    }
}

fn filter(kind: &str, params: &[(&str, ParamValue)]) -> Filter {
    Filter::build(Some(&entity(kind, params)), &mut Vec::new()).expect("valid filter")
}

const ALL: [&str; 7] = [
    "box",
    "gaussian",
    "mitchell",
    "triangle",
    "sinc",
    "catmullrom",
    "blackmanharris",
];

/// Midpoint-rule integral of `f` over [-rx, rx] x [-ry, ry].
fn integrate_2d(f: &Filter, n: usize) -> f64 {
    let r = f.radius();
    let (hx, hy) = (2.0 * r.x as f64 / n as f64, 2.0 * r.y as f64 / n as f64);
    let mut s = 0.0;
    for j in 0..n {
        let y = -r.y as f64 + (j as f64 + 0.5) * hy;
        for i in 0..n {
            let x = -r.x as f64 + (i as f64 + 0.5) * hx;
            s += f.eval(x as f32, y as f32) as f64;
        }
    }
    s * hx * hy
}

fn integrate_1d(f: &Filter, n: usize) -> f64 {
    let r = f.radius().x as f64;
    let h = 2.0 * r / n as f64;
    (0..n)
        .map(|i| f.eval((-r + (i as f64 + 0.5) * h) as f32, 0.0) as f64)
        .sum::<f64>()
        * h
}

#[test]
fn defaults_match_luxrender() {
    let none = Filter::build(None, &mut Vec::new()).unwrap();
    assert!(matches!(none.kind(), FilterKind::Mitchell(m) if !m.supersample));
    assert_eq!(none.radius(), Vec2::splat(2.0));
    let expected = [
        ("box", 0.5),
        ("gaussian", 2.0),
        ("mitchell", 2.0),
        ("triangle", 2.0),
        ("sinc", 4.0),
        ("catmullrom", 4.0),
        ("blackmanharris", 4.0),
    ];
    for (k, r) in expected {
        assert_eq!(filter(k, &[]).radius(), Vec2::splat(r), "{k}");
    }
    let ss = filter("mitchell", &[("supersample", ParamValue::Bool(vec![true]))]);
    assert!((ss.radius().x - 10.0 / 3.0).abs() < 1e-6);
}

#[test]
fn parameters_are_consumed_and_errors_name_the_statement() {
    let e = entity(
        "gaussian",
        &[
            ("xwidth", ParamValue::Float(vec![1.5])),
            ("ywidth", ParamValue::Float(vec![2.5])),
            ("alpha", ParamValue::Float(vec![1.0])),
        ],
    );
    let f = Filter::build(Some(&e), &mut Vec::new()).unwrap();
    assert_eq!(f.radius(), Vec2::new(1.5, 2.5));
    assert_eq!(e.params.unused().count(), 0);
    for (k, name) in [("sinc", "tau"), ("gaussian", "alpha"), ("mitchell", "B")] {
        let nan = entity(k, &[(name, ParamValue::Float(vec![f32::NAN]))]);
        assert!(
            Filter::build(Some(&nan), &mut Vec::new()).is_err(),
            "{k} {name}"
        );
    }
    let err = Filter::build(Some(&entity("lanczos", &[])), &mut Vec::new()).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("test.lxs:3:1: unknown pixel filter"),
        "{err}"
    );
    let err = Filter::build(
        Some(&entity("box", &[("xwidth", ParamValue::Float(vec![-1.0]))])),
        &mut Vec::new(),
    );
    assert!(err.is_err());
}

#[test]
fn values_at_centre_and_beyond_radius() {
    let centre = [
        ("box", 1.0),
        ("gaussian", (1.0 - (-8.0f32).exp()).powi(2)),
        ("mitchell", 1.0 - 1.0 / 9.0),
        ("triangle", 4.0),
        ("sinc", 1.0),
        ("catmullrom", 4.0),
        ("blackmanharris", 1.0),
    ];
    for (k, v) in centre {
        let f = filter(k, &[]);
        assert!(
            (f.eval(0.0, 0.0) - v).abs() < 1e-5,
            "{k}: {}",
            f.eval(0.0, 0.0)
        );
        let r = f.radius();
        for (dx, dy) in [
            (r.x * 1.01, 0.0),
            (0.0, -r.y * 1.01),
            (r.x + 3.0, r.y + 3.0),
        ] {
            assert_eq!(f.eval(dx, dy), 0.0, "{k} at {dx},{dy}");
        }
        // Symmetric in both axes.
        assert_eq!(f.eval(0.3, -0.7), f.eval(-0.3, 0.7), "{k}");
    }
}

#[test]
fn mitchell_and_catmullrom_have_negative_lobes() {
    let m = filter("mitchell", &[]);
    assert!(m.eval(1.5, 0.0) < -0.01, "{}", m.eval(1.5, 0.0));
    assert!(m.eval(0.5, 0.0) > 0.0);
    let c = filter("catmullrom", &[]);
    assert!(
        (c.eval(1.5, 0.0) - (-0.125 * 2.0)).abs() < 1e-6,
        "{}",
        c.eval(1.5, 0.0)
    );
    assert_eq!(c.eval(1.0, 0.0), 0.0);
    assert_eq!(c.eval(2.5, 0.0), 0.0);
    let s = filter("sinc", &[]);
    assert!(s.eval(1.8, 0.0) < 0.0);
}

#[test]
fn mitchell_is_radial_as_in_luxrender() {
    let m = filter("mitchell", &[]);
    let d = 0.9f32;
    let diag = d / 2f32.sqrt();
    assert!((m.eval(d, 0.0) - m.eval(diag, diag)).abs() < 1e-6);
    assert_eq!(
        m.eval(1.5, 1.5),
        0.0,
        "outside the unit disc of normalised distance"
    );
}

#[test]
fn integrals_match_closed_forms() {
    let bx = filter("box", &[("xwidth", ParamValue::Float(vec![1.5]))]);
    assert!((integrate_2d(&bx, 400) - 4.0 * 1.5 * 0.5).abs() < 1e-3);
    let tri = filter("triangle", &[]);
    assert!((integrate_2d(&tri, 400) - 16.0).abs() < 1e-3);
    // Blackman-Harris: the cosine terms vanish over the window, leaving w * A0 per axis.
    let bh = filter("blackmanharris", &[]);
    assert!((integrate_2d(&bh, 800) - (4.0 * 0.35875f64).powi(2)).abs() < 1e-3);
    // Catmull-Rom (LuxRender's, twice the textbook kernel): 2 per axis.
    let cr = filter("catmullrom", &[]);
    assert!((integrate_2d(&cr, 800) - 4.0).abs() < 2e-3);
    // Gaussian: separable, 1D integral sqrt(pi/a) erf(w sqrt a) - 2 w exp(-a w²) with
    // erf(2*sqrt 2) = 0.99993666.
    let g = filter("gaussian", &[]);
    let one_d = (std::f64::consts::PI / 2.0).sqrt() * 0.999_936_66 - 4.0 * (-8.0f64).exp();
    assert!((integrate_2d(&g, 800) - one_d * one_d).abs() < 1e-3);
    // Mitchell along an axis: the cubic integrates to width / 2, with and without the
    // supersampling blend (its taps sum to 1).
    for ss in [false, true] {
        let m = filter("mitchell", &[("supersample", ParamValue::Bool(vec![ss]))]);
        assert!(
            (integrate_1d(&m, 4000) - 1.0).abs() < 1e-3,
            "ss={ss}: {}",
            integrate_1d(&m, 4000)
        );
    }
}

/// A small deterministic generator for test positions.
fn positions(n: usize) -> impl Iterator<Item = Vec2> {
    let mut s = 0x9e37_79b9_7f4a_7c15u64;
    (0..n).map(move |_| {
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        };
        Vec2::new(20.0 + 10.0 * next(), 30.0 + 10.0 * next())
    })
}

#[test]
fn splat_weights_sum_to_one() {
    for k in ALL {
        let f = filter(k, &[]);
        for p in positions(200) {
            let mut sum = 0.0f64;
            f.splat(p, |_, _, w| sum += w as f64);
            assert!((sum - 1.0).abs() < 1e-5, "{k} at {p}: {sum}");
        }
    }
}

#[test]
fn splat_visits_exactly_the_pixels_within_radius() {
    // Box filters weigh every pixel of their support by 1, so the visited set is the support.
    for w in [0.5f32, 1.5, 2.0, 3.0] {
        let f = filter(
            "box",
            &[
                ("xwidth", ParamValue::Float(vec![w])),
                ("ywidth", ParamValue::Float(vec![w])),
            ],
        );
        for p in positions(300) {
            let mut got = Vec::new();
            f.splat(p, |x, y, wt| {
                assert!(wt > 0.0);
                got.push((x, y));
            });
            got.sort();
            let mut want = Vec::new();
            for y in (p.y - 5.0) as i32..(p.y + 5.0) as i32 {
                for x in (p.x - 5.0) as i32..(p.x + 5.0) as i32 {
                    let c = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                    if (c.x - p.x).abs() <= w && (c.y - p.y).abs() <= w {
                        want.push((x, y));
                    }
                }
            }
            want.sort();
            assert_eq!(got, want, "width {w} at {p}");
        }
    }
    // Every filter stays within its radius (plus the table's 1/16-pixel offset quantisation).
    for k in ALL {
        let f = filter(k, &[]);
        let r = f.radius() + Vec2::splat(1.0 / 16.0);
        for p in positions(100) {
            f.splat(p, |x, y, _| {
                let c = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                assert!(
                    (c.x - p.x).abs() <= r.x && (c.y - p.y).abs() <= r.y,
                    "{k} {p} -> {x},{y}"
                );
            });
        }
    }
}

#[test]
fn splat_weights_follow_the_filter_shape() {
    // Weights are the filter values at the pixel centres (offset quantised to 1/16 px),
    // divided by their sum.
    let f = filter("triangle", &[]);
    // Sub-pixel offset -15/32 selects the table built for exactly that offset.
    let p = Vec2::new(10.0 + 1.0 / 32.0, 7.0 + 1.0 / 32.0);
    let mut ws = Vec::new();
    f.splat(p, |x, y, w| ws.push((x, y, w)));
    let raw: Vec<f32> = ws
        .iter()
        .map(|&(x, y, _)| f.eval(x as f32 + 0.5 - p.x, y as f32 + 0.5 - p.y))
        .collect();
    let total: f32 = raw.iter().sum();
    for ((_, _, w), r) in ws.iter().zip(&raw) {
        assert!((w - r / total).abs() < 1e-6);
    }
    // The pixel containing the sample gets the largest weight.
    let best = ws
        .iter()
        .cloned()
        .fold((0, 0, f32::MIN), |a, b| if b.2 > a.2 { b } else { a });
    assert_eq!((best.0, best.1), (10, 7));
}

#[test]
fn non_finite_positions_visit_nothing() {
    let f = filter("mitchell", &[]);
    let mut n = 0;
    f.splat(Vec2::new(f32::NAN, 3.0), |_, _, _| n += 1);
    f.splat(Vec2::new(1.0, f32::INFINITY), |_, _, _| n += 1);
    assert_eq!(n, 0);
}

#[test]
fn sample_extent_as_luxrender() {
    let f = filter("mitchell", &[]);
    assert_eq!(f.sample_extent(0, 100, 0, 50), [-2, 102, -2, 52]);
    let b = filter("box", &[]);
    // LuxRender's extent reaches one pixel past the crop for a 0.5-wide box.
    assert_eq!(b.sample_extent(10, 20, 5, 5), [10, 31, 5, 11]);
}

#[test]
fn filter_quality_changes_table_resolution() {
    let f = filter("gaussian", &[]).with_filter_quality(6);
    for p in positions(50) {
        let mut sum = 0.0;
        f.splat(p, |_, _, w| sum += w);
        assert!((sum - 1.0).abs() < 1e-5);
    }
}

#[test]
fn film_weights_match_luxrender_reference_statistics() {
    // LuxRender's reference.flm of the directlighting regression scene (512², lowdiscrepancy
    // 128 spp, mitchell B=0.75 C=0.125) has a mean pixel weight sum of 128.0 (= spp), inner
    // pixels within 118..138, and border pixels near 128 too: normalised splat weights, and
    // samples taken over the filter-extended extent. Our sampler + filter reproduce that.
    use crate::sampler::Sampler;
    let f = filter(
        "mitchell",
        &[
            ("B", ParamValue::Float(vec![0.75])),
            ("C", ParamValue::Float(vec![0.125])),
        ],
    );
    let spp = 64u32;
    let s = Sampler::build(
        Some(&entity(
            "lowdiscrepancy",
            &[("pixelsamples", ParamValue::Integer(vec![spp as i32]))],
        )),
        &mut Vec::new(),
    )
    .unwrap();
    let (w, h) = (24i32, 20i32);
    let [x0, x1, y0, y1] = f.sample_extent(0, w as u32, 0, h as u32);
    assert_eq!([x0, x1, y0, y1], [-2, w + 2, -2, h + 2]);
    let mut weights = vec![0.0f64; (w * h) as usize];
    for py in y0..y1 {
        for px in x0..x1 {
            for i in 0..u64::from(spp) {
                let p = s.start_at(42, 0, px, py, i).camera_sample().p_film;
                f.splat(p, |x, y, wt| {
                    if (0..w).contains(&x) && (0..h).contains(&y) {
                        weights[(y * w + x) as usize] += f64::from(wt);
                    }
                });
            }
        }
    }
    let mean = weights.iter().sum::<f64>() / weights.len() as f64;
    assert!(
        (mean / f64::from(spp) - 1.0).abs() < 0.01,
        "mean weight {mean}"
    );
    for (i, wt) in weights.iter().enumerate() {
        assert!((wt / f64::from(spp) - 1.0).abs() < 0.15, "pixel {i}: {wt}");
    }
}

#[test]
fn the_footprint_holds_the_splat_and_stays_within_the_radius() {
    // The depth buffer's footprint (LuxRender adds depth with weight 1 to every cell): the
    // pixels splat visits, plus any cell of weight 0, all within the radius.
    for k in ALL {
        let f = filter(k, &[]);
        let r = f.radius() + Vec2::splat(1.0 / 16.0);
        for p in positions(100) {
            let mut splat = Vec::new();
            f.splat(p, |x, y, _| splat.push((x, y)));
            let mut cells = Vec::new();
            f.footprint(p, |x, y| {
                let c = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                assert!((c.x - p.x).abs() <= r.x && (c.y - p.y).abs() <= r.y);
                cells.push((x, y));
            });
            assert!(splat.iter().all(|c| cells.contains(c)), "{k} at {p}");
        }
    }
}
