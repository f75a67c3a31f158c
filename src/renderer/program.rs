//! The one shader module every pass compiles from, assembled from the rooms: constants
//! generated from Rust, the compiled-in lookups ([`ShaderFeatures`]), the bindings and the
//! G-buffer layout, then each technique's WGSL file. One module, because the surfaces, the
//! light loops and the post chain share `kit/common.wgsl`'s functions.

pub use super::kit::features::ShaderFeatures;
use super::kit::gbuffer::GBufferLayout;
use super::kit::{self, bindings, log_accum};
use super::settings::{self, DebugView, Settings};
use super::{plan, post, records, shadows, tiles};

/// WGSL constants generated from Rust, so the two never drift apart.
pub fn wgsl_constants() -> String {
    let mut s = String::new();
    let mut u = |name: &str, v: u32| s += &format!("const LS_{name}: u32 = {v}u;\n");
    u("LIGHT_POINT", records::LIGHT_KIND_POINT);
    u("LIGHT_SPOT", records::LIGHT_KIND_SPOT);
    u("MAT_NORMAL_MAP", records::MAT_NORMAL_MAP);
    u("MAT_METAL_ROUGH", records::MAT_METAL_ROUGH);
    u("MAT_UV_TRANSFORMED", records::MAT_UV_TRANSFORMED);
    u("MAT_METAL_BY_PIXEL", records::MAT_METAL_BY_PIXEL);
    u("MAT_LIGHTMAP", records::MAT_LIGHTMAP);
    u("MAT_BASE_MAP", records::MAT_BASE_MAP);
    u("MAT_EMISSIVE_MAP", records::MAT_EMISSIVE_MAP);
    u("NO_COOKIE", records::NO_COOKIE);
    u("COOKIE_ROW", records::COOKIE_ROW);
    for b in crate::scene::Brdf::ALL {
        u(&format!("BRDF_{}", b.name().to_uppercase().replace('-', "_")), b.id());
    }
    for v in DebugView::ALL {
        u(&format!("VIEW_{}", v.wgsl_name()), v as u32);
    }
    for t in post::Tonemap::ALL {
        u(&format!("TONEMAP_{}", t.wgsl_name()), t as u32);
    }
    u("HIST_BINS", post::HIST_BINS);
    u("MAX_EFFECTS", post::effects::MAX_EFFECTS as u32);
    for (i, e) in post::effects::EFFECTS.iter().enumerate() {
        u(&format!("EFFECT_{}", e.name.to_uppercase().replace('-', "_")), i as u32);
    }
    u("NO_SHADOW", records::NO_SHADOW);
    u("SHADOW_TABLE_WIDTH", records::SHADOW_TABLE_WIDTH);
    u("TILE_CHUNK", tiles::SHADE_CHUNK);
    u("TILE_ALL", tiles::ALL_LIGHTS);
    u("TILE_MAX_LIGHTS", tiles::GPU_LIST_MAX_LIGHTS);
    for f in [shadows::ShadowFilter::Pcf2x2, shadows::ShadowFilter::Pcf3x3, shadows::ShadowFilter::Poisson16] {
        u(&format!("SHADOW_FILTER_{}", f.name().to_uppercase()), f as u32);
    }
    for a in [post::Aa::Off, post::Aa::Edge, post::Aa::Fxaa] {
        u(&format!("AA_{}", a.name().to_uppercase()), a as u32);
    }
    let mut f = |name: &str, v: f32| s += &format!("const LS_{name}: f32 = {v:?};\n");
    f("LOG_ACCUM_MAX", settings::LOG_ACCUM_MAX);
    f("FP16_MAX", records::FP16_MAX);
    f("TILE_HEAT_MAX", tiles::HEAT_MAX);
    f("METAL_THRESHOLD", crate::scene::import::METAL_THRESHOLD);
    f("MAX_COC", post::MAX_COC);
    f("TILE_PERSPECTIVE", shadows::TILE_PERSPECTIVE);
    f("TILE_ORTHOGRAPHIC", shadows::TILE_ORTHOGRAPHIC);
    f("TILE_CUBE_FACE", shadows::TILE_CUBE_FACE);
    // Specular exponents are stored as log2(exponent) / range: exponents 1 ..= 2^range.
    f("SPEC_EXP_LOG_RANGE", super::kit::gbuffer::SPEC_EXP_LOG_RANGE);
    let [r, g, b] = crate::scene::LUMINANCE.map(|w| w as f32);
    s += &format!("const LS_LUMINANCE: vec3<f32> = vec3<f32>({r:?}, {g:?}, {b:?});\n");
    // The `material-id` view's colours (`Brdf::debug_color`; unknown IDs show magenta).
    s += "fn brdf_debug_color(id: u32) -> vec3<f32> {\n";
    for b in crate::scene::Brdf::ALL {
        let [r, g, bl] = b.debug_color();
        s += &format!("    if id == {}u {{ return vec3<f32>({r:?}, {g:?}, {bl:?}); }}\n", b.id());
    }
    s += "    return vec3<f32>(1.0, 0.0, 1.0);\n}\n";
    s
}

impl ShaderFeatures {
    /// The lookups on (the unrolled cubes, the 3x3 kernel), for checking the source: naga
    /// validates every branch, taken or not.
    pub const ALL: ShaderFeatures = ShaderFeatures {
        shadows: shadows::ShadowCode {
            sun: true,
            tiles: true,
            cubes: Some(shadows::ShadowCube::Unrolled),
            filter: shadows::ShadowFilter::Pcf3x3,
            format: shadows::ShadowFormat::Depth32,
            casters_apart: true,
        },
        cookies: true,
        light_planes: true,
        paired_loops: true,
        brdf_branch: true,
        colour_maps: true,
    };

    /// What `scene` can need under `settings`; with no scene, what the settings allow (no
    /// cookies: they come with a scene).
    /// The driver workarounds follow `quirks`: light planes only where uniform loads gather
    /// faster than storage loads, paired loops only under a loop limit.
    pub fn of(
        scene: Option<&crate::scene::Scene>,
        settings: &Settings,
        quirks: &crate::renderer::kit::adapter::Quirks,
    ) -> ShaderFeatures {
        ShaderFeatures {
            shadows: shadows::ShadowCode::of(scene, &settings.shadow_options()),
            cookies: scene.is_some_and(|s| s.lights.iter().any(|l| l.cookie().is_some())),
            light_planes: quirks.uniform_gathers && scene.is_some_and(|s| records::planes_hold(&s.lights)),
            paired_loops: quirks.loop_limit.is_some()
                && scene.is_some_and(|s| s.lights.len() > plan::FORWARD_LOOP_LIGHTS as usize),
            brdf_branch: settings.material_branch == crate::renderer::settings::MaterialBranch::Branch,
            colour_maps: scene.is_some_and(Self::samples_colour_maps),
        }
    }

    /// Whether some material of `scene` has a base-colour or emissive map.
    pub fn samples_colour_maps(scene: &crate::scene::Scene) -> bool {
        scene.materials.iter().any(|m| m.textures.base_color.is_some() || m.textures.emissive.is_some())
    }

    /// The lookups compiled in, by name (the stats and the viewer's shadow figures): `sun
    /// cascades`, `spot tiles`, `cubes unrolled` or `cubes array`, the kernel, `casters apart`,
    /// `cookies`.
    pub fn names(&self) -> Vec<String> {
        let sh = &self.shadows;
        let mut v = Vec::new();
        if sh.sun {
            v.push("sun cascades".to_string());
        }
        if sh.tiles {
            v.push("spot tiles".to_string());
        }
        if let Some(c) = sh.cubes {
            v.push(format!("cubes {}", c.name()));
        }
        if sh.sun || sh.tiles || sh.cubes.is_some() {
            v.push(format!("kernel {}", sh.filter.name()));
            v.push(format!("maps {}", sh.format.name()));
        }
        if sh.casters_apart {
            v.push("casters apart".to_string());
        }
        if self.cookies {
            v.push("cookies".to_string());
        }
        if self.light_planes {
            v.push("light planes".to_string());
        }
        if self.paired_loops {
            v.push("paired light loops".to_string());
        }
        if self.brdf_branch {
            v.push("branch on the material".to_string());
        }
        if self.colour_maps {
            v.push("colour maps".to_string());
        }
        v
    }

    fn wgsl(&self) -> String {
        let sh = &self.shadows;
        let cube_array = sh.cubes == Some(shadows::ShadowCube::Array);
        let cube_indirect = sh.cubes == Some(shadows::ShadowCube::Indirect);
        format!(
            "const LS_SUN_SHADOW: bool = {};\nconst LS_TILE_SHADOWS: bool = {};\n\
             const LS_CUBE_SHADOWS: bool = {};\nconst LS_CUBE_ARRAY: bool = {cube_array};\n\
             const LS_CUBE_INDIRECT: bool = {cube_indirect};\n\
             const LS_SHADOW_KERNEL: u32 = {}u;\nconst LS_COOKIES: bool = {};\n\
             const LS_CASTERS_APART: bool = {};\nconst LS_LIGHT_PLANES: bool = {};\n\
             const LS_PAIRED_LOOPS: bool = {};\nconst LS_BRDF_BRANCH: bool = {};\n\
             const LS_COLOUR_MAPS: bool = {};\n\
             const LS_SHADOW_DEPTH_STEP: f32 = {:?};\n\
             const LS_VOLUME_BIAS_UNITS: f32 = {:?};\nconst LS_VOLUME_BIAS_SLOPE: f32 = {:?};\n",
            sh.sun,
            sh.tiles,
            sh.cubes.is_some(),
            sh.filter as u32,
            self.cookies,
            sh.casters_apart,
            self.light_planes,
            self.paired_loops,
            self.brdf_branch,
            self.colour_maps,
            sh.format.step(),
            kit::VOLUME_BIAS_UNITS as f32,
            kit::VOLUME_BIAS_SLOPE
        )
    }
}

/// The whole shader source for a G-buffer layout and accumulation format, every lookup
/// compiled in: generated constants, binding declarations and G-buffer layout, then the WGSL
/// files.
pub fn shader_source(layout: &GBufferLayout, accum_format: wgpu::TextureFormat, ambient_in_gbuffer: bool) -> String {
    shader_source_for(layout, accum_format, ambient_in_gbuffer, false, ShaderFeatures::ALL)
}

/// [`shader_source`] for the deferred path or (`prepass`) the light pre-pass, whose light pass
/// writes one light buffer (RGB diffuse, mono specular in A) shaded with unit reflectance, with
/// the lookups `features` name.
pub fn shader_source_for(
    layout: &GBufferLayout,
    accum_format: wgpu::TextureFormat,
    ambient_in_gbuffer: bool,
    prepass: bool,
    features: ShaderFeatures,
) -> String {
    let mut parts = vec![
        wgsl_constants(),
        format!("const LS_ACCUM_LOG: bool = {};\n", log_accum(accum_format)),
        format!("const LS_PREPASS: bool = {prepass};\n"),
        features.wgsl(),
    ];
    parts.push(layout.wgsl(1, ambient_in_gbuffer));
    parts.extend(bindings::GROUPS.iter().map(|g| g.wgsl()));
    parts.extend(
        [
            include_str!("kit/common.wgsl"),
            include_str!("shadows/lookup.wgsl"),
            include_str!("surfaces/geometry.wgsl"),
            include_str!("paths/forward.wgsl"),
            include_str!("culling/lights.wgsl"),
            include_str!("surfaces/compose.wgsl"),
            include_str!("culling/tiled/tiled.wgsl"),
            include_str!("culling/zbin/zbin.wgsl"),
            include_str!("stochastic/ris.wgsl"),
            include_str!("stochastic/reuse.wgsl"),
            include_str!("stochastic/denoise.wgsl"),
            include_str!("stochastic/converge.wgsl"),
            include_str!("post/post.wgsl"),
            include_str!("shadows/casters.wgsl"),
            include_str!("paths/prepass.wgsl"),
            include_str!("shadows/atlas_view.wgsl"),
            include_str!("explain/explain.wgsl"),
        ]
        .map(String::from),
    );
    parts.join("\n")
}

/// The last light list a frame checked, by identity with the cookies it names
/// (`Scene::lights` is copied on write), and the shader features it needed with the sun and
/// settings then: a frame with the same list reads no light to validate it
/// (`Shape::of_checked`) or to pick its shaders' lookups (`ShaderFeatures::of`).
struct LightsSeen {
    lights: std::sync::Arc<Vec<crate::scene::Light>>,
    cookies: Vec<u64>,
    sun: Option<crate::scene::Sun>,
    settings: Settings,
    features: ShaderFeatures,
}

/// The shader features of the last frame's light list ([`LightsSeen`]).
#[derive(Default)]
pub struct FeatureCache {
    seen: Option<LightsSeen>,
}

impl FeatureCache {
    /// Whether `scene`'s lights are the list the last frame checked.
    pub fn same_list(&self, scene: &crate::scene::Scene) -> bool {
        self.seen.as_ref().is_some_and(|s| {
            std::sync::Arc::ptr_eq(&s.lights, &scene.lights)
                && s.cookies.iter().copied().eq(scene.cookies.iter().map(|c| c.id()))
        })
    }

    /// The shader features of a frame of `scene` with `settings` (`ShaderFeatures::of`), read
    /// from the lights only when they are another list than the last frame's (or the sun or
    /// settings changed). Called once the frame's lights passed validation: the list is kept as
    /// checked.
    pub fn of(
        &mut self,
        scene: &crate::scene::Scene,
        settings: &Settings,
        quirks: &crate::renderer::kit::adapter::Quirks,
    ) -> ShaderFeatures {
        if let Some(s) = self.seen.as_ref().filter(|_| self.same_list(scene)) {
            if s.sun == scene.sun && s.settings == *settings {
                // The materials' part is read afresh: it is not the lights'.
                return ShaderFeatures { colour_maps: ShaderFeatures::samples_colour_maps(scene), ..s.features };
            }
        }
        let features = ShaderFeatures::of(Some(scene), settings, quirks);
        self.seen = Some(LightsSeen {
            lights: scene.lights.clone(),
            cookies: scene.cookies.iter().map(|c| c.id()).collect(),
            sun: scene.sun,
            settings: settings.clone(),
            features,
        });
        features
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cookie_feature_is_set_only_for_scenes_with_cookies() {
        use crate::renderer::kit::adapter::{Quirks, GALLIVM_LOOP_LIMIT};
        use crate::scene::builtin::{build, BuiltinOptions};
        let st = Settings::default();
        let lavapipe = Quirks { loop_limit: Some(GALLIVM_LOOP_LIMIT), uniform_gathers: true, ..Quirks::NONE };
        let features = |name: &str| {
            let scene = build(name, BuiltinOptions::default()).expect("built-in scene");
            ShaderFeatures::of(Some(&scene), &st, &lavapipe)
        };
        assert!(features("cookies").cookies);
        assert!(!features("demo").cookies && !features("shadows").cookies);
        assert!(!ShaderFeatures::of(None, &st, &lavapipe).cookies);
        // The stats name what is compiled in: `demo` under the default `spots` has the sun and
        // narrow spots casting, no cube and no cookie, and its 1,028 lights read from the light
        // planes; a scene with cookies reads the storage buffer.
        assert_eq!(
            features("demo").names(),
            ["sun cascades", "spot tiles", "kernel pcf3x3", "maps depth32", "casters apart", "light planes"]
        );
        assert!(features("cookies").names().iter().any(|n| n == "cookies"));
        assert!(features("demo").light_planes && !features("cookies").light_planes);
        // The light planes and paired loops are lavapipe's workarounds: another adapter's
        // shaders read the storage buffer.
        let demo = build("demo", BuiltinOptions::default()).expect("built-in scene");
        assert!(!ShaderFeatures::of(Some(&demo), &st, &Quirks::NONE).light_planes);
        // The constant the shader's branches test follows the feature.
        let on = ShaderFeatures { cookies: true, ..ShaderFeatures::ALL };
        assert!(on.wgsl().contains("const LS_COOKIES: bool = true;"));
        assert!(ShaderFeatures { cookies: false, ..on }.wgsl().contains("const LS_COOKIES: bool = false;"));
    }
}
