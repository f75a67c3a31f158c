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
    return vec4<f32>(select(camera.background.rgb, diffuse * s.albedo + specular + s.emissive, s.valid), 1.0);
}

// Exposure and tonemapping of the HDR scene colour.
@fragment
fn fs_tonemap(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let c = finite(textureLoad(hdr_color, vec2<i32>(floor(frag.xy)), 0).rgb);
    return vec4<f32>(aces(c * camera.exposure), 1.0);
}

@fragment
fn fs_compose(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(floor(frag.xy * compose.scale));
    let s = gbuffer_load(p);
    let view = compose.view;
    let diffuse = finite(decode_light(textureLoad(light_diffuse, p, 0).rgb));
    var specular = finite(decode_light(textureLoad(light_specular, p, 0).rgb));
    if LS_PREPASS {
        // The light pre-pass's buffer: its mono specular (A) as grey.
        specular = finite(vec3<f32>(decode_light_buffer(textureLoad(light_diffuse, p, 0)).a));
    }
    let exposure = camera.exposure;
    let lit = select(camera.background.rgb, diffuse * s.albedo + specular + s.emissive, s.valid);
    var c = aces(lit * exposure);
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
    } else if view == LS_VIEW_MATERIAL_ID {
        // The pixel's reflectance model, one colour each; the viewer draws the legend.
        c = select(vec3<f32>(0.0), brdf_debug_color(s.brdf), s.valid);
    }
    return vec4<f32>(c, 1.0);
}
