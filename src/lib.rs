//! Lampshade's deferred core: a headless renderer for deferred shading with light-volume
//! culling. No window, no UI: the viewer (`app`, feature `viewer`) sits on top.

pub mod bench;
pub mod calibration;
pub mod cli;
pub mod compare;
pub mod gpu;
pub mod headless;
pub mod memory;
pub mod oracle;
pub mod pipeline_cache;
pub mod plot_layout;
pub mod reference;
pub mod renderer;
pub mod scene;
pub mod settings_file;

#[cfg(feature = "viewer")]
pub mod app;

pub use gpu::Gpu;
pub use renderer::{CullingMode, DebugView, FrameStats, LayoutChoice, Renderer, Settings};
pub use scene::Scene;
