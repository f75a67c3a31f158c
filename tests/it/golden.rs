//! Byte-for-byte pictures across a change that must not change them (moving code, renaming,
//! splitting a shader): every value of every choice knob and switch on `demo`, every path with
//! every culling mode and debug view, the shadow filters and cube kinds, the post effects, the
//! hard cases, each frame's picture and linear accumulation; a refusal is recorded as its
//! message. The first run records into the folder `LAMPSHADE_GOLDEN` names; later runs compare
//! with it, strictly (the same machine and driver), and write `NAME-actual.png` beside a
//! picture that differs.
//!
//! `LAMPSHADE_GOLDEN=/tmp/golden cargo test --test it -- --ignored golden::` before the change,
//! then again after it.

use crate::common::{gpu, scene};
use lampshade::headless::render_image;
use lampshade::renderer::knobs::{Values, KNOBS};
use lampshade::renderer::{Renderer, Settings, OUTPUT_FORMAT};
use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::path::Path;

const W: u32 = 96;
const H: u32 = 54;

/// Scene and knob settings (applied in order over the defaults) of every frame compared.
fn cases() -> Vec<(String, Vec<(String, String)>)> {
    let mut out = Vec::new();
    let mut add = |scene: &str, knobs: &[(&str, &str)]| {
        out.push((scene.to_string(), knobs.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect()));
    };
    // Every value of every choice knob and switch, alone, on the demo.
    for k in KNOBS.iter() {
        if matches!(k.values, Values::Choice(_) | Values::Switch | Values::File) {
            for v in k.names() {
                add("demo", &[(k.name, &v)]);
            }
        }
    }
    let paths = ["deferred", "light-prepass", "forward", "forward-multipass"];
    let culling =
        ["fullscreen", "volume", "stencil-two-pass", "stencil-invert", "stencil-replace", "tiled", "clustered", "auto"];
    for path in paths {
        for c in culling {
            add("demo", &[("path", path), ("culling", c)]);
            add("street", &[("shadows", "none"), ("path", path), ("culling", c)]);
        }
        for scene in ["spot", "classify", "materials", "cookies", "glass", "shadows"] {
            add(scene, &[("path", path)]);
        }
        for filter in ["pcf2x2", "pcf3x3", "poisson16"] {
            for cube in ["unrolled", "indirect", "array"] {
                add("shadows", &[("shadows", "all"), ("shadow-filter", filter), ("shadow-cube", cube), ("path", path)]);
            }
        }
        let views = lampshade::renderer::knobs::find("debug-view").map(|k| k.names()).unwrap_or_default();
        for v in &views {
            add("demo", &[("path", path), ("debug-view", v)]);
        }
    }
    for view in ["shadow", "cascades"] {
        add("shadows", &[("shadows", "all"), ("shadow-cascades", "3"), ("debug-view", view)]);
    }
    for layout in ["compact", "seed000", "packed", "reference", "fit", "oct8", "oct16", "xyz8", "xyz16f"] {
        add("normals", &[("shadows", "none"), ("layout", layout)]);
        add("demo", &[("layout", layout), ("culling", "stencil-replace")]);
    }
    // The post effects, one by one and together, with their numbers away from the defaults.
    add("demo", &[("vignette", "0.5")]);
    add("demo", &[("fog", "on"), ("fog-density", "0.05"), ("fog-height-falloff", "0.2")]);
    add("demo", &[("dof", "on"), ("focus-distance", "8"), ("aperture", "6")]);
    add("demo", &[("bloom", "on"), ("bloom-threshold", "0.5"), ("bloom-intensity", "2")]);
    add("demo", &[("auto-exposure", "on"), ("target-luminance", "0.3")]);
    let all_post = [
        ("bloom", "on"),
        ("auto-exposure", "on"),
        ("lut", "identity"),
        ("fog", "on"),
        ("dof", "on"),
        ("vignette", "0.3"),
        ("aa", "fxaa"),
        ("tonemap", "agx"),
    ];
    for path in paths {
        let mut knobs = all_post.to_vec();
        knobs.push(("path", path));
        add("demo", &knobs);
    }
    for case in crate::common::HARD_CASES {
        for c in culling {
            add(case, &[("shadows", "none"), ("culling", c)]);
        }
    }
    out
}

fn name_of(scene: &str, knobs: &[(String, String)]) -> String {
    let mut name = scene.to_string();
    for (k, v) in knobs {
        name.push_str(&format!("_{k}-{v}"));
    }
    name.replace(['/', '.', ' '], "_")
}

/// The frame's picture and a hash of its accumulation's bits, or the refusal's message.
fn render(scene_name: &str, knobs: &[(String, String)]) -> Result<(image::RgbaImage, u64), String> {
    let mut settings = Settings::default();
    for (k, v) in knobs {
        settings.set(k, v)?;
    }
    let scene = scene(scene_name);
    let gpu = gpu();
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &settings).map_err(|e| format!("{e:#}"))?;
    let (image, _) = render_image(gpu, &mut r, &scene, &settings, W, H).map_err(|e| format!("{e:#}"))?;
    let (diffuse, specular) = r.last_frame().read_accumulation(gpu).map_err(|e| format!("{e:#}"))?;
    let mut h = DefaultHasher::new();
    for v in diffuse.iter().chain(&specular) {
        v.to_bits().hash(&mut h);
    }
    Ok((image, h.finish()))
}

#[test]
#[ignore = "records or compares pictures in the folder LAMPSHADE_GOLDEN names"]
fn every_picture_matches_the_recorded_one() {
    let Some(dir) = std::env::var_os("LAMPSHADE_GOLDEN") else {
        panic!("set LAMPSHADE_GOLDEN to the folder of recorded pictures (empty: record them)");
    };
    let dir = Path::new(&dir);
    std::fs::create_dir_all(dir).expect("the golden folder");
    let (mut recorded, mut same, mut differ) = (0, 0, Vec::new());
    for (scene_name, knobs) in cases() {
        let name = name_of(&scene_name, &knobs);
        let (png, txt) = (dir.join(format!("{name}.png")), dir.join(format!("{name}.txt")));
        let got = render(&scene_name, &knobs);
        let text = match &got {
            Ok((_, hash)) => format!("accumulation {hash:016x}"),
            Err(e) => format!("error: {e}"),
        };
        if !txt.exists() {
            std::fs::write(&txt, &text).expect("write the record");
            if let Ok((image, _)) = &got {
                image.save(&png).expect("write the picture");
            }
            recorded += 1;
            continue;
        }
        let want = std::fs::read_to_string(&txt).expect("read the record");
        let mut why = Vec::new();
        if want != text {
            why.push(format!("{want} -> {text}"));
        }
        if let Ok((image, _)) = &got {
            match image::open(&png) {
                Ok(old) if old.to_rgba8().as_raw() == image.as_raw() => {}
                Ok(_) => {
                    why.push("the picture differs".into());
                    let _ = image.save(dir.join(format!("{name}-actual.png")));
                }
                Err(e) => why.push(format!("no recorded picture: {e}")),
            }
        }
        if why.is_empty() {
            same += 1;
        } else {
            differ.push(format!("{name}: {}", why.join("; ")));
        }
    }
    eprintln!("golden: {recorded} recorded, {same} the same, {} differ", differ.len());
    assert!(differ.is_empty(), "{} frames changed:\n{}", differ.len(), differ.join("\n"));
}
