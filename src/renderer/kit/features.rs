//! The flags a configuration's shader module is compiled with: which lookups and loops a scene
//! needs (`ShaderFeatures`, chosen by `program::ShaderFeatures::of`). Data only: each room says
//! what it needs (`ShadowCode::of`), `program.rs` assembles the source from them.

use crate::renderer::options::shadows::{ShadowCube, ShadowFilter, ShadowFormat};

/// The shadow lookups a configuration's shaders compile in (`program::ShaderFeatures`): the
/// lookups some light (or the sun) of `scene` can need under `st`, whatever the frame's budget
/// and view then grant. With no scene (a renderer not yet handed one), the lookups the settings
/// allow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShadowCode {
    /// The sun's cascades (`ls_sun_shadow`).
    pub sun: bool,
    /// One perspective tile a light (narrow spots).
    pub tiles: bool,
    /// Cubes (point lights, wide spots), where `st.shadow_cube` puts them.
    pub cubes: Option<ShadowCube>,
    /// The one kernel compiled in (`st.shadow_filter`).
    pub filter: ShadowFilter,
    /// The maps' depth format (`st.shadow_format`): the shadow pass's pipeline and the depth
    /// bias's format step (`LS_SHADOW_DEPTH_STEP`).
    pub format: ShadowFormat,
    /// Only the lights that cast this frame run the light lookups: the light pass draws the
    /// others with a pipeline compiled without them (`fs_light_plain`), and the tiled and
    /// clustered passes shade a list's casting lights in a loop of their own after the others
    /// (`LS_CASTERS_APART`). Set when lights can cast and at most half of the scene's lights
    /// may (`demo`'s 4 spots of 1,028 lights). lavapipe runs a branch's body whether or not a
    /// lane takes it, so in one shader every light pays for the lookup; with most lights
    /// casting, the second loop and pipelines would cost more than they save.
    pub casters_apart: bool,
}

/// The lookups a configuration's shaders compile in, from what the scene can need.
/// On lavapipe a fragment shader runs both sides of every branch under a lane mask, so a
/// lookup no light takes still costs every light at every pixel: with the shadow kernels and
/// the cookie compiled into `shade_light`, the clustered pass at 16,384 lights took 4.8× as
/// long as without them (`--shadows none` included, before this). A GPU that branches skips
/// them at run time; here they are left out when compiling. Each is a WGSL constant that the
/// shader's branches test (`LS_SUN_SHADOW`, `LS_TILE_SHADOWS`, `LS_CUBE_SHADOWS`,
/// `LS_CUBE_ARRAY`, `LS_CUBE_INDIRECT`, `LS_SHADOW_KERNEL`, `LS_COOKIES`), so the compiler drops what is off;
/// `LS_CASTERS_APART` (`ShadowCode::casters_apart`) moves the few casting lights of a tile or
/// cluster list into a loop of their own. Named in the stats' `shader_lookups`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShaderFeatures {
    pub shadows: ShadowCode,
    /// Some light projects a cookie.
    pub cookies: bool,
    /// The per-pixel light loops read the lights from the light planes (`records::planes_hold`:
    /// at most `records::UNIFORM_LIGHTS` lights, no cookies), not the storage buffer.
    pub light_planes: bool,
    /// The forward loops (`fs_forward`, `forward_single`) take two lights an iteration: the
    /// scene has more lights than lavapipe's loop limit lets a loop walk one at a time
    /// (`plan::FORWARD_LOOP_LIGHTS`), so some list may be longer. Other scenes compile the
    /// plain loops.
    pub paired_loops: bool,
    /// The reflectance models are picked by branching on the material ID
    /// (`MaterialBranch::Branch`, seed 002's "reasonably coherent dynamic branching"), not by
    /// computing every model's terms and selecting one.
    pub brdf_branch: bool,
    /// Some material samples a base-colour or emissive map. Without, the geometry passes
    /// sample neither (the maps would be the white defaults): lavapipe runs a sample inside a
    /// branch no lane takes anyway, so a per-object flag alone does not save it.
    pub colour_maps: bool,
}
