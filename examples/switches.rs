//! Judges a viewer frame log (`lampshade view … --frame-log FILE`, or the script's
//! `frame-log`) for stalls at configuration switches: each configuration's steady frame (the
//! median wall time of its frames with no build running and no wait), then for each switch
//! (the frames while the next configuration builds in the background, and the first frame
//! that draws it; a switch whose pipelines were compiled, that frame alone) its longest frame
//! against 1.5 times the slower configuration's steady frame plus 50 ms. The start (the
//! stand-in while the first configuration builds) is left out. Exits non-zero when a switch is
//! over.
//!
//! `cargo run --release --example switches -- FRAMES.jsonl`

use std::collections::HashMap;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v.get(v.len() / 2).copied().unwrap_or(0.0)
}

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: switches FRAMES.jsonl");
        std::process::exit(2);
    };
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        eprintln!("switches: reading {path}: {e}");
        std::process::exit(2);
    });
    let lines: Vec<serde_json::Value> = match text.lines().map(serde_json::from_str).collect() {
        Ok(l) => l,
        Err(e) => {
            eprintln!("switches: {path} is not a frame log: {e}");
            std::process::exit(2);
        }
    };
    let s = |l: &serde_json::Value, k: &str| l[k].as_str().map(str::to_string);
    let wall = |l: &serde_json::Value| l["wall_ms"].as_f64().unwrap_or(0.0);
    let mut by: HashMap<String, Vec<f64>> = HashMap::new();
    // The first frames start the viewer; steady frames are those after.
    for l in lines.iter().skip(5) {
        if let (Some(c), None, Some("nothing")) = (s(l, "config"), s(l, "building"), l["waited_on"].as_str()) {
            by.entry(c).or_default().push(wall(l));
        }
    }
    let steady: HashMap<String, f64> = by.into_iter().map(|(k, v)| (k, median(v))).collect();
    let mut names: Vec<_> = steady.iter().collect();
    names.sort_by(|a, b| a.0.cmp(b.0));
    for (name, ms) in names {
        println!("steady {ms:7.0} ms  {name}");
    }
    let stand_in = |l: &serde_json::Value| l["stand_in"].as_bool().unwrap_or(false);
    let (mut i, mut over) = (0, 0);
    while i < lines.len() {
        let building = s(&lines[i], "building").is_some();
        let changed = i > 0 && s(&lines[i], "config").is_some() && s(&lines[i], "config") != s(&lines[i - 1], "config");
        // The start (the stand-in while the first configuration builds) is the first frame's
        // measure, not a switch's.
        if stand_in(&lines[i]) || (i > 0 && stand_in(&lines[i - 1])) || !(building || changed) {
            i += 1;
            continue;
        }
        if !building {
            // Drawn at once: its pipelines were compiled.
            i -= 1;
        }
        let mut j = i + usize::from(!building);
        while j < lines.len() && s(&lines[j], "building").is_some() {
            j += 1;
        }
        let old = s(&lines[i], "config").unwrap_or_default();
        let new = lines.get(j).and_then(|l| s(l, "config")).unwrap_or_default();
        let slower = steady.get(&old).copied().unwrap_or(0.0).max(steady.get(&new).copied().unwrap_or(0.0));
        let longest = lines[i..(j + 1).min(lines.len())].iter().map(wall).fold(0.0, f64::max);
        let bound = 1.5 * slower + 50.0;
        let ok = longest <= bound;
        over += usize::from(!ok);
        println!(
            "{} frames {:>4}-{:<4} longest {longest:6.0} ms, bound {bound:6.0} ms  {old} -> {new}",
            if ok { "ok  " } else { "OVER" },
            lines[i]["frame"],
            lines.get(j).map_or(serde_json::Value::Null, |l| l["frame"].clone()),
        );
        i = j + 1;
    }
    if over > 0 {
        std::process::exit(1);
    }
}
