// G-buffer pass (seed 000: all lighting inputs in one pass with multiple render targets).

struct GeometryOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) object: u32,
};

@vertex
fn vs_geometry(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @builtin(instance_index) object: u32,
) -> GeometryOut {
    let o = objects[object];
    let v = o.model_view * vec4<f32>(position, 1.0);
    var out: GeometryOut;
    out.clip = camera.proj * v;
    out.view_pos = v.xyz;
    out.normal = (o.normal_view * vec4<f32>(normal, 0.0)).xyz;
    out.object = object;
    return out;
}

@fragment
fn fs_geometry(in: GeometryOut, @builtin(front_facing) front: bool) -> GBufferOut {
    let o = objects[in.object];
    var s: Surface;
    s.albedo = o.albedo_spec.rgb;
    s.spec_level = o.albedo_spec.a;
    s.spec_exp = o.emissive_exp.a;
    let n = safe_normalize(in.normal, vec3<f32>(0.0, 0.0, 1.0));
    s.normal = select(-n, n, front);
    s.emissive = o.emissive_exp.rgb;
    s.position = in.view_pos;
    s.depth = in.clip.z;
    s.valid = true;
    return gbuffer_store(s);
}
