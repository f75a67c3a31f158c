//! The command line: `render` writes a lit PNG and a stats JSON with every key filled; bad
//! arguments and files are clear errors with a non-zero exit, never a panic.

use std::process::Command;

fn lampshade(args: &[&str]) -> std::process::Output {
    let dir = std::env::temp_dir().join("lampshade-cli-xdg");
    let _ = std::fs::create_dir_all(&dir);
    Command::new(env!("CARGO_BIN_EXE_lampshade")).args(args).env("XDG_RUNTIME_DIR", &dir).output().expect("spawn")
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("lampshade-cli-{}", std::process::id()));
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
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
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
    assert!(v["adapter"]["name"].as_str().is_some_and(|s| !s.is_empty()));
    for pass in ["gbuffer", "lighting", "compose", "total"] {
        // Null only where the adapter lacks timestamps; lavapipe has them.
        assert!(v["gpu_ms"].get(pass).is_some(), "gpu_ms lacks {pass}");
    }
    assert!(v["shaded_fragments"].as_u64().unwrap() >= v["ideal_fragments"].as_u64().unwrap());
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
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["render", "nowhere", "--out", p], "unknown scene"),
        (vec!["render", "spot", "--out", p, "--size", "0x10"], "size"),
        (vec!["render", "spot", "--out", p, "--size", "big"], "WxH"),
        (vec!["render", "spot", "--out", p, "--culling", "magic"], "magic"),
        (vec!["render", "spot", "--out", p, "--light", "7"], "has 1 lights"),
        (vec!["render", "spot", "--out", p, "--settings", "/no/such/file.json"], "reading settings"),
        (vec!["render", "spot", "--out", p, "--settings", bad_settings.to_str().unwrap()], "sideways"),
        (vec!["render", "spot", "--size", "8x8", "--out", "/no/such/dir/x.png"], "writing"),
        (vec!["bench", "--out", p, "--only", "nothing"], "groups are"),
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
