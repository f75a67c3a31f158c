// The forward paths (seed 002): opaque and masked surfaces shaded as they are drawn,
// no G-buffer. Single-pass: each object walks its light list (`plan::forward_path_lists`) in
// one shader. Multi-pass: ambient + sun in one draw per object, then one additive draw per
// (object, light) pair. Both light a surface exactly as deferred shading does
// (`material_surface`, then `as_stored`: the G-buffer's ranges without its rounding), so the
// paths differ by the G-buffer's quantisation and the accumulation's rounding only.

struct ForwardOut {
    // Invariant: the depth pre-pass and the shading passes (LessEqual) must compute the same
    // depth for the same vertex, whichever vertex shader they use.
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) object: u32,
    @location(3) uv: vec2<f32>,
    @location(4) tangent: vec4<f32>,
    @location(5) uv1: vec2<f32>,
    // Multi-pass: the pair's light.
    @location(6) @interpolate(flat) light: u32,
};

fn forward_vertex(position: vec3<f32>, normal: vec3<f32>, uv: vec2<f32>, tangent: vec4<f32>, uv1: vec2<f32>, object: u32) -> ForwardOut {
    let o = objects[object];
    let v = o.model_view * vec4<f32>(position, 1.0);
    var out: ForwardOut;
    out.clip = camera.proj * v;
    out.view_pos = v.xyz;
    out.normal = (o.normal_view * vec4<f32>(normal, 0.0)).xyz;
    out.object = object;
    out.uv = uv;
    out.uv1 = uv1;
    out.tangent = vec4<f32>((o.model_view * vec4<f32>(tangent.xyz, 0.0)).xyz, tangent.w);
    out.light = 0u;
    return out;
}

// One object (the instance index), as `vs_geometry`.
@vertex
fn vs_forward(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
    @location(4) uv1: vec2<f32>,
    @builtin(instance_index) object: u32,
) -> ForwardOut {
    return forward_vertex(position, normal, uv, tangent, uv1, object);
}

// One (object, light) pair: the instance index names the pair, whose object and light are
// `light_lists[2 pair]` and `light_lists[2 pair + 1]` (`ForwardPathLists::pair_base`).
@vertex
fn vs_forward_pair(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
    @location(4) uv1: vec2<f32>,
    @builtin(instance_index) pair: u32,
) -> ForwardOut {
    var out = forward_vertex(position, normal, uv, tangent, uv1, light_lists[2u * pair]);
    out.light = light_lists[2u * pair + 1u];
    return out;
}

fn forward_geometry(in: ForwardOut) -> GeometryOut {
    var g: GeometryOut;
    g.clip = in.clip;
    g.view_pos = in.view_pos;
    g.normal = in.normal;
    g.object = in.object;
    g.uv = in.uv;
    g.tangent = in.tangent;
    g.uv1 = in.uv1;
    return g;
}

// The surface as deferred shading lights it (the G-buffer's clamps and ranges, `as_stored`,
// `attributes_of`), unrounded; the material's alpha returned.
fn forward_surface(in: ForwardOut, front: bool, s: ptr<function, Surface>) -> f32 {
    let alpha = material_surface(forward_geometry(in), front, s);
    var r = as_stored(*s);
    r.albedo = clamp(r.albedo, vec3<f32>(0.0), vec3<f32>(1.0));
    r.emissive = max(r.emissive, vec3<f32>(0.0));
    *s = r;
    return alpha;
}

// Ambient + sun, limited as the deferred path's accumulation start (`ambient_limit`).
fn forward_ambient(s: Surface) -> Lighting {
    let a = ambient_sun(s);
    var r: Lighting;
    r.diffuse = min(a.diffuse, ambient_limit(s));
    r.specular = min(a.specular, ambient_limit(s));
    return r;
}

// One light, limited as its deferred draw (`fs_light`: the light's fp16 clamp).
fn forward_light(s: Surface, l: GpuLight) -> Lighting {
    var r = shade_light(s, l);
    r.diffuse = min(r.diffuse, vec3<f32>(l.clamp));
    r.specular = min(r.specular, vec3<f32>(l.clamp));
    return r;
}

// Single-pass: ambient + sun, every light of the object's list, emission; composed as deferred
// composes (diffuse x albedo + specular + emissive).
fn forward_single(in: ForwardOut, s: Surface) -> vec4<f32> {
    let o = objects[in.object];
    let a = forward_ambient(s);
    var diffuse = a.diffuse;
    var specular = a.specular;
    // Two lights an iteration in scenes past lavapipe's loop limit, as `fs_forward`
    // (geometry.wgsl) walks its list (`plan::FORWARD_LOOP_LIGHTS`).
    var k = 0u;
    for (; LS_PAIRED_LOOPS && k + 1u < o.info.z; k += 2u) {
        let r0 = forward_light(s, light_at(light_lists[o.info.y + k]));
        let r1 = forward_light(s, light_at(light_lists[o.info.y + k + 1u]));
        diffuse += r0.diffuse;
        specular += r0.specular;
        diffuse += r1.diffuse;
        specular += r1.specular;
    }
    for (; k < o.info.z; k++) {
        let r = forward_light(s, light_at(light_lists[o.info.y + k]));
        diffuse += r.diffuse;
        specular += r.specular;
    }
    let lit = diffuse * s.albedo + specular + s.emissive;
    return vec4<f32>(min(lit, vec3<f32>(LS_FP16_MAX)), 1.0);
}

@fragment
fn fs_forward_single(in: ForwardOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var s: Surface;
    _ = forward_surface(in, front, &s);
    return forward_single(in, s);
}

@fragment
fn fs_forward_single_masked(in: ForwardOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var s: Surface;
    if forward_surface(in, front, &s) < objects[in.object].material.y {
        discard;
    }
    return forward_single(in, s);
}

// Multi-pass, first draw per object: ambient + sun and emission (replaces the colour).
fn forward_base(s: Surface) -> vec4<f32> {
    let a = forward_ambient(s);
    return vec4<f32>(min(a.diffuse * s.albedo + a.specular + s.emissive, vec3<f32>(LS_FP16_MAX)), 1.0);
}

@fragment
fn fs_forward_base(in: ForwardOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var s: Surface;
    _ = forward_surface(in, front, &s);
    return forward_base(s);
}

@fragment
fn fs_forward_base_masked(in: ForwardOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var s: Surface;
    if forward_surface(in, front, &s) < objects[in.object].material.y {
        discard;
    }
    return forward_base(s);
}

// Multi-pass, one (object, light) pair: the light's term, added (ADDITIVE blend).
fn forward_pair(in: ForwardOut, s: Surface) -> vec4<f32> {
    let r = forward_light(s, light_at(in.light));
    return vec4<f32>(r.diffuse * s.albedo + r.specular, 0.0);
}

@fragment
fn fs_forward_pair(in: ForwardOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var s: Surface;
    _ = forward_surface(in, front, &s);
    return forward_pair(in, s);
}

@fragment
fn fs_forward_pair_masked(in: ForwardOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var s: Surface;
    if forward_surface(in, front, &s) < objects[in.object].material.y {
        discard;
    }
    return forward_pair(in, s);
}

// Depth pre-pass of masked surfaces: alpha-tested like their shading draws, no colour.
@fragment
fn fs_forward_depth_masked(in: ForwardOut, @builtin(front_facing) front: bool) {
    var s: Surface;
    if material_surface(forward_geometry(in), front, &s) < objects[in.object].material.y {
        discard;
    }
}
