//! The frame log (`--frame-log FILE`, the script's `frame-log PATH`): one JSON line per
//! presented frame, so a stall can be found and named afterwards: its wall time, its GPU time,
//! the configuration it drew, the one building in the background meanwhile, and what the frame
//! waited on on the viewer's thread.

use anyhow::{Context, Result};
use std::io::Write;
use std::path::Path;

/// What a frame waited on, in milliseconds, on the viewer's thread.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct Waits {
    /// Pipelines the frame compiled itself before it recorded (`FrameStats::pipelines`).
    pub compile_ms: f64,
    /// Reading the GPU back: the pixel probe, a screenshot, the explanation.
    pub readback_ms: f64,
    /// Finishing a calibration.
    pub calibration_ms: f64,
    /// Asking whether the configuration's pipelines are compiled (`app::compiling`): its
    /// CPU part of a frame (the records and the culling plan), on the planner.
    pub check_ms: f64,
}

impl Waits {
    /// The longest wait's name, or `nothing` when none took a millisecond.
    pub fn main(&self) -> &'static str {
        let waits = [
            ("compile", self.compile_ms),
            ("read-back", self.readback_ms),
            ("calibration", self.calibration_ms),
            ("check", self.check_ms),
        ];
        match waits.iter().max_by(|a, b| a.1.total_cmp(&b.1)) {
            Some((name, ms)) if *ms >= 1.0 => name,
            _ => "nothing",
        }
    }
}

/// One presented frame.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FrameLine {
    pub frame: u64,
    /// Milliseconds from the viewer's start to this frame's presentation.
    pub at_ms: f64,
    /// Milliseconds since the frame before was presented.
    pub wall_ms: f64,
    /// The viewport frame's GPU time (where timestamps are on and the adapter has them).
    pub gpu_ms: Option<f64>,
    /// Milliseconds the viewport's frame took on the viewer's thread, from its settings to
    /// its submission (its compiles included).
    pub render_ms: f64,
    /// On the first line only: milliseconds from the start to the window, the device and the
    /// renderers made.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub init_ms: Option<f64>,
    /// The configuration the viewport drew this frame (`None`: it drew nothing new).
    pub config: Option<String>,
    /// The configuration building in the background while the viewport draws another.
    pub building: Option<String>,
    /// Whether the viewport shows a stand-in while the first configuration builds (ambient
    /// and sun, no lights).
    pub stand_in: bool,
    /// `compile`, `read-back`, `calibration`, `check` or `nothing`: the longest of `waits`.
    pub waited_on: &'static str,
    pub waits: Waits,
    /// The camera's position (input handled while a configuration builds moves it).
    pub camera: [f64; 3],
    /// The size the viewport's scene was rendered at this frame (the viewport's pixels times
    /// the resolution scale), where it drew.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub size: Option<[u32; 2]>,
    /// The viewport frame's GPU time per pass, where it drew and timestamps are on.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub passes: Option<crate::renderer::GpuMs>,
    /// How the frame's lights were drawn, by method (what `auto` chose), where it drew.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub methods: Option<std::collections::BTreeMap<String, usize>>,
}

/// An open frame log.
pub struct FrameLog {
    file: std::io::BufWriter<std::fs::File>,
}

impl FrameLog {
    pub fn create(path: &Path) -> Result<Self> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        }
        let file = std::fs::File::create(path).with_context(|| format!("creating the frame log {}", path.display()))?;
        Ok(Self { file: std::io::BufWriter::new(file) })
    }

    /// Appends one frame's line (flushed, so a run that ends abruptly keeps its frames).
    pub fn write(&mut self, line: &FrameLine) -> Result<()> {
        serde_json::to_writer(&mut self.file, line)?;
        self.file.write_all(b"\n")?;
        self.file.flush()?;
        Ok(())
    }
}
