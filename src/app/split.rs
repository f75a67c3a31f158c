//! Compare in the viewer: configuration A (the panels' settings) on the left of a draggable
//! divider, configuration B on the right. B is A with a set of knobs changed (`Split::b`: knob
//! name to value, as `set` takes them; a settings file loads as every renderer key it gives), so
//! everything else the panels change reaches both sides. B is drawn by a renderer of its own
//! into an image of the viewport's size, after A, from the same scene and camera.
//!
//! Views: `split` (A left, B right), `difference` (|B − A| per channel times
//! `compare::DIFFERENCE_GAIN`) and `flip` (FLIP's map of B against A). The difference and the
//! map are computed on the CPU from both images read back (`compare::difference_image`,
//! `compare::flip`: what `lampshade compare` writes), only while their view is shown. The
//! compare window lists each side's GPU time per pass (`bench::median_passes` of the last
//! frame) and the lights whose ledger cost changed most (`bench::ledger_delta`).

use super::gfx::Image;
use crate::renderer::{FrameStats, Renderer, Settings, OUTPUT_FORMAT};
use anyhow::Result;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What the viewport shows while comparing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum SplitView {
    #[default]
    Split,
    Difference,
    Flip,
}

crate::renderer::options::knob_names!(SplitView => "compare view");

/// The comparison's state (the UI's part; plain data, saved with a screenshot).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Split {
    pub on: bool,
    pub view: SplitView,
    /// The divider's place across the viewport, 0..1.
    pub divider: f32,
    /// B's knobs: name to value, applied over A's settings each frame.
    pub b: BTreeMap<String, String>,
    /// The knob the compare window's "set" row edits, and the value typed.
    #[serde(skip)]
    pub edit: (String, String),
    /// The settings file path typed into the compare window.
    #[serde(skip)]
    pub file: String,
}

impl Default for Split {
    fn default() -> Self {
        Self {
            on: false,
            view: SplitView::Split,
            divider: 0.5,
            b: BTreeMap::new(),
            edit: ("culling".into(), String::new()),
            file: String::new(),
        }
    }
}

impl Split {
    /// B's settings: `a` with B's knobs set, or why they cannot be.
    pub fn b_settings(&self, a: &Settings) -> Result<Settings, String> {
        let mut b = a.clone();
        for (k, v) in &self.b {
            b.set(k, v).map_err(|e| format!("B's {k} = {v}: {e}"))?;
        }
        Ok(b)
    }

    /// Sets one of B's knobs (checked over `a`).
    pub fn set(&mut self, a: &Settings, name: &str, value: &str) -> Result<(), String> {
        let mut next = self.b.clone();
        next.insert(name.to_string(), value.to_string());
        let trial = Split { b: next.clone(), ..self.clone() };
        trial.b_settings(a)?;
        self.b = next;
        Ok(())
    }

    /// B from a settings file: every renderer key the file gives (its scene keys are not
    /// B's: both sides draw one scene).
    pub fn load(&mut self, a: &Settings, path: &std::path::Path) -> Result<usize, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("reading {}: {e}", path.display()))?;
        let (settings, _) = crate::settings_file::parse(&text).map_err(|e| format!("{}: {e:#}", path.display()))?;
        let given: BTreeMap<String, serde_json::Value> = serde_json::from_str(&text).map_err(|e| e.to_string())?;
        let mut b = BTreeMap::new();
        for name in crate::renderer::knobs::KNOBS.iter().map(|k| k.name) {
            // The knobs whose settings key the file names (or which its preset set).
            let v = settings.get(name)?;
            if given.contains_key(name) || v != Settings::default().get(name)? {
                b.insert(name.to_string(), v);
            }
        }
        let trial = Split { b: b.clone(), ..self.clone() };
        trial.b_settings(a)?;
        let n = b.len();
        self.b = b;
        Ok(n)
    }
}

/// The figures of the last comparison drawn, for the compare window.
#[derive(Clone, Debug, Default)]
pub struct SplitFigures {
    pub a_ms: Vec<(String, f64)>,
    pub b_ms: Vec<(String, f64)>,
    /// Largest 8-bit step and FLIP mean of B against A (computed while the difference or FLIP
    /// view is shown).
    pub max_steps: Option<u8>,
    pub flip_mean: Option<f32>,
    pub ledger_delta: Vec<crate::bench::LightDelta>,
    /// Why B could not be drawn.
    pub error: Option<String>,
}

/// B's renderer and images (on the device).
pub struct SplitGfx {
    pub renderer: Renderer,
    pub image: Image,
    /// The difference or FLIP image, registered with egui once and replaced in place.
    pub overlay: Option<egui::TextureHandle>,
    pub stats: Option<FrameStats>,
    pub figures: SplitFigures,
}

impl SplitGfx {
    pub fn new(gpu: &crate::Gpu, egui: &mut egui_wgpu::Renderer, a: &Settings, size: (u32, u32)) -> Result<Self> {
        let views = gpu.caps.has_downlevel(wgpu::DownlevelFlags::VIEW_FORMATS);
        Ok(Self {
            renderer: Renderer::new(gpu, OUTPUT_FORMAT, a)?,
            image: Image::new(&gpu.device, egui, "compare B", size, wgpu::FilterMode::Linear, views),
            overlay: None,
            stats: None,
            figures: SplitFigures::default(),
        })
    }
}

/// The difference or FLIP image of `b` against `a` for `view`, the largest step and, in the
/// FLIP view, FLIP's mean (FLIP runs only there: it costs tens of milliseconds a frame).
pub fn overlay(
    view: SplitView,
    a: &image::RgbaImage,
    b: &image::RgbaImage,
) -> Result<(image::RgbaImage, u8, Option<f32>)> {
    let steps = crate::compare::max_channel_difference(a, b);
    Ok(match view {
        SplitView::Flip => {
            let (f, map) = crate::compare::flip(a, b)?;
            (map, steps, Some(f.mean))
        }
        _ => (crate::compare::difference_image(a, b), steps, None),
    })
}
