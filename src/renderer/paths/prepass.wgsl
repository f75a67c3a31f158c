// The light pre-pass's final pass (seeds 003/004, pass 3): the geometry again, depth tested
// against pass 1's depth (not written), each fragment combining its own material (textures
// included) with the light buffer at its pixel (every light and the sun), plus ambient and
// emission (seed 004:
// "fetch the computed lighting, combine it with color textures and add any ambient/emissive
// lighting"). Writes the HDR scene colour; blended surfaces are drawn forward over it after.
// Reads `light_diffuse` (the compose group, group 2): the one light buffer.

// The light at pixel `p` as the material `s` reflects it: (diffuse, specular), before the
// albedo multiplies the diffuse.
// The buffer's A holds the luminance of the specular light shaded with unit reflectance; its
// colour is taken from the diffuse light (seeds 003/004: specular colour = mono x the diffuse
// light's chromaticity, diffuse / luminance(diffuse)). Exact for one light or lights of one
// colour; lights of different colours mix their chromaticities by diffuse weight, not by
// specular weight. A pixel with specular and no diffuse light (only when the diffuse rounded
// to zero) takes white.
fn prepass_light(s: Surface, p: vec2<i32>) -> Lighting {
    let v = decode_light_buffer(textureLoad(light_diffuse, p, 0));
    let diffuse = finite(v.rgb);
    let mono = finite(vec3<f32>(v.a)).x;
    let lum = dot(diffuse, LS_LUMINANCE);
    let chroma = select(vec3<f32>(1.0), diffuse / lum, lum > 1e-6);
    // The material's reflectance f0 (level x 8 / (n + 8)) scales the unit-reflectance term.
    let f0 = s.spec_level * 8.0 / (s.spec_exp + 8.0);
    var r: Lighting;
    r.diffuse = diffuse;
    r.specular = chroma * (mono * f0);
    // The reflectance models the one Blinn-Phong buffer can express (`brdf_light`); toon and
    // Phong are shaded forward after this pass (`Brdf::prepass_lit`).
    if s.brdf == LS_BRDF_LAMBERT {
        r.specular = vec3<f32>(0.0);
    } else if s.brdf == LS_BRDF_UNLIT {
        r.diffuse = vec3<f32>(0.0);
        r.specular = vec3<f32>(0.0);
    } else if s.brdf == LS_BRDF_METAL {
        r.diffuse = vec3<f32>(0.0);
        r.specular = r.specular * s.albedo;
    }
    return r;
}

fn prepass_shade(s: Surface, p: vec2<i32>) -> vec4<f32> {
    let light = prepass_light(s, p);
    var diffuse = light.diffuse + min(ambient_diffuse(s), ambient_limit(s));
    var specular = light.specular + min(ambient_specular(s), ambient_limit(s));
    // Seed 004's lightmaps: the buffer's sun faded out by `baked_weight` (`fs_ambient`); a
    // lightmapped surface takes the baked part (`ambient_sun`'s crossfade), any other adds
    // the faded share of the sun back, from its own normal.
    let w = baked_weight(s.position);
    if takes_lightmap(s) {
        diffuse = light.diffuse + min((ambient_diffuse(s) * s.baked.a) * (1.0 - w) + s.baked.rgb * w, ambient_limit(s));
        specular = light.specular + min(ambient_specular(s) * s.baked.a * (1.0 - w), ambient_limit(s));
    } else if w > 0.0 {
        let sun = sun_light(s);
        diffuse += min(sun.diffuse * w, ambient_limit(s));
        specular += min(sun.specular * w, ambient_limit(s));
    }
    let lit = diffuse * s.albedo + specular + s.emissive;
    return vec4<f32>(min(lit, vec3<f32>(LS_FP16_MAX)), 1.0);
}

// `--msaa 4`: pass 1's depth has one sample a pixel, so pass 3's multisampled depth is primed
// by a depth-only draw of pass 1's list first (seed 003: "the z-buffer is already in a primed
// state"), alpha-masked surfaces discarding as pass 1 does.
@fragment
fn fs_prepass_prime_masked(in: GeometryOut, @builtin(front_facing) front: bool) {
    var s: Surface;
    if material_surface(in, front, &s) < objects[in.object].material.y {
        discard;
    }
}

@fragment
fn fs_prepass(in: GeometryOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var s: Surface;
    _ = material_surface(in, front, &s);
    return prepass_shade(s, vec2<i32>(in.clip.xy));
}

// Alpha MASK: discarded again below the cutoff (seed 003: punch-through in the 3rd pass), or
// the surface behind, which pass 1 left in the depth buffer, would be shaded with this one.
@fragment
fn fs_prepass_masked(in: GeometryOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var s: Surface;
    let alpha = material_surface(in, front, &s);
    if alpha < objects[in.object].material.y {
        discard;
    }
    return prepass_shade(s, vec2<i32>(in.clip.xy));
}
