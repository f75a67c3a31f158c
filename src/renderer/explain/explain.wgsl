// Why each light lit (or did not light) one pixel (`explain`): one invocation a light, each
// shading the pixel's G-buffer surface exactly as the light pass and the tiled/clustered loop
// do (`shade_light_view` with the shadow lookup, then the light's own clamp), whatever the
// culling mode decided, and writing the terms apart: what it added, its shadow and cookie
// factors, and the tests that can zero it (range, cone, N.L, the culling mask).
// explain_out, 4 vec4 a light: (diffuse, shadow), (specular, cookie), (lit colour: diffuse x
// albedo + specular, valid), (distance / radius, spot attenuation, N.L, reaches the layer).
@compute @workgroup_size(64)
fn cs_explain(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= explain_params[2] {
        return;
    }
    let s = gbuffer_load(vec2<i32>(i32(explain_params[0]), i32(explain_params[1])));
    let at = 4u * i;
    if !s.valid {
        for (var k = 0u; k < 4u; k++) {
            explain_out[at + k] = vec4<f32>(0.0);
        }
        return;
    }
    let l = light_at(i);
    let r = shade_light_view(s, view_dir(s), l, true);
    let diffuse = min(r.diffuse, vec3<f32>(l.clamp));
    let specular = min(r.specular, vec3<f32>(l.clamp));
    // The same tests as `shade_light_view`, apart.
    let to_light = l.position - s.position;
    let d = length(to_light);
    let L = select(s.normal, to_light / d, d > 1e-6 * l.falloff);
    let att = spot_attenuation(l, -L);
    let ndl = dot(s.normal, L);
    let reaches = ls_light_reaches(l, s.layer);
    var shadow = 1.0;
    if reaches && d < l.radius && att > 0.0 && ndl > 0.0 {
        shadow = ls_shadow(l, s.position, s.normal, s.position_error);
    }
    var cookie = 1.0;
    if LS_COOKIES && l.cookie != LS_NO_COOKIE {
        cookie = dot(ls_cookie(l, s.position), vec3<f32>(0.2126, 0.7152, 0.0722));
    }
    explain_out[at] = vec4<f32>(diffuse, shadow);
    explain_out[at + 1u] = vec4<f32>(specular, cookie);
    explain_out[at + 2u] = vec4<f32>(diffuse * s.albedo + specular, 1.0);
    explain_out[at + 3u] = vec4<f32>(d / l.radius, att, ndl, select(0.0, 1.0, reaches));
}

// Brute force, the culling oracle's reference: every light of [first, first + count) shades
// each pixel's G-buffer surface exactly as `cs_explain` does (`shade_light_view` with the
// shadow lookup, then the light's own clamp), summed in f32 onto what the earlier chunks left.
// explain_params: (width, height, first, count). explain_out, 3 vec4 a pixel: (diffuse, lights
// adding), (specular, 0), (lit colour: diffuse x albedo + specular, 0); background pixels keep
// the zeros the buffer was cleared to.
@compute @workgroup_size(8, 8)
fn cs_brute_force(@builtin(global_invocation_id) id: vec3<u32>) {
    let w = explain_params[0];
    if id.x >= w || id.y >= explain_params[1] {
        return;
    }
    let s = gbuffer_load(vec2<i32>(id.xy));
    if !s.valid {
        return;
    }
    let at = 3u * (id.y * w + id.x);
    var diffuse = explain_out[at];
    var specular = explain_out[at + 1u].xyz;
    var lit = explain_out[at + 2u].xyz;
    let V = view_dir(s);
    let end = explain_params[2] + explain_params[3];
    for (var i = explain_params[2]; i < end; i++) {
        let l = light_at(i);
        let r = shade_light_view(s, V, l, true);
        let d = min(r.diffuse, vec3<f32>(l.clamp));
        let sp = min(r.specular, vec3<f32>(l.clamp));
        diffuse += vec4<f32>(d, select(0.0, 1.0, any(d + sp > vec3<f32>(0.0))));
        specular += sp;
        lit += d * s.albedo + sp;
    }
    explain_out[at] = diffuse;
    explain_out[at + 1u] = vec4<f32>(specular, 0.0);
    explain_out[at + 2u] = vec4<f32>(lit, 0.0);
}
