//! The configurations each group of the bench sweeps, and the scenes and light counts it sweeps them over.

use super::*;
use crate::renderer::BlendedMode;

/// The cut-off thresholds the `cutoff` group sweeps (fractions of each light's peak).
pub const CUTOFFS: [(f32, &str); 4] = [(0.0, "0"), (1.0 / 256.0, "1/256"), (1.0 / 64.0, "1/64"), (1.0 / 16.0, "1/16")];

/// The sweep. Every configuration differs from the default (`volume` culling, `compact`
/// layout, Rgba16Float accumulation, Depth32FloatStencil8, exact radii, an 80-triangle sphere
/// and a 12-sided cone) in one knob; `--quick` keeps a subset of each group.
///
/// Long (about 230 lines) because it is the sweep's table written as code: one block per group,
/// in the order the report lists them, each setting the one knob its group varies. A reader
/// holds it against the report's tables; split by group, the sweep would be scattered.
pub fn configs(o: &BenchOptions) -> Vec<Config> {
    // Timed frames do not count: counting splits every batch's shading draw into a draw per
    // light (its occlusion query). The counts come from a separate counted render. Unshadowed:
    // shadows are the `shadows` group's knob, so every other row differs from its (unshadowed)
    // reference in its own knob only, and the tables from before shadows were on by default
    // are reproduced by the same commands.
    let base = Settings {
        count_fragments: false,
        count_ideal: false,
        timestamps: true,
        shadows: ShadowMode::None,
        ..Settings::default()
    };
    let c = |group, label: String, settings: Settings, lights| Config {
        group,
        label,
        settings,
        lights,
        size: o.size,
        scene: None,
        radius_scale: 1.0,
        calibration: false,
    };
    let q = o.quick;
    let mut v = Vec::new();
    // `fullscreen` only while its frame stays within the reference's budget of light-pixel
    // pairs: at 100,000 lights and 1920x1080 it is 2e11 pairs, about 45 s a frame even on an
    // NVIDIA H200 (0.22 ns a pair measured there), and the reference is then `volume` anyway.
    let pairs = o.lights as f64 * o.size.0 as f64 * o.size.1 as f64;
    for mode in CullingMode::ALL {
        if mode == CullingMode::Fullscreen && pairs > REFERENCE_FULLSCREEN_BUDGET {
            continue;
        }
        v.push(c("culling", mode.name(), Settings { culling: mode, ..base.clone() }, o.lights));
    }
    // Seed 000's fp16 targets, the packed and fitted layouts, and the normal encodings with
    // everything else as `compact` stores it (compact itself is the `volume` row).
    let layouts: Vec<LayoutChoice> = if q {
        vec![LayoutChoice::Seed000, LayoutChoice::Oct8, LayoutChoice::Xyz8]
    } else {
        [LayoutChoice::Seed000, LayoutChoice::Packed, LayoutChoice::Fit]
            .into_iter()
            .chain(LayoutChoice::NORMAL_ENCODINGS)
            .collect()
    };
    for layout in layouts {
        v.push(c("layout", format!("{layout:?}").to_lowercase(), Settings { layout, ..base.clone() }, o.lights));
    }
    let accumulations: &[AccumFormat] = if q {
        &[AccumFormat::Rgba8Log]
    } else {
        &[AccumFormat::Rgba32Float, AccumFormat::Rg11b10Ufloat, AccumFormat::Rgba8Log, AccumFormat::Rgba8Unorm]
    };
    for &accumulation in accumulations {
        v.push(c("accumulation", accumulation.name(), Settings { accumulation, ..base.clone() }, o.lights));
    }
    // Depth format x depth convention, on the bench's scene and on the far-origin hard case.
    let scenes: &[Option<&'static str>] = if q { &[None] } else { &[None, Some("far-origin")] };
    for &scene in scenes {
        for depth_format in DepthFormat::ALL {
            for reversed_z in [false, true] {
                if q && depth_format == DepthFormat::default() && !reversed_z {
                    continue; // the `volume` row
                }
                let label = format!(
                    "{}{}{}",
                    scene.map_or(String::new(), |s| format!("{s} ")),
                    depth_format.name(),
                    if reversed_z { " reversed-z" } else { "" }
                );
                let settings = Settings { depth_format, reversed_z, ..base.clone() };
                v.push(Config { scene, ..c("depth", label, settings, o.lights) });
            }
        }
    }
    // Seed 004's depth read: the depth buffer itself in place of the R32F copy (the base's
    // volume culling allows it; `key::depth_read_refusal`).
    let settings = Settings { depth_read: crate::renderer::DepthRead::Buffer, ..base.clone() };
    v.push(c("depth", "depth read buffer".into(), settings, o.lights));
    for (t, name) in CUTOFFS {
        if t == 0.0 && q {
            continue;
        }
        v.push(c("cutoff", format!("cutoff {name}"), Settings { light_cutoff: t, ..base.clone() }, o.lights));
    }
    let subdivisions: &[u32] = if q { &[0, 2] } else { &[0, 1, 2, 3] };
    for &sphere_subdivisions in subdivisions {
        let faces = 20 * 4u32.pow(sphere_subdivisions);
        let label = format!("sphere {faces} tris");
        v.push(c("tessellation", label, Settings { sphere_subdivisions, ..base.clone() }, o.lights));
    }
    let sides: &[u32] = if q { &[] } else { &[6, 24] };
    for &cone_sides in sides {
        v.push(c(
            "tessellation",
            format!("cone {cone_sides} sides"),
            Settings { cone_sides, ..base.clone() },
            o.lights,
        ));
    }
    let sizes: &[(u32, u32)] =
        if q { &[(160, 90), (640, 360)] } else { &[(160, 90), (320, 180), (640, 360), (1280, 720)] };
    for &size in sizes {
        let label = format!("{}x{}", size.0, size.1);
        v.push(Config { size, ..c("resolution", label, base.clone(), o.lights) });
    }
    // Where each culling mode wins, over the light count: every mode at every count, but
    // `fullscreen` (every light over every pixel) only where a frame takes seconds, not minutes.
    // A file's added lights each reach past the model's centre (a dome around it), so their
    // cost grows much faster with the count than the demo's small lights.
    let counts: &[usize] = match (crate::scene::import::is_gltf_path(&o.scene), o.quick) {
        (_, _) if o.fixed_lights => &[],
        (true, true) => &[16, 64],
        (true, false) => &[16, 64, 256],
        (false, true) => &[16, 1024],
        (false, false) => &LIGHT_COUNTS,
    };
    for &n in counts {
        for mode in CullingMode::ALL {
            if mode == CullingMode::Fullscreen && n > FULLSCREEN_MAX_LIGHTS {
                continue;
            }
            v.push(c("lights", format!("{} x{n}", mode.name()), Settings { culling: mode, ..base.clone() }, n));
        }
        // Clustered with its lists built on the GPU, so its culling share is measured (the
        // default CPU build's lists cost no GPU time).
        let gpu_lists = Settings {
            culling: CullingMode::Clustered,
            cluster_build: crate::renderer::settings::ClusterBuilder::Gpu,
            ..base.clone()
        };
        v.push(c("lights", format!("clustered gpu-lists x{n}"), gpu_lists, n));
    }
    // Over the light radius: every mode with each light's radius scaled (the bench's light
    // count; a file's own lights are scaled too).
    let scales: &[f64] = if q { &[0.5, 2.0] } else { &RADIUS_SCALES };
    for &radius_scale in scales {
        for mode in CullingMode::ALL {
            let label = format!("{} r x{radius_scale}", mode.name());
            let settings = Settings { culling: mode, ..base.clone() };
            v.push(Config { radius_scale, ..c("radius", label, settings, o.lights) });
        }
    }
    // Seed 000's ambient + sun written by the G-buffer pass (the default) against a full-screen
    // pass of their own.
    for ambient_in_gbuffer in [true, false] {
        let label = if ambient_in_gbuffer { "ambient in g-buffer pass" } else { "ambient own pass" };
        v.push(c("ambient", label.into(), Settings { ambient_in_gbuffer, ..base.clone() }, o.lights));
    }
    // The forward pass's light lists (the same picture each; its time is `forward_ms`; only
    // scenes with blended surfaces, e.g. `glass`, have a forward pass).
    for forward_lights in ForwardLights::ALL {
        let label = format!("forward {}", forward_lights.name());
        v.push(c("forward", label, Settings { forward_lights, ..base.clone() }, o.lights));
    }
    // How blended surfaces are composited: the rows above sort them (alpha); seed 003's
    // additive blending needs no sort, depth peeling (seed 002) a pass pair per layer.
    v.push(c(
        "forward",
        "blended additive".into(),
        Settings { blended: BlendedMode::Additive, ..base.clone() },
        o.lights,
    ));
    for peel_layers in [2, 4, 8] {
        let s = Settings { blended: BlendedMode::Peeled, peel_layers, ..base.clone() };
        v.push(c("forward", format!("blended peeled x{peel_layers}"), s, o.lights));
    }
    // The rendering paths side by side (seed 002): every path over the light count,
    // and on the room. A path that cannot render on this build is a row saying why.
    let counts: &[usize] = if o.fixed_lights {
        &[]
    } else if q {
        &[64, 256]
    } else {
        &PATH_LIGHT_COUNTS
    };
    for &n in counts {
        for path in RenderPath::ALL {
            v.push(c("path", format!("{} x{n}", path.name()), Settings { path, ..base.clone() }, n));
        }
    }
    for path in RenderPath::ALL {
        let label = format!("{} room", path.name());
        v.push(Config { scene: Some(ROOM), ..c("path", label, Settings { path, ..base.clone() }, o.lights) });
    }
    // The light pre-pass with `--msaa 4`: pass 3 and the forward pass over four samples, primed
    // by a depth-only draw of pass 1's list.
    let msaa = Settings { path: RenderPath::LightPrepass, msaa: crate::renderer::Msaa::X4, ..base.clone() };
    v.push(c("path", format!("light-prepass msaa x4 x{}", o.lights), msaa, o.lights));
    // The post chain, one effect at a time, then all of them; the light error is of
    // the accumulation, before post, so it is the `volume` row's in every one of these.
    let post: Vec<(&str, Settings)> = {
        let mut p = vec![
            ("post off", base.clone()),
            ("bloom", Settings { bloom: true, ..base.clone() }),
            ("auto-exposure", Settings { auto_exposure: true, ..base.clone() }),
        ];
        let curves: &[Tonemap] = if q { &[Tonemap::Agx] } else { &Tonemap::ALL };
        p.extend(curves.iter().map(|&t| {
            let label: &'static str = match t {
                Tonemap::Aces => "tonemap aces (chain)",
                Tonemap::Reinhard => "tonemap reinhard",
                Tonemap::Agx => "tonemap agx",
                Tonemap::PbrNeutral => "tonemap pbr-neutral",
                Tonemap::None => "tonemap none",
            };
            // ACES alone is compose's own curve; the identity LUT takes it through the chain.
            let lut = (t == Tonemap::Aces).then(|| "identity".to_string());
            (label, Settings { tonemap: t, lut, ..base.clone() })
        }));
        p.push(("lut identity", Settings { lut: Some("identity".into()), tonemap: Tonemap::Agx, ..base.clone() }));
        // After tone mapping (AgX, so the chain runs for the curve alone in `tonemap agx`).
        let ldr = Settings { tonemap: Tonemap::Agx, ..base.clone() };
        p.push(("fog", Settings { fog: true, ..ldr.clone() }));
        p.push(("dof", Settings { dof: true, ..ldr.clone() }));
        p.push(("vignette", Settings { vignette: 0.5, ..ldr.clone() }));
        // Seed 002's distortion: its buffer's draws (the scene's distorting materials; none on
        // most scenes, `glass` has them) and the effect's pass.
        p.push(("distortion", Settings { distortion: true, ..ldr.clone() }));
        p.push(("aa edge", Settings { aa: Aa::Edge, ..ldr.clone() }));
        p.push(("aa fxaa", Settings { aa: Aa::Fxaa, ..ldr.clone() }));
        p.push((
            "all on",
            Settings {
                bloom: true,
                auto_exposure: true,
                lut: Some("identity".into()),
                fog: true,
                dof: true,
                vignette: 0.5,
                aa: Aa::Edge,
                ..ldr.clone()
            },
        ));
        p
    };
    for (label, settings) in post {
        v.push(c("post", label.into(), settings, o.lights));
    }
    // Shadows of the sun and the spots, against the finest shadows (`shadow_reference`):
    // atlas size, kernel, cascades. (Point lights' cube array is not built; the unrolled cube is
    // the only layout.)
    let shadowed = Settings { shadows: ShadowMode::Spots, ..base.clone() };
    let mut sh = vec![("none".to_string(), Settings { shadows: ShadowMode::None, ..base.clone() })];
    for mb in if q { vec![4.0, 64.0] } else { vec![1.0, 4.0, 16.0, 64.0] } {
        sh.push((format!("atlas {mb} MiB"), Settings { shadow_budget_mb: mb, ..shadowed.clone() }));
    }
    for f in [ShadowFilter::Pcf2x2, ShadowFilter::Poisson16] {
        sh.push((f.name(), Settings { shadow_filter: f, ..shadowed.clone() }));
    }
    for n in if q { vec![1, 4] } else { vec![1, 2, 4] } {
        sh.push((format!("{n} cascades"), Settings { shadow_cascades: n, ..shadowed.clone() }));
    }
    // Seed 002's D16 / D24X8 maps (at the same budget: D16 halves the bytes, the side only
    // doubles when the budget holds the next power of two).
    for f in if q { vec![ShadowFormat::Depth16] } else { vec![ShadowFormat::Depth24, ShadowFormat::Depth16] } {
        sh.push((f.name(), Settings { shadow_format: f, ..shadowed.clone() }));
    }
    for (label, settings) in sh {
        v.push(c("shadows", label, settings, o.lights));
    }
    // Point lights' six faces (every light casting; `CUBE_LIGHTS` point lights, plus the
    // scene's spots): unrolled into the atlas (seed 002's virtual cube), the same tiles read
    // through seed 002's indirection cube (not in `--quick`), or a cube array, at the default
    // budget, against the finest shadows of `all` (`shadow_reference`).
    let cubes: &[ShadowCube] = if q {
        &[ShadowCube::Unrolled, ShadowCube::Array]
    } else {
        &[ShadowCube::Unrolled, ShadowCube::Indirect, ShadowCube::Array]
    };
    for &cube in cubes {
        let settings = Settings { shadows: ShadowMode::All, shadow_cube: cube, ..base.clone() };
        v.push(c("shadows", format!("cube {}", cube.name()), settings, CUBE_LIGHTS));
    }
    // Seed 004's near-plane rule (lights crossing the near plane drawn full-screen) against
    // `auto` and plain volumes, on `street` (a street-level camera among 64 lights, several
    // crossing the near plane); `--quick` keeps the rule under `auto`. The last row is `auto`
    // without depth clamp, where the plan draws near-crossing volumes full-screen whatever the
    // rule (their faces clipped at the near plane have no depth bound).
    let near: &[(CullingMode, NearLights, bool)] = if q {
        &[(CullingMode::Auto, NearLights::Fullscreen, true)]
    } else {
        &[
            (CullingMode::Auto, NearLights::Volume, true),
            (CullingMode::Auto, NearLights::Fullscreen, true),
            (CullingMode::Volume, NearLights::Volume, true),
            (CullingMode::Volume, NearLights::Fullscreen, true),
            (CullingMode::Auto, NearLights::Volume, false),
        ]
    };
    for &(mode, near_lights, depth_clamp) in near {
        let clamp = if depth_clamp { "" } else { ", no depth clamp" };
        let label = format!("street {} near {}{clamp}", mode.name(), near_lights.name());
        let settings = Settings { culling: mode, near_lights, depth_clamp, ..base.clone() };
        v.push(Config { scene: Some("street"), ..c("near", label, settings, 64) });
    }
    // Seed 002's material IDs: every model computed and one selected, or a branch on the ID
    // (the same values; on a scene of one model both compile to that model alone).
    for material_branch in [MaterialBranch::Select, MaterialBranch::Branch] {
        let label = format!("material {}", material_branch.name());
        v.push(c("materials", label, Settings { material_branch, ..base.clone() }, o.lights));
    }
    // Each seed's whole pipeline as its preset sets it, shadows and post chain included (held
    // against the reference with the preset's shadows: the FLIP column includes the seeds'
    // post effects); the counters as every row has them.
    let presets: &[Preset] = if q { &[Preset::Seed000, Preset::Seed004] } else { &Preset::SEEDS };
    for &p in presets {
        v.push(c("presets", p.name(), p.settings(&base), o.lights));
    }
    // The shortcuts engines ship (`renderer::caps::ENGINES`), each against the same frame
    // uncapped: clustered deferred, and the forward path for the engines that shade forward.
    v.push(c(
        ENGINES_GROUP,
        "clustered uncapped".into(),
        Settings { culling: CullingMode::Clustered, ..base.clone() },
        o.lights,
    ));
    v.push(c(
        ENGINES_GROUP,
        "forward uncapped".into(),
        Settings { path: crate::renderer::RenderPath::Forward, ..base.clone() },
        o.lights,
    ));
    for e in crate::renderer::caps::ENGINES {
        if let Ok(s) = crate::renderer::presets::engine_settings(e, &base) {
            v.push(c(ENGINES_GROUP, e.name.into(), s, o.lights));
        }
    }
    v.retain(|c| o.groups.is_empty() || o.groups.iter().any(|g| g == c.group));
    // The calibration pass at every scene and size the sweep renders, timed in the same
    // interleaved rounds: the unit of ρ_fs and of the fixed passes' cost.
    let mut at: Vec<(Option<&'static str>, (u32, u32))> = Vec::new();
    for k in v.iter().map(|c| (c.scene, c.size)) {
        if !at.contains(&k) {
            at.push(k);
        }
    }
    for (scene, size) in at {
        let settings = Settings { culling: CullingMode::Fullscreen, ..base.clone() };
        v.push(Config {
            scene,
            size,
            calibration: true,
            ..c(
                CALIBRATION,
                format!("calibration {}{}x{}", scene.map_or(String::new(), |s| format!("{s} ")), size.0, size.1),
                settings,
                1,
            )
        });
    }
    v
}

/// The group of the calibration rows: one point light reaching every pixel, shaded
/// `fullscreen` over the scene's G-buffer (the scene's own lights left out), at each scene and
/// size of the sweep. Its lighting time is one full-screen light pass: the unit of ρ_fs.
pub const CALIBRATION: &str = "calibration";

/// The calibration pass's scene: `scene` with its lights replaced by one white point light at
/// the camera whose radius reaches past every surface (so no pixel is outside it).
pub fn calibration_scene(scene: &mut crate::Scene) {
    let reach = scene.bounds().map_or(1e3, |(lo, hi)| {
        let c = scene.camera.position;
        // The farthest corner of the bounds from the camera.
        (hi - c).abs().max((c - lo).abs()).length() * 2.0 + 1.0
    });
    scene.set_lights(vec![crate::scene::Light::Point(crate::scene::PointLight {
        position: scene.camera.position,
        color: glam::Vec3::ONE,
        intensity: 1.0,
        radius: reach as f32,
        cookie: None,
        mask: u32::MAX,
        cast_shadows: false,
    })]);
}

/// Point lights of the `shadows` group's cube rows (each casts six faces).
pub const CUBE_LIGHTS: usize = 16;

/// The light counts of the `path` group (plus the room, with its own lights).
pub const PATH_LIGHT_COUNTS: [usize; 3] = [64, 256, 1024];
/// The project's glTF room, the `path` group's second scene.
pub const ROOM: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/room/room.gltf");

/// The group of the engines' presets.
pub const ENGINES_GROUP: &str = "engines";

/// The configuration groups, for `--only`.
pub const GROUPS: &[&str] = &[
    "culling",
    ENGINES_GROUP,
    "presets",
    "near",
    "materials",
    "layout",
    "accumulation",
    "depth",
    "cutoff",
    "tessellation",
    "resolution",
    "lights",
    "radius",
    "ambient",
    "forward",
    "post",
    "shadows",
    "path",
];

/// The light counts the full sweep's `lights` group runs every mode at (plus the scene's spots),
/// up to Bevy's `many_lights` stress count.
pub const LIGHT_COUNTS: [usize; 6] = [64, 256, 1024, 4096, 16384, 100_000];
/// `fullscreen` runs in the `lights` group only up to this many lights: at 1280x720 each light is
/// 0.9 M fragments (~17 ns each on lavapipe), so 256 lights are ~4 s a frame and 16,384 would be
/// over four minutes.
pub const FULLSCREEN_MAX_LIGHTS: usize = 256;
/// The radius factors of the `radius` group.
pub const RADIUS_SCALES: [f64; 4] = [0.5, 1.0, 2.0, 4.0];
/// A reference frame is rendered with every light full-screen while lights x pixels stays under
/// this (about 40 s on lavapipe); above it the reference draws plain volumes, which every
/// culling test holds equal to full-screen within one 8-bit step (`tests/it/culling.rs`), so the
/// error figures stay those of the layout and accumulation, not of a culling approximation.
pub const REFERENCE_FULLSCREEN_BUDGET: f64 = 2.5e9;

/// The culling mode of the reference frame for `lights` lights at `size`.
pub fn reference_culling(lights: usize, size: (u32, u32)) -> CullingMode {
    if lights as f64 * size.0 as f64 * size.1 as f64 <= REFERENCE_FULLSCREEN_BUDGET {
        CullingMode::Fullscreen
    } else {
        CullingMode::Volume
    }
}

/// Scales every light's radius (and so its reach and volume) by `k`.
pub fn scale_light_radii(scene: &mut crate::Scene, k: f64) {
    for l in scene.lights_mut() {
        match l {
            crate::scene::Light::Point(p) => p.radius *= k as f32,
            crate::scene::Light::Spot(s) => s.radius *= k as f32,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn culling_rows(lights: usize, size: (u32, u32)) -> Vec<String> {
        let o = BenchOptions {
            scene: "demo".into(),
            quick: false,
            frames: 1,
            size,
            lights,
            time: 0.0,
            groups: vec!["culling".into()],
            fixed_lights: false,
        };
        configs(&o).into_iter().filter(|c| c.group == "culling").map(|c| c.label).collect()
    }

    #[test]
    fn the_culling_group_drops_fullscreen_only_past_the_references_budget() {
        let every: Vec<String> = CullingMode::ALL.iter().map(|m| m.name()).collect();
        assert_eq!(culling_rows(1024, (1280, 720)), every);
        // 1024 x 1920 x 1080 = 2.1e9 pairs: within the budget, so the GPU run's 1,024 rows
        // include it; 16,384 lights at the same size do not.
        assert_eq!(culling_rows(1024, (1920, 1080)), every);
        let without: Vec<String> = every.iter().filter(|m| *m != "fullscreen").cloned().collect();
        assert_eq!(culling_rows(16_384, (1920, 1080)), without);
        assert_eq!(culling_rows(100_000, (1920, 1080)), without);
    }
}
