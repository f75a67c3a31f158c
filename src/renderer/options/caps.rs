//! The options of `caps/`.

use serde::{Deserialize, Serialize};

/// Which lights a cap keeps when more than it allows compete.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum CapOrder {
    /// The first in the scene's order (an engine that fills its buffer as it walks its lights:
    /// three.js's tiles, Bevy's uniform buffers, PlayCanvas).
    #[default]
    Scene,
    /// The nearest: to the eye (per camera), to the cell's or the object's centre (per cluster,
    /// per object). Filament sorts its lights by distance to the camera.
    Nearest,
    /// The brightest: per camera, the most screen-space irradiance (peak luminance times the
    /// solid angle of the light's sphere seen from the eye); per cluster or object, the most
    /// irradiance at the cell's or object's centre. Unity ranks a renderer's lights by
    /// brightness at the object.
    Brightest,
}

/// Declared with the other options types from the fields of `fields.rs`.
pub use super::CapsOptions;
