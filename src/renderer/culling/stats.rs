//! What the culling reports per light and for the forward lists.

use serde::{Deserialize, Serialize};

use super::plan::Method;
use crate::renderer::options::culling::ForwardLights;
use std::borrow::Cow;

/// The forward pass's work: its light lists (from the plan) and the fragments it shaded.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct ForwardStats {
    /// Which lists the pass walked (`Settings::forward_lights`).
    pub lights: ForwardLights,
    /// Blended objects drawn.
    pub objects: usize,
    /// Entries of the objects' lists, summed, and the longest.
    pub object_list_entries: u64,
    pub longest_object_list: u32,
    /// Screen tiles (`tiled` only), their lists' entries summed, and the longest.
    pub tiles: u64,
    pub tile_list_entries: u64,
    pub longest_tile_list: u32,
    /// Samples the forward pass shaded (passed the depth test; occlusion query), when counting;
    /// peeled, every layer's together (the light pre-pass's forward-shaded opaque objects, which
    /// the unpeeled count includes, left out).
    pub fragments: Option<u64>,
    /// Layers depth peeling peeled (`--blended peeled`), and the blended samples behind the
    /// last one, which it dropped (when counting).
    pub peel_layers: Option<u32>,
    pub unpeeled: Option<u64>,
}

#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct LightStats {
    pub index: usize,
    /// "point" or "spot", borrowed: an allocated name per light made the per-light stats cost
    /// 1.1-1.3 ms of CPU a frame at 16,384 lights (0.16-0.62 ms borrowed; docs/measurements.md).
    pub kind: Cow<'static, str>,
    pub method: Method,
    pub crosses_near: bool,
    pub crosses_far: bool,
    pub screen_share: f32,
    /// Samples that reached the lighting shader.
    pub shaded: Option<u64>,
    /// Samples whose G-buffer point lies inside the light's true shape.
    pub ideal: Option<u64>,
    /// Rasterised coverage of the light's bounding volume (its back faces, or the screen for
    /// full-screen lights): fragment-shader invocations from pipeline statistics, counted with
    /// the ideal.
    pub coverage: Option<u64>,
    /// Its shadow maps this frame (`ShadowPlan::light_share`): tiles (atlas tiles or cube-array
    /// faces), their texels, and the caster draws into them; 0 when it casts no shadow.
    #[serde(default)]
    pub shadow_tiles: u32,
    #[serde(default)]
    pub shadow_texels: u64,
    #[serde(default)]
    pub caster_draws: u64,
    /// Its shadow maps' drawing time (ms): the render passes of its tiles in a ledger frame
    /// (counted, with timestamps), each timed on its own; `None` otherwise or when it casts none.
    #[serde(default)]
    pub shadow_ms: Option<f64>,
    /// Evaluated pairs that the light's true shape does not hold: `shaded - ideal`, when
    /// both were counted (the culling's false positives for this light).
    #[serde(default)]
    pub wasted: Option<u64>,
    /// Its cost in the light pass by the frame's [`CostModel`](crate::renderer::explain::cost::CostModel)
    /// (ms): its draws and its evaluated pairs.
    #[serde(default)]
    pub cost_ms: Option<f64>,
    /// Its share of the light pass's measured time (ms): the measured pass times its cost over
    /// the model's whole pass (fixed part + every light's cost). The shares and the fixed part's
    /// add up to the measured pass by construction; the model only weighs them.
    #[serde(default)]
    pub share_ms: Option<f64>,
}
