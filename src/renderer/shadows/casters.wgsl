// The shadow pass (`shadows::pass`). Each instance is one caster in one tile
// (instance = tile * objects + object); the depth written is linear in the distance along the
// tile's axis (`ShadowTile`), clipped at the tile's near plane. A face of the cube array
// (`--shadow-cube array`, info.x = LS_TILE_CUBE_FACE) writes the distance from the light
// instead (|q| / far): the hardware filters across faces with one reference depth, which only
// a face-independent depth makes right (`shadow_cube_lookup` scales its reference to match).

struct ShadowOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) depth: f32,
    // Light-space position (affine in the object's position, so interpolated exactly) and,
    // for a cube-array face, 1 / far (0 otherwise).
    @location(1) q: vec3<f32>,
    @location(2) @interpolate(flat) radial: f32,
};

@vertex
fn vs_shadow(@location(0) position: vec3<f32>, @builtin(instance_index) instance: u32) -> ShadowOut {
    let objects_n = max(shadow_params_load().sun.w, 1u);
    let t = shadow_tile_load(instance / objects_n);
    let o = objects[instance % objects_n];
    let q = (t.to_light * (o.model_view * vec4<f32>(position, 1.0))).xyz;
    let depth = -q.z * t.proj.z + t.proj.w;
    var out: ShadowOut;
    out.depth = depth;
    out.q = q;
    out.radial = select(0.0, t.proj.z, t.info.x == LS_TILE_CUBE_FACE);
    if t.info.x == LS_TILE_ORTHOGRAPHIC {
        out.clip = vec4<f32>(q.xy * t.proj.xy, depth, 1.0);
    } else {
        // z / w runs 0 .. 1 from the near plane to the far one (w = -q.z), so clipping is
        // right; the fragment writes the linear depth itself.
        let w = -q.z;
        let far = 1.0 / t.proj.z;
        let near = t.info.w;
        out.clip = vec4<f32>(q.xy * t.proj.xy, (w - near) * far / (far - near), w);
    }
    return out;
}

@fragment
fn fs_shadow(in: ShadowOut) -> @builtin(frag_depth) f32 {
    if in.radial > 0.0 {
        return clamp(length(in.q) * in.radial, 0.0, 1.0);
    }
    return clamp(in.depth, 0.0, 1.0);
}
