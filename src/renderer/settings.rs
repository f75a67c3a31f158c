//! What the user chooses per frame: culling mode, G-buffer layout, debug view, counters.
//! Plain serde data, apart from GPU objects, so the viewer can persist it and
//! `lampshade render --settings FILE` can reproduce a screenshot.

use serde::{Deserialize, Serialize};

pub use super::options::caps::CapOrder;
pub use super::options::culling::{
    cutoff_radius, ClusterBuilder, CullingMode, ForwardLights, NearLights, CONE_SIDES_RANGE, DEFAULT_CONE_SIDES,
    DEFAULT_SPHERE_SUBDIVISIONS, MAX_LIGHTS_EVERY_MODE, MAX_SPHERE_SUBDIVISIONS,
};
pub use super::options::post::{Aa, Tonemap};
pub use super::options::shadows::{ShadowCube, ShadowFilter, ShadowFormat, ShadowMode};
pub use super::options::*;

/// Every knob's value, by the knob's name: the one flat struct the CLI, settings files, scripts
/// and the viewer name options by.
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

/// Each technique's options, built from the flat `Settings` in this one place: a technique
/// reads its own (and the frame's), never `Settings`.
impl Settings {
    pub fn frame_options(&self) -> super::options::FrameOptions {
        super::options::FrameOptions {
            path: self.path,
            msaa: self.msaa,
            debug_view: self.debug_view,
            selected_light: self.selected_light,
            reversed_z: self.reversed_z,
            count_fragments: self.count_fragments,
            count_ideal: self.count_ideal,
            per_light_stats: self.per_light_stats,
            timestamps: self.timestamps,
            accumulation: self.accumulation,
            depth_clamp: self.depth_clamp,
            depth_format: self.depth_format,
            depth_read: self.depth_read,
            layout: self.layout,
        }
    }

    pub fn culling_options(&self) -> super::options::culling::CullingOptions {
        super::options::culling::CullingOptions {
            culling: self.culling,
            near_lights: self.near_lights,
            light_cutoff: self.light_cutoff,
            tile_view_depth: self.tile_view_depth,
            sphere_subdivisions: self.sphere_subdivisions,
            cone_sides: self.cone_sides,
            forward_lights: self.forward_lights,
            light_batching: self.light_batching,
            cluster_build: self.cluster_build,
            lights_per_cluster: self.lights_per_cluster,
            lights_per_object: self.lights_per_object,
            cluster_tile: self.cluster_tile,
            cluster_budget: self.cluster_budget,
            cluster_slices: self.cluster_slices,
            first_slice_depth: self.first_slice_depth,
        }
    }

    pub fn caps_options(&self) -> super::options::caps::CapsOptions {
        super::options::caps::CapsOptions {
            max_lights: self.max_lights,
            light_distance: self.light_distance,
            cap_order: self.cap_order,
        }
    }

    pub fn shadow_options(&self) -> super::options::shadows::ShadowOptions {
        super::options::shadows::ShadowOptions {
            shadows: self.shadows,
            shadow_budget_mb: self.shadow_budget_mb,
            shadow_bias: self.shadow_bias,
            shadow_slope_bias: self.shadow_slope_bias,
            shadow_normal_offset: self.shadow_normal_offset,
            shadow_filter: self.shadow_filter,
            shadow_format: self.shadow_format,
            shadow_cascades: self.shadow_cascades,
            shadow_split_lambda: self.shadow_split_lambda,
            shadow_cube: self.shadow_cube,
        }
    }

    pub fn post_options(&self) -> super::options::post::PostOptions {
        super::options::post::PostOptions {
            exposure: self.exposure,
            tonemap: self.tonemap,
            auto_exposure: self.auto_exposure,
            adaptation_speed: self.adaptation_speed,
            target_luminance: self.target_luminance,
            bloom: self.bloom,
            bloom_threshold: self.bloom_threshold,
            bloom_intensity: self.bloom_intensity,
            lut: self.lut.clone(),
            fog: self.fog,
            fog_density: self.fog_density,
            fog_height_falloff: self.fog_height_falloff,
            dof: self.dof,
            focus_distance: self.focus_distance,
            aperture: self.aperture,
            vignette: self.vignette,
            aa: self.aa,
            distortion: self.distortion,
        }
    }

    pub fn surfaces_options(&self) -> super::options::surfaces::SurfaceOptions {
        super::options::surfaces::SurfaceOptions {
            depth_prepass: self.depth_prepass,
            draw_order: self.draw_order,
            blended: self.blended,
            lightmaps: self.lightmaps,
            lightmap_distance: self.lightmap_distance,
            peel_layers: self.peel_layers,
            material_branch: self.material_branch,
            anisotropy: self.anisotropy,
            ambient_in_gbuffer: self.ambient_in_gbuffer,
            brdf: self.brdf,
        }
    }

    /// Every technique's options.
    pub fn options(&self) -> super::options::Options {
        super::options::Options {
            frame: self.frame_options(),
            culling: self.culling_options(),
            caps: self.caps_options(),
            shadows: self.shadow_options(),
            post: self.post_options(),
            surfaces: self.surfaces_options(),
        }
    }
}
