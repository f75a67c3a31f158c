//! What the user chooses per frame: culling mode, G-buffer layout, debug view, counters.
//! Plain serde data, apart from GPU objects, so the viewer can persist it and
//! `lampshade render --settings FILE` can reproduce a screenshot.

use serde::{Deserialize, Serialize};

pub use super::gbuffer::LayoutChoice;

/// How light volumes are applied.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum CullingMode {
    /// Every light a full-screen triangle: the no-culling reference.
    Fullscreen,
    /// Volume back faces with depth GreaterEqual, no stencil.
    #[default]
    Volume,
    /// Seed 000: front faces mark (depth-fail increment), back faces shade where stencil = 0.
    StencilTwoPass,
    /// Seed 001: one double-sided draw inverts stencil on depth fail, back faces shade where != 0.
    StencilInvert,
    /// Seed 002: mark with depth-fail REPLACE of a per-light value, shade where stencil equals it.
    StencilReplace,
    /// Per light, the cheapest correct method (see `Renderer::plan_light`).
    Auto,
}

impl CullingMode {
    pub const ALL: [CullingMode; 6] = [
        CullingMode::Fullscreen,
        CullingMode::Volume,
        CullingMode::StencilTwoPass,
        CullingMode::StencilInvert,
        CullingMode::StencilReplace,
        CullingMode::Auto,
    ];

    pub fn name(self) -> &'static str {
        match self {
            CullingMode::Fullscreen => "fullscreen",
            CullingMode::Volume => "volume",
            CullingMode::StencilTwoPass => "stencil-two-pass",
            CullingMode::StencilInvert => "stencil-invert",
            CullingMode::StencilReplace => "stencil-replace",
            CullingMode::Auto => "auto",
        }
    }
}

/// What the compose pass shows. The values are shared with WGSL as generated constants.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum DebugView {
    #[default]
    Lit = 0,
    Albedo = 1,
    Normal = 2,
    Depth = 3,
    Specular = 4,
    Emissive = 5,
    DiffuseLight = 6,
    SpecularLight = 7,
    /// Seed 000's diagram: blue passed Z in the marking pass, red passed Z in the shading pass,
    /// green passed the stencil test (lit).
    Stencil = 8,
    /// Lights touching each pixel.
    Complexity = 9,
}

impl DebugView {
    pub const ALL: [DebugView; 10] = [
        DebugView::Lit,
        DebugView::Albedo,
        DebugView::Normal,
        DebugView::Depth,
        DebugView::Specular,
        DebugView::Emissive,
        DebugView::DiffuseLight,
        DebugView::SpecularLight,
        DebugView::Stencil,
        DebugView::Complexity,
    ];

    pub fn wgsl_name(self) -> &'static str {
        match self {
            DebugView::Lit => "LIT",
            DebugView::Albedo => "ALBEDO",
            DebugView::Normal => "NORMAL",
            DebugView::Depth => "DEPTH",
            DebugView::Specular => "SPECULAR",
            DebugView::Emissive => "EMISSIVE",
            DebugView::DiffuseLight => "DIFFUSE_LIGHT",
            DebugView::SpecularLight => "SPECULAR_LIGHT",
            DebugView::Stencil => "STENCIL",
            DebugView::Complexity => "COMPLEXITY",
        }
    }
}

/// Light accumulation precision (seed 002: "16-bit floating point enables HDR; can use 8-bit
/// for higher performance, beware of saturation").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum AccumFormat {
    #[default]
    Rgba16Float,
    Rgba32Float,
    Rg11b10Ufloat,
}

impl AccumFormat {
    pub const ALL: [AccumFormat; 3] = [AccumFormat::Rgba16Float, AccumFormat::Rgba32Float, AccumFormat::Rg11b10Ufloat];

    /// The texture format, or why the adapter cannot blend into it.
    pub fn format(self, features: wgpu::Features) -> anyhow::Result<wgpu::TextureFormat> {
        let (format, needs) = match self {
            AccumFormat::Rgba16Float => (wgpu::TextureFormat::Rgba16Float, wgpu::Features::empty()),
            AccumFormat::Rgba32Float => (wgpu::TextureFormat::Rgba32Float, wgpu::Features::FLOAT32_BLENDABLE),
            AccumFormat::Rg11b10Ufloat => {
                (wgpu::TextureFormat::Rg11b10Ufloat, wgpu::Features::RG11B10UFLOAT_RENDERABLE)
            }
        };
        if !features.contains(needs) {
            anyhow::bail!("{self:?} accumulation needs {needs:?}, which this adapter lacks");
        }
        Ok(format)
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    pub culling: CullingMode,
    pub layout: LayoutChoice,
    pub debug_view: DebugView,
    /// Restrict the stencil and complexity views to one light.
    pub selected_light: Option<usize>,
    /// Store depth reversed (near = 1): better precision far away. The seeds' compare
    /// functions are written for standard depth and flipped when this is on.
    pub reversed_z: bool,
    pub exposure: f32,
    /// Read back per-light occlusion counts (shaded fragments).
    pub count_fragments: bool,
    /// Also count the ideal: G-buffer points inside each light's true shape (costs a
    /// full-screen pass per light).
    pub count_ideal: bool,
    /// Read back GPU timestamps.
    pub timestamps: bool,
    /// Format of the light accumulation targets.
    pub accumulation: AccumFormat,
    /// Use depth clamp on light volumes when the adapter has it. Off, lights whose volume
    /// crosses the far plane fall back to full-screen draws (the path for adapters without it).
    pub depth_clamp: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            culling: CullingMode::default(),
            layout: LayoutChoice::default(),
            debug_view: DebugView::Lit,
            selected_light: None,
            reversed_z: false,
            exposure: 1.0,
            count_fragments: true,
            count_ideal: false,
            timestamps: true,
            depth_clamp: true,
            accumulation: AccumFormat::default(),
        }
    }
}

impl Settings {
    pub fn validate(&self) -> Result<(), String> {
        if !(self.exposure.is_finite() && self.exposure > 0.0 && self.exposure < 1e6) {
            return Err(format!("exposure {} must be a positive finite number", self.exposure));
        }
        Ok(())
    }
}
