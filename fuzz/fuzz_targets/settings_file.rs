//! Fuzzes settings files (`lampshade render --settings FILE`, what the viewer's F12 writes):
//! `lampshade::settings_file::parse` on arbitrary text (bytes that are not UTF-8 replaced, as
//! `String::from_utf8_lossy` does). An error is fine; a panic, a hang or an unbounded
//! allocation is a bug.
//!
//! A file that parses must also survive a round trip: written back as the viewer writes it
//! (the settings' fields and the scene keys in one object) it parses again, to the same values
//! up to float rounding (serde_json without `float_roundtrip` may read a float one ulp off).
#![no_main]

use lampshade::settings_file::parse;
use libfuzzer_sys::fuzz_target;
use serde_json::Value;

/// Both values as one JSON object, as the viewer writes a settings file.
fn written(settings: &lampshade::Settings, keys: &lampshade::settings_file::SceneKeys) -> Value {
    let mut doc = serde_json::to_value(settings).expect("settings serialise");
    let extra = serde_json::to_value(keys).expect("scene keys serialise");
    let (Some(doc_map), Some(extra)) = (doc.as_object_mut(), extra.as_object()) else {
        panic!("settings or scene keys are not a JSON object");
    };
    doc_map.extend(extra.clone());
    doc
}

/// Equal, with numbers within a relative 1e-6 (f32 fields) of each other.
fn close(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => match (x.as_f64(), y.as_f64()) {
            (Some(x), Some(y)) => x == y || (x - y).abs() <= 1e-6 * x.abs().max(y.abs()),
            _ => x == y,
        },
        (Value::Array(x), Value::Array(y)) => x.len() == y.len() && x.iter().zip(y).all(|(x, y)| close(x, y)),
        (Value::Object(x), Value::Object(y)) => {
            x.len() == y.len() && x.iter().all(|(k, v)| y.get(k).is_some_and(|w| close(v, w)))
        }
        _ => a == b,
    }
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let Ok((settings, keys)) = parse(&text) else {
        return;
    };
    let doc = written(&settings, &keys);
    let again = doc.to_string();
    match parse(&again) {
        Ok((s, k)) => assert!(close(&written(&s, &k), &doc), "round trip changed the values: {again}"),
        Err(e) => panic!("a parsed settings file does not parse once written back: {e:#}\n{again}"),
    }
});
