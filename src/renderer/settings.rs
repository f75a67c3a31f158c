//! What the user chooses per frame: culling mode, G-buffer layout, debug view, counters.
//! Plain serde data, apart from GPU objects, so the viewer can persist it and
//! `lampshade render --settings FILE` can reproduce a screenshot.

use serde::{Deserialize, Serialize};

/// Default sphere tessellation: 80 triangles (one subdivision of an icosahedron), seed 000's
/// "low-poly".
pub const DEFAULT_SPHERE_SUBDIVISIONS: u32 = 1;
/// Default sides of the spot lights' bounding pyramid.
pub const DEFAULT_CONE_SIDES: u32 = 12;

pub use super::kit::gbuffer::LayoutChoice;

/// The one name of a knob's value, used by the CLI, settings files, scripts, the viewer and the
/// bench: clap's `ValueEnum` name, which is the kebab-case name serde writes (the
/// `every_knob_value_has_one_name` test holds the two together).
pub fn name_of<T: clap::ValueEnum>(v: &T) -> String {
    v.to_possible_value().map_or_else(String::new, |p| p.get_name().to_string())
}

/// The value of a knob (`what`, for the message) named `s` (or one of its old aliases).
pub fn parse_name<T: clap::ValueEnum>(what: &str, s: &str) -> Result<T, String> {
    T::from_str(s, false).map_err(|_| {
        let names: Vec<String> = T::value_variants().iter().map(name_of).collect();
        format!("unknown {what} '{s}' (one of {})", names.join(", "))
    })
}

/// The value's one-line description (its doc comment), for tooltips.
pub fn help_of<T: clap::ValueEnum>(v: &T) -> String {
    v.to_possible_value().and_then(|p| p.get_help().map(|h| h.to_string())).unwrap_or_default()
}

/// `name()` and `parse()` for a knob enum, in terms of [`name_of`] and [`parse_name`].
macro_rules! knob_names {
    ($($t:ty => $what:literal),* $(,)?) => {$(
        impl $t {
            /// The value's one name (see [`name_of`]).
            pub fn name(self) -> String {
                $crate::renderer::settings::name_of(&self)
            }

            #[doc = concat!("Parses a ", $what, " by its name (see [`parse_name`]).")]
            pub fn parse(s: &str) -> Result<Self, String> {
                $crate::renderer::settings::parse_name($what, s)
            }
        }
    )*};
}

pub(crate) use knob_names;

knob_names!(
    CullingMode => "culling mode",
    DebugView => "view",
    AccumFormat => "accumulation format",
    DepthFormat => "depth format",
    LayoutChoice => "layout",
    ForwardLights => "forward light list",
    BrdfOverride => "reflectance model",
    Tonemap => "tonemap",
    Aa => "anti-aliasing",
    RenderPath => "rendering path",
    ClusterBuilder => "cluster list builder",
    Msaa => "MSAA sample count",
    NearLights => "near-plane rule",
    DrawOrder => "draw order",
    DepthRead => "depth read",
    BlendedMode => "blending of blended surfaces",
    MaterialBranch => "material selection",
    ShadowMode => "shadow casters",
    ShadowFilter => "shadow filter",
    ShadowCube => "shadow cube layout",
    ShadowFormat => "shadow map format",
    CapOrder => "cap order",
);

pub use super::caps::CapOrder;

pub use super::shadows::{ShadowCube, ShadowFilter, ShadowFormat, ShadowMode};

pub use super::post::{Aa, Tonemap};

/// Which reflectance model shades the objects: each material's own, or one for all (an
/// experiment: the same scene as a metal, toon or unlit).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum BrdfOverride {
    /// Each material's own model.
    #[default]
    Scene,
    /// Lambert diffuse + normalised Blinn-Phong specular.
    BlinnPhong,
    /// Lambert diffuse only.
    Lambert,
    /// No diffuse; the Blinn-Phong lobe tinted by the base colour.
    Metal,
    /// Banded diffuse and highlight.
    Toon,
    /// The base colour as it is, no lighting.
    Unlit,
    /// Seed 000's standard Phong: Lambert diffuse + level x (R.V)^n.
    Phong,
}

impl BrdfOverride {
    /// The forced model, or `None` for each material's own.
    pub fn brdf(self) -> Option<crate::scene::Brdf> {
        use crate::scene::Brdf;
        match self {
            BrdfOverride::Scene => None,
            BrdfOverride::BlinnPhong => Some(Brdf::BlinnPhong),
            BrdfOverride::Lambert => Some(Brdf::Lambert),
            BrdfOverride::Metal => Some(Brdf::Metal),
            BrdfOverride::Toon => Some(Brdf::Toon),
            BrdfOverride::Unlit => Some(Brdf::Unlit),
            BrdfOverride::Phong => Some(Brdf::Phong),
        }
    }
}

/// The rendering pipeline: the three the seeds describe, side by side.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum RenderPath {
    /// Deferred shading (seeds 000-002): a G-buffer, lights as volumes over it, compose.
    #[default]
    Deferred,
    /// Deferred lighting (seeds 003-004): normals + exponent, lights into a light buffer, the
    /// geometry drawn again with its maps.
    LightPrepass,
    /// Forward single-pass (seed 002): each object with its light list in one shader.
    Forward,
    /// Forward multi-pass (seed 002): one additive draw per (object, light) pair.
    ForwardMultipass,
}

impl RenderPath {
    pub const ALL: [RenderPath; 4] =
        [RenderPath::Deferred, RenderPath::LightPrepass, RenderPath::Forward, RenderPath::ForwardMultipass];

    /// Whether the path can multisample: deferred shading cannot (seed 002: a G-buffer of
    /// samples costs samples x its bytes, and lighting per sample).
    pub fn can_multisample(self) -> bool {
        self != RenderPath::Deferred
    }
}

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

/// The order of the opaque draws (the G-buffer pass, the light pre-pass's passes 1 and 3, the
/// forward paths' depth pre-pass and opaque passes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum DrawOrder {
    /// By pipeline and material: the fewest state changes.
    #[default]
    Material,
    /// Nearest first, by each object's bounding sphere (seed 002: "an initial
    /// front-to-back-sorted z-only pass"): later, farther surfaces fail the depth test, so
    /// fewer fragments are shaded; the stats' `gbuffer_fragments` counts them.
    FrontToBack,
}

/// Where the passes after the G-buffer read each pixel's depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum DepthRead {
    /// From an R32Float copy the G-buffer pass writes beside its other targets (4 bytes a
    /// pixel written and read again): the stencil methods keep the depth-stencil buffer
    /// attached for writing while they read it, which a buffer bound for reading cannot be.
    #[default]
    Copy,
    /// From the depth buffer itself, through a depth-aspect view (seed 004: "if the platform
    /// supports reading Z as a texture, depth is not explicitly rendered"), where the frame
    /// allows (`kit::gbuffer::depth_read_refusal`); the copy otherwise, and the stats say why.
    Buffer,
}

/// How the lighting shaders pick a pixel's reflectance model (seed 002's material IDs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum MaterialBranch {
    /// Every model's terms computed, one selected: no divergent branch (lavapipe runs both
    /// sides of a branch whenever one lane takes each).
    #[default]
    Select,
    /// A branch on the material ID, each model computing only its own terms (seed 002:
    /// "reasonably coherent dynamic branching"). The same values.
    Branch,
}

/// How blended (alpha `BLEND`) surfaces are composited over the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum BlendedMode {
    /// Alpha blending (`src x alpha + dst x (1 - alpha)`), sorted back to front by each
    /// object's bounding sphere.
    #[default]
    Alpha,
    /// Additive (`src x alpha + dst`; seed 003: "additive blending modes be used to eliminate
    /// the need to sort polygons"): drawn unsorted, in scene order; the sum does not depend on
    /// it beyond the fp16 target's rounding.
    Additive,
    /// Depth peeling (seed 002: "can use depth peeling"; Everitt 2001, "Interactive
    /// Order-Independent Transparency"): `peel_layers` passes each keep the nearest blended
    /// fragment behind the last layer and add it under the layers before it, so every pixel's
    /// fragments are composited in depth order without sorting objects, interpenetrating ones
    /// included. Fragments behind the last layer are dropped (the stats count them).
    Peeled,
}

/// The most layers depth peeling peels (`Settings::peel_layers`).
pub const MAX_PEEL_LAYERS: u32 = 16;

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

/// Samples per pixel of the paths that can multisample (`RenderPath::can_multisample`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
pub enum Msaa {
    /// One sample per pixel.
    #[default]
    #[value(name = "1")]
    #[serde(rename = "1")]
    X1,
    /// Four samples per pixel.
    #[value(name = "4")]
    #[serde(rename = "4")]
    X4,
}

impl Msaa {
    pub fn samples(self) -> u32 {
        match self {
            Msaa::X1 => 1,
            Msaa::X4 => 4,
        }
    }
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
    /// Per light, the cheapest correct method (see `plan::plan_light`), or `clustered` for the
    /// whole frame when that is estimated cheaper (see `tiles::frame_rule`).
    Auto,
}

impl CullingMode {
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
/// walk whole ([`FORWARD_LIST_MAX`](super::culling::plan::FORWARD_LIST_MAX)), so 100,000 lights
/// from `--lights` and a scene's own on top are taken by every mode. Past it only `zbin` and
/// `clustered` on the G-buffer paths do (up to [`crate::scene::builtin::MAX_LIGHTS`]), and
/// `auto` shades with `zbin`: the per-light modes draw a volume a light (up to a million draws),
/// and `tiled` keeps a bit for 65,536 lights per tile and walks every light past them.
pub const MAX_LIGHTS_EVERY_MODE: usize = super::culling::plan::FORWARD_LIST_MAX as usize;

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
    /// Lights in each pixel's tile list (`tiled`) or cluster list (`clustered`; `tiled` for
    /// the other modes): a heatmap, the legend in the viewer.
    TileLights = 10,
    /// The reflectance model of each pixel (the material ID, or the scene's one model), one
    /// colour per model (`Brdf::debug_color`), the legend in the viewer.
    MaterialId = 11,
    /// The post chain's bloom buffer (the upsampled chain before it is added), exposed and
    /// tonemapped; runs bloom even when it is off.
    Bloom = 12,
    /// The auto-exposure histogram (bins of log2 luminance, 1/3 stop each) over the dimmed
    /// picture; yellow: the adapted luminance, white: the frame's mean.
    Histogram = 13,
    /// The anti-aliasing's edge mask (the edge blur's G-buffer discontinuities, or FXAA's luma
    /// contrast test; `edge` when anti-aliasing is off): white where it may change a pixel.
    Edges = 14,
    /// Depth of field's circle of confusion: dark green where in focus (under half a pixel,
    /// copied unchanged), grey growing to white at `post::MAX_COC` px.
    Coc = 15,
    /// The shadow factor, the least of the sun's and of every casting light's that
    /// reaches the pixel: white lit, black shadowed; dark blue where no surface is drawn.
    Shadow = 16,
    /// The sun's cascades, one colour each (red, green, blue, yellow), darkened by its shadow;
    /// grey beyond the last cascade.
    Cascades = 17,
    /// The light ledger's waste at each pixel: the lights the frame evaluated there whose true
    /// shape does not hold the pixel's point (evaluated minus ideal), drawn with each light's
    /// own culling (its stencil marks, its tile or cluster list): a heatmap on the tile-lights
    /// scale; with a selected light, that light's alone. Deferred path.
    Waste = 18,
}

impl DebugView {
    pub const ALL: [DebugView; 19] = [
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
        DebugView::TileLights,
        DebugView::MaterialId,
        DebugView::Bloom,
        DebugView::Histogram,
        DebugView::Edges,
        DebugView::Coc,
        DebugView::Shadow,
        DebugView::Cascades,
        DebugView::Waste,
    ];

    /// The name of the view's generated WGSL constant (`LS_VIEW_…`): its name in capitals.
    pub fn wgsl_name(self) -> String {
        self.name().to_uppercase().replace('-', "_")
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
    /// Seed 004 (Unity's deferred lighting): Rgba8Unorm holding `exp2(-light)`, blended
    /// multiplicatively (src x dst), so the product of the lights' factors encodes the sum of
    /// their light; compose decodes `-log2`. Range: 0 ..= [`LOG_ACCUM_MAX`] (= log2 255, about 8):
    /// more light saturates at the top of the range. Precision: one 8-bit step of the stored
    /// value is `log2(q / (q - 1))` of light at code q, i.e. 0.0057 near 0, 0.011 at 1, 0.09 at 4
    /// and 1.0 at the top; every blend rounds once more (see [`log_accum_error_bound`]).
    Rgba8Log,
    /// Seed 003's light buffer ("24-bit diffuse color (rgb) and 8-bit specular value", blended
    /// `GL_ONE, GL_ONE`) and seed 002's "8-bit for higher performance, beware of saturation":
    /// 8-bit linear channels, added. Stored as Bgra8Unorm, the byte order of the seeds'
    /// ARGB32. Range 0 ..= 1: more light saturates at 1. Precision: every write rounds to the
    /// nearest of 255 steps, so a sum of `blends` writes below 1 is off by at most
    /// `blends x 0.5 / 255` ([`unorm_accum_error_bound`]).
    Rgba8Unorm,
}

/// How far an [`AccumFormat::Rgba8Unorm`] channel may be from the exact sum when `blends`
/// writes produced it and the sum stays below 1: the blender adds each write's value to a
/// stored code and rounds the result to the nearest code, half a step (0.5/255); the stored
/// codes themselves add exactly. So at most `blends x 0.5 / 255`, whatever the order.
pub fn unorm_accum_error_bound(blends: u32) -> f32 {
    blends as f32 * 0.5 / 255.0
}

/// Largest light an [`AccumFormat::Rgba8Log`] channel holds: the smallest non-zero code, 1/255,
/// decodes to log2(255). A code of 0 (saturated) decodes to the same value, never infinity.
pub const LOG_ACCUM_MAX: f32 = 7.994_353_4;

/// Decodes a stored [`AccumFormat::Rgba8Log`] value (in 0..=1) to light, as compose does.
pub fn log_accum_decode(stored: f32) -> f32 {
    -(stored.max(1.0 / 255.0)).log2()
}

/// How far an [`AccumFormat::Rgba8Log`] channel may be from the exact sum `light` when `blends`
/// writes (the ambient pass and each light touching the pixel) produced it and the sum is below
/// [`LOG_ACCUM_MAX`]: each write rounds the source factor and the product to the nearest 8-bit
/// code (half a step, 0.5/255, each), an error `e` in a stored value `v >= 2^-light` moves the
/// decoded light by at most `e / (v ln 2)`. So at most `blends x (1/255) x 2^light / ln 2`.
pub fn log_accum_error_bound(light: f32, blends: u32) -> f32 {
    blends as f32 * (1.0 / 255.0) * light.exp2() / std::f32::consts::LN_2
}

impl AccumFormat {
    pub const ALL: [AccumFormat; 5] = [
        AccumFormat::Rgba16Float,
        AccumFormat::Rgba32Float,
        AccumFormat::Rg11b10Ufloat,
        AccumFormat::Rgba8Log,
        AccumFormat::Rgba8Unorm,
    ];

    /// The texture format, or why the adapter cannot blend into it.
    pub fn format(self, caps: &super::kit::caps::Caps) -> anyhow::Result<wgpu::TextureFormat> {
        let format = match self {
            AccumFormat::Rgba16Float => wgpu::TextureFormat::Rgba16Float,
            AccumFormat::Rgba32Float => wgpu::TextureFormat::Rgba32Float,
            AccumFormat::Rg11b10Ufloat => wgpu::TextureFormat::Rg11b10Ufloat,
            AccumFormat::Rgba8Log => wgpu::TextureFormat::Rgba8Unorm,
            // Bgra8Unorm tells the linear 8-bit buffer from the log one (`kit::log_accum`).
            AccumFormat::Rgba8Unorm => wgpu::TextureFormat::Bgra8Unorm,
        };
        // The lights add into it: it must take blending.
        if !caps.blendable(format) {
            return Err(caps.refuse(
                &format!("--accumulation {}", super::settings::name_of(&self)),
                &format!("blending into {format:?} render targets"),
                "use --accumulation rgba16-float",
            ));
        }
        Ok(format)
    }
}

/// The depth-stencil buffer's format. Position is reconstructed from the G-buffer's depth copy
/// (`GBufferLayout::for_caps`) either way; this decides the precision of every depth *test* (visibility in the
/// G-buffer pass, the light volumes' tests against the scene).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum DepthFormat {
    /// Depth32FloatStencil8 (needs the adapter's DEPTH32FLOAT_STENCIL8; without it the renderer
    /// falls back to Depth24PlusStencil8 and says so in the frame's stats).
    #[default]
    #[value(alias = "d32s8")]
    #[serde(alias = "d32s8")]
    Depth32FloatStencil8,
    /// Depth24PlusStencil8: 24-bit (or better, the implementation's choice) depth.
    #[value(alias = "d24s8")]
    #[serde(alias = "d24s8")]
    Depth24PlusStencil8,
}

impl DepthFormat {
    pub const ALL: [DepthFormat; 2] = [DepthFormat::Depth32FloatStencil8, DepthFormat::Depth24PlusStencil8];

    /// The texture format on an adapter with `features`.
    pub fn format(self, features: wgpu::Features) -> wgpu::TextureFormat {
        match self {
            DepthFormat::Depth32FloatStencil8 if features.contains(wgpu::Features::DEPTH32FLOAT_STENCIL8) => {
                wgpu::TextureFormat::Depth32FloatStencil8
            }
            _ => wgpu::TextureFormat::Depth24PlusStencil8,
        }
    }
}

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

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    /// The rendering pipeline (deferred shading, light pre-pass, forward single-/multi-pass).
    pub path: RenderPath,
    /// Samples per pixel where the path can multisample; deferred refuses 4.
    pub msaa: Msaa,
    /// The forward single-pass path draws depth first, so each pixel is shaded once (seed
    /// 002's "Z-cull"); off: shaded as drawn, overdraw included.
    pub depth_prepass: bool,
    pub culling: CullingMode,
    /// How lights crossing the near plane are drawn (seed 004's rule: full-screen).
    pub near_lights: NearLights,
    /// The order of the opaque draws.
    pub draw_order: DrawOrder,
    /// Where the passes after the G-buffer read depth: its copy or the depth buffer.
    pub depth_read: DepthRead,
    /// How blended surfaces are composited (alpha, sorted; additive, unsorted; or peeled).
    pub blended: BlendedMode,
    /// Seed 004's lightmaps, where the scene's materials have them (`scene::Lightmap`); off:
    /// realtime lighting everywhere.
    pub lightmaps: bool,
    /// Seed 004's crossfade: view distance from which lightmapped surfaces are fully baked
    /// (realtime up to `records::LIGHTMAP_FADE_START` of it).
    pub lightmap_distance: f32,
    /// Layers `BlendedMode::Peeled` peels, 1 ..= `MAX_PEEL_LAYERS`: a pixel's nearest this many
    /// blended fragments are composited, the rest dropped.
    pub peel_layers: u32,
    /// How the lighting shaders pick the reflectance model (select or branch).
    pub material_branch: MaterialBranch,
    /// The material sampler's anisotropy clamp, 1 ..= 16 (seed 002: "use aniso filtering
    /// during G-buffer pass"; 1: trilinear).
    pub anisotropy: u32,
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
    /// Build the stats' per-light table (`FrameStats::per_light`: each light's kind, method,
    /// screen share, shadow share and cost) in a frame that counts nothing. A counting frame
    /// always builds it (its counts are per light); a frame that neither counts nor asks pays
    /// nothing per light for its stats.
    pub per_light_stats: bool,
    /// Read back GPU timestamps.
    pub timestamps: bool,
    /// Format of the light accumulation targets.
    pub accumulation: AccumFormat,
    /// Use depth clamp on light volumes when the adapter has it. Off, lights whose volume
    /// crosses the far plane fall back to full-screen draws (the path for adapters without it).
    pub depth_clamp: bool,
    /// Format of the depth-stencil buffer.
    pub depth_format: DepthFormat,
    /// Cut each light off where its attenuation falls below this fraction of its peak (see
    /// [`cutoff_radius`]); 0 draws and shades the exact radius.
    pub light_cutoff: f32,
    /// The `tile-lights` view of a clustered frame: 0 shows each pixel's own cluster; a view
    /// depth d > 0 shows the slice of clusters at d across the whole screen.
    pub tile_view_depth: f32,
    /// Subdivisions of the icosphere bounding point lights (0 ..= 4).
    pub sphere_subdivisions: u32,
    /// Sides of the pyramid bounding spot lights (3 ..= 64).
    pub cone_sides: u32,
    /// Which lights the forward pass evaluates per blended fragment.
    pub forward_lights: ForwardLights,
    /// Write ambient + sun into the light accumulation from the G-buffer pass itself (seed
    /// 000: its RT1 starts with them), instead of a full-screen pass of their own. Where the
    /// device cannot take the accumulation targets beside the G-buffer's (colour attachment
    /// bytes per sample), the own pass is used and the stats say so. A layout without an
    /// emissive target (`seed000`, `packed`) always writes them in the G-buffer pass, which also
    /// carries the surfaces' emission into the accumulation.
    pub ambient_in_gbuffer: bool,
    /// Draw lights in instanced batches (`renderer::batches`): one draw per volume kind for
    /// plain volumes and full-screen lights, shared mark and shade draws for stencil-culled
    /// lights whose screen rectangles do not overlap. Off: a draw (or two) per light.
    pub light_batching: bool,
    /// Shade every object with one reflectance model instead of its material's.
    pub brdf: BrdfOverride,
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
    /// Which lights cast shadows (`renderer::shadows`): none, the sun, the sun and
    /// spots, or every light. A light's own `cast_shadows` flag can only turn it off.
    pub shadows: ShadowMode,
    /// The shadow atlas's byte budget in MiB (one Depth32Float texture; its side is the largest
    /// power of two that fits, up to the device's limit). With `shadow_cube` = `array` the atlas
    /// and the cube array share it (`shadows::cube_array_fit`).
    pub shadow_budget_mb: f32,
    /// Constant depth bias, in shadow-map texels (projected to world units at the receiver).
    pub shadow_bias: f32,
    /// Slope-scaled depth bias: texels x tan(angle between the normal and the light).
    pub shadow_slope_bias: f32,
    /// Normal offset: the lookup point moves this many texels along the surface normal beyond
    /// the filter's own reach (`ShadowFilter::reach`).
    pub shadow_normal_offset: f32,
    /// The filter kernel of the shadow lookup.
    pub shadow_filter: ShadowFilter,
    /// The shadow maps' depth format (seed 002: D16 or D24).
    pub shadow_format: ShadowFormat,
    /// Sun cascades (1 ..= 4) over the view frustum.
    pub shadow_cascades: u32,
    /// Cascade splits: lambda x logarithmic + (1 - lambda) x uniform.
    pub shadow_split_lambda: f32,
    /// Who builds the clustered mode's lists.
    pub cluster_build: ClusterBuilder,
    /// Where point lights' (and wide spots') six shadow faces live: tiles of the atlas
    /// (`unrolled`) or layers of a cube-array texture (`array`).
    pub shadow_cube: ShadowCube,
    /// Engine-style caps (`caps`): lights kept per camera (0: every light).
    pub max_lights: u32,
    /// Lights whose sphere lies wholly farther than this from the camera are dropped (0: none).
    pub light_distance: f32,
    /// Lights kept per cluster of the clustered mode's lists (0: every light).
    pub lights_per_cluster: u32,
    /// Lights kept per object in the forward paths' lists (0: every light).
    pub lights_per_object: u32,
    /// Which lights a cap keeps: the first in scene order, the nearest, or the brightest.
    pub cap_order: CapOrder,
    /// The clustered grid's tile side in pixels (0: the default, or what `cluster_budget` gives).
    pub cluster_tile: u32,
    /// The clustered grid's cell budget (0: none): the tiles Bevy's `ClusterConfig::FixedZ`
    /// gives for this many cells over `cluster_slices` slices, made square.
    pub cluster_budget: u32,
    /// The clustered grid's depth slices (0: the default).
    pub cluster_slices: u32,
    /// The clustered grid's first slice runs from the eye to this view depth, the rest
    /// exponentially to the farthest light (Bevy's `ClusterZConfig`); 0 spreads every slice
    /// exponentially over the depths the lights reach.
    pub first_slice_depth: f32,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            path: RenderPath::Deferred,
            msaa: Msaa::X1,
            depth_prepass: true,
            culling: CullingMode::default(),
            near_lights: NearLights::default(),
            draw_order: DrawOrder::default(),
            depth_read: DepthRead::default(),
            blended: BlendedMode::default(),
            peel_layers: 4,
            lightmaps: true,
            lightmap_distance: 40.0,
            material_branch: MaterialBranch::default(),
            anisotropy: 1,
            layout: LayoutChoice::default(),
            debug_view: DebugView::Lit,
            selected_light: None,
            reversed_z: false,
            exposure: 1.0,
            count_fragments: true,
            count_ideal: false,
            per_light_stats: false,
            timestamps: true,
            depth_clamp: true,
            accumulation: AccumFormat::default(),
            depth_format: DepthFormat::default(),
            light_cutoff: 0.0,
            tile_view_depth: 0.0,
            sphere_subdivisions: DEFAULT_SPHERE_SUBDIVISIONS,
            cone_sides: DEFAULT_CONE_SIDES,
            forward_lights: ForwardLights::default(),
            ambient_in_gbuffer: true,
            light_batching: true,
            brdf: BrdfOverride::Scene,
            tonemap: Tonemap::Aces,
            auto_exposure: false,
            adaptation_speed: 2.0,
            target_luminance: 0.18,
            bloom: false,
            bloom_threshold: 1.0,
            bloom_intensity: 0.1,
            lut: None,
            fog: false,
            fog_density: 0.02,
            fog_height_falloff: 0.1,
            dof: false,
            focus_distance: 10.0,
            aperture: 8.0,
            vignette: 0.0,
            aa: Aa::Off,
            distortion: false,
            shadows: ShadowMode::Spots,
            shadow_budget_mb: 16.0,
            shadow_bias: 1.0,
            shadow_slope_bias: 1.0,
            shadow_normal_offset: 1.0,
            shadow_filter: ShadowFilter::Pcf3x3,
            shadow_format: ShadowFormat::Depth32,
            shadow_cascades: 3,
            shadow_split_lambda: 0.7,
            cluster_build: ClusterBuilder::Cpu,
            shadow_cube: ShadowCube::Unrolled,
            max_lights: 0,
            light_distance: 0.0,
            lights_per_cluster: 0,
            lights_per_object: 0,
            cap_order: CapOrder::default(),
            cluster_tile: 0,
            cluster_budget: 0,
            cluster_slices: 0,
            first_slice_depth: 0.0,
        }
    }
}

impl Settings {
    /// Checks every knob against its row of the table ([`super::knobs::KNOBS`]): one place for
    /// the ranges that the CLI, settings files, scripts and the viewer's sliders share.
    pub fn validate(&self) -> Result<(), String> {
        super::knobs::KNOBS.iter().try_for_each(|k| k.check(self))?;
        if self.msaa != Msaa::X1 && !self.path.can_multisample() {
            return Err(format!(
                "the {} path cannot multisample (seed 002: a G-buffer of samples, lit per sample); \
                 use --msaa 1, or the light-prepass or forward paths",
                self.path.name()
            ));
        }
        if self.msaa != Msaa::X1 && self.blended == BlendedMode::Peeled {
            return Err("depth peeling peels single-sampled depth; use --msaa 1 or another --blended mode".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_files_without_the_new_knobs_still_load() {
        // A settings file as the viewer wrote it before depth format, cut-off and tessellation.
        let old = r#"{"culling":"stencil-two-pass","layout":"compact","debug_view":"lit","selected_light":null,
            "reversed_z":true,"exposure":1.5,"count_fragments":true,"count_ideal":false,"timestamps":true,
            "accumulation":"rgba16-float","depth_clamp":true}"#;
        let s: Settings = serde_json::from_str(old).unwrap();
        assert_eq!(s.culling, CullingMode::StencilTwoPass);
        assert!(s.reversed_z);
        assert_eq!(s.depth_format, DepthFormat::Depth32FloatStencil8);
        assert_eq!((s.light_cutoff, s.sphere_subdivisions, s.cone_sides), (0.0, 1, 12));
        assert_eq!((s.path, s.msaa), (RenderPath::Deferred, Msaa::X1));
        s.validate().unwrap();
        // And the new ones round-trip.
        let new = Settings {
            accumulation: AccumFormat::Rgba8Log,
            depth_format: DepthFormat::Depth24PlusStencil8,
            light_cutoff: 1.0 / 64.0,
            sphere_subdivisions: 3,
            cone_sides: 24,
            ..Settings::default()
        };
        let text = serde_json::to_string(&new).unwrap();
        assert!(text.contains("\"rgba8-log\"") && text.contains("\"depth24-plus-stencil8\""), "{text}");
        assert_eq!(serde_json::from_str::<Settings>(&text).unwrap(), new);
    }

    /// The serde name (settings files) and the clap name (CLI, scripts, viewer, bench) of every
    /// knob value are the same string, and `parse` takes it back.
    fn one_name<T: clap::ValueEnum + Serialize + PartialEq + std::fmt::Debug>() {
        for v in T::value_variants() {
            let serde_name = serde_json::to_value(v).unwrap();
            assert_eq!(serde_name.as_str(), Some(name_of(v).as_str()), "{v:?}");
            assert_eq!(parse_name::<T>("knob", &name_of(v)).as_ref(), Ok(v));
        }
    }

    #[test]
    fn every_knob_value_has_one_name() {
        one_name::<CullingMode>();
        one_name::<DebugView>();
        one_name::<AccumFormat>();
        one_name::<DepthFormat>();
        one_name::<LayoutChoice>();
        one_name::<ForwardLights>();
        one_name::<BrdfOverride>();
        one_name::<crate::scene::Brdf>();
        one_name::<Tonemap>();
        one_name::<Aa>();
        one_name::<RenderPath>();
        one_name::<Msaa>();
        one_name::<ClusterBuilder>();
        for l in LayoutChoice::ALL.into_iter().filter(|l| *l != LayoutChoice::Fit) {
            assert_eq!(l.layout().name, l.name(), "the layout table's name");
        }
        for m in CullingMode::ALL {
            if let Some(method) = m.method() {
                assert_eq!(serde_json::to_value(method).unwrap().as_str(), Some(m.name().as_str()));
                assert_eq!(method.name(), m.name());
            }
        }
        // The old short names still load.
        assert_eq!(DepthFormat::parse("d24s8"), Ok(DepthFormat::Depth24PlusStencil8));
        assert_eq!(serde_json::from_str::<DepthFormat>("\"d32s8\"").unwrap(), DepthFormat::Depth32FloatStencil8);
        assert!(CullingMode::parse("stencil").unwrap_err().contains("one of fullscreen, volume, stencil-two-pass"));
    }

    #[test]
    fn bad_knob_values_are_clear_errors() {
        let bad = |s: Settings| s.validate().unwrap_err();
        for t in [1.0, -0.1, f32::NAN, f32::INFINITY] {
            assert!(bad(Settings { light_cutoff: t, ..Settings::default() }).contains("cut-off"), "{t}");
        }
        assert!(bad(Settings { sphere_subdivisions: 5, ..Settings::default() }).contains("sphere subdivisions 5"));
        assert!(bad(Settings { cone_sides: 2, ..Settings::default() }).contains("cone sides 2"));
        assert!(bad(Settings { cone_sides: 65, ..Settings::default() }).contains("between 3 and 64"));
        assert!(serde_json::from_str::<Settings>(r#"{"depth_format":"depth16"}"#).is_err());
        assert!(serde_json::from_str::<Settings>(r#"{"accumulation":"rgba8"}"#).is_err());
        let e = bad(Settings { msaa: Msaa::X4, ..Settings::default() });
        assert!(e.contains("deferred path cannot multisample"), "{e}");
        Settings { msaa: Msaa::X4, path: RenderPath::Forward, ..Settings::default() }.validate().unwrap();
    }

    #[test]
    fn the_cutoff_radius_is_where_the_attenuation_reaches_the_threshold() {
        let attenuation = |d: f32, r: f32| (1.0 - (d / r).powi(2)).clamp(0.0, 1.0).powi(2);
        assert_eq!(cutoff_radius(10.0, 0.0), 10.0);
        for t in [1.0 / 256.0, 1.0 / 64.0, 1.0 / 16.0, 0.5] {
            let r = cutoff_radius(10.0, t);
            assert!(r < 10.0);
            assert!((attenuation(r, 10.0) - t).abs() < 1e-5, "{t}: attenuation {} at {r}", attenuation(r, 10.0));
        }
        assert!((cutoff_radius(1.0, 1.0 / 16.0) - 0.75f32.sqrt()).abs() < 1e-6);
    }

    #[test]
    fn the_log_encoding_decodes_what_it_stores() {
        // Light L is stored as the 8-bit code nearest 255 * 2^-L; decoding is within the stated
        // bound for one write, and saturation decodes to the finite top of the range.
        for k in 0..=800 {
            let light = k as f32 / 100.0;
            let code = (255.0 * (-light).exp2()).round() / 255.0;
            let back = log_accum_decode(code);
            if light < LOG_ACCUM_MAX - 1.0 {
                let err = (back - light).abs();
                assert!(err <= log_accum_error_bound(light, 1), "{light}: decoded {back}");
            }
            assert!(back.is_finite() && back <= LOG_ACCUM_MAX);
        }
        assert_eq!(log_accum_decode(0.0), LOG_ACCUM_MAX);
        assert_eq!(log_accum_decode(1.0), 0.0);
    }
}
