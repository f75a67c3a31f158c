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

/// Depth of field's focus (`focus_distance`): `auto`, or a fixed view distance. Its one name is
/// `auto` or the number, in the CLI, scripts and settings files alike (a settings file holds
/// `"auto"` or a plain number, so files written when the knob was a number still load).
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize, Deserialize)]
#[serde(try_from = "FocusValue", into = "FocusValue")]
pub enum Focus {
    /// The view depth of the surface at the screen's centre pixel (`size / 2`), read by the
    /// depth-of-field shader from the depth the post chain already binds, so there is no
    /// read-back and no stall, and a moving camera refocuses in the same frame. Where that pixel
    /// is background (sky), the focus is the framed scene's distance, computed on the CPU
    /// (`post::focus_fallback`): the view depth of the centre of the scene's bounds, or their
    /// radius when that centre is not in front of the camera, within the near and far planes.
    #[default]
    Auto,
    /// A fixed view distance, > 0.
    Distance(f32),
}

impl Focus {
    /// `auto` or a number (a view distance > 0; the range is the knob's, checked by
    /// `Settings::validate`).
    pub fn parse(v: &str) -> Result<Focus, String> {
        match v.trim() {
            "auto" => Ok(Focus::Auto),
            t => match t.parse::<f32>() {
                Ok(x) if x.is_finite() => Ok(Focus::Distance(x)),
                _ => Err(format!("'{v}' is not auto or a finite number")),
            },
        }
    }

    /// The one name: `auto` or the distance.
    pub fn name(&self) -> String {
        match self {
            Focus::Auto => "auto".into(),
            Focus::Distance(d) => d.to_string(),
        }
    }

    /// The fixed distance (`None`: auto).
    pub fn distance(&self) -> Option<f32> {
        match self {
            Focus::Auto => None,
            Focus::Distance(d) => Some(*d),
        }
    }
}

/// How a settings file writes a [`Focus`]: a number or the name `auto`.
#[derive(Serialize, Deserialize)]
#[serde(untagged)]
enum FocusValue {
    Distance(f32),
    Name(String),
}

impl TryFrom<FocusValue> for Focus {
    type Error = String;
    fn try_from(v: FocusValue) -> Result<Self, String> {
        match v {
            FocusValue::Distance(d) => Ok(Focus::Distance(d)),
            FocusValue::Name(n) => Focus::parse(&n),
        }
    }
}

impl From<Focus> for FocusValue {
    fn from(f: Focus) -> Self {
        match f {
            Focus::Auto => FocusValue::Name("auto".into()),
            Focus::Distance(d) => FocusValue::Distance(d),
        }
    }
}
