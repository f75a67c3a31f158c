//! The options of `culling/`.

use serde::{Deserialize, Serialize};

/// Default sphere tessellation: 80 triangles (one subdivision of an icosahedron), seed 000's
/// "low-poly".
pub const DEFAULT_SPHERE_SUBDIVISIONS: u32 = 1;

/// Default sides of the spot lights' bounding pyramid.
pub const DEFAULT_CONE_SIDES: u32 = 12;

/// Who builds the `clustered` mode's light lists each frame (`tiles::ClusterBuild`): the same
/// lists either way.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum ClusterBuilder {
    /// The CPU, as Bevy does: the lists are uploaded (CPU time grows with their entries). The
    /// default: on lavapipe the GPU's build costs more GPU time than it saves CPU time.
    #[default]
    Cpu,
    /// The GPU, from each light's span of clusters: the CPU uploads a 16-byte span per light.
    Gpu,
}

/// How lights whose volume crosses the near plane are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum NearLights {
    /// By the culling mode's method, as every other light (a plain volume under `auto`: its
    /// back faces, GreaterEqual, shade every pixel a full-screen draw would that the volume
    /// holds). Without depth clamp such a light is drawn full-screen under either rule: the near
    /// plane clips its faces, and their clipped depth has no bound (`methods::CROSSING_NEAR`).
    #[default]
    Volume,
    /// Full-screen (seed 004: "Point/Spot lights that cross the near plane are rendered as
    /// fullscreen quads"); tiled and clustered shading are unchanged.
    Fullscreen,
}

/// Which lights the forward pass (blended surfaces) evaluates at each of its fragments, and
/// whether the forward paths cull their objects' lists (`All`: they do not). Every choice gives
/// the same picture: a light left out reaches no fragment it is left out of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum ForwardLights {
    /// Per fragment, the shorter of its object's list and its screen tile's list (the lights
    /// whose volume's screen rectangle covers the tile).
    #[default]
    Tiled,
    /// The object's list alone: the lights whose sphere reaches its bounding sphere.
    Object,
    /// Every light at every fragment: the unculled reference (on the forward paths too: every
    /// light in every object's list, multi-pass's pairs drawn full screen).
    All,
}

impl ForwardLights {
    pub const ALL: [ForwardLights; 3] = [ForwardLights::Tiled, ForwardLights::Object, ForwardLights::All];
}

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
    /// Andersson 2011: a compute pass lists the lights reaching each 16x16-pixel tile between
    /// its depth bounds; one full-screen pass shades each pixel with its tile's list.
    Tiled,
    /// Olsson et al. 2012: screen tiles x exponential depth slices, lights assigned on the CPU;
    /// one full-screen pass shades each pixel with its cluster's list.
    Clustered,
    /// Drobot 2017 (z-binning, "Improved Culling for Tiled and Clustered Rendering"): lights
    /// sorted by view depth, each depth bin the range of sorted lights it holds, each screen
    /// tile a bitmask of the lights reaching it (built on the GPU); one full-screen pass walks
    /// the tile's bits within the pixel's bin.
    Zbin,
    /// Per light, the cheapest correct method (see `plan::plan_light`), or a list mode for the
    /// whole frame when that is estimated cheaper by the calibration (see `tiles::frame_rule`).
    Auto,
}

impl CullingMode {
    /// Whether the mode can shade from light lists (tiled, clustered, z-binned, or `auto`,
    /// which lists where it picks a list mode): what RIS draws its candidates from.
    pub fn can_list(self) -> bool {
        matches!(self, CullingMode::Tiled | CullingMode::Clustered | CullingMode::Zbin | CullingMode::Auto)
    }

    pub const ALL: [CullingMode; 9] = [
        CullingMode::Fullscreen,
        CullingMode::Volume,
        CullingMode::StencilTwoPass,
        CullingMode::StencilInvert,
        CullingMode::StencilReplace,
        CullingMode::Tiled,
        CullingMode::Clustered,
        CullingMode::Zbin,
        CullingMode::Auto,
    ];
}

/// The most lights every culling mode and path takes: the longest list the forward paths' loops
/// walk whole ([`FORWARD_LIST_MAX`](FORWARD_LIST_MAX)), so 100,000 lights
/// from `--lights` and a scene's own on top are taken by every mode. Past it only the list modes
/// (`zbin`, `clustered`, `tiled`) on the G-buffer paths do (up to
/// [`crate::scene::builtin::MAX_LIGHTS`]), and `auto` shades with `zbin`: the per-light modes
/// draw a volume a light (up to a million draws).
pub const MAX_LIGHTS_EVERY_MODE: usize = FORWARD_LIST_MAX as usize;

/// The radius a light is drawn (and shaded) to under a cut-off `threshold` (a fraction of the
/// light's peak): the attenuation `(1 - (d/r)^2)^2` falls below `threshold` at
/// `d = r sqrt(1 - sqrt(threshold))`. 0 keeps the exact radius; 1/256 gives 0.968 r, 1/64
/// 0.935 r, 1/16 0.866 r. Beyond it the light is cut off, so the largest error one light causes
/// is `threshold` times its peak (colour x intensity).
pub fn cutoff_radius(radius: f32, threshold: f32) -> f32 {
    if threshold <= 0.0 {
        return radius;
    }
    radius * (1.0 - threshold.sqrt()).max(0.0).sqrt()
}

/// Sphere subdivisions allowed in [`Settings::sphere_subdivisions`] (level 0 is the 20-face
/// icosahedron, each level multiplies the faces by 4).
pub const MAX_SPHERE_SUBDIVISIONS: u32 = 4;

/// Cone sides allowed in [`Settings::cone_sides`].
pub const CONE_SIDES_RANGE: std::ops::RangeInclusive<u32> = 3..=64;

/// The longest light list the forward loops (`fs_forward` for blended surfaces,
/// `forward_single` for the forward path) walk a light an iteration: gallivm (lavapipe) ends a
/// shader invocation's loops once they have run 65,535 iterations between them, silently, and
/// 65,000 leave room for the invocation's other loops (the tiled and clustered passes split
/// their lists instead, `tiles::SHADE_CHUNK`). Scenes with more lights compile loops that take
/// two lights an iteration (`ShaderFeatures::paired_loops`; they cost `glass`'s blended pass a
/// few percent, 389 and 393 ms against 367-385, so other scenes keep the plain loops).
pub const FORWARD_LOOP_LIGHTS: u32 = 65_000;

/// The longest list the paired loops walk whole. Longer lists (a scene of more than 130,000
/// lights reaching one object, which only `zbin` and `clustered` take) are warned of
/// ([`long_forward_list_warnings`]), not split.
pub const FORWARD_LIST_MAX: u32 = 2 * FORWARD_LOOP_LIGHTS;

/// Declared with the other options types from the fields of `fields.rs`.
pub use super::CullingOptions;
