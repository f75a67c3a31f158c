//! Fuzzes the glTF importer (`.gltf` JSON and `.glb` binary) from memory.
//!
//! `base: None`, so no filesystem access: only embedded data (data URIs, a .glb's binary chunk)
//! can be read. Any error is fine; a panic, a hang or an unbounded allocation is a bug.
//!
//! `LAMPSHADE_FUZZ_SKIP=glb-length,position-index` (comma-separated) skips inputs that hit a
//! known, already-reported bug, so a run can get past it (libFuzzer stops at the first crash).
//! See README.md; drop a name once the importer guards against it.
#![no_main]

use lampshade::scene::import::{load_bytes, ImportOptions, Progress};
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

fn skip_list() -> &'static [String] {
    static SKIP: OnceLock<Vec<String>> = OnceLock::new();
    SKIP.get_or_init(|| {
        std::env::var("LAMPSHADE_FUZZ_SKIP")
            .unwrap_or_default()
            .split(',')
            .map(|s| s.trim().to_string())
            .filter(|s| !s.is_empty())
            .collect()
    })
}

/// Whether `data` triggers a known bug that the skip list names.
fn known_bug(data: &[u8]) -> bool {
    let skip = skip_list();
    let on = |name: &str| skip.iter().any(|s| s == name);
    // gltf 1.4.1 binary.rs:252: `header.length as usize - 12` overflows (panics with overflow
    // checks, as in dev/test builds) when a GLB header declares a total length below 12.
    let glb_length_bug =
        data.len() >= 12 && &data[..4] == b"glTF" && u32::from_le_bytes([data[8], data[9], data[10], data[11]]) < 12;
    if glb_length_bug {
        return on("glb-length");
    }
    // gltf-json 1.4.1 mesh.rs:151: validation indexes `root.accessors[POSITION]` unchecked.
    if on("position-index") {
        if let Ok(g) = gltf::Gltf::from_slice_without_validation(data) {
            let root = g.document.as_json();
            let bad = root.meshes.iter().flat_map(|m| &m.primitives).any(|p| {
                p.attributes
                    .get(&gltf::json::validation::Checked::Valid(gltf::Semantic::Positions))
                    .is_some_and(|i| i.value() >= root.accessors.len())
            });
            if bad {
                return true;
            }
        }
    }
    false
}

fuzz_target!(|data: &[u8]| {
    if known_bug(data) {
        return;
    }
    // `..Default::default()`: later options (a decode budget, say) take their defaults.
    #[allow(clippy::needless_update)]
    let options = ImportOptions { light_grid: 2, max_texture_size: 256, max_elements: 1 << 20 };
    let mut progress = |_: Progress<'_>| {};
    let _ = load_bytes(data, None, "fuzz", &options, &mut progress);
});
