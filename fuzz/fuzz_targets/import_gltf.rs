//! Fuzzes the glTF importer (`.gltf` JSON and `.glb` binary) from memory.
//!
//! `base: None`, so no filesystem access: only embedded data (data URIs, a .glb's binary chunk)
//! can be read. Any error is fine; a panic, a hang or an unbounded allocation is a bug.
#![no_main]

use lampshade::scene::import::{load_bytes, ImportOptions, Progress};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let options = ImportOptions { light_grid: 2, max_texture_size: 256 };
    let mut progress = |_: Progress<'_>| {};
    let _ = load_bytes(data, None, "fuzz", &options, &mut progress);
});
