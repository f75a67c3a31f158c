//! The knobs' table: a row per [`Settings`](crate::renderer::Settings) field, in the order
//! `--help` and the script documentation list them.
// tidy-filelength: one row per knob, the one list the CLI, settings files, scripts and the viewer read

use super::{choice, names, number, parse_switch, switch_name, whole, Knob, Values};
use crate::renderer::presets::{Preset, CUSTOM};
use crate::renderer::settings::{
    name_of, Aa, AccumFormat, BlendedMode, BrdfOverride, CapOrder, ClusterBuilder, CullingMode, DebugView, DepthFormat,
    DepthRead, DrawOrder, Focus, ForwardLights, LayoutChoice, MaterialBranch, Msaa, NearLights, RenderPath, ShadowCube,
    ShadowFilter, ShadowFormat, ShadowMode, Tonemap, CONE_SIDES_RANGE, MAX_SPHERE_SUBDIVISIONS,
};

/// Every knob, in the order `--help` and the script documentation list them.
pub const KNOBS: &[Knob] = &[
    // First: the flags and keys after it apply on top of the preset.
    Knob {
        name: "preset",
        what: "preset",
        help: "A seed's pipeline as the seed writes it (seed000 .. seed004; docs/presets.md), or the defaults; \
               the other knobs given apply on top; reads `custom` when the settings are no preset's",
        values: Values::Choice(names::<Preset>),
        cli: true,
        get: |s| Preset::of(s).map_or_else(|| CUSTOM.to_string(), |p| name_of(&p)),
        put: |s, v| {
            if v == CUSTOM {
                return Ok(());
            }
            *s = choice::<Preset>("preset", v)?.apply(s)?;
            Ok(())
        },
    },
    Knob {
        name: "path",
        what: "rendering path",
        help: "Rendering path: deferred shading, light pre-pass (deferred lighting), forward single- or multi-pass",
        values: Values::Choice(names::<RenderPath>),
        cli: true,
        get: |s| name_of(&s.path),
        put: |s, v| {
            s.path = choice("rendering path", v)?;
            Ok(())
        },
    },
    Knob {
        name: "msaa",
        what: "MSAA sample count",
        help: "Samples per pixel (1 or 4); the light pre-pass and forward paths can multisample, deferred cannot",
        values: Values::Choice(names::<Msaa>),
        cli: true,
        get: |s| name_of(&s.msaa),
        put: |s, v| {
            s.msaa = choice("MSAA sample count", v)?;
            Ok(())
        },
    },
    Knob {
        name: "depth-prepass",
        what: "depth pre-pass",
        help: "Forward single-pass: draw depth first so each pixel is shaded once (off: overdraw shaded)",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.depth_prepass),
        put: |s, v| {
            s.depth_prepass = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "gbuffer-depth-prepass",
        what: "G-buffer depth pre-pass",
        help: "Deferred and light pre-pass: a depth-only pass before the G-buffer pass, which then writes only the kept surfaces",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.gbuffer_depth_prepass),
        put: |s, v| {
            s.gbuffer_depth_prepass = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "culling",
        what: "culling mode",
        help: "How light volumes are culled",
        values: Values::Choice(names::<CullingMode>),
        cli: true,
        get: |s| name_of(&s.culling),
        put: |s, v| {
            s.culling = choice("culling mode", v)?;
            Ok(())
        },
    },
    Knob {
        name: "near-lights",
        what: "near-plane rule",
        help: "Lights whose volume crosses the near plane: by the culling mode's method (volume) or full-screen \
               (fullscreen, seed 004's rule)",
        values: Values::Choice(names::<NearLights>),
        cli: true,
        get: |s| name_of(&s.near_lights),
        put: |s, v| {
            s.near_lights = choice("near-plane rule", v)?;
            Ok(())
        },
    },
    Knob {
        name: "draw-order",
        what: "draw order",
        help: "Order of the opaque draws: by material (fewest state changes) or front-to-back (seed 002; fewer \
               fragments shaded)",
        values: Values::Choice(names::<DrawOrder>),
        cli: true,
        get: |s| name_of(&s.draw_order),
        put: |s, v| {
            s.draw_order = choice("draw order", v)?;
            Ok(())
        },
    },
    Knob {
        name: "depth-read",
        what: "depth read",
        help: "Where the passes after the G-buffer read depth: its R32F copy, or the depth buffer itself (seeds \
               003 and 004; stencil-free culling modes only, else the copy, and the stats say why)",
        values: Values::Choice(names::<DepthRead>),
        cli: true,
        get: |s| name_of(&s.depth_read),
        put: |s, v| {
            s.depth_read = choice("depth read", v)?;
            Ok(())
        },
    },
    Knob {
        name: "blended",
        what: "blending of blended surfaces",
        help: "Blended surfaces: alpha blending, sorted back to front; additive (seed 003), unsorted; or depth \
               peeling (seed 002), in depth order per pixel",
        values: Values::Choice(names::<BlendedMode>),
        cli: true,
        get: |s| name_of(&s.blended),
        put: |s, v| {
            s.blended = choice("blending of blended surfaces", v)?;
            Ok(())
        },
    },
    Knob {
        name: "peel-layers",
        what: "depth peeling layers",
        help: "Layers --blended peeled peels: each pixel's nearest N blended fragments are composited in depth \
               order, any behind them dropped",
        values: Values::Whole { min: 1, max: crate::renderer::settings::MAX_PEEL_LAYERS },
        cli: true,
        get: |s| s.peel_layers.to_string(),
        put: |s, v| {
            s.peel_layers = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "material-branch",
        what: "material selection",
        help: "How the lighting shaders pick a pixel's reflectance model: compute every model and select (select) \
               or branch on the material ID (branch, seed 002); the same values",
        values: Values::Choice(names::<MaterialBranch>),
        cli: true,
        get: |s| name_of(&s.material_branch),
        put: |s, v| {
            s.material_branch = choice("material selection", v)?;
            Ok(())
        },
    },
    Knob {
        name: "anisotropy",
        what: "anisotropic filtering",
        help: "The material textures' anisotropic filtering: up to N samples along a footprint (1: trilinear; \
               seed 002 asks for it in the G-buffer pass)",
        values: Values::Whole { min: 1, max: 16 },
        cli: true,
        get: |s| s.anisotropy.to_string(),
        put: |s, v| {
            s.anisotropy = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "cluster-build",
        what: "cluster list builder",
        help: "Who builds the clustered mode's light lists: the CPU (uploaded) or the GPU (from each light's span)",
        values: Values::Choice(names::<ClusterBuilder>),
        cli: true,
        get: |s| name_of(&s.cluster_build),
        put: |s, v| {
            s.cluster_build = choice("cluster list builder", v)?;
            Ok(())
        },
    },
    Knob {
        name: "max-lights",
        what: "lights per camera",
        help: "Keep at most this many lights per frame, by the cap order (0 = every light)",
        values: Values::Whole { min: 0, max: 1 << 24 },
        cli: true,
        get: |s| s.max_lights.to_string(),
        put: |s, v| {
            s.max_lights = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "light-distance",
        what: "light distance cut-off",
        help: "Drop lights whose sphere lies wholly beyond this distance from the camera (0 = none)",
        values: Values::Float { min: 0.0, max: 1e12, open: (false, false), slider: (0.0, 200.0) },
        cli: true,
        get: |s| s.light_distance.to_string(),
        put: |s, v| {
            s.light_distance = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "lights-per-cluster",
        what: "lights per cluster",
        help: "Keep at most this many lights in each cluster's list, by the cap order (clustered; 0 = every light)",
        values: Values::Whole { min: 0, max: 1 << 24 },
        cli: true,
        get: |s| s.lights_per_cluster.to_string(),
        put: |s, v| {
            s.lights_per_cluster = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "lights-per-object",
        what: "lights per object",
        help: "Keep at most this many lights in each object's list, by the cap order (forward paths; 0 = every light)",
        values: Values::Whole { min: 0, max: 1 << 24 },
        cli: true,
        get: |s| s.lights_per_object.to_string(),
        put: |s, v| {
            s.lights_per_object = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "cap-order",
        what: "cap order",
        help: "Which lights a cap keeps: the first in scene order, the nearest, or the brightest",
        values: Values::Choice(names::<CapOrder>),
        cli: true,
        get: |s| name_of(&s.cap_order),
        put: |s, v| {
            s.cap_order = choice("cap order", v)?;
            Ok(())
        },
    },
    Knob {
        name: "cluster-tile",
        what: "cluster tile",
        help: "The clustered grid's tile side in pixels (0 = 32, or what cluster-budget gives)",
        values: Values::Whole { min: 0, max: 4096 },
        cli: true,
        get: |s| s.cluster_tile.to_string(),
        put: |s, v| {
            s.cluster_tile = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "cluster-budget",
        what: "cluster budget",
        help: "Cells of the clustered grid: tiles as Bevy's FixedZ rule gives them for this total over cluster-slices (0 = none)",
        values: Values::Whole { min: 0, max: 1 << 22 },
        cli: true,
        get: |s| s.cluster_budget.to_string(),
        put: |s, v| {
            s.cluster_budget = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "cluster-slices",
        what: "cluster slices",
        help: "Depth slices of the clustered grid (0 = 64)",
        values: Values::Whole { min: 0, max: 1024 },
        cli: true,
        get: |s| s.cluster_slices.to_string(),
        put: |s, v| {
            s.cluster_slices = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "first-slice-depth",
        what: "first slice depth",
        help: "The clustered grid's first slice ends at this view depth, the rest exponential to the farthest light (0 = all exponential over the lights' depths)",
        values: Values::Float { min: 0.0, max: 1e9, open: (false, false), slider: (0.0, 50.0) },
        cli: true,
        get: |s| s.first_slice_depth.to_string(),
        put: |s, v| {
            s.first_slice_depth = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "layout",
        what: "layout",
        help: "G-buffer layout",
        values: Values::Choice(names::<LayoutChoice>),
        cli: true,
        get: |s| name_of(&s.layout),
        put: |s, v| {
            s.layout = choice("layout", v)?;
            Ok(())
        },
    },
    Knob {
        name: "debug-view",
        what: "view",
        help: "What the frame shows: the lit picture or one of the debug views",
        values: Values::Choice(names::<DebugView>),
        cli: true,
        get: |s| name_of(&s.debug_view),
        put: |s, v| {
            s.debug_view = choice("view", v)?;
            Ok(())
        },
    },
    Knob {
        name: "brdf",
        what: "reflectance model",
        help: "Shade every object with one reflectance model instead of its material's (scene: each its own)",
        values: Values::Choice(names::<BrdfOverride>),
        cli: true,
        get: |s| name_of(&s.brdf),
        put: |s, v| {
            s.brdf = choice("reflectance model", v)?;
            Ok(())
        },
    },
    Knob {
        name: "accumulation",
        what: "accumulation format",
        help: "Light accumulation format",
        values: Values::Choice(names::<AccumFormat>),
        cli: true,
        get: |s| name_of(&s.accumulation),
        put: |s, v| {
            s.accumulation = choice("accumulation format", v)?;
            Ok(())
        },
    },
    Knob {
        name: "depth-format",
        what: "depth format",
        help: "Depth-stencil format",
        values: Values::Choice(names::<DepthFormat>),
        cli: true,
        get: |s| name_of(&s.depth_format),
        put: |s, v| {
            s.depth_format = choice("depth format", v)?;
            Ok(())
        },
    },
    Knob {
        name: "tile-view-depth",
        what: "tile view depth",
        help: "The tile-lights view of a clustered frame: 0 shows each pixel's own cluster; a view depth shows the slice of clusters there",
        values: Values::Float { min: 0.0, max: 1e9, open: (false, false), slider: (0.0, 100.0) },
        cli: true,
        get: |s| s.tile_view_depth.to_string(),
        put: |s, v| {
            s.tile_view_depth = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "light-cutoff",
        what: "light cut-off",
        help: "Cut lights off where they fall below this fraction of their peak (0 = exact radius)",
        // 1 would remove the light; the slider covers cut-offs up to a quarter of the peak.
        values: Values::Float { min: 0.0, max: 1.0, open: (false, true), slider: (0.0, 0.25) },
        cli: true,
        get: |s| s.light_cutoff.to_string(),
        put: |s, v| {
            s.light_cutoff = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "sphere-subdivisions",
        what: "sphere subdivisions",
        help: "Subdivisions of the point lights' bounding icosphere",
        values: Values::Whole { min: 0, max: MAX_SPHERE_SUBDIVISIONS },
        cli: true,
        get: |s| s.sphere_subdivisions.to_string(),
        put: |s, v| {
            s.sphere_subdivisions = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "cone-sides",
        what: "cone sides",
        help: "Sides of the spot lights' bounding pyramid",
        values: Values::Whole { min: *CONE_SIDES_RANGE.start(), max: *CONE_SIDES_RANGE.end() },
        cli: true,
        get: |s| s.cone_sides.to_string(),
        put: |s, v| {
            s.cone_sides = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "forward-lights",
        what: "forward light list",
        help: "Lights the forward pass evaluates per blended fragment",
        values: Values::Choice(names::<ForwardLights>),
        cli: true,
        get: |s| name_of(&s.forward_lights),
        put: |s, v| {
            s.forward_lights = choice("forward light list", v)?;
            Ok(())
        },
    },
    Knob {
        name: "exposure",
        what: "exposure",
        help: "Exposure: a factor on the lit picture before tonemapping",
        values: Values::Float { min: 0.0, max: 1e6, open: (true, true), slider: (0.05, 16.0) },
        cli: true,
        get: |s| s.exposure.to_string(),
        put: |s, v| {
            s.exposure = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "reversed-z",
        what: "reversed Z",
        help: "Store depth reversed (near = 1)",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.reversed_z),
        put: |s, v| {
            s.reversed_z = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "ambient-in-gbuffer",
        what: "ambient + sun in the G-buffer pass",
        help: "Write ambient + sun into the light accumulation from the G-buffer pass (seed 000) instead of a full-screen pass",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.ambient_in_gbuffer),
        put: |s, v| {
            s.ambient_in_gbuffer = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "depth-clamp",
        what: "depth clamp",
        help: "Depth clamp on light volumes (off: volumes crossing the near or far plane go full-screen)",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.depth_clamp),
        put: |s, v| {
            s.depth_clamp = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "light-batching",
        what: "light batching",
        help: "Draw lights in instanced batches (off: a draw per light, the same picture)",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.light_batching),
        put: |s, v| {
            s.light_batching = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "tonemap",
        what: "tonemap",
        help: "Tone curve of the post chain",
        values: Values::Choice(names::<Tonemap>),
        cli: true,
        get: |s| name_of(&s.tonemap),
        put: |s, v| {
            s.tonemap = choice("tonemap", v)?;
            Ok(())
        },
    },
    Knob {
        name: "auto-exposure",
        what: "auto-exposure",
        help: "Adapt the exposure to the frame's luminance histogram (1/60 s per frame)",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.auto_exposure),
        put: |s, v| {
            s.auto_exposure = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "adaptation-speed",
        what: "adaptation speed",
        help: "Auto-exposure adaptation speed, per second (each frame moves 1 - exp(-speed/60) of the way)",
        values: Values::Float { min: 0.0, max: 1e4, open: (true, false), slider: (0.1, 20.0) },
        cli: true,
        get: |s| s.adaptation_speed.to_string(),
        put: |s, v| {
            s.adaptation_speed = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "target-luminance",
        what: "target luminance",
        help: "Luminance auto-exposure maps the frame's geometric mean to",
        values: Values::Float { min: 0.0, max: 1e3, open: (true, false), slider: (0.02, 1.0) },
        cli: true,
        get: |s| s.target_luminance.to_string(),
        put: |s, v| {
            s.target_luminance = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "bloom",
        what: "bloom",
        help: "Bloom: bright pass, 5-level downsample/upsample chain, added back",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.bloom),
        put: |s, v| {
            s.bloom = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "bloom-threshold",
        what: "bloom threshold",
        help: "Luminance above which pixels bloom (the part above it)",
        values: Values::Float { min: 0.0, max: 1e6, open: (false, false), slider: (0.0, 8.0) },
        cli: true,
        get: |s| s.bloom_threshold.to_string(),
        put: |s, v| {
            s.bloom_threshold = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "bloom-intensity",
        what: "bloom intensity",
        help: "Factor on the bloom added back",
        values: Values::Float { min: 0.0, max: 100.0, open: (false, false), slider: (0.0, 1.0) },
        cli: true,
        get: |s| s.bloom_intensity.to_string(),
        put: |s, v| {
            s.bloom_intensity = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "lut",
        what: "colour grading LUT",
        help: "Colour grading: a .cube 3D LUT file, identity (built in) or none",
        values: Values::File,
        cli: true,
        get: |s| s.lut.clone().unwrap_or_else(|| "none".into()),
        put: |s, v| {
            s.lut = match v.trim() {
                "none" | "" => None,
                name => {
                    // Read now, so a bad file is an error where it is named; the renderer
                    // reads it again when it changes.
                    crate::renderer::post::Lut::load(name)?;
                    Some(name.to_string())
                }
            };
            Ok(())
        },
    },
    Knob {
        name: "fog",
        what: "fog",
        help: "Fog: distance with an exponential height falloff, towards the background colour",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.fog),
        put: |s, v| {
            s.fog = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "fog-density",
        what: "fog density",
        help: "Fog density per unit of distance at the camera's height",
        values: Values::Float { min: 0.0, max: 1e3, open: (false, false), slider: (0.0, 0.2) },
        cli: true,
        get: |s| s.fog_density.to_string(),
        put: |s, v| {
            s.fog_density = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "fog-height-falloff",
        what: "fog height falloff",
        help: "Exponential falloff of the fog's density per unit of height above the camera (0: distance fog)",
        values: Values::Float { min: 0.0, max: 1e3, open: (false, false), slider: (0.0, 2.0) },
        cli: true,
        get: |s| s.fog_height_falloff.to_string(),
        put: |s, v| {
            s.fog_height_falloff = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "dof",
        what: "depth of field",
        help: "Depth of field: a gather blur by each pixel's circle of confusion",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.dof),
        put: |s, v| {
            s.dof = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "focus-distance",
        what: "focus distance",
        help: "What is in focus: auto (the surface at the screen's centre; the scene's distance where that is \
               sky) or a view distance",
        values: Values::FloatOrAuto { min: 0.0, max: 1e7, open: (true, false), slider: (0.5, 100.0) },
        cli: true,
        get: |s| s.focus_distance.name(),
        put: |s, v| {
            s.focus_distance = Focus::parse(v)?;
            Ok(())
        },
    },
    Knob {
        name: "aperture",
        what: "aperture",
        help: "Circle of confusion in pixels at infinity (CoC = aperture |z - focus| / z, at most 16 px)",
        values: Values::Float { min: 0.0, max: 1e3, open: (false, false), slider: (0.0, 32.0) },
        cli: true,
        get: |s| s.aperture.to_string(),
        put: |s, v| {
            s.aperture = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "vignette",
        what: "vignette",
        help: "Vignette strength: the fraction the corners are darkened by (0 = off)",
        values: Values::Float { min: 0.0, max: 1.0, open: (false, false), slider: (0.0, 1.0) },
        cli: true,
        get: |s| s.vignette.to_string(),
        put: |s, v| {
            s.vignette = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "lightmaps",
        what: "lightmaps",
        help: "Seed 004's lightmaps, where the scene's materials have them (`lampshade bake`): near the camera realtime \
               light plus the baked occlusion, crossfading to fully baked light by --lightmap-distance",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.lightmaps),
        put: |s, v| {
            s.lightmaps = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "lightmap-distance",
        what: "lightmap distance",
        help: "View distance from which lightmapped surfaces are fully baked; the crossfade starts at 0.8 of it",
        values: Values::Float { min: 0.0, max: 1e6, open: (true, false), slider: (1.0, 200.0) },
        cli: true,
        get: |s| s.lightmap_distance.to_string(),
        put: |s, v| {
            s.lightmap_distance = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "distortion",
        what: "distortion",
        help: "Distortion (seed 002's post chain): the picture behind a material with a distortion strength shifted by its view-space normal",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.distortion),
        put: |s, v| {
            s.distortion = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "aa",
        what: "anti-aliasing",
        help: "Anti-aliasing: seed 002's edge blur (G-buffer depth and normal discontinuities) or FXAA",
        values: Values::Choice(names::<Aa>),
        cli: true,
        get: |s| name_of(&s.aa),
        put: |s, v| {
            s.aa = choice("anti-aliasing", v)?;
            Ok(())
        },
    },
    Knob {
        name: "shadows",
        what: "shadow casters",
        help: "Which lights cast shadows: none, sun, spots (the sun and spots) or all (points too)",
        values: Values::Choice(names::<ShadowMode>),
        cli: true,
        get: |s| name_of(&s.shadows),
        put: |s, v| {
            s.shadows = choice("shadow casters", v)?;
            Ok(())
        },
    },
    Knob {
        name: "shadow-budget",
        what: "shadow atlas budget",
        help: "Shadow atlas byte budget in MiB (at --shadow-format's bytes a texel; the side is the largest power of two that fits; with --shadow-cube array, the atlas and the cube array share it)",
        values: Values::Float { min: 0.25, max: 1024.0, open: (false, false), slider: (1.0, 64.0) },
        cli: true,
        get: |s| s.shadow_budget_mb.to_string(),
        put: |s, v| {
            s.shadow_budget_mb = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "shadow-bias",
        what: "shadow depth bias",
        help: "Constant shadow depth bias, in shadow-map texels at the receiver",
        values: Values::Float { min: 0.0, max: 100.0, open: (false, false), slider: (0.0, 4.0) },
        cli: true,
        get: |s| s.shadow_bias.to_string(),
        put: |s, v| {
            s.shadow_bias = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "shadow-slope-bias",
        what: "shadow slope bias",
        help: "Slope-scaled shadow depth bias: texels x tan(angle to the light), tan at most 10",
        values: Values::Float { min: 0.0, max: 100.0, open: (false, false), slider: (0.0, 4.0) },
        cli: true,
        get: |s| s.shadow_slope_bias.to_string(),
        put: |s, v| {
            s.shadow_slope_bias = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "shadow-normal-offset",
        what: "shadow normal offset",
        help: "Shadow lookups move this many texels along the surface normal, beyond the filter's reach (1, 2 or 3 texels)",
        values: Values::Float { min: 0.0, max: 100.0, open: (false, false), slider: (0.0, 4.0) },
        cli: true,
        get: |s| s.shadow_normal_offset.to_string(),
        put: |s, v| {
            s.shadow_normal_offset = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "shadow-filter",
        what: "shadow filter",
        help: "Shadow filter kernel: hardware 2x2 PCF, 3x3 of them, or 16 Poisson taps",
        values: Values::Choice(names::<ShadowFilter>),
        cli: true,
        get: |s| name_of(&s.shadow_filter),
        put: |s, v| {
            s.shadow_filter = choice("shadow filter", v)?;
            Ok(())
        },
    },
    Knob {
        name: "shadow-format",
        what: "shadow map format",
        help: "Depth format of the shadow atlas and cube array: depth32 (Depth32Float), depth24 (Depth24Plus) or depth16 (Depth16Unorm, 2 bytes a texel); its step is added to the depth bias",
        values: Values::Choice(names::<ShadowFormat>),
        cli: true,
        get: |s| name_of(&s.shadow_format),
        put: |s, v| {
            s.shadow_format = choice("shadow map format", v)?;
            Ok(())
        },
    },
    Knob {
        name: "shadow-cascades",
        what: "sun shadow cascades",
        help: "Cascades of the sun's shadow map over the view frustum",
        values: Values::Whole { min: 1, max: 4 },
        cli: true,
        get: |s| s.shadow_cascades.to_string(),
        put: |s, v| {
            s.shadow_cascades = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "shadow-split-lambda",
        what: "cascade split lambda",
        help: "Cascade splits: lambda x logarithmic + (1 - lambda) x uniform",
        values: Values::Float { min: 0.0, max: 1.0, open: (false, false), slider: (0.0, 1.0) },
        cli: true,
        get: |s| s.shadow_split_lambda.to_string(),
        put: |s, v| {
            s.shadow_split_lambda = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "shadow-cube",
        what: "shadow cube layout",
        help: "Point lights' six shadow faces: tiles of the atlas (unrolled) or a cube-array texture (array)",
        values: Values::Choice(names::<ShadowCube>),
        cli: true,
        get: |s| name_of(&s.shadow_cube),
        put: |s, v| {
            s.shadow_cube = choice("shadow cube layout", v)?;
            Ok(())
        },
    },
    Knob {
        name: "ris-samples",
        what: "RIS samples",
        help: "Reservoir-resampled lighting on the list modes: samples each pixel keeps and shades (0: every listed light exactly)",
        values: Values::Whole { min: 0, max: 64 },
        cli: true,
        get: |s| s.ris_samples.to_string(),
        put: |s, v| {
            s.ris_samples = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "ris-candidates",
        what: "RIS candidates",
        help: "Lights drawn uniformly from the pixel's list for each RIS sample",
        values: Values::Whole { min: 1, max: 256 },
        cli: true,
        get: |s| s.ris_candidates.to_string(),
        put: |s, v| {
            s.ris_candidates = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "ris-spatial",
        what: "RIS spatial reuse",
        help: "Neighbours each RIS sample is combined with (ReSTIR's spatial reuse, unbiased 1/Z weights; 0: off)",
        values: Values::Whole { min: 0, max: 16 },
        cli: true,
        get: |s| s.ris_spatial.to_string(),
        put: |s, v| {
            s.ris_spatial = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "ris-temporal",
        what: "RIS temporal reuse",
        help: "Combine each RIS sample with the last frame's at the reprojected point (ReSTIR's temporal reuse; biased where things move)",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.ris_temporal),
        put: |s, v| {
            s.ris_temporal = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "ris-denoise",
        what: "RIS denoiser",
        help: "Filter RIS's light: temporal accumulation and an edge-aware a-trous filter guided by its variance (SVGF; biased)",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.ris_denoise),
        put: |s, v| {
            s.ris_denoise = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "stochastic-culling",
        what: "stochastic light culling",
        help: "Draw each light's range anew each frame and compensate its attenuation (every culling mode; unbiased)",
        values: Values::Switch,
        cli: true,
        get: |s| switch_name(s.stochastic_culling),
        put: |s, v| {
            s.stochastic_culling = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "stochastic-threshold",
        what: "stochastic culling threshold",
        help: "Attenuation below which stochastic culling randomises a light",
        values: Values::Float { min: 0.0, max: 1.0, open: (true, false), slider: (0.01, 1.0) },
        cli: true,
        get: |s| s.stochastic_threshold.to_string(),
        put: |s, v| {
            s.stochastic_threshold = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "noise-seed",
        what: "noise seed",
        help: "Seed of the stochastic estimators' random numbers (the same seed, the same frame)",
        values: Values::Whole { min: 0, max: u32::MAX - 1 },
        cli: true,
        get: |s| s.noise_seed.to_string(),
        put: |s, v| {
            s.noise_seed = whole(v)?;
            Ok(())
        },
    },
    Knob {
        name: "planted-bias",
        what: "planted bias",
        help: "Tests only: the stochastic estimators weight lights of odd index by this factor (1: unbiased)",
        values: Values::Float { min: 0.0, max: 2.0, open: (true, false), slider: (0.9, 1.1) },
        cli: false,
        get: |s| s.planted_bias.to_string(),
        put: |s, v| {
            s.planted_bias = number(v)? as f32;
            Ok(())
        },
    },
    Knob {
        name: "counts",
        what: "fragment counting",
        help: "Count each light's shaded fragments (occlusion queries)",
        values: Values::Switch,
        cli: false,
        get: |s| switch_name(s.count_fragments),
        put: |s, v| {
            s.count_fragments = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "ideal",
        what: "ideal counting",
        help: "Count the ideal fragments too (a full-screen counting pass per light)",
        values: Values::Switch,
        cli: false,
        get: |s| switch_name(s.count_ideal),
        put: |s, v| {
            s.count_ideal = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "per-light-stats",
        what: "per-light statistics",
        help: "Build the per-light table of the stats in frames that count nothing (counting frames always do)",
        values: Values::Switch,
        cli: false,
        get: |s| switch_name(s.per_light_stats),
        put: |s, v| {
            s.per_light_stats = parse_switch(v)?;
            Ok(())
        },
    },
    Knob {
        name: "timestamps",
        what: "timestamps",
        help: "Read back GPU timestamps",
        values: Values::Switch,
        cli: false,
        get: |s| switch_name(s.timestamps),
        put: |s, v| {
            s.timestamps = parse_switch(v)?;
            Ok(())
        },
    },
];
