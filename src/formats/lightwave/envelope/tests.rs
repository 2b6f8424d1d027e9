//! Unit tests of envelope evaluation (linear, stepped, TCB, Hermite and 2-D Bézier spans, the
//! pre/post behaviours) and of reading an envelope block, on hand-computed values.

use super::*;

fn key(value: f64, time: f64, span: Span, p: [f64; 6]) -> Key {
    Key {
        value,
        time,
        span,
        p,
    }
}

fn env(keys: Vec<Key>, pre: Behavior, post: Behavior) -> Envelope {
    Envelope { keys, pre, post }
}

fn close(a: f64, b: f64) {
    assert!((a - b).abs() < 1e-9, "{a} != {b}");
}

#[test]
fn linear_and_stepped_spans() {
    let e = env(
        vec![
            key(0.0, 0.0, Span::Tcb, [0.0; 6]),
            key(2.0, 1.0, Span::Linear, [0.0; 6]),
            key(4.0, 2.0, Span::Stepped, [0.0; 6]),
        ],
        Behavior::Constant,
        Behavior::Constant,
    );
    close(e.value(0.25), 0.5);
    close(e.value(1.0), 2.0);
    close(e.value(1.5), 2.0); // stepped: holds the previous key
    close(e.value(2.0), 4.0);
    close(e.value(-1.0), 0.0);
    close(e.value(9.0), 4.0);
}

#[test]
fn tcb_with_zero_parameters_is_catmull_rom_like() {
    // Keys (0,0), (1,1), (2,0). At the middle key the tangents are
    // (1 - 0 + 0 - 1) * 1/2 = 0; the first key's outgoing tangent is d = 1, the last key's
    // incoming tangent d = -1.
    let e = env(
        vec![
            key(0.0, 0.0, Span::Tcb, [0.0; 6]),
            key(1.0, 1.0, Span::Tcb, [0.0; 6]),
            key(0.0, 2.0, Span::Tcb, [0.0; 6]),
        ],
        Behavior::Constant,
        Behavior::Constant,
    );
    // s = 0.5 on the first span: h1 = 0.5, h2 = 0.5, h3 = 0.125, h4 = -0.125;
    // value = 0.5*0 + 0.5*1 + 0.125*1 + (-0.125)*0 = 0.625.
    close(e.value(0.5), 0.625);
    // Second span, s = 0.5: out(k1) = 0, in(k2) = -1 -> 0.5 + 0.125*0 - 0.125*(-1) = 0.625.
    close(e.value(1.5), 0.625);
}

#[test]
fn hermite_uses_the_written_tangents() {
    // p4 = incoming, p5 = outgoing tangent. Single span: no scaling by neighbours.
    let e = env(
        vec![
            key(0.0, 0.0, Span::Hermite, [0.0, 0.0, 0.0, 0.0, 3.0, 0.0]),
            key(1.0, 2.0, Span::Hermite, [0.0, 0.0, 0.0, -1.0, 0.0, 0.0]),
        ],
        Behavior::Constant,
        Behavior::Constant,
    );
    // s = 0.5: 0.5*1 + 0.125*3 - 0.125*(-1) = 1.0
    close(e.value(1.0), 1.0);
}

#[test]
fn bezier2d_with_handles_on_the_straight_line_is_linear() {
    let e = env(
        vec![
            key(
                0.0,
                0.0,
                Span::Bezier2d,
                [0.0, 0.0, 1.0 / 3.0, 1.0 / 3.0, 0.0, 0.0],
            ),
            key(
                1.0,
                1.0,
                Span::Bezier2d,
                [-1.0 / 3.0, -1.0 / 3.0, 0.0, 0.0, 0.0, 0.0],
            ),
        ],
        Behavior::Constant,
        Behavior::Constant,
    );
    for t in [0.1, 0.3, 0.5, 0.9] {
        assert!((e.value(t) - t).abs() < 1e-9);
    }
}

#[test]
fn behaviours_extrapolate() {
    let keys = vec![
        key(1.0, 0.0, Span::Tcb, [0.0; 6]),
        key(3.0, 2.0, Span::Linear, [0.0; 6]),
    ];
    let mk = |b| env(keys.clone(), b, b);
    close(mk(Behavior::Reset).value(3.0), 0.0);
    close(mk(Behavior::Constant).value(3.0), 3.0);
    close(mk(Behavior::Constant).value(-3.0), 1.0);
    // repeat: t = 3 -> 1 -> value 2
    close(mk(Behavior::Repeat).value(3.0), 2.0);
    close(mk(Behavior::Repeat).value(-0.5), 2.5);
    // oscillate: t = 2.5 is in the second (reversed) copy: 2 - 0.5 = 1.5 -> 2.5
    close(mk(Behavior::Oscillate).value(2.5), 2.5);
    // offset repeat: t = 3 -> 1 (value 2) plus one cycle's rise (2) = 4
    close(mk(Behavior::OffsetRepeat).value(3.0), 4.0);
    close(mk(Behavior::OffsetRepeat).value(-1.0), 0.0);
    // linear: slope 1 continues
    close(mk(Behavior::Linear).value(4.0), 5.0);
    close(mk(Behavior::Linear).value(-1.0), 0.0);
}

#[test]
fn reads_a_block_and_checks_counts() {
    let text = "{ Envelope\n  2\n  Key 0 0 0 0 0 0 0 0 0\n  Key 1 1 3 0 0 0 0 0 0\n  Behaviors 1 2\n  { ChannelHandler\n    x\n  }\n}\n";
    let mut c = Cursor::new("s.lws", text);
    let open = c.next_line().unwrap();
    let mut skipped = Vec::new();
    let e = Envelope::read(&mut c, &open, &mut skipped).unwrap();
    assert_eq!(e.keys.len(), 2);
    assert_eq!(e.post, Behavior::Repeat);
    assert_eq!(skipped.len(), 1);
    assert_eq!(skipped[0].0.line, 6);
    let bad = "{ Envelope\n  3\n  Key 0 0 0\n  Behaviors 1 1\n}\n";
    let mut c = Cursor::new("s.lws", bad);
    let open = c.next_line().unwrap();
    let e = Envelope::read(&mut c, &open, &mut skipped).unwrap_err();
    assert_eq!(e.loc.line, 2, "{e}");
    let bad_span = "{ Envelope\n  1\n  Key 0 0 9\n}\n";
    let mut c = Cursor::new("s.lws", bad_span);
    let open = c.next_line().unwrap();
    let e = Envelope::read(&mut c, &open, &mut skipped).unwrap_err();
    assert_eq!(e.loc.line, 3, "{e}");
}
