// G-buffer pass (seed 000: all lighting inputs in one pass with multiple render targets), with
// the material's textures (seed 003: diffuse, normal and specular maps), and the forward pass
// that shades what deferred shading cannot: blended (transparent) surfaces (seeds 002-004).

// The material's bindings (group 1) are declared from Rust: renderer::bindings::MATERIAL.

struct GeometryOut {
    // Invariant: depth peeling draws the same triangles again at Equal depth.
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) object: u32,
    @location(3) uv: vec2<f32>,
    @location(4) tangent: vec4<f32>,
    @location(5) uv1: vec2<f32>,
};

@vertex
fn vs_geometry(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
    @location(4) uv1: vec2<f32>,
    @builtin(instance_index) object: u32,
) -> GeometryOut {
    let o = objects[object];
    let v = o.model_view * vec4<f32>(position, 1.0);
    var out: GeometryOut;
    out.clip = camera.proj * v;
    out.view_pos = v.xyz;
    out.normal = (o.normal_view * vec4<f32>(normal, 0.0)).xyz;
    out.object = object;
    out.uv = uv;
    out.uv1 = uv1;
    // Tangents transform with the model-view matrix (they lie in the surface).
    out.tangent = vec4<f32>((o.model_view * vec4<f32>(tangent.xyz, 0.0)).xyz, tangent.w);
    return out;
}

// Blinn-Phong terms from metallic-roughness, per pixel; the same mapping as
// `Material::blinn_phong_from_pbr` in Rust (keep the two in step).
fn blinn_phong_from_pbr(base: vec3<f32>, metallic: f32, roughness: f32, f0_dielectric: f32, s: ptr<function, Surface>) {
    let m = clamp(metallic, 0.0, 1.0);
    let r = clamp(roughness, 0.0, 1.0);
    let lum = dot(base, vec3<f32>(0.2126, 0.7152, 0.0722));
    let f0 = mix(f0_dielectric, lum, m);
    let a = max(r * r, 1e-3);
    let e = clamp(2.0 / (a * a) - 2.0, 1.0, 2048.0);
    (*s).albedo = base * (1.0 - m);
    (*s).spec_exp = e;
    (*s).spec_level = f0 * (e + 8.0) / 8.0;
}

// The metal model's terms (after `blinn_phong_from_pbr`, whose exponent it keeps): the
// specular colour F0 = mix(f0_dielectric, base, metallic) in the albedo, reflectance 1 in the
// level; the same mapping as `Material::metal_from_pbr` in Rust.
fn metal_from_pbr(base: vec3<f32>, metallic: f32, f0_dielectric: f32, s: ptr<function, Surface>) {
    let m = clamp(metallic, 0.0, 1.0);
    (*s).albedo = mix(vec3<f32>(clamp(f0_dielectric, 0.0, 1.0)), clamp(base, vec3<f32>(0.0), vec3<f32>(1.0)), m);
    (*s).spec_level = ((*s).spec_exp + 8.0) / 8.0;
}

// The texture coordinates map `slot` samples (0 base colour, 1 normal, 2 emissive,
// 3 metal-rough): its set, transformed by its KHR_texture_transform (`UvTransform::rows`).
fn map_uv(in: GeometryOut, o: GpuObject, slot: u32) -> vec2<f32> {
    let r0 = o.uv_transform[slot * 2u];
    let r1 = o.uv_transform[slot * 2u + 1u];
    let uv = vec3<f32>(select(in.uv, in.uv1, r0.w > 0.5), 1.0);
    return vec2<f32>(dot(r0.xyz, uv), dot(r1.xyz, uv));
}

// Map `slot` of the object's material sampled at its coordinates (`map_uv`), or at the
// interpolated TEXCOORD_0 itself when the map reads those untransformed.
fn sample_map(tex: texture_2d<f32>, in: GeometryOut, o: GpuObject, slot: u32) -> vec4<f32> {
    if (o.info.x & (LS_MAT_UV_TRANSFORMED << slot)) != 0u {
        return textureSample(tex, material_sampler, map_uv(in, o, slot));
    }
    return textureSample(tex, material_sampler, in.uv);
}

// The surface a fragment describes, with its material's textures applied; .w of the result
// is the alpha.
fn material_surface(in: GeometryOut, front: bool, s: ptr<function, Surface>) -> f32 {
    let o = objects[in.object];
    let flags = o.info.x;
    // A map the material lacks is the white default: not sampled (exactly 1.0 either way), nor
    // compiled in when no material of the scene has one (`ShaderFeatures::colour_maps`).
    var base = vec4<f32>(1.0);
    if LS_COLOUR_MAPS && (flags & LS_MAT_BASE_MAP) != 0u {
        base = sample_map(base_color_tex, in, o, 0u);
    }
    (*s).albedo = o.albedo_spec.rgb * base.rgb;
    (*s).spec_level = o.albedo_spec.a;
    (*s).spec_exp = o.emissive_exp.a;
    (*s).brdf = o.info.w;
    // Seed 004's culling layer: the G-buffer stores it (when the scene's masks need it) and the
    // forward pass reads it here.
    (*s).layer = u32(o.material.w) & 31u;
    // Unlit shows the base colour as it is: no metal-roughness mapping darkens it.
    if (flags & LS_MAT_METAL_ROUGH) != 0u && o.info.w != LS_BRDF_UNLIT {
        let mr = sample_map(metal_rough_tex, in, o, 3u);
        blinn_phong_from_pbr(o.albedo_spec.rgb * base.rgb, o.pbr.x * mr.b, o.pbr.y * mr.g, o.pbr.z, s);
        let metallic = o.pbr.x * mr.b;
        if (flags & LS_MAT_METAL_BY_PIXEL) != 0u && metallic < LS_METAL_THRESHOLD {
            // The non-metal parts of a metal's map keep blinn-phong (and their diffuse).
            (*s).brdf = LS_BRDF_BLINN_PHONG;
        } else if o.info.w == LS_BRDF_METAL {
            metal_from_pbr(o.albedo_spec.rgb * base.rgb, metallic, o.pbr.z, s);
        }
    }
    var n = safe_normalize(in.normal, vec3<f32>(0.0, 0.0, 1.0));
    if (flags & LS_MAT_NORMAL_MAP) != 0u {
        // Tangent space from the interpolated frame (MikkTSpace convention: the bitangent is
        // rebuilt from normal x tangent with the stored sign, not interpolated).
        let t = safe_normalize(in.tangent.xyz - n * dot(n, in.tangent.xyz), vec3<f32>(1.0, 0.0, 0.0));
        let b = cross(n, t) * select(1.0, -1.0, in.tangent.w < 0.0);
        let m = sample_map(normal_tex, in, o, 1u).xyz * 2.0 - 1.0;
        let scaled = vec3<f32>(m.xy * o.material.z, m.z);
        n = safe_normalize(t * scaled.x + b * scaled.y + n * scaled.z, n);
    }
    // Back faces (double-sided materials) are lit from their own side.
    (*s).normal = select(-n, n, front);
    var emissive = o.emissive_exp.rgb;
    if LS_COLOUR_MAPS && (flags & LS_MAT_EMISSIVE_MAP) != 0u {
        emissive *= sample_map(emissive_tex, in, o, 2u).rgb;
    }
    (*s).emissive = emissive;
    (*s).position = in.view_pos;
    (*s).depth = in.clip.z;
    (*s).valid = true;
    // Seed 004's lightmap, at TEXCOORD_1, level 0 (the faces' cells are apart by a gutter of a
    // level-0 texel or more; coarser levels would blend neighbouring faces).
    if (flags & LS_MAT_LIGHTMAP) != 0u && camera.lightmap_fade.z > 0.5 {
        let l = textureSampleLevel(lightmap_tex, material_sampler, in.uv1, 0.0);
        (*s).baked = vec4<f32>(l.rgb * o.lightmap.x, l.a);
        (*s).lightmapped = true;
    }
    return o.material.x * base.a;
}

@fragment
fn fs_geometry(in: GeometryOut, @builtin(front_facing) front: bool) -> GBufferOut {
    var s: Surface;
    _ = material_surface(in, front, &s);
    return gbuffer_store(s);
}

// Alpha MASK: punch-through, the fragment is dropped below the cutoff.
@fragment
fn fs_geometry_masked(in: GeometryOut, @builtin(front_facing) front: bool) -> GBufferOut {
    var s: Surface;
    let alpha = material_surface(in, front, &s);
    if alpha < objects[in.object].material.y {
        discard;
    }
    return gbuffer_store(s);
}

// Alpha BLEND: shaded forward, in the same lighting model, by the lights that can reach the
// fragment (lists built on the CPU, see `plan::plan_draws`), into the HDR scene colour the
// compose pass wrote.
// The result is blended over it with the material's alpha.
@fragment
fn fs_forward(in: GeometryOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    return forward_shade(in, front);
}

// The light pre-pass's alpha-masked objects shaded forward (`DrawLists::forward_opaque`):
// dropped below the cutoff, as pass 1 dropped them, else written opaque.
@fragment
fn fs_forward_masked(in: GeometryOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let c = forward_shade(in, front);
    if c.a < objects[in.object].material.y {
        discard;
    }
    return vec4<f32>(c.rgb, 1.0);
}

// The blended fragment's colour and alpha (straight, not premultiplied).
fn forward_shade(in: GeometryOut, front: bool) -> vec4<f32> {
    var s: Surface;
    let alpha = clamp(material_surface(in, front, &s), 0.0, 1.0);
    let o = objects[in.object];
    // Ambient + sun as the deferred path adds them, in the object's reflectance model.
    let ambient = ambient_sun(s);
    var diffuse = min(ambient.diffuse, ambient_limit(s));
    var specular = min(ambient.specular, ambient_limit(s));
    // Two lists hold every light that can reach this fragment: the object's and its screen
    // tile's (lights whose volume's screen rectangle covers the tile); the shorter is walked.
    // Both are in light order, so the same non-zero terms are summed in the same order.
    var first = o.info.y;
    var count = o.info.z;
    let grid = camera.forward_tiles;
    if grid.x > 0u {
        let t = min(vec2<u32>(max(in.clip.xy, vec2<f32>(0.0))) / grid.x, vec2<u32>(grid.y - 1u, grid.z - 1u));
        let h = grid.w + 2u * (t.y * grid.y + t.x);
        if light_lists[h + 1u] < count {
            first = light_lists[h];
            count = light_lists[h + 1u];
        }
    }
    // lavapipe ends a shader invocation's loops once they have run 65,535 iterations between
    // them (gallivm's shared loop limiter, silently), so a list walked a light an iteration
    // loses every light past the 65,535th: scenes of more than `plan::FORWARD_LOOP_LIGHTS`
    // (65,000) lights walk two an iteration, lists of up to
    // `plan::FORWARD_LIST_MAX` entries. The same terms are added in the same order.
    var k = 0u;
    for (; LS_PAIRED_LOOPS && k + 1u < count; k += 2u) {
        let l0 = light_at(light_lists[first + k]);
        let l1 = light_at(light_lists[first + k + 1u]);
        let r0 = shade_light(s, l0);
        let r1 = shade_light(s, l1);
        diffuse += min(r0.diffuse, vec3<f32>(l0.clamp));
        specular += min(r0.specular, vec3<f32>(l0.clamp));
        diffuse += min(r1.diffuse, vec3<f32>(l1.clamp));
        specular += min(r1.specular, vec3<f32>(l1.clamp));
    }
    for (; k < count; k++) {
        let l = light_at(light_lists[first + k]);
        let r = shade_light(s, l);
        diffuse += min(r.diffuse, vec3<f32>(l.clamp));
        specular += min(r.specular, vec3<f32>(l.clamp));
    }
    let lit = diffuse * s.albedo + specular + s.emissive;
    return vec4<f32>(min(lit, vec3<f32>(LS_FP16_MAX)), alpha);
}

// Depth peeling (seed 002; Everitt 2001, "Interactive Order-Independent Transparency"). Layer
// k keeps, per pixel, the nearest blended fragment strictly behind layer k - 1's and not behind
// the opaque surfaces: first a depth-only pass finds its depth (`fs_peel_depth` discards the
// rest, the depth test keeps the nearest), then `fs_peel_colour` shades the fragments at exactly
// that depth and adds them under the layers before (front to back: the blend multiplies by the
// coverage not yet taken, 1 - dst.a). Coincident fragments are one layer, each added.
fn peel_keeps(in: GeometryOut) -> bool {
    let p = vec2<i32>(in.clip.xy);
    let opaque = textureLoad(peel_opaque, p, 0).r;
    let previous = textureLoad(peel_previous, p, 0).r;
    // Reversed Z (far plane at 0) flips both comparisons.
    if camera.far_depth == 0.0 {
        return in.clip.z >= opaque && in.clip.z < previous;
    }
    return in.clip.z <= opaque && in.clip.z > previous;
}

@fragment
fn fs_peel_depth(in: GeometryOut) {
    if !peel_keeps(in) {
        discard;
    }
}

@fragment
fn fs_peel_colour(in: GeometryOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let c = forward_shade(in, front);
    if !peel_keeps(in) {
        discard;
    }
    return vec4<f32>(c.rgb * c.a, c.a);
}

// The layers, composited front to back (premultiplied), over the scene colour.
@fragment
fn fs_peeled(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(peeled, vec2<i32>(floor(frag.xy)), 0);
}
