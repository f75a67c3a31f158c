//! Calibrations: `lampshade calibrate` writes one that reads back, the CLI weighs `auto`'s
//! choice with the cache's calibration for its adapter, and a corrupt or stale cache file is a
//! warning and the built-in defaults. Each test gives the binary a cache folder of its own.

use lampshade::renderer::options::calibration::{Calibration, CostConstants, ListCost, CALIBRATION_VERSION};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// An empty cache home of the test's own (`XDG_CACHE_HOME`).
fn cache_home(tag: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("calibration-tests").join(tag);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("creating the cache home");
    d
}

/// `lampshade args` with the cache home `home`.
fn lampshade(args: &[&str], home: &Path) -> Output {
    let runtime = std::env::temp_dir().join("lampshade-cli-xdg");
    let _ = std::fs::create_dir_all(&runtime);
    Command::new(env!("CARGO_BIN_EXE_lampshade"))
        .args(args)
        .env("XDG_RUNTIME_DIR", &runtime)
        .env("XDG_CACHE_HOME", home)
        .env_remove(lampshade::calibration::ENV)
        .output()
        .expect("spawn")
}

fn text(out: &Output) -> (String, String) {
    (String::from_utf8_lossy(&out.stdout).into_owned(), String::from_utf8_lossy(&out.stderr).into_owned())
}

/// The key the binary's default adapter is calibrated under (the suite's device is opened the
/// same way).
fn key() -> String {
    lampshade::calibration::key(&crate::common::gpu().info)
}

/// The cache file of this adapter under the cache home `home`.
fn cache_file(home: &Path) -> PathBuf {
    lampshade::calibration::cache_file(&home.join("lampshade"), &key())
}

/// `auto` on `demo` with 1,024 lights at 160x90: the stats' calibration and the list mode the
/// frame shaded with, if any.
fn auto_frame(home: &Path, tag: &str) -> (String, Option<String>, String) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("calibration-tests");
    let (png, json) = (dir.join(format!("{tag}.png")), dir.join(format!("{tag}.json")));
    let out = lampshade(
        &[
            "render",
            "demo",
            "--lights",
            "1024",
            "--size",
            "160x90",
            "--culling",
            "auto",
            "--ledger",
            "off",
            "--out",
            png.to_str().unwrap(),
            "--stats",
            json.to_str().unwrap(),
        ],
        home,
    );
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "render failed:\n{stdout}\n{stderr}");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let calibration = v["calibration"].as_str().expect("the stats name the calibration").to_string();
    assert!(stdout.contains(&format!("calibration: {calibration}")), "{stdout}");
    let method = v["stats"]["tiles"]["method"].as_str().map(str::to_string);
    (calibration, method, stderr)
}

#[test]
fn a_planted_calibration_that_makes_tiled_cheap_changes_autos_choice() {
    let home = cache_home("planted");
    // The built-in defaults: `clustered` or the per-light plan, never `tiled`.
    let (calibration, method, _) = auto_frame(&home, "defaults");
    assert_eq!(calibration, "built-in defaults");
    assert_ne!(method.as_deref(), Some("tiled"));
    // A calibration of this adapter in which `tiled` costs next to nothing.
    let cheap = ListCost { fixed_ms_per_mpx: 0.001, pair_ns: 0.001, pairs_per_footprint: 0.001 };
    let planted = Calibration {
        version: CALIBRATION_VERSION,
        key: key(),
        measured: "2026-01-01".into(),
        how: "planted by the test".into(),
        costs: CostConstants { tiled: Some(cheap), ..CostConstants::BUILTIN },
    };
    let path = lampshade::calibration::write(&home.join("lampshade"), &planted).expect("planting the calibration");
    assert_eq!(path, cache_file(&home));
    let (calibration, method, _) = auto_frame(&home, "planted");
    assert_eq!(calibration, format!("{}, measured 2026-01-01", key()));
    assert_eq!(method.as_deref(), Some("tiled"), "auto did not take the calibration's cheap tiled");
    // The same file named explicitly from another (empty) cache home.
    let other = cache_home("planted-explicit");
    let png = other.join("x.png");
    let out = lampshade(
        &[
            "render",
            "demo",
            "--lights",
            "1024",
            "--size",
            "160x90",
            "--ledger",
            "off",
            "--culling",
            "auto",
            "--calibration",
            path.to_str().unwrap(),
            "--out",
            png.to_str().unwrap(),
        ],
        &other,
    );
    let (stdout, stderr) = text(&out);
    assert!(out.status.success() && stdout.contains("auto (tiled)"), "{stdout}\n{stderr}");
    // The same constants measured only from 2,048 lights up: at 1,024 the rule does not
    // extrapolate them, and the frame keeps its per-light plan.
    let above_home = cache_home("planted-above");
    let above = Calibration { costs: CostConstants { min_lights: 2048, ..planted.costs }, ..planted };
    lampshade::calibration::write(&above_home.join("lampshade"), &above).expect("planting the calibration");
    let (_, method, _) = auto_frame(&above_home, "planted-above");
    assert_eq!(method, None, "auto weighed the list modes below the calibration's fewest lights");
}

#[test]
fn a_corrupt_or_stale_cache_file_is_a_warning_and_the_defaults() {
    let home = cache_home("corrupt");
    let file = cache_file(&home);
    std::fs::create_dir_all(file.parent().unwrap()).unwrap();
    let stale = serde_json::json!({ "version": CALIBRATION_VERSION + 1, "key": key(), "costs": {} });
    let other_key =
        Calibration { key: "another adapter".into(), measured: "2026-01-01".into(), ..Calibration::builtin() };
    for (what, contents) in [
        ("corrupt", "{\"version\": 1, \"key\": \"trunc".to_string()),
        ("stale", stale.to_string()),
        ("another key's", serde_json::to_string(&other_key).unwrap()),
    ] {
        std::fs::write(&file, contents).unwrap();
        let (calibration, _, stderr) = auto_frame(&home, what);
        assert_eq!(calibration, "built-in defaults", "a {what} cache file");
        assert!(
            stderr.contains("WARN") && stderr.contains("calibration cache") && stderr.contains("built-in defaults"),
            "a {what} cache file gave no warning:\n{stderr}"
        );
    }
    // An explicit file that is not a calibration is an error that names it.
    std::fs::write(&file, "not json").unwrap();
    let png = home.join("x.png");
    let out = lampshade(
        &["render", "spot", "--size", "32x32", "--calibration", file.to_str().unwrap(), "--out", png.to_str().unwrap()],
        &home,
    );
    let (_, stderr) = text(&out);
    assert!(!out.status.success() && stderr.contains("calibration") && !stderr.contains("panicked"), "{stderr}");
}

#[test]
fn calibrate_measures_and_writes_a_calibration_that_reads_back() {
    let home = cache_home("calibrate");
    let out = lampshade(&["calibrate", "--size", "96x54", "--lights", "256,512", "--frames", "1"], &home);
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "calibrate failed:\n{stdout}\n{stderr}");
    let file = cache_file(&home);
    assert!(stdout.contains(file.to_str().unwrap()), "{stdout}");
    let c = lampshade::calibration::read(&file).expect("the calibration reads back");
    assert_eq!((c.version, c.key.as_str()), (CALIBRATION_VERSION, key().as_str()));
    assert_eq!(c.costs.validate(), Ok(()));
    assert!(c.costs != CostConstants::BUILTIN, "nothing was measured: {:?}", c.costs);
    for mode in ["volume", "clustered", "tiled", "zbin"] {
        for lights in [256, 512] {
            assert!(
                stdout.contains(&format!("| {mode} | {lights} | x1 |")),
                "no {mode} frame at {lights} lights:\n{stdout}"
            );
        }
    }
    // The next command reads it.
    let (calibration, _, _) = auto_frame(&home, "calibrated");
    assert_eq!(calibration, format!("{}, measured {}", key(), c.measured));
    // Bad arguments are errors before any frame.
    let out = lampshade(&["calibrate", "--lights", "0"], &home);
    assert!(!out.status.success() && text(&out).1.contains("--lights"), "{:?}", text(&out));
}

#[test]
fn the_viewer_calibrates_when_asked_and_draws_with_it() {
    if !["DISPLAY", "WAYLAND_DISPLAY"].iter().any(|v| std::env::var(v).is_ok_and(|s| !s.is_empty())) {
        eprintln!("SKIPPED the_viewer_calibrates_when_asked_and_draws_with_it: no DISPLAY (run under xvfb-run)");
        return;
    }
    let home = cache_home("viewer");
    let script = home.join("calibrate.script");
    std::fs::write(&script, "2 calibrate\n4 quit\n").unwrap();
    let out = lampshade(
        &["view", "demo", "--lights", "64", "--size", "640x400", "--script", script.to_str().unwrap()],
        &home,
    );
    let (stdout, stderr) = text(&out);
    assert!(out.status.success() && !stderr.contains("panicked"), "the viewer failed:\n{stdout}\n{stderr}");
    let c = lampshade::calibration::read(&cache_file(&home)).expect("the viewer's calibration reads back");
    // Measured on the window's adapter, and taken by its renderer.
    assert!(stdout.contains(&format!("frame 2: calibration: {}", c.describe())), "{stdout}");
}
