// The views that average RIS's frames (`DebugView::Converge`, `DebugView::Variance`;
// stochastic/reuse.rs): `converge` holds two vec4 a pixel, the sums over the frames averaged of
// (diffuse, luminance) and (specular, luminance squared), the light of each frame as the
// resolve (or the denoiser) left it in region B (`denoise.wgsl`). The count of frames n is the
// header's word [9].w from bit 8 (`reuse.wgsl`); n = 1 starts the sums anew.

fn converge_count() -> f32 {
    return f32(reuse[9u].w >> 8u);
}

@compute @workgroup_size(8, 8)
fn cs_converge(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = reuse[9u];
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = vec2<i32>(id.xy);
    let d = denoise_load(1u, p);
    let l = denoise_luminance(d.diffuse, d.specular);
    var a = vec4<f32>(d.diffuse, l);
    var b = vec4<f32>(d.specular, l * l);
    let at = 2u * (u32(p.y) * size.x + u32(p.x));
    if converge_count() > 1.0 {
        a += bitcast<vec4<f32>>(converge[at]);
        b += bitcast<vec4<f32>>(converge[at + 1u]);
    }
    converge[at] = bitcast<vec4<u32>>(a);
    converge[at + 1u] = bitcast<vec4<u32>>(b);
}

// The mean of the frames into the accumulation (the `converge` view).
@fragment
fn fs_ris_converged(in: TiledVarying) -> LightTargets {
    let p = vec2<i32>(in.clip.xy);
    let s = gbuffer_load(p);
    let at = 2u * (u32(p.y) * reuse[9u].x + u32(p.x));
    let n = max(converge_count(), 1.0);
    var diffuse = vec3<f32>(0.0);
    var specular = vec3<f32>(0.0);
    if s.valid {
        diffuse = bitcast<vec4<f32>>(converge[at]).xyz / n;
        specular = bitcast<vec4<f32>>(converge[at + 1u]).xyz / n;
    }
    return light_targets(s, diffuse, specular);
}

// The light's deviation over its mean across the frames averaged (the `variance` view's
// debug target; the sample deviation, 0 until two frames are in).
@fragment
fn fs_ris_variance(in: TiledVarying) -> @location(0) vec4<f32> {
    let p = vec2<i32>(in.clip.xy);
    let at = 2u * (u32(p.y) * reuse[9u].x + u32(p.x));
    let n = converge_count();
    let sum = bitcast<vec4<f32>>(converge[at]).w;
    let squares = bitcast<vec4<f32>>(converge[at + 1u]).w;
    var v = 0.0;
    if n > 1.0 && sum > 0.0 {
        let mean = sum / n;
        let deviation = sqrt(max((squares - n * mean * mean) / (n - 1.0), 0.0));
        v = deviation / mean;
    }
    return vec4<f32>(v, 0.0, 0.0, 1.0);
}
