// Bindings (groups 2 and 3) are declared from Rust: renderer::bindings::{COMPOSE, HDR}.
// Compose (seed 002's final pass): diffuse x albedo + specular + emissive, tonemapped, or one
// of the debug views.

struct ComposeParams {
    // Which view (LS_VIEW_*), and the scale from output pixels to G-buffer pixels (thumbnails).
    view: u32,
    pad0: u32,
    scale: vec2<f32>,
};

// ACES filmic tonemapping curve, Narkowicz 2015 fit.
fn aces(x: vec3<f32>) -> vec3<f32> {
    let a = 2.51;
    let b = 0.03;
    let c = 2.43;
    let d = 0.59;
    let e = 0.14;
    return clamp((x * (a * x + b)) / (x * (c * x + d) + e), vec3<f32>(0.0), vec3<f32>(1.0));
}

// fp16 overflow: +inf becomes the largest finite fp16 value; NaN becomes magenta-free zero.
fn finite(v: vec3<f32>) -> vec3<f32> {
    let c = min(v, vec3<f32>(LS_FP16_MAX));
    return select(vec3<f32>(0.0), c, c == c);
}

fn heat(t: f32) -> vec3<f32> {
    let x = clamp(t, 0.0, 1.0);
    return clamp(vec3<f32>(1.5 * x, 1.5 * x - 0.5, 0.5 - abs(x - 0.5) + max(0.0, 3.0 * x - 2.0)), vec3<f32>(0.0), vec3<f32>(1.0));
}

@vertex
fn vs_compose(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(vi);
}

// The lit picture in linear HDR, before exposure and tonemapping: what the forward pass blends
// transparent surfaces over.
@fragment
fn fs_compose_hdr(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(floor(frag.xy));
    let s = gbuffer_load(p);
    let diffuse = finite(decode_light(textureLoad(light_diffuse, p, 0).rgb));
    let specular = finite(decode_light(textureLoad(light_specular, p, 0).rgb));
    return vec4<f32>(select(camera.background.rgb, lit_colour(s, diffuse, specular), s.valid), 1.0);
}

// The lit colour from the accumulation: diffuse x albedo + specular + emissive, or seed 000's
// one RT1 as it is (GBUFFER_ONE_ACCUM: the lights multiplied the albedo in, and its layout has
// no emissive target: the G-buffer pass wrote the emission into RT1).
fn lit_colour(s: Surface, diffuse: vec3<f32>, specular: vec3<f32>) -> vec3<f32> {
    if GBUFFER_ONE_ACCUM {
        return diffuse;
    }
    return diffuse * s.albedo + specular + s.emissive;
}

// Exposure and tonemapping of the HDR scene colour.
@fragment
fn fs_tonemap(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let c = finite(textureLoad(hdr_color, vec2<i32>(floor(frag.xy)), 0).rgb);
    return vec4<f32>(aces(c * camera.exposure), 1.0);
}

// The `shadow` view's factor: the least of the sun's (where it faces the sun) and of every
// casting light's that reaches the point and faces it; 1 where none casts. It walks the casters
// (shadows::ShadowPlan::casters, four light indices a texel from row counts.z of the table), not
// every light: lavapipe ends an invocation's loops after 65,535 iterations, which a walk over
// every light of a larger scene would pass.
fn shadow_view_factor(s: Surface) -> f32 {
    let shadow_params = shadow_params_load();
    var f = 1.0;
    if camera.sun_dir.w > 0.5 && dot(s.normal, camera.sun_dir.xyz) > 0.0 {
        f = ls_sun_shadow(s.position, s.normal, s.position_error);
    }
    let per_row = 4u * LS_SHADOW_TABLE_WIDTH;
    for (var k = 0u; k < shadow_params.counts.y; k++) {
        let at = vec2<i32>(i32((k % per_row) / 4u), i32(shadow_params.counts.z + k / per_row));
        let l = light_at(textureLoad(shadow_table, at, 0)[k % 4u]);
        if l.shadow.x != LS_NO_SHADOW && inside_light(s, l) && dot(s.normal, l.position - s.position) > 0.0 {
            f = min(f, ls_shadow(l, s.position, s.normal, s.position_error));
        }
    }
    return f;
}

// What every compose reads at its G-buffer pixel: the surface and the two light sums.
struct ComposeInputs {
    p: vec2<i32>,
    s: Surface,
    diffuse: vec3<f32>,
    specular: vec3<f32>,
};

fn compose_inputs(frag: vec4<f32>) -> ComposeInputs {
    var i: ComposeInputs;
    i.p = vec2<i32>(floor(frag.xy * compose.scale));
    i.s = gbuffer_load(i.p);
    i.diffuse = finite(decode_light(textureLoad(light_diffuse, i.p, 0).rgb));
    i.specular = finite(decode_light(textureLoad(light_specular, i.p, 0).rgb));
    if LS_PREPASS {
        // The light pre-pass's buffer: its mono specular (A) as grey.
        i.specular = finite(vec3<f32>(decode_light_buffer(textureLoad(light_diffuse, i.p, 0)).a));
    } else if GBUFFER_ONE_ACCUM {
        // Seed 000's one RT1 (the `specular` binding is a 1x1 stand-in): all light in `diffuse`.
        i.specular = vec3<f32>(0.0);
    }
    return i;
}

// The lit picture, exposed and tonemapped.
fn compose_lit(i: ComposeInputs) -> vec3<f32> {
    let s = i.s;
    let lit = select(camera.background.rgb, lit_colour(s, i.diffuse, i.specular), s.valid);
    return aces(lit * camera.exposure);
}

// The frame's own compose: the lit picture only. A pipeline of its own, because lavapipe runs
// every branch of a shader at every pixel: with the debug views beside it (the `shadow` and
// `cascades` views' lookups among them) the lit compose cost every view's work.
@fragment
fn fs_compose(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(compose_lit(compose_inputs(frag)), 1.0);
}

// The lit picture or one of the debug views (`compose.view`): the viewer's views and
// thumbnails, and frames drawn with `--debug-view`.
@fragment
fn fs_compose_view(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let i = compose_inputs(frag);
    let p = i.p;
    let s = i.s;
    let diffuse = i.diffuse;
    let specular = i.specular;
    let view = compose.view;
    let exposure = camera.exposure;
    var c = compose_lit(i);
    if view == LS_VIEW_ALBEDO {
        c = s.albedo;
    } else if view == LS_VIEW_NORMAL {
        c = select(vec3<f32>(0.0), s.normal * 0.5 + 0.5, s.valid);
    } else if view == LS_VIEW_DEPTH {
        // Linear view distance on a log scale, 0.1 .. 1000 units.
        let t = clamp(log2(max(-s.position.z, 0.1) / 0.1) / log2(10000.0), 0.0, 1.0);
        c = select(vec3<f32>(0.0), vec3<f32>(1.0 - t), s.valid);
    } else if view == LS_VIEW_SPECULAR {
        // Reflectance f0 (the stored channel; the level is f0 (n + 8) / 8) and exponent.
        c = vec3<f32>(s.spec_level * 8.0 / (s.spec_exp + 8.0), log2(s.spec_exp) / LS_SPEC_EXP_LOG_RANGE, 0.0);
    } else if view == LS_VIEW_EMISSIVE {
        c = aces(s.emissive * exposure);
    } else if view == LS_VIEW_DIFFUSE_LIGHT {
        c = aces(diffuse * exposure);
    } else if view == LS_VIEW_SPECULAR_LIGHT {
        c = aces(specular * exposure);
    } else if view == LS_VIEW_STENCIL {
        // Seed 000's diagram over a dimmed picture: green lit, red passed Z in pass 2, blue
        // passed Z in pass 1 and left the stencil intact.
        let k = textureLoad(debug_tex, p, 0);
        let base = vec3<f32>(dot(c, vec3<f32>(0.299, 0.587, 0.114)) * 0.35);
        if k.g > 0.0 {
            c = vec3<f32>(0.0, 1.0, 0.0);
        } else if k.r > 0.0 {
            c = vec3<f32>(1.0, 0.0, 0.0);
        } else if k.b > 0.0 {
            c = vec3<f32>(0.0, 0.0, 1.0);
        } else {
            c = base;
        }
    } else if view == LS_VIEW_COMPLEXITY {
        let n = textureLoad(debug_tex, p, 0).r;
        c = select(vec3<f32>(0.02), heat(n / 8.0), n > 0.0);
    } else if view == LS_VIEW_TILE_LIGHTS {
        // Lights in the pixel's tile or cluster list; the viewer draws the legend.
        let n = textureLoad(debug_tex, p, 0).r;
        c = select(vec3<f32>(0.02), heat(n / LS_TILE_HEAT_MAX), n > 0.0);
    } else if view == LS_VIEW_WASTE {
        // Lights evaluated at the pixel for nothing, on the tile-lights scale and legend.
        let n = textureLoad(debug_tex, p, 0).r;
        c = select(vec3<f32>(0.02), heat(n / LS_TILE_HEAT_MAX), n > 0.0);
    } else if view == LS_VIEW_VARIANCE {
        // RIS's light's deviation over its mean across the frames averaged, 0 to 2 (written
        // only by RIS's frames: none when exact).
        let v = select(0.0, textureLoad(debug_tex, p, 0).r, camera.noise.z > 0u);
        c = select(vec3<f32>(0.02), heat(v / 2.0), v > 0.0);
    } else if view == LS_VIEW_MATERIAL_ID {
        // The pixel's reflectance model, one colour each; the viewer draws the legend.
        c = select(vec3<f32>(0.0), brdf_debug_color(s.brdf), s.valid);
    } else if view == LS_VIEW_SHADOW {
        c = vec3<f32>(0.0, 0.0, 0.15);
        if s.valid {
            c = vec3<f32>(shadow_view_factor(s));
        }
    } else if view == LS_VIEW_CASCADES {
        c = vec3<f32>(0.0, 0.0, 0.15);
        if s.valid {
            let shadow_params = shadow_params_load();
            let i = sun_cascade(s.position);
            var tint = vec3<f32>(0.5);
            if shadow_params.sun.x != LS_NO_SHADOW && i < shadow_params.sun.y {
                tint = array<vec3<f32>, 4>(
                    vec3<f32>(1.0, 0.25, 0.25),
                    vec3<f32>(0.25, 1.0, 0.25),
                    vec3<f32>(0.3, 0.45, 1.0),
                    vec3<f32>(1.0, 1.0, 0.25),
                )[min(i, 3u)];
            }
            c = tint * (0.3 + 0.7 * ls_sun_shadow(s.position, s.normal, s.position_error));
        }
    }
    return vec4<f32>(c, 1.0);
}
