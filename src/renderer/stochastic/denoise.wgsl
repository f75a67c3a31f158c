// The denoiser of RIS's light (stochastic/reuse.rs, `ris_denoise`): temporal accumulation and a
// variance-guided, edge-aware a-trous filter, after Schied et al. 2017, "Spatiotemporal
// variance-guided filtering" (SVGF). It filters only the stochastic light (the lights'
// diffuse and specular, before the albedo: the accumulation holds them without it), in four
// buffers of a record a pixel: A and B (`denoise_a`, `denoise_b`), the ping-pong of the
// filter, and H0 and H1, the history each frame reads one of and writes the other (the
// header's word [9].w, `reuse.wgsl`: bit 0 denoise, bit 1 the history is valid, bit 2 which
// one is read).
// A record is three vec4: (diffuse, variance), (specular, luminance), (depth, octahedral normal
// bits, 1 where a surface is, history length).
//
// Biased by design: the filter spreads light across like pixels and the history lags behind
// what moved; the bench measures the error it leaves (docs/stochastic.md).

struct Denoised {
    diffuse: vec3<f32>,
    variance: f32,
    specular: vec3<f32>,
    luminance: f32,
    depth: f32,
    normal: vec3<f32>,
    valid: bool,
    length: f32,
};

// Where pixel p's record starts in its region (0: A, 1: B, 2: H0, 3: H1).
fn denoise_slot(p: vec2<i32>) -> u32 {
    return 3u * (u32(p.y) * reuse[9u].x + u32(p.x));
}

fn denoise_word(region: u32, at: u32) -> vec4<u32> {
    switch region {
        case 0u: {
            return denoise_a[at];
        }
        case 1u: {
            return denoise_b[at];
        }
        case 2u: {
            return denoise_h0[at];
        }
        default: {
            return denoise_h1[at];
        }
    }
}

fn denoise_put(region: u32, at: u32, v: vec4<u32>) {
    switch region {
        case 0u: {
            denoise_a[at] = v;
        }
        case 1u: {
            denoise_b[at] = v;
        }
        case 2u: {
            denoise_h0[at] = v;
        }
        default: {
            denoise_h1[at] = v;
        }
    }
}

fn denoise_load(region: u32, p: vec2<i32>) -> Denoised {
    let at = denoise_slot(p);
    let a = bitcast<vec4<f32>>(denoise_word(region, at));
    let b = bitcast<vec4<f32>>(denoise_word(region, at + 1u));
    let c = denoise_word(region, at + 2u);
    let n = oct_decode(unpack2x16snorm(c.y));
    return Denoised(a.xyz, a.w, b.xyz, b.w, bitcast<f32>(c.x), n, c.z == 1u, bitcast<f32>(c.w));
}

fn denoise_store(region: u32, p: vec2<i32>, d: Denoised) {
    let at = denoise_slot(p);
    denoise_put(region, at, bitcast<vec4<u32>>(vec4<f32>(d.diffuse, d.variance)));
    denoise_put(region, at + 1u, bitcast<vec4<u32>>(vec4<f32>(d.specular, d.luminance)));
    let valid = select(0u, 1u, d.valid);
    let c = vec4<u32>(bitcast<u32>(d.depth), pack2x16snorm(oct_encode(d.normal)), valid, bitcast<u32>(d.length));
    denoise_put(region, at + 2u, c);
}

fn denoise_luminance(d: vec3<f32>, sp: vec3<f32>) -> f32 {
    return dot(d + sp, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// The resolve into region B: each pixel's final samples shaded with their shadows, the K
// averaged (what `fs_ris_resolve` draws without the denoiser).
@compute @workgroup_size(8, 8)
fn cs_denoise_resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = reuse[9u];
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = vec2<i32>(id.xy);
    let s = gbuffer_load(p);
    var out = Lighting(vec3<f32>(0.0), vec3<f32>(0.0));
    if s.valid {
        let view = view_dir(s);
        for (var j = 0u; j < size.z; j++) {
            let r = reuse_load(1u, reuse_slot(1u, p, j));
            let lit = ris_shade_light(s, view, r.light, r.weight);
            out.diffuse += lit.diffuse;
            out.specular += lit.specular;
        }
        out.diffuse /= f32(max(size.z, 1u));
        out.specular /= f32(max(size.z, 1u));
    }
    let l = denoise_luminance(out.diffuse, out.specular);
    denoise_store(1u, p, Denoised(out.diffuse, 0.0, out.specular, l, -s.position.z, s.normal, s.valid, 0.0));
}

// Temporal accumulation, B into A and the history: the last frame's history at the reprojected
// point, where alike (`reuse_alike`), blended with this frame's by 1 / (length + 1), at least
// 1/10 (an exponential average over about ten frames once the history is long); the first and
// second moments of the luminance alike, whose difference is the variance the filter is
// guided by. Where the history is shorter than 4 frames the variance is the 3x3
// neighbourhood's instead.
@compute @workgroup_size(8, 8)
fn cs_denoise_temporal(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = reuse[9u];
    let flags = size.w;
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = vec2<i32>(id.xy);
    var d = denoise_load(1u, p);
    let read = 2u + ((flags >> 2u) & 1u);
    let write = 5u - read;
    var m1 = d.luminance;
    var m2 = d.luminance * d.luminance;
    var length = 1.0;
    if d.valid && (flags & 2u) != 0u {
        let s = gbuffer_load(p);
        let here = reuse_matrix(0u) * vec4<f32>(s.position, 1.0);
        let clip = reuse_matrix(4u) * here;
        if clip.w > 0.0 {
            let ndc = clip.xy / clip.w;
            let q = vec2<i32>(floor(vec2<f32>(0.5 * ndc.x + 0.5, 0.5 - 0.5 * ndc.y) * vec2<f32>(size.xy)));
            if all(q >= vec2<i32>(0)) && all(q < vec2<i32>(size.xy)) {
                let h = denoise_load(read, q);
                let normal = normalize((reuse_matrix(0u) * vec4<f32>(s.normal, 0.0)).xyz);
                if h.valid && reuse_alike(h.depth, h.normal, -here.z, normal) {
                    length = min(h.length + 1.0, 32.0);
                    let a = max(1.0 / length, 0.1);
                    d.diffuse = mix(h.diffuse, d.diffuse, a);
                    d.specular = mix(h.specular, d.specular, a);
                    m1 = mix(h.variance, m1, a);
                    m2 = mix(h.luminance, m2, a);
                }
            }
        }
    }
    // The history keeps the moments in the variance and luminance fields.
    denoise_store(write, p, Denoised(d.diffuse, m1, d.specular, m2, d.depth, d.normal, d.valid, length));
    var variance = max(m2 - m1 * m1, 0.0);
    if length < 4.0 {
        var s1 = 0.0;
        var s2 = 0.0;
        var n = 0.0;
        for (var y = -1; y <= 1; y++) {
            for (var x = -1; x <= 1; x++) {
                let q = clamp(p + vec2<i32>(x, y), vec2<i32>(0), vec2<i32>(size.xy) - 1);
                let o = denoise_load(1u, q);
                if o.valid {
                    s1 += o.luminance;
                    s2 += o.luminance * o.luminance;
                    n += 1.0;
                }
            }
        }
        let mean = s1 / max(n, 1.0);
        variance = max(s2 / max(n, 1.0) - mean * mean, 0.0);
    }
    d.variance = variance;
    d.luminance = denoise_luminance(d.diffuse, d.specular);
    d.length = length;
    denoise_store(0u, p, d);
}

// One a-trous step (Dammertz et al. 2010, "Edge-avoiding a-trous wavelet transform for fast
// global illumination filtering"): a 5x5 B3-spline kernel with holes of `step` pixels, each tap
// weighted by depth (relative, within 5% per step), normal (cos^64) and luminance (within 4
// standard deviations of the pixel's variance, SVGF's sigma_l); the variance carried with the
// squared weights.
fn denoise_atrous(p: vec2<i32>, step: i32, source: u32, dest: u32) {
    let size = reuse[9u];
    let c = denoise_load(source, p);
    if !c.valid {
        denoise_store(dest, p, c);
        return;
    }
    let kernel = array<f32, 3>(0.375, 0.25, 0.0625);
    let sigma = 4.0 * sqrt(max(c.variance, 0.0)) + 1e-6;
    var diffuse = vec3<f32>(0.0);
    var specular = vec3<f32>(0.0);
    var variance = 0.0;
    var total = 0.0;
    for (var y = -2; y <= 2; y++) {
        for (var x = -2; x <= 2; x++) {
            let q = p + step * vec2<i32>(x, y);
            if any(q < vec2<i32>(0)) || any(q >= vec2<i32>(size.xy)) {
                continue;
            }
            let o = denoise_load(source, q);
            if !o.valid {
                continue;
            }
            let k = kernel[abs(x)] * kernel[abs(y)];
            let wz = exp(-abs(o.depth - c.depth) / (0.05 * c.depth * f32(step) + 1e-6));
            let wn = pow(max(dot(o.normal, c.normal), 0.0), 64.0);
            let wl = exp(-abs(o.luminance - c.luminance) / sigma);
            let w = k * wz * wn * wl;
            diffuse += w * o.diffuse;
            specular += w * o.specular;
            variance += w * w * o.variance;
            total += w;
        }
    }
    var out = c;
    out.diffuse = diffuse / total;
    out.specular = specular / total;
    out.variance = variance / (total * total);
    out.luminance = denoise_luminance(out.diffuse, out.specular);
    denoise_store(dest, p, out);
}

@compute @workgroup_size(8, 8)
fn cs_denoise_atrous1(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x < reuse[9u].x && id.y < reuse[9u].y {
        denoise_atrous(vec2<i32>(id.xy), 1, 0u, 1u);
    }
}

@compute @workgroup_size(8, 8)
fn cs_denoise_atrous2(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x < reuse[9u].x && id.y < reuse[9u].y {
        denoise_atrous(vec2<i32>(id.xy), 2, 1u, 0u);
    }
}

@compute @workgroup_size(8, 8)
fn cs_denoise_atrous4(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x < reuse[9u].x && id.y < reuse[9u].y {
        denoise_atrous(vec2<i32>(id.xy), 4, 0u, 1u);
    }
}

// The filtered light (region B after the third step) into the accumulation.
@fragment
fn fs_ris_denoised(in: TiledVarying) -> LightTargets {
    let p = vec2<i32>(in.clip.xy);
    let s = gbuffer_load(p);
    let d = denoise_load(1u, p);
    var diffuse = vec3<f32>(0.0);
    var specular = vec3<f32>(0.0);
    if s.valid && d.valid {
        diffuse = d.diffuse;
        specular = d.specular;
    }
    return light_targets(s, diffuse, specular);
}
