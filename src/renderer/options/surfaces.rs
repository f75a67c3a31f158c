//! The options of `surfaces/`.

use super::{BlendedMode, BrdfOverride, DrawOrder, MaterialBranch};

/// The surfaces' options: how they are drawn, sorted, blended, lightmapped and shaded.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceOptions {
    /// The forward single-pass path draws depth first, so each pixel is shaded once (seed
    /// 002's "Z-cull"); off: shaded as drawn, overdraw included.
    pub depth_prepass: bool,
    /// The order of the opaque draws.
    pub draw_order: DrawOrder,
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
    /// Write ambient + sun into the light accumulation from the G-buffer pass itself (seed
    /// 000: its RT1 starts with them), instead of a full-screen pass of their own. Where the
    /// device cannot take the accumulation targets beside the G-buffer's (colour attachment
    /// bytes per sample), the own pass is used and the stats say so. A layout without an
    /// emissive target (`seed000`, `packed`) always writes them in the G-buffer pass, which also
    /// carries the surfaces' emission into the accumulation.
    pub ambient_in_gbuffer: bool,
    /// Shade every object with one reflectance model instead of its material's.
    pub brdf: BrdfOverride,
}
