// Light accumulation (seeds 000/001/002): ambient + sun full-screen first, then the lights in
// instanced draws, full-screen or as bounding volumes, blended additively into diffuse and
// specular.

struct LightTargets {
    @location(0) diffuse: vec4<f32>,
    @location(1) specular: vec4<f32>,
};

// A term's light as the accumulation stores it: diffuse (before the albedo) and specular in
// two targets; the light pre-pass's one buffer (RGB diffuse, mono specular in A); or seed 000's
// one RT1 (GBUFFER_ONE_ACCUM), the lit colour albedo x diffuse + specular. `s` is the pixel's
// surface (its albedo).
fn light_targets(s: Surface, diffuse: vec3<f32>, specular: vec3<f32>) -> LightTargets {
    var out: LightTargets;
    out.specular = encode_light(vec3<f32>(0.0));
    if LS_PREPASS {
        out.diffuse = encode_light_buffer(diffuse, specular);
    } else if GBUFFER_ONE_ACCUM {
        out.diffuse = encode_light(diffuse * s.albedo + specular);
    } else {
        out.diffuse = encode_light(diffuse);
        out.specular = encode_light(specular);
    }
    return out;
}

struct LightVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) light: u32,
};

// Orthonormal basis around a unit vector (Duff et al. 2017).
fn basis(n: vec3<f32>) -> mat3x3<f32> {
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let t = vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let u = vec3<f32>(b, sign + n.y * n.y * a, -n.y);
    return mat3x3<f32>(t, u, n);
}

// Places the unit bounding mesh on a light, grown all round by `volume_pad`, as
// `volumes::place` does on the CPU. w = 0: unit sphere (already circumscribing); w = 1: unit
// cone, apex at the origin, axis +z, base at z = 1 circumscribing radius 1.
fn volume_position(p: vec4<f32>, l: GpuLight) -> vec3<f32> {
    if p.w < 0.5 {
        return l.position + p.xyz * (l.radius + l.volume_pad);
    }
    let b = basis(l.direction);
    let back = l.volume_pad * (1.0 + 1.0 / l.volume_tan);
    let length = l.radius + l.volume_pad + back;
    let r = length * l.volume_tan;
    return l.position - l.direction * back + b[0] * (p.x * r) + b[1] * (p.y * r) + b[2] * (p.z * length);
}

// Light draws are instanced: instance i draws light draw_lights[i] (instance_index counts from
// the draw's first instance). The list starts with the identity, for draws of one light.
@vertex
fn vs_volume(@location(0) p: vec4<f32>, @builtin(instance_index) instance: u32) -> LightVarying {
    let light = draw_lights[instance];
    var out: LightVarying;
    out.clip = camera.proj * vec4<f32>(volume_position(p, lights[light]), 1.0);
    out.light = light;
    return out;
}

@vertex
fn vs_fullscreen(@builtin(vertex_index) vi: u32, @builtin(instance_index) instance: u32) -> LightVarying {
    var out: LightVarying;
    out.clip = fullscreen_position(vi);
    out.light = draw_lights[instance];
    return out;
}


// Two entry points: `fs_light` runs the light's shadow lookup, `fs_light_plain` (with
// LS_CASTERS_APART, for the draws of lights that cast no shadow this frame) does not. `lookups`
// is a literal at each call, so the driver's inlining drops the lookup from the plain one:
// lavapipe runs a branch's body whether or not a lane takes it.
@fragment
fn fs_light(in: LightVarying) -> LightTargets {
    return light_fragment(in, true);
}

@fragment
fn fs_light_plain(in: LightVarying) -> LightTargets {
    return light_fragment(in, false);
}

fn light_fragment(in: LightVarying, lookups: bool) -> LightTargets {
    let s = gbuffer_load(vec2<i32>(in.clip.xy));
    if !s.valid {
        return light_targets(s, vec3<f32>(0.0), vec3<f32>(0.0));
    }
    let l = light_at(in.light);
    let r = shade_light_as(s, l, lookups);
    return light_targets(s, min(r.diffuse, vec3<f32>(l.clamp)), min(r.specular, vec3<f32>(l.clamp)));
}

// Ambient + sun at a surface point: the accumulation's starting value (seed 000's RT1). Written
// by the G-buffer pass itself (`gbuffer_store`, from the surface as stored: `as_stored`), or by
// `fs_ambient` from the decoded G-buffer where the device cannot take the extra targets.
// In the pixel's reflectance model (`ambient_diffuse`, `ambient_specular`, `brdf_light`); the
// forward pass calls it too.
// A lightmapped surface (seed 004): near the camera the sun stays realtime and the ambient
// takes the baked occlusion ("only baked indirect lighting is added"); far away both are the
// baked irradiance; between, mixed by `baked_weight`. Unchanged, bit for bit, without one.
fn ambient_sun(s: Surface) -> Lighting {
    var r = sun_light(s);
    if takes_lightmap(s) {
        let w = baked_weight(s.position);
        r.diffuse = (r.diffuse + ambient_diffuse(s) * s.baked.a) * (1.0 - w) + s.baked.rgb * w;
        r.specular = (r.specular + ambient_specular(s) * s.baked.a) * (1.0 - w);
        return r;
    }
    r.diffuse += ambient_diffuse(s);
    r.specular += ambient_specular(s);
    return r;
}

// The sun (the scene's directional light) at a surface point, shadowed; zero without a sun.
fn sun_light(s: Surface) -> Lighting {
    var sun: Lighting;
    if camera.sun_dir.w > 0.5 {
        let L = camera.sun_dir.xyz;
        let ndl = max(dot(s.normal, L), 0.0);
        sun = brdf_light(s, L, ndl, camera.sun_color.rgb, 1.0);
        if ndl > 0.0 {
            let shadow = ls_sun_shadow(s.position, s.normal, s.position_error);
            sun.diffuse *= shadow;
            sun.specular *= shadow;
        }
    }
    return sun;
}

// The surface as the G-buffer stores it, without the targets' rounding: exponent and
// reflectance clamped to their stored ranges, the normal normalised (`attributes_of`,
// `surface_of`), the position exact.
fn as_stored(s: Surface) -> Surface {
    let a = attributes_of(s);
    var r = s;
    r.spec_exp = exp2(a.spec_exp * LS_SPEC_EXP_LOG_RANGE);
    r.spec_level = select(a.spec_level * (r.spec_exp + 8.0) / 8.0, a.spec_level, GBUFFER_SPEC_LEVEL_RAW);
    r.normal = safe_normalize(s.normal, vec3<f32>(0.0, 0.0, 1.0));
    if !GBUFFER_HAS_MATERIAL {
        r.brdf = GBUFFER_BRDF;
    }
    return r;
}

@fragment
fn fs_ambient(@builtin(position) frag: vec4<f32>) -> LightTargets {
    let s = gbuffer_load(vec2<i32>(frag.xy));
    var r: Lighting;
    if s.valid {
        if LS_PREPASS {
            // Seeds 003 and 004 draw directional lights as full-screen quads into the light
            // buffer: the sun starts it, shaded like every light from the thin buffer's normal
            // and exponent with unit reflectance, its specular summed into the mono A. Ambient
            // and emission are added in pass 3 from the material. With lightmaps the sun
            // fades out with distance at every pixel (the thin buffer cannot tell lightmapped
            // ones): pass 3 takes it from the lightmap there, or adds the rest back.
            r = sun_light(s);
            let w = baked_weight(s.position);
            r.diffuse *= 1.0 - w;
            r.specular *= 1.0 - w;
        } else {
            r = ambient_sun(s);
        }
    }
    return light_targets(s, min(r.diffuse, ambient_limit(s)), min(r.specular, ambient_limit(s)));
}

@vertex
fn vs_fullscreen_plain(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(vi);
}

// Stencil marking draws write no colour.
@fragment
fn fs_no_color() {
}

// Seed 001's marking draw rasterises both faces in one pipeline, so one fixed-function bias
// cannot draw front faces nearer and back faces farther (`kit::volume_depth_bias`): each face
// is biased here by the same constant and slope, the constant's unit the depth resolution at
// the fragment (2^(e-23) for float depth of exponent e, at least 24-bit's 2^-24).
fn biased_volume_depth(pos: vec4<f32>, front: bool) -> f32 {
    let slope = max(abs(dpdx(pos.z)), abs(dpdy(pos.z)));
    let unit = max(ldexp(1.0, frexp(pos.z).exp - 24), ldexp(1.0, -24));
    let bias = LS_VOLUME_BIAS_UNITS * unit + LS_VOLUME_BIAS_SLOPE * slope;
    let farther = select(1.0, -1.0, camera.far_depth == 0.0);
    return clamp(pos.z + select(farther, -farther, front) * bias, 0.0, 1.0);
}

@fragment
fn fs_mark_both_faces(@builtin(position) pos: vec4<f32>, @builtin(front_facing) front: bool) -> @builtin(frag_depth) f32 {
    return biased_volume_depth(pos, front);
}

// Counts the ideal: samples whose G-buffer point lies inside the light's true shape.
@fragment
fn fs_ideal(in: LightVarying) {
    let s = gbuffer_load(vec2<i32>(in.clip.xy));
    if !s.valid || !inside_light(s, light_at(in.light)) {
        discard;
    }
}

// Debug: seed 000's stencil diagram colours, combined with max blending.
@fragment
fn fs_blue() -> @location(0) vec4<f32> {
    return vec4<f32>(0.0, 0.0, 1.0, 1.0);
}

@fragment
fn fs_red() -> @location(0) vec4<f32> {
    return vec4<f32>(1.0, 0.0, 0.0, 1.0);
}

@fragment
fn fs_green() -> @location(0) vec4<f32> {
    return vec4<f32>(0.0, 1.0, 0.0, 1.0);
}

// Debug: the ledger's waste, +1 where the light was evaluated (this draw passed its method's
// depth and stencil tests, as its shading draw does) and its true shape does not hold the
// pixel's point, or the pixel has none (additive). It adds zero rather than discard: a
// discarded fragment skips its stencil pass operation, which the INVERT method's shading draw
// needs to clear its mark for the next light. `fs_waste_mark`: a marking draw's, adding
// nothing.
@fragment
fn fs_waste(in: LightVarying) -> @location(0) vec4<f32> {
    let s = gbuffer_load(vec2<i32>(in.clip.xy));
    let useful = s.valid && inside_light(s, light_at(in.light));
    return vec4<f32>(select(1.0, 0.0, useful), 0.0, 0.0, 0.0);
}

@fragment
fn fs_waste_mark() -> @location(0) vec4<f32> {
    return vec4<f32>(0.0);
}

struct WasteMark {
    @location(0) colour: vec4<f32>,
    @builtin(frag_depth) depth: f32,
};

@fragment
fn fs_waste_mark_both_faces(@builtin(position) pos: vec4<f32>, @builtin(front_facing) front: bool) -> WasteMark {
    return WasteMark(vec4<f32>(0.0), biased_volume_depth(pos, front));
}

// Debug: light complexity, +1 where a light touches the pixel (additive).
@fragment
fn fs_complexity(in: LightVarying) -> @location(0) vec4<f32> {
    let s = gbuffer_load(vec2<i32>(in.clip.xy));
    if !s.valid || !inside_light(s, light_at(in.light)) {
        discard;
    }
    return vec4<f32>(1.0, 0.0, 0.0, 0.0);
}
