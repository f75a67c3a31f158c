//! The one declaration of every knob's field: `Settings` (`settings.rs`) is built from it with
//! each field's default, and each technique's options type (`FrameOptions`, `CullingOptions`,
//! …, in `mod.rs`) from the fields tagged with its technique, so a field is named, typed and
//! documented once.

/// Calls macro `$then` with `$args` and then every field of `Settings`, in its order (which is
/// the order settings files list the keys in), each as `[technique] name: Type = default,`
/// after its doc comment. The technique is the options type the field belongs to: `frame`,
/// `culling`, `caps`, `shadows`, `post`, `surfaces` or `stochastic`. The types and defaults are resolved where
/// `$then` expands.
macro_rules! settings_fields {
    ($then:ident $($args:tt)*) => {
        $then! {
            $($args)*
            /// The rendering pipeline (deferred shading, light pre-pass, forward single-/multi-pass).
            [frame] path: RenderPath = RenderPath::Deferred,
            /// Samples per pixel where the path can multisample; deferred refuses 4.
            [frame] msaa: Msaa = Msaa::X1,
            /// The forward single-pass path draws depth first, so each pixel is shaded once (seed
            /// 002's "Z-cull"); off: shaded as drawn, overdraw included.
            [surfaces] depth_prepass: bool = true,
            /// The G-buffer pass (deferred shading, the light pre-pass's pass 1) is preceded by a
            /// depth-only pass over the same draws (seed 002: "Do an initial front-to-back-sorted
            /// z-only pass"), and writes only the surfaces that pass kept.
            [surfaces] gbuffer_depth_prepass: bool = false,
            [culling] culling: CullingMode = CullingMode::default(),
            /// How lights crossing the near plane are drawn (seed 004's rule: full-screen).
            [culling] near_lights: NearLights = NearLights::default(),
            /// The order of the opaque draws.
            [surfaces] draw_order: DrawOrder = DrawOrder::default(),
            /// Where the passes after the G-buffer read depth: its copy or the depth buffer.
            [frame] depth_read: DepthRead = DepthRead::default(),
            /// How blended surfaces are composited (alpha, sorted; additive, unsorted; or peeled).
            [surfaces] blended: BlendedMode = BlendedMode::default(),
            /// Seed 004's lightmaps, where the scene's materials have them (`scene::Lightmap`); off:
            /// realtime lighting everywhere.
            [surfaces] lightmaps: bool = true,
            /// Seed 004's crossfade: view distance from which lightmapped surfaces are fully baked
            /// (realtime up to `records::LIGHTMAP_FADE_START` of it).
            [surfaces] lightmap_distance: f32 = 40.0,
            /// Layers `BlendedMode::Peeled` peels, 1 ..= `MAX_PEEL_LAYERS`: a pixel's nearest this many
            /// blended fragments are composited, the rest dropped.
            [surfaces] peel_layers: u32 = 4,
            /// How the lighting shaders pick the reflectance model (select or branch).
            [surfaces] material_branch: MaterialBranch = MaterialBranch::default(),
            /// The material sampler's anisotropy clamp, 1 ..= 16 (seed 002: "use aniso filtering
            /// during G-buffer pass"; 1: trilinear).
            [surfaces] anisotropy: u32 = 1,
            [frame] layout: LayoutChoice = LayoutChoice::default(),
            [frame] debug_view: DebugView = DebugView::Lit,
            /// Restrict the stencil and complexity views to one light.
            [frame] selected_light: Option<usize> = None,
            /// Store depth reversed (near = 1): better precision far away. The seeds' compare
            /// functions are written for standard depth and flipped when this is on.
            [frame] reversed_z: bool = false,
            [post] exposure: f32 = 1.0,
            /// Read back per-light occlusion counts (shaded fragments).
            [frame] count_fragments: bool = true,
            /// Also count the ideal: G-buffer points inside each light's true shape (costs a
            /// full-screen pass per light).
            [frame] count_ideal: bool = false,
            /// Build the stats' per-light table (`FrameStats::per_light`: each light's kind, method,
            /// screen share, shadow share and cost) in a frame that counts nothing. A counting frame
            /// always builds it (its counts are per light); a frame that neither counts nor asks pays
            /// nothing per light for its stats.
            [frame] per_light_stats: bool = false,
            /// Read back GPU timestamps.
            [frame] timestamps: bool = true,
            /// Format of the light accumulation targets.
            [frame] accumulation: AccumFormat = AccumFormat::default(),
            /// Use depth clamp on light volumes when the adapter has it. Off, lights whose volume
            /// crosses the far plane fall back to full-screen draws (the path for adapters without it).
            [frame] depth_clamp: bool = true,
            /// Format of the depth-stencil buffer.
            [frame] depth_format: DepthFormat = DepthFormat::default(),
            /// Cut each light off where its attenuation falls below this fraction of its peak (see
            /// [`cutoff_radius`]); 0 draws and shades the exact radius.
            [culling] light_cutoff: f32 = 0.0,
            /// The `tile-lights` view of a clustered frame: 0 shows each pixel's own cluster; a view
            /// depth d > 0 shows the slice of clusters at d across the whole screen.
            [culling] tile_view_depth: f32 = 0.0,
            /// Subdivisions of the icosphere bounding point lights (0 ..= 4).
            [culling] sphere_subdivisions: u32 = DEFAULT_SPHERE_SUBDIVISIONS,
            /// Sides of the pyramid bounding spot lights (3 ..= 64).
            [culling] cone_sides: u32 = DEFAULT_CONE_SIDES,
            /// Which lights the forward pass evaluates per blended fragment.
            [culling] forward_lights: ForwardLights = ForwardLights::default(),
            /// Write ambient + sun into the light accumulation from the G-buffer pass itself (seed
            /// 000: its RT1 starts with them), instead of a full-screen pass of their own. Where the
            /// device cannot take the accumulation targets beside the G-buffer's (colour attachment
            /// bytes per sample), the own pass is used and the stats say so. A layout without an
            /// emissive target (`seed000`, `packed`) always writes them in the G-buffer pass, which also
            /// carries the surfaces' emission into the accumulation.
            [surfaces] ambient_in_gbuffer: bool = true,
            /// Draw lights in instanced batches (`renderer::batches`): one draw per volume kind for
            /// plain volumes and full-screen lights, shared mark and shade draws for stencil-culled
            /// lights whose screen rectangles do not overlap. Off: a draw (or two) per light.
            [culling] light_batching: bool = true,
            /// Shade every object with one reflectance model instead of its material's.
            [surfaces] brdf: BrdfOverride = BrdfOverride::Scene,
            /// The tone curve of the post chain (`post::Tonemap`); ACES is the one compose always used.
            [post] tonemap: Tonemap = Tonemap::Aces,
            /// Auto-exposure: a luminance histogram each frame, the exposure adapting towards
            /// `target_luminance` / (the frame's geometric mean luminance), time-stepped at a fixed
            /// 1/60 s per frame. `exposure` stays a factor on top (exposure compensation).
            [post] auto_exposure: bool = false,
            /// Adaptation speed of auto-exposure, per second: each frame moves the adapted log2
            /// luminance by `1 - exp(-speed / 60)` of the way to the frame's.
            [post] adaptation_speed: f32 = 2.0,
            /// The luminance auto-exposure maps the frame's geometric mean to (middle grey, 0.18).
            [post] target_luminance: f32 = 0.18,
            /// Bloom: a bright pass above `bloom_threshold`, a 5-level downsample/upsample chain, added
            /// back times `bloom_intensity`.
            [post] bloom: bool = false,
            /// Luminance above which a pixel blooms (the part above it blooms, hue kept).
            [post] bloom_threshold: f32 = 1.0,
            /// Factor on the bloom added back.
            [post] bloom_intensity: f32 = 0.1,
            /// Colour grading: a `.cube` 3D LUT file, or `identity` (built in); `None`: no grading.
            [post] lut: Option<String> = None,
            /// Fog (after grading, seed 002's order): distance fog with an exponential height falloff,
            /// towards the background colour.
            [post] fog: bool = false,
            /// Fog density per unit of distance at the camera's height.
            [post] fog_density: f32 = 0.02,
            /// Exponential falloff of the fog's density per unit of height above the camera (0: plain
            /// distance fog).
            [post] fog_height_falloff: f32 = 0.1,
            /// Depth of field: a gather blur by each pixel's circle of confusion.
            [post] dof: bool = false,
            /// What is in focus: `auto` (the surface at the screen's centre, read on the GPU; see
            /// [`Focus::Auto`]) or a fixed view distance.
            [post] focus_distance: Focus = Focus::Auto,
            /// Circle of confusion diameter in pixels at infinite distance: CoC = aperture x |z - focus| / z,
            /// at most `post::MAX_COC` px.
            [post] aperture: f32 = 8.0,
            /// Vignette strength: the corners are darkened by this fraction (0: off).
            [post] vignette: f32 = 0.0,
            /// Anti-aliasing, before fog in the chain (seed 002's order): seed 002's edge blur from
            /// G-buffer discontinuities, or FXAA.
            [post] aa: Aa = Aa::Off,
            /// Seed 002's distortion (before edge smoothing in the chain): the picture behind each
            /// distorting material (`Material::distortion`) shifted by its view-space normal.
            [post] distortion: bool = false,
            /// Which lights cast shadows (`renderer::shadows`): none, the sun, the sun and
            /// spots, or every light. A light's own `cast_shadows` flag can only turn it off.
            [shadows] shadows: ShadowMode = ShadowMode::Spots,
            /// The shadow atlas's byte budget in MiB (one Depth32Float texture; its side is the largest
            /// power of two that fits, up to the device's limit). With `shadow_cube` = `array` the atlas
            /// and the cube array share it (`shadows::cube_array_fit`).
            [shadows] shadow_budget_mb: f32 = 16.0,
            /// Constant depth bias, in shadow-map texels (projected to world units at the receiver).
            [shadows] shadow_bias: f32 = 1.0,
            /// Slope-scaled depth bias: texels x tan(angle between the normal and the light).
            [shadows] shadow_slope_bias: f32 = 1.0,
            /// Normal offset: the lookup point moves this many texels along the surface normal beyond
            /// the filter's own reach (`ShadowFilter::reach`).
            [shadows] shadow_normal_offset: f32 = 1.0,
            /// The filter kernel of the shadow lookup.
            [shadows] shadow_filter: ShadowFilter = ShadowFilter::Pcf3x3,
            /// The shadow maps' depth format (seed 002: D16 or D24).
            [shadows] shadow_format: ShadowFormat = ShadowFormat::Depth32,
            /// Sun cascades (1 ..= 4) over the view frustum.
            [shadows] shadow_cascades: u32 = 3,
            /// Cascade splits: lambda x logarithmic + (1 - lambda) x uniform.
            [shadows] shadow_split_lambda: f32 = 0.7,
            /// Who builds the clustered mode's lists.
            [culling] cluster_build: ClusterBuilder = ClusterBuilder::Cpu,
            /// Where point lights' (and wide spots') six shadow faces live: tiles of the atlas
            /// (`unrolled`) or layers of a cube-array texture (`array`).
            [shadows] shadow_cube: ShadowCube = ShadowCube::Unrolled,
            /// Engine-style caps (`caps`): lights kept per camera (0: every light).
            [caps] max_lights: u32 = 0,
            /// Lights whose sphere lies wholly farther than this from the camera are dropped (0: none).
            [caps] light_distance: f32 = 0.0,
            /// Lights kept per cluster of the clustered mode's lists (0: every light).
            [culling] lights_per_cluster: u32 = 0,
            /// Lights kept per object in the forward paths' lists (0: every light).
            [culling] lights_per_object: u32 = 0,
            /// Which lights a cap keeps: the first in scene order, the nearest, or the brightest.
            [caps] cap_order: CapOrder = CapOrder::default(),
            /// The clustered grid's tile side in pixels (0: the default, or what `cluster_budget` gives).
            [culling] cluster_tile: u32 = 0,
            /// The clustered grid's cell budget (0: none): the tiles Bevy's `ClusterConfig::FixedZ`
            /// gives for this many cells over `cluster_slices` slices, made square.
            [culling] cluster_budget: u32 = 0,
            /// The clustered grid's depth slices (0: the default).
            [culling] cluster_slices: u32 = 0,
            /// The clustered grid's first slice runs from the eye to this view depth, the rest
            /// exponentially to the farthest light (Bevy's `ClusterZConfig`); 0 spreads every slice
            /// exponentially over the depths the lights reach.
            [culling] first_slice_depth: f32 = 0.0,
            /// Reservoir-resampled lighting (RIS; Talbot et al. 2005, Bitterli et al. 2020) on the
            /// list modes (tiled, clustered, z-binned): the samples K each pixel keeps and shades
            /// with its shadow, each chosen by weighted reservoir sampling from `ris_candidates`
            /// lights drawn uniformly from the pixel's list; 0: every listed light shaded exactly.
            [stochastic] ris_samples: u32 = 0,
            /// The candidates M each RIS sample is drawn from (its cost: M unshadowed evaluations).
            [stochastic] ris_candidates: u32 = 8,
            /// ReSTIR's spatial reuse (Bitterli et al. 2020, with its unbiased 1/Z weights): each
            /// RIS sample is combined with this many neighbours' samples within 16 pixels, those
            /// with another depth or normal left out; 0: off.
            [stochastic] ris_spatial: u32 = 0,
            /// ReSTIR's temporal reuse: each RIS sample is combined with the last frame's final
            /// sample at the point reprojected through the last camera (rejected on depth and
            /// normal), its count capped at 20 M. Biased where the surface or the lights changed
            /// (the 1/M weights); docs/stochastic.md measures it.
            [stochastic] ris_temporal: bool = false,
            /// A denoiser for RIS's light: temporal accumulation and a variance-guided, edge-aware
            /// a-trous filter (Schied et al. 2017, SVGF). Biased by design; the bench measures it.
            [stochastic] ris_denoise: bool = false,
            /// Stochastic light culling (Tokuyoshi and Harada 2016), on every culling mode: each
            /// light's range is drawn anew for the frame and its attenuation below
            /// `stochastic_threshold` compensated, so the frame's expectation is the exact sum.
            [stochastic] stochastic_culling: bool = false,
            /// The attenuation below which stochastic culling randomises a light (0 < t <= 1): at
            /// distance d the light adds with probability min(1, a(d) / t), as max(a(d), t).
            [stochastic] stochastic_threshold: f32 = 0.25,
            /// The seed of every random number the stochastic estimators draw: the same seed gives
            /// the same frame, byte for byte.
            [stochastic] noise_seed: u32 = 0,
            /// For the unbiasedness tests only: the stochastic estimators weight the lights of odd
            /// index by this factor (1: no bias), so a test can show that it catches a known bias.
            [stochastic] planted_bias: f32 = 1.0,
        }
    };
}

/// Sorts the fields of [`settings_fields`] by technique and calls macro `$then` with the seven
/// lists, each field as `name: Type,` after its doc comment:
/// `$then! { frame { … } culling { … } caps { … } shadows { … } post { … } surfaces { … } stochastic { … } }`.
/// Invoked as `settings_fields!(by_technique @sort $then {} {} {} {} {} {} {})`.
macro_rules! by_technique {
    (@sort $then:ident {$($frame:tt)*} {$($culling:tt)*} {$($caps:tt)*} {$($shadows:tt)*} {$($post:tt)*} {$($surfaces:tt)*} {$($stochastic:tt)*}) => {
        $then! {
            frame { $($frame)* }
            culling { $($culling)* }
            caps { $($caps)* }
            shadows { $($shadows)* }
            post { $($post)* }
            surfaces { $($surfaces)* }
            stochastic { $($stochastic)* }
        }
    };
    (@sort $then:ident {$($frame:tt)*} $culling:tt $caps:tt $shadows:tt $post:tt $surfaces:tt $stochastic:tt
        $(#[$m:meta])* [frame] $f:ident: $t:ty = $d:expr, $($rest:tt)*) => {
        by_technique! { @sort $then {$($frame)* $(#[$m])* $f: $t,} $culling $caps $shadows $post $surfaces $stochastic $($rest)* }
    };
    (@sort $then:ident $frame:tt {$($culling:tt)*} $caps:tt $shadows:tt $post:tt $surfaces:tt $stochastic:tt
        $(#[$m:meta])* [culling] $f:ident: $t:ty = $d:expr, $($rest:tt)*) => {
        by_technique! { @sort $then $frame {$($culling)* $(#[$m])* $f: $t,} $caps $shadows $post $surfaces $stochastic $($rest)* }
    };
    (@sort $then:ident $frame:tt $culling:tt {$($caps:tt)*} $shadows:tt $post:tt $surfaces:tt $stochastic:tt
        $(#[$m:meta])* [caps] $f:ident: $t:ty = $d:expr, $($rest:tt)*) => {
        by_technique! { @sort $then $frame $culling {$($caps)* $(#[$m])* $f: $t,} $shadows $post $surfaces $stochastic $($rest)* }
    };
    (@sort $then:ident $frame:tt $culling:tt $caps:tt {$($shadows:tt)*} $post:tt $surfaces:tt $stochastic:tt
        $(#[$m:meta])* [shadows] $f:ident: $t:ty = $d:expr, $($rest:tt)*) => {
        by_technique! { @sort $then $frame $culling $caps {$($shadows)* $(#[$m])* $f: $t,} $post $surfaces $stochastic $($rest)* }
    };
    (@sort $then:ident $frame:tt $culling:tt $caps:tt $shadows:tt {$($post:tt)*} $surfaces:tt $stochastic:tt
        $(#[$m:meta])* [post] $f:ident: $t:ty = $d:expr, $($rest:tt)*) => {
        by_technique! { @sort $then $frame $culling $caps $shadows {$($post)* $(#[$m])* $f: $t,} $surfaces $stochastic $($rest)* }
    };
    (@sort $then:ident $frame:tt $culling:tt $caps:tt $shadows:tt $post:tt {$($surfaces:tt)*} $stochastic:tt
        $(#[$m:meta])* [surfaces] $f:ident: $t:ty = $d:expr, $($rest:tt)*) => {
        by_technique! { @sort $then $frame $culling $caps $shadows $post {$($surfaces)* $(#[$m])* $f: $t,} $stochastic $($rest)* }
    };
    (@sort $then:ident $frame:tt $culling:tt $caps:tt $shadows:tt $post:tt $surfaces:tt {$($stochastic:tt)*}
        $(#[$m:meta])* [stochastic] $f:ident: $t:ty = $d:expr, $($rest:tt)*) => {
        by_technique! { @sort $then $frame $culling $caps $shadows $post $surfaces {$($stochastic)* $(#[$m])* $f: $t,} $($rest)* }
    };
}

pub(crate) use {by_technique, settings_fields};
