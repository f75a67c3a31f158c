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

/// Declared with the other options types from the fields of `fields.rs`.
pub use super::PostOptions;
