//! The options of `post/`.

use serde::{Deserialize, Serialize};

/// The tone curve. The values are shared with WGSL as generated constants (`LS_TONEMAP_*`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum Tonemap {
    /// ACES filmic, Krzysztof Narkowicz's 2015 fit (the curve compose always used).
    #[default]
    Aces = 0,
    /// Reinhard et al. 2002, "Photographic Tone Reproduction", eq. 3: x / (1 + x) per channel.
    Reinhard = 1,
    /// Troy Sobotka's AgX, in Benjamin Wrensch's minimal polynomial fit (iolite, 2023).
    Agx = 2,
    /// Khronos PBR Neutral (KhronosGroup/ToneMapping, PBR_Neutral, 2024).
    PbrNeutral = 3,
    /// No curve: clamped to 0 ..= 1.
    None = 4,
}

/// Anti-aliasing, the chain's last pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum Aa {
    #[default]
    Off = 0,
    /// Seed 002's "intelligent blur": pixels on G-buffer edges (second difference of 1/depth,
    /// normals turning) blended with their four neighbours by the edge's strength.
    Edge = 1,
    /// FXAA (Lottes 2009–2011), its minimal console form: luma contrast test, then a blend
    /// along the edge direction found from the diagonal lumas.
    Fxaa = 2,
}

/// The post chain's options: exposure and tone curve, bloom, grading, fog, depth of field, vignette, anti-aliasing, distortion.
#[derive(Clone, Debug, PartialEq)]
pub struct PostOptions {
    pub exposure: f32,
    /// The tone curve of the post chain (`post::Tonemap`); ACES is the one compose always used.
    pub tonemap: Tonemap,
    /// Auto-exposure: a luminance histogram each frame, the exposure adapting towards
    /// `target_luminance` / (the frame's geometric mean luminance), time-stepped at a fixed
    /// 1/60 s per frame. `exposure` stays a factor on top (exposure compensation).
    pub auto_exposure: bool,
    /// Adaptation speed of auto-exposure, per second: each frame moves the adapted log2
    /// luminance by `1 - exp(-speed / 60)` of the way to the frame's.
    pub adaptation_speed: f32,
    /// The luminance auto-exposure maps the frame's geometric mean to (middle grey, 0.18).
    pub target_luminance: f32,
    /// Bloom: a bright pass above `bloom_threshold`, a 5-level downsample/upsample chain, added
    /// back times `bloom_intensity`.
    pub bloom: bool,
    /// Luminance above which a pixel blooms (the part above it blooms, hue kept).
    pub bloom_threshold: f32,
    /// Factor on the bloom added back.
    pub bloom_intensity: f32,
    /// Colour grading: a `.cube` 3D LUT file, or `identity` (built in); `None`: no grading.
    pub lut: Option<String>,
    /// Fog (after grading, seed 002's order): distance fog with an exponential height falloff,
    /// towards the background colour.
    pub fog: bool,
    /// Fog density per unit of distance at the camera's height.
    pub fog_density: f32,
    /// Exponential falloff of the fog's density per unit of height above the camera (0: plain
    /// distance fog).
    pub fog_height_falloff: f32,
    /// Depth of field: a gather blur by each pixel's circle of confusion.
    pub dof: bool,
    /// View distance that is in focus.
    pub focus_distance: f32,
    /// Circle of confusion diameter in pixels at infinite distance: CoC = aperture x |z - focus| / z,
    /// at most `post::MAX_COC` px.
    pub aperture: f32,
    /// Vignette strength: the corners are darkened by this fraction (0: off).
    pub vignette: f32,
    /// Anti-aliasing, before fog in the chain (seed 002's order): seed 002's edge blur from
    /// G-buffer discontinuities, or FXAA.
    pub aa: Aa,
    /// Seed 002's distortion (before edge smoothing in the chain): the picture behind each
    /// distorting material (`Material::distortion`) shifted by its view-space normal.
    pub distortion: bool,
}
