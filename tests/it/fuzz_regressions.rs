//! Inputs for the fuzz targets `settings_file` and `viewer_script` (fuzz/README.md): every
//! regression input they found, kept in `tests/data/fuzz-regressions/` (`settings-*`,
//! `script-*`), must be a clear error, and the seeds' edge cases must parse or fail as stated.
//! A panic anywhere fails the test. (`import_gltf`'s findings are `tests/it/gltf.rs`'s
//! `fuzzer_findings_stay_fixed`.)

use lampshade::settings_file;
use std::path::Path;

/// The regression inputs whose names start with `prefix`, sorted by name.
fn regressions(prefix: &str) -> Vec<(String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz-regressions");
    let mut out: Vec<(String, String)> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.starts_with(prefix)))
        .map(|p| {
            // As the fuzz targets read them: bytes that are not UTF-8 replaced.
            let text = String::from_utf8_lossy(&std::fs::read(&p).unwrap()).into_owned();
            (p.file_name().unwrap().to_string_lossy().into_owned(), text)
        })
        .collect();
    out.sort();
    out
}

#[test]
fn settings_file_regressions_are_errors() {
    for (name, text) in regressions("settings-") {
        let e = settings_file::parse(&text).expect_err(&name);
        assert!(!format!("{e:#}").is_empty(), "{name}");
    }
}

/// Edge cases from `fuzz/seeds/make_text_seeds.py`: `Ok(())` must parse, `Err(s)` must fail with
/// a message containing `s`.
#[test]
fn settings_file_edge_cases() {
    let ok = Ok(());
    let cases: &[(&str, Result<(), &str>)] = &[
        ("{}", ok),
        (r#"{"viewer": {"anything": [1, {"x": null}]}}"#, ok),
        (r#"{"viewer": {"anything": [1, {"x": null}]}, "unknown": 3}"#, Err("unknown key \"unknown\"")),
        (r#"{"selected_light": 18446744073709551615, "lights": 18446744073709551615}"#, ok),
        (r#"{"exposure": 999999, "light_cutoff": 0.999999, "size": [8192, 1], "time": -1.7e308}"#, ok),
        (r#"{"scene": "d\u00e9mo \ud83d\ude00", "scene": null}"#, Err("duplicate field")),
        ("", Err("one JSON object")),
        ("[1, 2, 3]", Err("one JSON object")),
        (r#"{"exposure": 1} {"exposure": 2}"#, Err("trailing characters")),
        (r#"{"exposure": 1e39}"#, Err("exposure inf")),
        (r#"{"exposure": -1e-400}"#, Err("exposure")),
        (r#"{"time": 1e400}"#, Err("out of range")),
        (r#"{"light_cutoff": 1.0}"#, Err("cut-off 1")),
        (r#"{"sphere_subdivisions": 4294967295}"#, Err("sphere subdivisions 4294967295")),
        (r#"{"cone_sides": 4294967296}"#, Err("expected u32")),
        (r#"{"cone_sides": -1}"#, Err("expected u32")),
        (r#"{"lights": -5}"#, Err("scene keys")),
        (r#"{"size": [8193, 1]}"#, Err("size 8193x1")),
        (r#"{"size": [1, 2, 3]}"#, Err("scene keys")),
        (r#"{"reversed_z": "yes"}"#, Err("expected a boolean")),
        (r#"{"culling": 3}"#, Err("renderer settings")),
        (r#"{"camera": []}"#, Err("scene keys")),
        (
            r#"{"camera": {"position": [0, 0, 0], "yaw": 0, "pitch": 0, "fov_y": 0.9, "near": 1e-300, "far": 1.7e308}}"#,
            ok,
        ),
        (
            r#"{"camera": {"position": [0, 0, 0], "yaw": 0, "pitch": 0, "fov_y": 0.9, "near": 2, "far": 1}}"#,
            Err("near 2 far 1"),
        ),
    ];
    for (text, want) in cases {
        match (settings_file::parse(text), want) {
            (Ok(_), Ok(())) => {}
            (Err(e), Err(needle)) => assert!(format!("{e:#}").contains(needle), "{text}: {e:#}"),
            (got, want) => panic!("{text}: got {:?}, want {want:?}", got.map(|_| ())),
        }
    }
    // Deep nesting never overflows the stack: an ignored key is skipped without recursion, and a
    // known key fails at the first level its type does not expect.
    let deep = |key: &str| format!("{{\"{key}\": {}{}}}", "[".repeat(1_000_000), "]".repeat(1_000_000));
    assert!(settings_file::parse(&deep("viewer")).is_ok());
    let e = format!("{:#}", settings_file::parse(&deep("size")).unwrap_err());
    assert!(e.contains("expected u32"), "{e}");
}

#[cfg(feature = "viewer")]
mod scripts {
    use super::regressions;
    use lampshade::app::script::{Action, Script};
    use std::path::Path;

    #[test]
    fn viewer_script_regressions_are_errors() {
        for (name, text) in regressions("script-") {
            let e = Script::parse(&text, Path::new("/base")).expect_err(&name);
            assert!(format!("{e:#}").contains("line "), "{name}: {e:#}");
        }
    }

    /// Edge cases from `fuzz/seeds/make_text_seeds.py`.
    #[test]
    fn viewer_script_edge_cases() {
        let parse = |text: &str| Script::parse(text, Path::new("/base"));
        let err = |text: &str| format!("{:#}", parse(text).unwrap_err());
        for text in [
            "1 hover NaN 0",
            "1 hover inf 0",
            "1 hover 0 -inf",
            "1 hover 1.0000001 0",
            "-1 quit",
            "1 select -1",
            "1 resize -800 600",
            "1 resize 16385 1",
            "1 resize 4294967296 1",
            "1 hold W -3",
            "1 hold W 0",
            "18446744073709551616 quit",
            "18446744073709551615 quit",
            "4294967297 quit",
            "1 hold W 4294967297",
            "1 key Tab",
            "1 tab nowhere",
            "1 jump",
            "1 quit now",
            "1\tscreenshot",
            "",
            "# only a comment\n   \n",
        ] {
            assert!(!err(text).is_empty(), "{text:?}");
        }
        // Accepted: tabs, CRLF, a comment glued to a word, the edges of each range.
        let s = parse("\t1\tquit\t# tabs\r\n2 key W#glued\r\n3 resize 0 0\n3 resize 16384 16384\n4 click 1e-45 1\n")
            .unwrap();
        assert_eq!(s.actions.len(), 5);
        assert_eq!(s.actions[1], (2, Action::Key(winit::keyboard::KeyCode::KeyW)));
        // The largest frame and hold a script may use; the viewer's `frame + n - 1` fits.
        let s = parse("4294967296 hold W 4294967296").unwrap();
        assert_eq!(s.actions[0].0, lampshade::app::script::MAX_FRAME);
        // Screenshot paths are joined to the base, whatever they look like.
        let s = parse("1 screenshot ..\n1 screenshot /\n1 screenshot \u{e9}.png").unwrap();
        let paths: Vec<_> = s.actions.iter().map(|(_, a)| a.clone()).collect();
        assert_eq!(paths[0], Action::Screenshot("/base/..".into()));
        assert_eq!(paths[1], Action::Screenshot("/".into()));
        // `set` values are checked when the action runs (UiState::set), not here.
        assert!(parse("1 set warp 9").is_ok());
    }
}
