//! Property test: arbitrary token sequences (and arbitrary text) never panic the parser; they
//! parse or fail with an error that has a location inside the input.

use luxfarm::lxs::{self, parser::STATEMENTS, ParseOptions};
use proptest::prelude::*;

const DECLS: &[&str] = &[
    "\"float fov\"",
    "\"integer indices\"",
    "\"point P\"",
    "\"normal N\"",
    "\"color Kd\"",
    "\"bool smooth\"",
    "\"string type\"",
    "\"texture Kd\"",
    "\"spectrum s\"",
    "\"vector v\"",
    "\"flaot x\"",
    "\"float\"",
    "\"\"",
    "\"matte\"",
    "\"true\"",
    "\"a\\\"b\"",
    "\"unterminated",
];

fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => prop::sample::select(STATEMENTS).prop_map(str::to_string),
        3 => prop::sample::select(DECLS).prop_map(str::to_string),
        3 => any::<f32>().prop_map(|f| f.to_string()),
        2 => any::<i64>().prop_map(|i| i.to_string()),
        2 => Just("[".to_string()),
        2 => Just("]".to_string()),
        1 => Just("\n".to_string()),
        1 => Just("# comment\n".to_string()),
        1 => "[a-zA-Z_]{1,12}".prop_map(|s| s),
        1 => "[ -~]{0,6}".prop_map(|s| s),
        1 => Just("1e999".to_string()),
        1 => Just("-.e+".to_string()),
    ]
}

fn check(text: &str) {
    let opts = ParseOptions {
        max_array_len: 64,
        ..ParseOptions::default()
    };
    if let Err(e) = lxs::parse_str(text, "p.lxs", &opts) {
        let lines = text.matches('\n').count() as u32 + 1;
        assert!(e.loc.line <= lines + 1, "{e} beyond {lines} lines");
        assert!(!e.message.is_empty());
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn token_sequences_never_panic(tokens in prop::collection::vec(token(), 0..60)) {
        check(&tokens.join(" "));
    }

    #[test]
    fn world_wrapped_sequences_never_panic(tokens in prop::collection::vec(token(), 0..40)) {
        check(&format!("WorldBegin\n{}\nWorldEnd\n", tokens.join(" ")));
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        check(&String::from_utf8_lossy(&bytes));
    }
}
