//! The command line: `render` writes a lit PNG and a stats JSON with every key filled; bad
//! arguments and files are clear errors with a non-zero exit, never a panic.

use std::process::Command;

/// A third-party file with a camera of its own (`assimp-testmodels`, installed by `.ci/run`).
const CAMERAS: &str = "/usr/share/assimp/models/glTF2/cameras/Cameras.gltf";

fn lampshade(args: &[&str]) -> std::process::Output {
    let dir = std::env::temp_dir().join("lampshade-cli-xdg");
    let _ = std::fs::create_dir_all(&dir);
    Command::new(env!("CARGO_BIN_EXE_lampshade"))
        .args(args)
        .env("XDG_RUNTIME_DIR", &dir)
        .env("XDG_CACHE_HOME", crate::common::empty_cache_home())
        .env_remove(lampshade::calibration::ENV)
        .output()
        .expect("spawn")
}

fn tmp(name: &str) -> std::path::PathBuf {
    // Under target/, emptied once a run so no test reads an earlier run's files (the files'
    // names are each test's own).
    static EMPTIED: std::sync::Once = std::sync::Once::new();
    let d = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/cli-tests");
    EMPTIED.call_once(|| {
        let _ = std::fs::remove_dir_all(&d);
    });
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

#[test]
fn render_writes_an_image_and_complete_stats() {
    let png = tmp("demo.png");
    let json = tmp("demo.json");
    let out = lampshade(&[
        "render",
        "demo",
        "--size",
        "160x90",
        "--lights",
        "64",
        "--culling",
        "stencil-two-pass",
        "--out",
        png.to_str().unwrap(),
        "--stats",
        json.to_str().unwrap(),
        "--ideal",
        "--probe",
        "80,60",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("pixel 80,60 (deferred path, stencil-two-pass culling)"), "{stdout}");
    let img = image::open(&png).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (160, 90));
    let lit = img.pixels().filter(|p| p[0] as u32 + p[1] as u32 + p[2] as u32 > 60).count();
    assert!(lit > 160 * 90 / 4, "the demo image is mostly dark");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    for key in [
        "adapter",
        "size",
        "culling",
        "lights",
        "gpu_ms",
        "shaded_fragments",
        "ideal_fragments",
        "gbuffer_bytes_per_pixel",
        "per_light",
    ] {
        assert!(v.get(key).is_some_and(|x| !x.is_null()), "stats JSON lacks {key}");
    }
    assert_eq!(v["lights"], 68);
    assert_eq!(v["culling"], "stencil-two-pass");
    assert_eq!(v["per_light"].as_array().unwrap().len(), 68);
    // Each light's kind by name: demo's 64 point lights and its 4 spots.
    let kinds = |k: &str| v["per_light"].as_array().unwrap().iter().filter(|l| l["kind"] == k).count();
    assert_eq!((kinds("point"), kinds("spot")), (64, 4), "per-light kinds in the stats JSON");
    assert!(v["adapter"]["name"].as_str().is_some_and(|s| !s.is_empty()));
    for pass in ["gbuffer", "lighting", "compose", "total"] {
        // Null only where the adapter lacks timestamps; lavapipe has them.
        assert!(v["gpu_ms"].get(pass).is_some(), "gpu_ms lacks {pass}");
    }
    assert!(v["shaded_fragments"].as_u64().unwrap() >= v["ideal_fragments"].as_u64().unwrap());
    // `--probe`'s explanation: the pixel, and no light missed.
    assert_eq!((v["probe"]["x"].as_u64(), v["probe"]["y"].as_u64()), (Some(80), Some(60)));
    assert_eq!(v["probe"]["missed"], 0);
    assert!(v["probe"]["lights"].is_array());
}

#[test]
fn stats_alone_do_not_count_the_ideal_and_say_so() {
    let png = tmp("no-ideal.png");
    let json = tmp("no-ideal.json");
    let args = ["render", "demo", "--size", "64x36", "--lights", "16", "--out", png.to_str().unwrap()];
    let out = lampshade(&[&args[..], &["--stats", json.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["ideal_counted"], false);
    assert!(v["ideal_fragments"].is_null(), "ideal counted without --ideal: {}", v["ideal_fragments"]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("not counted (--ideal)"));
    let out = lampshade(&[&args[..], &["--stats", json.to_str().unwrap(), "--ideal"]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["ideal_counted"], true);
    assert!(v["ideal_fragments"].as_u64().is_some_and(|n| n > 0));
}

/// The ledger in `--stats`: on by default (each light's pairs, wasted pairs with `--ideal`, cost
/// and the model), off above 4,096 lights with a note, on again when asked.
#[test]
fn the_ledger_is_in_the_stats_and_off_above_4096_lights_unless_asked() {
    let png = tmp("ledger.png");
    let json = tmp("ledger.json");
    let read = || -> serde_json::Value { serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap() };
    let base = ["render", "demo", "--size", "64x36", "--culling", "tiled", "--out", png.to_str().unwrap()];
    let stats = ["--stats", json.to_str().unwrap()];
    let out = lampshade(&[&base[..], &stats, &["--lights", "16", "--ideal"]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v = read();
    assert_eq!(v["ledger"], true);
    let lights = v["per_light"].as_array().unwrap();
    let (mut shaded, mut wasted) = (0, 0);
    for l in lights {
        let (s, i, w) = (l["shaded"].as_u64().unwrap(), l["ideal"].as_u64().unwrap(), l["wasted"].as_u64().unwrap());
        assert_eq!(w, s - i, "{l}");
        assert!(l["cost_ms"].as_f64().is_some_and(|c| c >= 0.0), "{l}");
        (shaded, wasted) = (shaded + s, wasted + w);
    }
    assert_eq!((v["shaded_fragments"].as_u64(), v["wasted_fragments"].as_u64()), (Some(shaded), Some(wasted)));
    assert!(v["cost_model"]["pair_ns"].as_f64().is_some() && v["light_cost_ms"].as_f64().is_some());
    // Each light's share of the measured pass: the pass split in proportion to the model's
    // costs, the fixed part's share apart.
    let (measured, model) = (v["stats"]["gpu_ms"]["lighting"].as_f64().unwrap(), v["light_cost_ms"].as_f64().unwrap());
    let fixed = v["cost_model"]["fixed_ms"].as_f64().unwrap();
    let shares: f64 = lights.iter().map(|l| l["share_ms"].as_f64().unwrap()).sum();
    let expected = measured * model / (model + fixed);
    assert!((shares - expected).abs() <= 1e-9 * measured, "shares {shares} ms, expected {expected} of {measured}");
    let many = ["--lights", "4100"];
    let out = lampshade(&[&base[..], &stats, &many].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("ledger is off above 4096"));
    let v = read();
    assert_eq!(v["ledger"], false);
    assert!(v["shaded_fragments"].is_null() && v["per_light"][0]["cost_ms"].is_null());
    let out = lampshade(&[&base[..], &stats, &many, &["--ledger", "on"]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v = read();
    assert_eq!(v["ledger"], true);
    assert!(v["shaded_fragments"].as_u64().is_some() && v["per_light"][0]["cost_ms"].as_f64().is_some());
    let out = lampshade(&[&base[..], &["--ledger", "maybe"]].concat());
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("--ledger"));
}

#[test]
fn a_headless_render_needs_no_runtime_dir_and_prints_no_display_errors() {
    let png = tmp("no-xdg.png");
    let out = Command::new(env!("CARGO_BIN_EXE_lampshade"))
        .args(["render", "spot", "--size", "32x32", "--out", png.to_str().unwrap()])
        .env_remove("XDG_RUNTIME_DIR")
        .env("XDG_CACHE_HOME", crate::common::empty_cache_home())
        .env_remove(lampshade::calibration::ENV)
        .env_remove("NODEVICE_SELECT")
        .env_remove("WGPU_BACKEND")
        .output()
        .expect("spawn");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    for noise in ["XDG_RUNTIME_DIR", "EGL", "ERROR"] {
        assert!(!err.contains(noise), "stderr mentions {noise}: {err}");
    }
}

/// A copy of the project's room without its lights, in a scratch directory.
fn lightless_room(tag: &str) -> std::path::PathBuf {
    let dir = tmp(tag);
    std::fs::create_dir_all(&dir).unwrap();
    lampshade::scene::room::write(&dir).unwrap();
    let path = dir.join("room.gltf");
    let mut v: serde_json::Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    for n in v["nodes"].as_array_mut().unwrap() {
        n.as_object_mut().unwrap().remove("extensions");
    }
    v["extensions"].as_object_mut().unwrap().remove("KHR_lights_punctual");
    v["extensionsUsed"].as_array_mut().unwrap().retain(|e| e != "KHR_lights_punctual");
    std::fs::write(&path, serde_json::to_vec(&v).unwrap()).unwrap();
    path
}

fn bench_rows(csv: &std::path::Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(csv).unwrap();
    text.lines().skip(1).map(|l| l.split(',').map(String::from).collect()).collect()
}

#[test]
fn bench_takes_a_gltf_file_and_a_light_count_for_it() {
    let room = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/room/room.gltf");
    let quick = ["--quick", "--frames", "1", "--size", "64x36"];
    // The room brings 11 lights: they are kept, and the light count is not varied.
    let out_dir = tmp("bench-room");
    let out = lampshade(
        &[&["bench", room, "--out", out_dir.to_str().unwrap(), "--only", "culling,lights"][..], &quick].concat(),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("brings its own 11 light(s)"), "{err}");
    let rows = bench_rows(&out_dir.join("bench.csv"));
    let modes = lampshade::renderer::CullingMode::ALL.len();
    assert_eq!(
        rows.len(),
        modes + 2,
        "a row per culling mode, the limit and the calibration, no `lights` rows: {rows:?}"
    );
    assert!(rows.iter().all(|r| r[2] == room), "{rows:?}");
    assert_eq!(rows.iter().filter(|r| r[1] == "limit").count(), 1, "{rows:?}");
    // Every culling row in the units that survive a change of hardware, against the one
    // calibration pass (one light over every pixel), which is one full-screen pass of itself.
    let header = std::fs::read_to_string(out_dir.join("bench.csv")).unwrap();
    let col = |name: &str| header.lines().next().unwrap().split(',').position(|c| c == name).unwrap();
    let (rho, per_pair) = (col("rho_fs"), col("ns_per_pair"));
    let calibration: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] == "calibration").collect();
    assert_eq!(calibration.len(), 1, "{rows:?}");
    assert_eq!(calibration[0][rho], "1.000", "{:?}", calibration[0]);
    for r in rows.iter().filter(|r| r[0] == "culling" && r[1] != "limit") {
        let (rho, ns) = (r[rho].parse::<f64>().unwrap(), r[per_pair].parse::<f64>().unwrap());
        assert!(rho.is_finite() && rho > 0.0 && ns.is_finite() && ns > 0.0, "{r:?}");
    }
    // A file without lights takes --lights N: N lights, and the `lights` group varies it.
    let path = lightless_room("lightless-bench");
    let out_dir = tmp("bench-lightless");
    let out = lampshade(
        &[
            &[
                "bench",
                path.to_str().unwrap(),
                "--lights",
                "8",
                "--out",
                out_dir.to_str().unwrap(),
                "--only",
                "culling,lights",
            ][..],
            &quick,
        ]
        .concat(),
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rows = bench_rows(&out_dir.join("bench.csv"));
    let header = std::fs::read_to_string(out_dir.join("bench.csv")).unwrap();
    let lights_col = header.lines().next().unwrap().split(',').position(|c| c == "lights").unwrap();
    let culling: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] == "culling" && r[1] != "limit").collect();
    assert_eq!(culling.len(), modes);
    assert!(culling.iter().all(|r| r[lights_col] == "8"), "{culling:?}");
    let counts: Vec<&str> = rows.iter().filter(|r| r[0] == "lights").map(|r| r[lights_col].as_str()).collect();
    assert!(counts.contains(&"16") && counts.contains(&"64"), "{counts:?}");
}

/// `bench --only gbuffer`: the G-buffer span split into its cases, each timed (lavapipe has
/// timestamps) but the untimed frame's, which has the wall clock alone.
#[test]
fn bench_splits_the_gbuffer_span_into_clears_a_triangle_the_scene_and_a_bare_pass() {
    let out_dir = tmp("bench-gbuffer-split");
    let args = ["bench", "demo", "--only", "gbuffer", "--quick", "--size", "64x36", "--out", out_dir.to_str().unwrap()];
    let out = lampshade(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let md = std::fs::read_to_string(out_dir.join("bench.md")).unwrap();
    let section = md.split("## The G-buffer span, split").nth(1).expect("the split's section");
    let row = |label: &str| -> Vec<String> {
        let line = section
            .lines()
            .find(|l| l.starts_with(&format!("| {label} |")))
            .unwrap_or_else(|| panic!("{label}: {section}"));
        line.split('|').map(|c| c.trim().to_string()).filter(|c| !c.is_empty()).collect()
    };
    // A measured figure: "ms ± se" with both finite and the span positive.
    let measured = |cell: &str| {
        let (v, se) = cell.split_once(" ± ").unwrap_or_else(|| panic!("{cell}"));
        let (v, se): (f64, f64) = (v.parse().unwrap(), se.parse().unwrap());
        assert!(v > 0.0 && v.is_finite() && se >= 0.0 && se.is_finite(), "{cell}");
    };
    for label in [
        "empty scene (G-buffer: the clears alone)",
        "one triangle",
        "the scene",
        "bare wgpu pass, the same targets cleared",
    ] {
        let r = row(label);
        measured(&r[1]);
        measured(&r[3]);
    }
    let untimed = row("the scene, no timestamps");
    assert_eq!((untimed[1].as_str(), untimed[2].as_str()), ("-", "-"), "{untimed:?}");
    measured(&untimed[3]);
}

#[test]
fn a_light_count_a_scene_does_not_take_is_a_warning() {
    let png = tmp("unused-lights.png");
    let p = png.to_str().unwrap();
    let room = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/room/room.gltf");
    for (scene, expect) in [(room, "the file has 11 light(s) of its own"), ("spot", "has a fixed set of lights")] {
        let out = lampshade(&["render", scene, "--size", "32x18", "--lights", "5", "--out", p]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{err}");
        assert!(err.contains("--lights 5 is not used") && err.contains(expect), "{scene}: {err}");
    }
    // Taken: no warning.
    let out = lampshade(&[
        "render",
        lightless_room("lightless-render").to_str().unwrap(),
        "--size",
        "32x18",
        "--lights",
        "5",
        "--out",
        p,
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && !err.contains("not used"), "{err}");
    assert!(String::from_utf8_lossy(&out.stdout).contains(": 5 lights"), "{}", String::from_utf8_lossy(&out.stdout));
}

#[test]
fn the_forward_pass_has_its_own_stats() {
    let (png, json) = (tmp("glass.png"), tmp("glass.json"));
    let args = ["render", "glass", "--size", "160x90", "--lights", "64", "--forward-lights", "object", "--out"];
    let out = lampshade(&[&args[..], &[png.to_str().unwrap(), "--stats", json.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert!(v["gpu_ms"]["forward"].as_f64().is_some(), "gpu_ms: {}", v["gpu_ms"]);
    let f = &v["forward"];
    assert_eq!(f["lights"], "object");
    assert_eq!(f["objects"], 17);
    assert!(f["fragments"].as_u64().is_some_and(|n| n > 0), "forward: {f}");
    assert_eq!(f["tiles"], 0);
}

#[test]
fn bad_input_is_a_clear_error() {
    let png = tmp("x.png");
    let p = png.to_str().unwrap();
    let bad_settings = tmp("bad.json");
    std::fs::write(&bad_settings, "{\"culling\": \"sideways\"}").unwrap();
    let bad_gltf = tmp("bad.glb");
    std::fs::write(&bad_gltf, b"glTF\x02\x00\x00\x00\xff\xff").unwrap();
    let restir_dir = tmp("restir-out");
    let restir_out = restir_dir.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["render", "nowhere", "--out", p], "unknown scene"),
        (vec!["render", "spot", "--out", p, "--size", "0x10"], "size"),
        (vec!["render", "spot", "--out", p, "--size", "big"], "WxH"),
        (vec!["render", "spot", "--out", p, "--culling", "magic"], "magic"),
        (vec!["render", "spot", "--out", p, "--light", "7"], "has 1 lights"),
        (
            vec![
                "render",
                concat!(env!("CARGO_MANIFEST_DIR"), "/assets/room/room.gltf"),
                "--out",
                p,
                "--lights",
                "100000000000",
            ],
            "more than the 1000000",
        ),
        (vec!["render", "spot", "--out", p, "--settings", "/no/such/file.json"], "reading settings"),
        (vec!["render", "spot", "--out", p, "--settings", bad_settings.to_str().unwrap()], "sideways"),
        (vec!["render", "spot", "--size", "8x8", "--out", "/no/such/dir/x.png"], "writing"),
        (vec!["render", "spot", "--size", "8x8", "--out", p, "--probe", "5"], "not X,Y"),
        (vec!["render", "spot", "--size", "8x8", "--out", p, "--probe", "8,2"], "outside the 8x8 frame"),
        (vec!["render", "spot", "--size", "8x8", "--out", p, "--probe", "2,2", "--path", "forward"], "deferred path"),
        (vec!["bench", "--out", p, "--only", "nothing"], "groups are"),
        (vec!["bench", "nowhere", "--out", p], "unknown scene"),
        (vec!["render", "spot", "--out", p, "--cap-order", "loudest"], "unknown cap order"),
        (
            vec!["render", "spot", "--out", p, "--culling", "clustered", "--cluster-tile", "1"],
            "use a larger --cluster-tile",
        ),
        (vec!["render", "spot", "--out", p, "--max-lights=-3"], "not a whole number"),
        (vec!["render", "spot", "--out", p, "--culling", "tiled", "--ris-spatial", "4"], "work on RIS's samples"),
        (
            vec!["render", "spot", "--out", p, "--culling", "tiled", "--ris-samples", "8", "--ris-denoise", "on"],
            "at most 4 samples",
        ),
        (
            vec!["render", "spot", "--out", p, "--culling", "volume", "--ris-samples", "1"],
            "draws its samples from the light lists",
        ),
        (vec!["bench", "--out", restir_out, "--only", "restir", "--restir-json", "/no/such/restir.json"], "reading"),
        (vec!["bench", "--out", p, "--only", "restir,culling"], "replays run alone"),
        (vec!["advise", "demo", "--lights", "0"], "at least 1"),
        (vec!["advise", "spot", "--lights", "9"], "it can be advised at that many or fewer"),
        (vec!["advise", "demo", "--frames", "0"], "at least 1"),
        (vec!["advise", "nowhere"], "unknown scene"),
        (vec!["advise", CAMERAS, "--viewpoint", "7"], "offers 2 viewpoint"),
        (vec!["view", "--no-state", "--exposure=0"], "exposure 0 must be"),
        (vec!["render", "/no/such/model.gltf", "--out", p], "/no/such/model.gltf: cannot open"),
        (vec!["render", bad_gltf.to_str().unwrap(), "--out", p], "not a valid glTF"),
        (
            vec![
                "render",
                concat!(env!("CARGO_MANIFEST_DIR"), "/assets/room/room.gltf"),
                "--out",
                p,
                "--viewpoint",
                "9",
            ],
            "offers 2 viewpoint",
        ),
    ];
    for (args, expect) in cases {
        let out = lampshade(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(err.contains(expect), "{args:?}: stderr does not mention '{expect}': {err}");
        assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    }
}

/// `--backend`, `--adapter` and `--restrict` pick the adapter on every command, the stats name
/// it with its capability table, `adapters` lists both backends of Mesa's driver with what each
/// gives, and an adapter or a choice that cannot be had is a clear error, never a panic.
#[test]
fn every_command_takes_an_adapter_and_says_what_it_cannot_do() {
    let png = tmp("gl.png");
    let json = tmp("gl.json");
    let bench_dir = tmp("bench-on-dx12");
    let (p, j, b) = (png.to_str().unwrap(), json.to_str().unwrap(), bench_dir.to_str().unwrap());
    let size = ["--size", "96x54", "--lights", "16"];
    let out = lampshade(&[&["render", "demo", "--backend", "gl", "--out", p, "--stats", j][..], &size].concat());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "GL render: {err}");
    assert!(!err.contains("Cube` rather than `CubeArray"), "GL's cube guess: {err}");
    assert!(!err.contains("Features {"), "a feature printed as a debug struct: {err}");
    assert_eq!(err.matches("lacks: PIPELINE_STATISTICS_QUERY").count(), 1, "{err}");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let a = &v["adapter"];
    assert_eq!(a["backend"], "gl");
    assert!(a["name"].as_str().is_some_and(|n| !n.is_empty()), "{a}");
    assert_eq!(a["capabilities"]["R32Float render targets"], false);
    assert!(a["fallbacks"].as_array().unwrap().iter().any(|f| f.as_str().unwrap().contains("R32Uint")), "{a}");
    assert!(v["shaded_fragments"].is_null(), "GL's binary occlusion counted fragments");

    let out = lampshade(&["adapters"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("(vulkan, ") && text.contains("(gl, "), "{text}");
    assert!(text.contains("not reference: layout reference"), "{text}");
    let out = lampshade(&["adapters", "--json", "--backend", "vulkan"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("adapters --json");
    assert_eq!(v.as_array().map(|a| a.len()), Some(1));
    assert_eq!(v[0]["table"]["capabilities"]["R32Float render targets"], true);
    // `--adapter` picks one of `adapters`' list by its index there, on any backend.
    let gl_index = text.lines().find(|l| l.contains("(gl, ")).and_then(|l| l.split(':').next()).expect("GL's line");
    let out = lampshade(&["adapters", "--adapter", gl_index]);
    let one = String::from_utf8_lossy(&out.stdout);
    assert!(one.contains("(gl, ") && !one.contains("(vulkan, "), "{one}");
    let out = lampshade(&[&["render", "demo", "--adapter", gl_index, "--out", p, "--stats", j][..], &size].concat());
    assert!(out.status.success(), "--adapter {gl_index}: {}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["adapter"]["backend"], "gl");

    for (args, expect) in [
        (vec!["render", "demo", "--out", p, "--adapter", "99"], "no adapter '99'; the adapters found are: 0: "),
        (vec!["render", "demo", "--out", p, "--adapter", "no-such-gpu"], "no adapter 'no-such-gpu'"),
        (vec!["render", "demo", "--out", p, "--backend", "metal"], "no graphics adapter found on the Metal backend"),
        (
            vec!["render", "demo", "--out", p, "--backend", "gl", "--layout", "reference"],
            "needs Rgba32Float render targets",
        ),
        (vec!["render", "demo", "--out", p, "--restrict", "gl", "--accumulation", "rgba32-float"], "Gl profile lacks"),
        (vec!["bench", "--out", b, "--backend", "dx12"], "no graphics adapter found on the Dx12 backend"),
        (vec!["bench", "--out", b, "--backend", "gl", "--quick"], "error reference cannot be rendered here"),
        (vec!["view", "--no-state", "--backend", "warp"], "invalid value 'warp'"),
    ] {
        let out = lampshade(&[&args[..], &size].concat());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(err.contains(expect), "{args:?}: stderr does not mention '{expect}': {err}");
        assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    }
}

/// A file of three spheres in three reflectance models (`blinn-phong`, `metal`, and `unlit`
/// through KHR_materials_unlit), generated from `room::stress`, with no lights of its own.
fn three_model_spheres(tag: &str) -> std::path::PathBuf {
    let dir = tmp(tag);
    std::fs::create_dir_all(&dir).unwrap();
    for (name, bytes) in lampshade::scene::room::stress(3).unwrap() {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    let path = dir.join("stress.gltf");
    let mut v: serde_json::Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    let materials = v["materials"].as_array_mut().unwrap();
    materials[1]["pbrMetallicRoughness"]["metallicFactor"] = 1.0.into();
    materials[2]["extensions"] = serde_json::json!({ "KHR_materials_unlit": {} });
    let used = v.as_object_mut().unwrap().entry("extensionsUsed").or_insert(serde_json::json!([]));
    used.as_array_mut().unwrap().push("KHR_materials_unlit".into());
    std::fs::write(&path, serde_json::to_vec(&v).unwrap()).unwrap();
    path
}

/// Every bench group runs on a file whose materials need a material-ID channel: the layouts
/// without a spare channel are skipped, named with their reason on the console and in the
/// report, and every other configuration still gives its row. At 64x36 and one timed frame:
/// the size only has to hold a frame of each configuration (the `resolution` group brings its
/// own sizes). `fixed`: the file brings its own lights, so the `lights` group has no rows.
fn bench_runs_every_group(file: &str, extra: &[&str], fixed: bool) {
    let dir = tmp(&format!("bench-all-{}", if fixed { "room" } else { "spheres" }));
    let out = lampshade(
        &[&["bench", file, "--quick", "--frames", "1", "--size", "64x36", "--out", dir.to_str().unwrap()][..], extra]
            .concat(),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{file}: {err}");
    // The quick sweep's layouts: oct8 has no channel to spare, seed000 and xyz8 have one.
    let line = err.lines().find(|l| l.starts_with("skipped layout `oct8`"));
    assert!(
        line.is_some_and(|l| l.contains("no spare channel for the material ID")),
        "{file}: oct8 not reported as skipped with its reason:\n{err}"
    );
    let md = std::fs::read_to_string(dir.join("bench.md")).unwrap();
    let skipped = md.split("### Skipped").nth(1).unwrap_or_else(|| panic!("{file}: no Skipped section:\n{md}"));
    assert!(skipped.contains("| layout | oct8 |") && skipped.contains("material ID"), "{file}: {skipped}");
    // The ledger group: a row per mode it checks, each with its fit or the reason it has none.
    let ledger = md.split("## The light ledger").nth(1).unwrap_or_else(|| panic!("{file}: no ledger section:\n{md}"));
    for mode in lampshade::bench::ledger_modes() {
        assert!(
            ledger.contains(&format!("\n| {} |", mode.name())),
            "{file}: no ledger row for {}:\n{ledger}",
            mode.name()
        );
    }
    // The engines group: a row per engine's preset, each with its source.
    let engines = md
        .split("### The shortcuts engines ship")
        .nth(1)
        .unwrap_or_else(|| panic!("{file}: no engines section:\n{md}"));
    for e in lampshade::renderer::caps::ENGINES {
        let row = engines.lines().find(|l| l.starts_with(&format!("| {} |", e.name)));
        assert!(
            row.is_some_and(|l| l.ends_with(&format!("| {} |", e.source))),
            "{file}: no row for {}:\n{engines}",
            e.name
        );
    }
    let rows = bench_rows(&dir.join("bench.csv"));
    for group in lampshade::bench::GROUPS {
        // The stochastic group's own sweep runs only when named.
        let expected = !(fixed && *group == "lights") && *group != lampshade::bench::STOCHASTIC_GROUP;
        let n = rows.iter().filter(|r| r[0] == *group).count();
        assert_eq!(n > 0, expected, "{file}: {n} rows in group {group}");
    }
    for layout in ["seed000", "xyz8"] {
        assert!(rows.iter().any(|r| r[0] == "layout" && r[1] == layout), "{file}: no {layout} row");
    }
    assert!(!rows.iter().any(|r| r[0] == "layout" && r[1] == "oct8"), "{file}: a row for the skipped oct8");
}

/// The room: blinn-phong and metal, its own 11 lights.
#[test]
fn bench_runs_every_group_on_the_room_and_skips_what_it_cannot_take() {
    bench_runs_every_group(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/room/room.gltf"), &[], true);
}

/// Generated spheres in three models, lit by the 8 lights the bench adds.
#[test]
fn bench_runs_every_group_on_a_three_model_file_and_skips_what_it_cannot_take() {
    let spheres = three_model_spheres("bench-three-models");
    bench_runs_every_group(spheres.to_str().unwrap(), &["--lights", "8"], false);
}

/// `lampshade check` on the project's room and on a third-party file: every mode on both
/// G-buffer paths and the forward paths' lists at the file's cameras and generated ones, none missing or adding light, the
/// report in check.json (a frame per camera, path and mode); bad arguments are clear errors.
#[test]
fn check_holds_every_mode_against_brute_force_on_a_users_file() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let engine = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
    let room = root.join("assets/room/room.gltf");
    for (file, cameras) in [(room.to_str().unwrap(), "3"), (engine, "2")] {
        let dir = tmp(&format!("check-{cameras}"));
        let out = lampshade(&["check", file, "--cameras", cameras, "--size", "96x54", "--out", dir.to_str().unwrap()]);
        let said = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        assert!(out.status.success(), "{file}: {said}");
        assert!(said.contains("0 miss or add light, 0 refused"), "{file}: {said}");
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("check.json")).expect("check.json")).expect("json");
        let frames = json["frames"].as_array().expect("frames");
        let viewpoints =
            frames.iter().filter(|f| f["camera"].as_str().is_some_and(|c| c.starts_with("viewpoint"))).count() / 16;
        assert_eq!(frames.len(), (1 + viewpoints + cameras.parse::<usize>().unwrap()) * 20, "{file}");
        assert!(frames.iter().all(|f| f["result"]["missed"] == 0 && f["result"]["extra"] == 0), "{file}");
    }
    for (args, says) in [
        (vec!["check", "demo", "--size", "0x9"], "must be between"),
        (vec!["check", "demo", "--viewpoint", "3"], "offers 0 viewpoint"),
        (vec!["check", "no-such-scene"], "no-such-scene"),
    ] {
        let out = lampshade(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(says), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

#[test]
fn advise_takes_a_viewpoint_and_advises_for_its_camera() {
    // `advise --viewpoint K` on a file with a camera of its own: the advice names the viewpoint,
    // and its calibration frames are drawn from that camera. The pairs each light adds to a
    // frame depend only on what the camera sees, so the file's camera (viewpoint 0) and the
    // framing view (1) give other pairs per light.
    let pairs = |k: &str| {
        let dir = tmp(&format!("advise-viewpoint-{k}"));
        let d = dir.to_str().unwrap();
        let out = lampshade(&["advise", CAMERAS, "--viewpoint", k, "--size", "160x90", "--frames", "1", "--out", d]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("advise.json")).unwrap()).unwrap();
        let scene = json["scene"].as_str().unwrap_or_default().to_string();
        assert!(scene.contains(&format!("viewpoint {k}")), "the advice does not name its viewpoint: {scene}");
        let fits = json["fits"].as_array().expect("the fits").clone();
        fits.iter().map(|f| f["pairs"].to_string()).collect::<Vec<_>>()
    };
    let (file_camera, framing) = (pairs("0"), pairs("1"));
    assert!(!file_camera.is_empty());
    assert_ne!(file_camera, framing, "the two viewpoints' frames add the same pairs: the camera was not used");
}

/// `lampshade compare`: both pictures, the FLIP map, the difference and the tables, as files;
/// B against A in the JSON. Two files that set the scene differently, or a missing file, are
/// errors that say so.
#[test]
fn compare_writes_both_pictures_the_maps_and_the_tables_and_refuses_two_scenes() {
    let (a, b, out) = (tmp("cmp-a.json"), tmp("cmp-b.json"), tmp("cmp-out"));
    std::fs::write(&a, r#"{"culling": "tiled", "shadows": "none", "size": [96, 54]}"#).unwrap();
    std::fs::write(&b, r#"{"culling": "clustered", "shadows": "none"}"#).unwrap();
    let run = |b: &std::path::Path| {
        lampshade(&[
            "compare",
            "demo",
            a.to_str().unwrap(),
            b.to_str().unwrap(),
            "--lights",
            "64",
            "--frames",
            "1",
            "--out",
            out.to_str().unwrap(),
        ])
    };
    let o = run(&b);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in ["a.png", "b.png", "flip.png", "difference.png"] {
        let img = image::open(out.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
        assert_eq!((img.width(), img.height()), (96, 54), "{f}: the files' size");
    }
    let md = std::fs::read_to_string(out.join("compare.md")).unwrap();
    assert!(md.contains("| lighting |") && md.contains("| FLIP mean |"), "{md}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("compare.json")).unwrap()).unwrap();
    assert_eq!(json["a"]["settings"]["culling"], "tiled");
    assert_eq!(json["b"]["settings"]["culling"], "clustered");
    assert!(json["max_steps"].as_u64().is_some_and(|s| s <= 1), "{}", json["max_steps"]);

    std::fs::write(&b, r#"{"culling": "clustered", "size": [64, 64]}"#).unwrap();
    let o = run(&b);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("both set \"size\"") && !err.contains("panicked"), "{err}");
    let o = run(&tmp("no-such-file.json"));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.code() == Some(1) && err.contains("no-such-file.json") && !err.contains("panicked"), "{err}");
}

/// `bench --camera-path`: three modes replayed along the demo's path (a 0.12 s step: 101
/// frames), each row with its p50, p95 and p99, the worst frame, the flicker and the fastest
/// exact mode's beside it; a path too short for 100 frames is an error that says how to fix it.
#[test]
fn bench_replays_a_camera_path_and_reports_percentiles_and_flicker() {
    let out = tmp("path-bench");
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/paths/demo.json");
    let args = |step: &str| {
        vec![
            "bench".to_string(),
            "demo".into(),
            "--lights".into(),
            "64".into(),
            "--size".into(),
            "64x36".into(),
            "--camera-path".into(),
            path.to_str().unwrap().into(),
            "--path-step".into(),
            step.into(),
            "--modes".into(),
            "tiled,clustered,zbin".into(),
            "--out".into(),
            out.to_str().unwrap().into(),
        ]
    };
    let a = args("0.12");
    let o = lampshade(&a.iter().map(|s| s.as_str()).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("path.json")).unwrap()).unwrap();
    let rows = rows.as_array().expect("rows");
    assert_eq!(rows.len(), 3);
    for r in rows {
        let v = |k: &str| r[k].as_f64().unwrap_or_else(|| panic!("{k}: {r}"));
        assert_eq!(r["frames"], 101, "{r}");
        assert!(
            v("p50_ms") > 0.0
                && v("p50_ms") <= v("p95_ms")
                && v("p95_ms") <= v("p99_ms")
                && v("p99_ms") <= v("worst_ms"),
            "{r}"
        );
        assert!(v("flicker") > 0.0 && v("exact_flicker") > 0.0, "the camera moves, so adjacent frames differ: {r}");
        assert!(r["worst_frame"].as_u64().is_some_and(|f| f < 101), "{r}");
    }
    let md = std::fs::read_to_string(out.join("path.md")).unwrap();
    assert!(md.contains("| tiled |") && md.contains("| zbin |") && md.contains("flicker"), "{md}");
    let a = args("1");
    let o = lampshade(&a.iter().map(|s| s.as_str()).collect::<Vec<_>>());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.code() == Some(1) && err.contains("at least 100") && !err.contains("panicked"), "{err}");
}
