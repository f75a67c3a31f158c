//! The integration suite, one binary: one process, one GPU device and one set of compiled
//! pipelines for every subject. A module per subject; `docs/testing.md` lists the properties
//! each proves and the test that proves it.
//!
//! - Fast tier while working: `.ci/fast` (the unit tests and a named smoke set).
//! - One subject: `cargo test --test it shadows::`.
//! - Window tests (`viewer`) need an X server: `xvfb-run -a cargo test --test it viewer::`.

mod common;

mod adapters;
mod batching;
mod calibration;
mod camera_paths;
mod caps;
mod cli;
mod compare;
mod cookies_masks;
mod culling;
mod explain;
mod forward;
mod fuzz_regressions;
mod gltf;
mod golden;
mod hard_cases;
mod images;
mod materials;
mod oracle;
mod passes;
mod paths;
mod post;
mod prepass;
mod preset_rows;
pub mod presets;
mod renderer;
mod scale;
mod shader_contract;
mod shadows;
mod soak;
mod stochastic;
mod suite;
mod tidy;
mod tiled;
mod viewer;
