use super::*;
use crate::output::number::round_json;

/// Items replayed along the first one's layout are the bytes written
/// afresh (the first item has no comma, the others have); an item with
/// another number of values is refused with nothing written, and the
/// writer goes on as if it had not been tried.
#[test]
fn replayed_items_are_the_written_ones() {
    let item = |w: &mut Json, k: u64| {
        w.begin_object();
        w.key("a").num(k as f64 * 0.1 - 0.2);
        w.key("b").begin_array();
        for i in 0..3 {
            w.int(i + k);
        }
        w.end_array();
        w.key("c").str(if k % 2 == 0 { "x" } else { "y\"z" });
        w.key("d").bool(k % 3 == 0);
        w.end_object();
    };
    let short = |w: &mut Json| {
        w.begin_object();
        w.key("a").num(1.0);
        w.end_object();
    };
    let mut w = Json::new();
    w.begin_object();
    w.key("items").begin_array();
    (0..5).for_each(|k| item(&mut w, k));
    short(&mut w);
    item(&mut w, 5);
    w.end_array();
    w.end_object();
    let plain = w.finish();
    let mut w = Json::new();
    w.begin_object();
    w.key("items").begin_array();
    let mut layout = w.record(|w| item(w, 0));
    for k in 1..5 {
        assert!(w.replay(&mut layout, |w| item(w, k)));
    }
    let len = w.out.len();
    assert!(!w.replay(&mut layout, short));
    assert_eq!(w.out.len(), len);
    short(&mut w);
    assert!(w.replay(&mut layout, |w| item(w, 5)));
    w.end_array();
    w.end_object();
    assert_eq!(w.finish(), plain);
}

/// The word-wise test agrees with the byte-wise one for every byte at
/// every place of a word and of the remainder, between plain bytes.
#[test]
fn plain_strings_are_those_without_a_byte_to_escape() {
    for len in [1, 7, 8, 9, 16, 19] {
        for at in 0..len {
            for c in 0..=255u8 {
                let mut b = vec![b'a'; len];
                b[at] = c;
                let bytewise = c >= 0x20 && c != b'"' && c != b'\\';
                assert_eq!(plain(&b), bytewise, "byte {c:#x} at {at} of {len}");
            }
        }
    }
    assert!(plain(b"") && plain("front_left.upright é".as_bytes()));
}

#[test]
fn values_print_as_serde_json_prints_the_rounded_tree() {
    let mut v = serde_json::json!({
        "a": [0.30000000000000004, 5, -3, [], {}, [1.0, [2.5e-7, 1e21]]],
        "b": {"c": -1e-13, "d": null, "e": true, "f": "q\"\\\n\t\u{1}\u{7f}é"},
        "empty": {}, "g": 1234567.89049999
    });
    let mut w = Json::new();
    w.value(&v);
    round_json(&mut v);
    assert_eq!(w.finish(), format!("{v:#}\n"));
}

/// Deeper than the indents copied whole: the same bytes.
#[test]
fn deep_nesting_indents_as_serde_json() {
    let mut v = serde_json::json!([1.5]);
    for k in 0..20 {
        v = serde_json::json!({ format!("k{k}"): [v, 2.0] });
    }
    let mut w = Json::new();
    w.value(&v);
    round_json(&mut v);
    assert_eq!(w.finish(), format!("{v:#}\n"));
}
