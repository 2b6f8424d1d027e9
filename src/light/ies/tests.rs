//! IES parsing and evaluation on hand-written profiles, with hand-computed candela values.

use super::*;

/// Type C, quadrant symmetric (H 0 and 90), V 0/45/90; multiplier 2.
const QUADRANT: &str = "IESNA:LM-63-2002
[TEST] luxfarm quadrant profile
[MANUFAC] none
TILT=NONE
1 1000 2 3 2 1 2 0.1 0.1 0
1.0 1.0 50
0 45 90
0 90
1000 800 0
1000, 400, 0
";

fn dir(v_deg: f32, h_deg: f32) -> [f32; 3] {
    let (v, h) = (v_deg.to_radians(), h_deg.to_radians());
    [v.sin() * h.cos(), v.sin() * h.sin(), v.cos()]
}

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 1e-3 * b.abs().max(1.0)
}

#[test]
fn type_c_quadrant_profile_by_hand() {
    let p = parse(QUADRANT).unwrap();
    assert_eq!(p.kind, PhotometricType::C);
    // (V, H) → candela × 2: nadir 2000; V 45 at H 0 1600, at H 90 800, at H 45 their mean;
    // the quadrant unfolds (H 180 → 0, H 270 → 90); V 22.5 at H 0 between 2000 and 1600;
    // beyond V 90 nothing.
    for (v, h, want) in [
        (0.0, 0.0, 2000.0),
        (45.0, 0.0, 1600.0),
        (45.0, 90.0, 800.0),
        (45.0, 45.0, 1200.0),
        (45.0, 180.0, 1600.0),
        (45.0, 270.0, 800.0),
        (45.0, 315.0, 1200.0),
        (22.5, 0.0, 1800.0),
        (67.5, 90.0, 400.0),
        (120.0, 0.0, 0.0),
    ] {
        let c = p.candela(dir(v, h));
        assert!(close(c, want), "V {v} H {h}: {c} want {want}");
    }
    assert_eq!(p.max_candela(), 2000.0);
}

#[test]
fn type_c_symmetric_bilateral_and_full_turn() {
    // One horizontal angle: the same in every azimuth. LM-63-1986 files have no IESNA line.
    let sym = "TILT=NONE\n1 -1 1 2 1 1 2 0 0 0\n1 1 10\n0 180\n0\n300 100\n";
    let p = parse(sym).unwrap();
    for h in [0.0, 77.0, 200.0] {
        assert!(close(p.candela(dir(90.0, h)), 200.0));
    }
    // Bilateral 0..180: H 270 mirrors to 90.
    let bi = "TILT=NONE\n1 -1 1 1 3 1 2 0 0 0\n1 1 10\n60\n0 90 180\n10 20 30\n";
    let p = parse(bi).unwrap();
    assert!(close(p.candela(dir(60.0, 270.0)), 20.0));
    assert!(close(p.candela(dir(60.0, 225.0)), 25.0));
    // A full turn given as 0, 120, 240: between 240 and 360 it interpolates back to 0's row.
    let full = "TILT=NONE\n1 -1 1 1 3 1 2 0 0 0\n1 1 10\n90\n0 120 240\n30 60 90\n";
    let p = parse(full).unwrap();
    assert!(close(p.candela(dir(90.0, 300.0)), 60.0));
    assert!(close(p.candela(dir(90.0, 60.0)), 45.0));
}

#[test]
fn type_b_profile_about_the_beam() {
    // V −45/0/45, H 0/30 (symmetric in H); beam along +z.
    let b = "TILT=NONE\n1 -1 1 3 2 2 2 0 0 0\n1 1 100\n-45 0 45\n0 30\n100 500 100\n50 250 50\n";
    let p = parse(b).unwrap();
    assert_eq!(p.kind, PhotometricType::B);
    let h15 = 15f32.to_radians();
    assert!(close(p.candela([0.0, 0.0, 1.0]), 500.0));
    assert!(close(p.candela([h15.sin(), 0.0, h15.cos()]), 375.0));
    assert!(close(p.candela([-h15.sin(), 0.0, h15.cos()]), 375.0));
    let v45 = 45f32.to_radians();
    assert!(close(p.candela([0.0, v45.sin(), v45.cos()]), 100.0));
    assert_eq!(p.candela([0.0, 0.0, -1.0]), 0.0);
    // Type A: H is left/right (x), V up/down about the lateral axis.
    let a = b.replacen(" 2 2 2 ", " 2 3 2 ", 1);
    let p = parse(&a).unwrap();
    assert_eq!(p.kind, PhotometricType::A);
    assert!(close(p.candela([h15.sin(), 0.0, h15.cos()]), 375.0));
    assert!(close(p.candela([0.0, v45.sin(), v45.cos()]), 100.0));
}

#[test]
fn malformed_files_are_refused_with_their_line() {
    let tilt = QUADRANT.replace("TILT=NONE", "TILT=INCLUDE");
    let e = parse(&tilt).unwrap_err();
    assert!(e.contains("line 4") && e.contains("TILT=INCLUDE"), "{e}");
    assert!(parse("no tilt here\n1 2 3\n").unwrap_err().contains("TILT"));
    let short = QUADRANT.replace("1000, 400, 0\n", "1000, 400\n");
    assert!(parse(&short).unwrap_err().contains("ends"), "short");
    let unsorted = QUADRANT.replace("0 45 90\n", "0 90 45\n");
    let e = parse(&unsorted).unwrap_err();
    assert!(e.contains("line 7") && e.contains("ascend"), "{e}");
    let huge = QUADRANT.replace("1 1000 2 3 2 1", "1 1000 2 3000 3000 1");
    assert!(parse(&huge).is_err());
    let word = QUADRANT.replace("1000 800 0", "1000 eight 0");
    assert!(parse(&word).unwrap_err().contains("line 9"));
    let negative = QUADRANT.replace("1000 800 0", "1000 -800 0");
    assert!(parse(&negative).is_err());
    let bad_type = QUADRANT.replacen(" 2 1 2 ", " 2 7 2 ", 1);
    assert!(parse(&bad_type).unwrap_err().contains("photometric type"));
}
