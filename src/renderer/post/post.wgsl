// The HDR post chain (seed 002's order): bloom -> auto-exposure -> tone mapping ->
// colour grading. Bindings (group 2, slots 30..) are declared from Rust: renderer::bindings::POST;
// the curves' CPU twins are in renderer::post (Tonemap::apply), formula for formula.

struct PostParams {
    tonemap: u32,
    auto_exposure: u32,
    lut_size: u32,
    pad0: u32,
    exposure: f32,
    threshold: f32,
    intensity: f32,
    target_luminance: f32,
    adapt_rate: f32,
    log_min: f32,
    log_max: f32,
    focus_fallback: f32,
    lut_min: vec4<f32>,
    lut_max: vec4<f32>,
    fog_density: f32,
    fog_falloff: f32,
    focus_distance: f32,
    aperture: f32,
    vignette: f32,
    aa: u32,
    pad2: u32,
    pad3: u32,
    effect: array<vec4<f32>, LS_MAX_EFFECTS>,
};

fn post_luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

fn post_inside(q: vec2<i32>, size: vec2<u32>) -> bool {
    return all(q >= vec2<i32>(0)) && all(vec2<u32>(q) < size);
}

// Bloom's bright pass: the part of a pixel above the threshold luminance, its hue kept.
fn bloom_bright(c: vec3<f32>) -> vec3<f32> {
    let l = post_luminance(c);
    if l <= post_params.threshold {
        return vec3<f32>(0.0);
    }
    return c * ((l - post_params.threshold) / l);
}

// A 2x2 box of `post_src` (pixels outside count as zero, so the sum over the level times its
// texel area is conserved).
fn bloom_box(p: vec2<i32>, bright: bool) -> vec3<f32> {
    let size = textureDimensions(post_src);
    var sum = vec3<f32>(0.0);
    for (var j = 0; j < 2; j++) {
        for (var i = 0; i < 2; i++) {
            let q = 2 * p + vec2<i32>(i, j);
            if post_inside(q, size) {
                var c = finite(textureLoad(post_src, q, 0).rgb);
                if bright {
                    c = bloom_bright(c);
                }
                sum += c;
            }
        }
    }
    return sum * 0.25;
}

// The 2x bilinear upsample of `t` at output pixel p, clamped to the edge: each source texel
// gives 0.75 + 0.75 + 0.25 + 0.25 of weight per axis to the output, edges included.
fn bloom_up(t: texture_2d<f32>, p: vec2<i32>) -> vec3<f32> {
    let size = vec2<i32>(textureDimensions(t));
    let x = vec2<f32>(p) * 0.5 - 0.25;
    let f = x - floor(x);
    let i0 = vec2<i32>(floor(x));
    let a = clamp(i0, vec2<i32>(0), size - 1);
    let b = clamp(i0 + 1, vec2<i32>(0), size - 1);
    let c00 = textureLoad(t, vec2<i32>(a.x, a.y), 0).rgb;
    let c10 = textureLoad(t, vec2<i32>(b.x, a.y), 0).rgb;
    let c01 = textureLoad(t, vec2<i32>(a.x, b.y), 0).rgb;
    let c11 = textureLoad(t, vec2<i32>(b.x, b.y), 0).rgb;
    return mix(mix(c00, c10, f.x), mix(c01, c11, f.x), f.y);
}

@fragment
fn fs_bloom_bright(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(bloom_box(vec2<i32>(floor(frag.xy)), true), 1.0);
}

@fragment
fn fs_bloom_down(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(bloom_box(vec2<i32>(floor(frag.xy)), false), 1.0);
}

// Level k of the upsample: half its own downsampled level, half the coarser result.
@fragment
fn fs_bloom_up(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(floor(frag.xy));
    return vec4<f32>(0.5 * textureLoad(post_aux, p, 0).rgb + 0.5 * bloom_up(post_src, p), 1.0);
}

// The HDR colour plus intensity x the bloom (the finest upsampled level, upsampled once more).
@fragment
fn fs_bloom_combine(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(floor(frag.xy));
    let c = finite(textureLoad(post_src, p, 0).rgb);
    return vec4<f32>(c + post_params.intensity * bloom_up(post_aux, p), 1.0);
}

// Auto-exposure, 1: the luminance histogram of the frame (before exposure), per workgroup in
// shared memory, then added to the state's bins.
var<workgroup> post_bins: array<atomic<u32>, LS_HIST_BINS>;

fn hist_bin(l: f32) -> u32 {
    if !(l >= exp2(post_params.log_min)) {
        return 0u;
    }
    let t = (log2(l) - post_params.log_min) / (post_params.log_max - post_params.log_min);
    return 1u + u32(clamp(floor(t * f32(LS_HIST_BINS - 1u)), 0.0, f32(LS_HIST_BINS - 2u)));
}

@compute @workgroup_size(16, 16)
fn cs_histogram(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    if li < LS_HIST_BINS {
        atomicStore(&post_bins[li], 0u);
    }
    workgroupBarrier();
    let size = textureDimensions(post_src);
    if all(gid.xy < size) {
        let c = finite(textureLoad(post_src, vec2<i32>(gid.xy), 0).rgb);
        atomicAdd(&post_bins[hist_bin(post_luminance(c))], 1u);
    }
    workgroupBarrier();
    if li < LS_HIST_BINS {
        let n = atomicLoad(&post_bins[li]);
        if n > 0u {
            atomicAdd(&post_state[li], n);
        }
    }
}

// Auto-exposure, 2: the frame's mean log2 luminance from the bins' centres (bin 0, black, left
// out), and one time step of the adapted value towards it; the bins cleared for the next frame.
// The first frame after the state is made (word HIST_BINS + 2 still 0) starts at the measured
// value, so a single rendered frame is exposed for itself.
@compute @workgroup_size(1)
fn cs_adapt() {
    let w = (post_params.log_max - post_params.log_min) / f32(LS_HIST_BINS - 1u);
    var n = 0.0;
    var sum = 0.0;
    // The bins are kept for the histogram view (after the adapted value, the measured one and
    // the first-frame flag), then cleared for the next frame.
    atomicStore(&post_state[LS_HIST_BINS + 3u], atomicLoad(&post_state[0]));
    for (var b = 1u; b < LS_HIST_BINS; b++) {
        atomicStore(&post_state[LS_HIST_BINS + 3u + b], atomicLoad(&post_state[b]));
        let k = f32(atomicLoad(&post_state[b]));
        n += k;
        sum += k * (post_params.log_min + (f32(b) - 0.5) * w);
        atomicStore(&post_state[b], 0u);
    }
    atomicStore(&post_state[0], 0u);
    var adapted = bitcast<f32>(atomicLoad(&post_state[LS_HIST_BINS]));
    var measured = adapted;
    if n > 0.0 {
        measured = sum / n;
    }
    if atomicLoad(&post_state[LS_HIST_BINS + 2u]) == 0u {
        adapted = measured;
        atomicStore(&post_state[LS_HIST_BINS + 2u], 1u);
    }
    let next = adapted + (measured - adapted) * post_params.adapt_rate;
    atomicStore(&post_state[LS_HIST_BINS], bitcast<u32>(next));
    atomicStore(&post_state[LS_HIST_BINS + 1u], bitcast<u32>(measured));
}

// The exposure the tonemap applies: the knob, times target / adapted luminance when adapting.
fn post_exposure() -> f32 {
    var e = post_params.exposure;
    if post_params.auto_exposure != 0u {
        let adapted = bitcast<f32>(atomicLoad(&post_state[LS_HIST_BINS]));
        e *= post_params.target_luminance / exp2(adapted);
    }
    return e;
}

// Reinhard et al. 2002, "Photographic Tone Reproduction for Digital Images", eq. 3.
fn tonemap_reinhard(x: vec3<f32>) -> vec3<f32> {
    let v = max(x, vec3<f32>(0.0));
    return v / (vec3<f32>(1.0) + v);
}

// AgX (Troy Sobotka), Benjamin Wrensch's minimal fit ("Minimal AgX implementation", iolite,
// 2023): inset matrix, log2 encoding over [-12.47393, 4.026069] EV, 6th-order contrast
// polynomial, outset matrix, 2.2 power back to linear.
fn tonemap_agx(x: vec3<f32>) -> vec3<f32> {
    let inset = mat3x3<f32>(
        0.842479062253094, 0.0423282422610123, 0.0423756549057051,
        0.0784335999999992, 0.878468636469772, 0.0784336,
        0.0792237451477643, 0.0791661274605434, 0.879142973793104,
    );
    let outset = mat3x3<f32>(
        1.19687900512017, -0.0528968517574562, -0.0529716355144438,
        -0.0980208811401368, 1.15190312990417, -0.0980434501171241,
        -0.0990297440797205, -0.0989611768448433, 1.15107367264116,
    );
    let min_ev = -12.47393;
    let max_ev = 4.026069;
    let v = inset * max(x, vec3<f32>(0.0));
    let t = (clamp(log2(max(v, vec3<f32>(1e-10))), vec3<f32>(min_ev), vec3<f32>(max_ev)) - min_ev) / (max_ev - min_ev);
    let t2 = t * t;
    let t4 = t2 * t2;
    let p = 15.5 * t4 * t2 - 40.14 * t4 * t + 31.96 * t4 - 6.868 * t2 * t + 0.4298 * t2 + 0.1191 * t - 0.00232;
    return clamp(pow(max(outset * p, vec3<f32>(0.0)), vec3<f32>(2.2)), vec3<f32>(0.0), vec3<f32>(1.0));
}

// Khronos PBR Neutral (KhronosGroup/ToneMapping, PBR_Neutral/README.md, 2024).
fn tonemap_pbr_neutral(x: vec3<f32>) -> vec3<f32> {
    let start = 0.8 - 0.04;
    let desaturation = 0.15;
    var c = max(x, vec3<f32>(0.0));
    let m = min(c.r, min(c.g, c.b));
    var offset = 0.04;
    if m < 0.08 {
        offset = m - 6.25 * m * m;
    }
    c -= offset;
    let peak = max(c.r, max(c.g, c.b));
    if peak < start {
        return clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    }
    let d = 1.0 - start;
    let new_peak = 1.0 - d * d / (peak + d - start);
    c *= new_peak / peak;
    let g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    return clamp(mix(c, vec3<f32>(new_peak), g), vec3<f32>(0.0), vec3<f32>(1.0));
}

fn tonemap(x: vec3<f32>, curve: u32) -> vec3<f32> {
    if curve == LS_TONEMAP_REINHARD {
        return tonemap_reinhard(x);
    } else if curve == LS_TONEMAP_AGX {
        return tonemap_agx(x);
    } else if curve == LS_TONEMAP_PBR_NEUTRAL {
        return tonemap_pbr_neutral(x);
    } else if curve == LS_TONEMAP_NONE {
        return clamp(x, vec3<f32>(0.0), vec3<f32>(1.0));
    }
    // ACES, Narkowicz 2015 (compose.wgsl's `aces`).
    return aces(x);
}

@fragment
fn fs_post_tonemap(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let c = finite(textureLoad(post_src, vec2<i32>(floor(frag.xy)), 0).rgb);
    return vec4<f32>(tonemap(c * post_exposure(), post_params.tonemap), 1.0);
}

fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    return select(1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055, 12.92 * c, c <= vec3<f32>(0.0031308));
}

fn srgb_decode(c: vec3<f32>) -> vec3<f32> {
    return select(pow((c + 0.055) / 1.055, vec3<f32>(2.4)), c / 12.92, c <= vec3<f32>(0.04045));
}

fn lut_entry(i: vec3<u32>) -> vec3<f32> {
    let n = post_params.lut_size;
    return post_lut[i.x + n * (i.y + n * i.z)].rgb;
}

// Colour grading: the tonemapped colour, sRGB-encoded (the space .cube LUTs are made in), through
// the LUT with trilinear interpolation, decoded back to linear for the sRGB target.
fn grade(colour: vec3<f32>) -> vec3<f32> {
    let c = clamp(colour, vec3<f32>(0.0), vec3<f32>(1.0));
    let n = post_params.lut_size;
    let lo = post_params.lut_min.xyz;
    let hi = post_params.lut_max.xyz;
    let t = clamp((srgb_encode(c) - lo) / (hi - lo), vec3<f32>(0.0), vec3<f32>(1.0)) * f32(n - 1u);
    let i0 = min(vec3<u32>(floor(t)), vec3<u32>(n - 1u));
    let i1 = min(i0 + 1u, vec3<u32>(n - 1u));
    let f = t - floor(t);
    let c00 = mix(lut_entry(i0), lut_entry(vec3<u32>(i1.x, i0.y, i0.z)), f.x);
    let c10 = mix(lut_entry(vec3<u32>(i0.x, i1.y, i0.z)), lut_entry(vec3<u32>(i1.x, i1.y, i0.z)), f.x);
    let c01 = mix(lut_entry(vec3<u32>(i0.x, i0.y, i1.z)), lut_entry(vec3<u32>(i1.x, i0.y, i1.z)), f.x);
    let c11 = mix(lut_entry(vec3<u32>(i0.x, i1.y, i1.z)), lut_entry(i1), f.x);
    let graded = mix(mix(c00, c10, f.y), mix(c01, c11, f.y), f.z);
    return srgb_decode(clamp(graded, vec3<f32>(0.0), vec3<f32>(1.0)));
}

@fragment
fn fs_grade(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(grade(textureLoad(post_src, vec2<i32>(floor(frag.xy)), 0).rgb), 1.0);
}

// The bloom view: the bloom the chain adds (before its intensity), exposed and tonemapped.
@fragment
fn fs_view_bloom(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let b = bloom_up(post_aux, vec2<i32>(floor(frag.xy)));
    return vec4<f32>(tonemap(b * post_exposure(), post_params.tonemap), 1.0);
}

// The histogram view: the picture dimmed, the last frame's bins as bars over the bottom 40%
// (bin 0, black pixels, in grey), the adapted luminance yellow and the frame's mean white.
@fragment
fn fs_view_histogram(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(floor(frag.xy));
    let size = vec2<f32>(textureDimensions(post_src));
    let c = finite(textureLoad(post_src, p, 0).rgb);
    var out = tonemap(c * post_exposure(), post_params.tonemap) * 0.35;
    var most = 1u;
    for (var b = 0u; b < LS_HIST_BINS; b++) {
        most = max(most, atomicLoad(&post_state[LS_HIST_BINS + 3u + b]));
    }
    let x = frag.x / size.x;
    let bin = min(u32(x * f32(LS_HIST_BINS)), LS_HIST_BINS - 1u);
    let height = f32(atomicLoad(&post_state[LS_HIST_BINS + 3u + bin])) / f32(most);
    let y = 1.0 - frag.y / size.y;
    if y < 0.4 * height {
        out = select(vec3<f32>(0.2, 0.6, 1.0), vec3<f32>(0.5), bin == 0u);
    }
    // A log2 luminance's x position: bin 1 starts at log_min, 63 bins to log_max.
    let w = (post_params.log_max - post_params.log_min) / f32(LS_HIST_BINS - 1u);
    let px = 1.0 / size.x;
    let adapted = (1.0 + (bitcast<f32>(atomicLoad(&post_state[LS_HIST_BINS])) - post_params.log_min) / w) / f32(LS_HIST_BINS);
    let mean = (1.0 + (bitcast<f32>(atomicLoad(&post_state[LS_HIST_BINS + 1u])) - post_params.log_min) / w) / f32(LS_HIST_BINS);
    if abs(x - mean) < 1.5 * px && y < 0.45 {
        out = vec3<f32>(1.0);
    }
    if abs(x - adapted) < 1.5 * px && y < 0.45 {
        out = vec3<f32>(1.0, 0.9, 0.0);
    }
    return vec4<f32>(out, 1.0);
}

// ---- After grading (seed 002's order): fog, depth of field, vignette, anti-aliasing. They read
// the G-buffer (group 1) for depth and normals; background pixels have none.

fn post_src_at(p: vec2<i32>) -> vec3<f32> {
    let size = vec2<i32>(textureDimensions(post_src));
    return textureLoad(post_src, clamp(p, vec2<i32>(0), size - 1), 0).rgb;
}

// Fog's share at view-space point `v` (renderer::post::fog_amount, formula for formula).
fn fog_amount(v: vec3<f32>) -> f32 {
    let up = (camera.view_rotation * vec4<f32>(0.0, 1.0, 0.0, 0.0)).xyz;
    let distance = length(v);
    let x = post_params.fog_falloff * dot(v, up);
    var shape = 1.0 - 0.5 * x;
    if abs(x) >= 1e-4 {
        shape = (1.0 - exp(-x)) / x;
    }
    return 1.0 - exp(-post_params.fog_density * distance * shape);
}

@fragment
fn fs_fog(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(floor(frag.xy));
    let c = textureLoad(post_src, p, 0).rgb;
    let s = gbuffer_load(p);
    if !s.valid {
        return vec4<f32>(c, 1.0);
    }
    // Fog comes after tone mapping and grading (seed 002's order), so its colour is the
    // background as those passes turned the sky's own pixels: exposed, tone mapped and graded.
    var fog = tonemap(max(camera.background.rgb, vec3<f32>(0.0)) * post_exposure(), post_params.tonemap);
    if post_params.lut_size != 0u {
        fog = grade(fog);
    }
    return vec4<f32>(mix(c, fog, fog_amount(s.position)), 1.0);
}

// The view distance in focus (renderer::options::post::Focus): the fixed distance, or with
// auto focus (focus_distance 0) the view depth of the surface at the screen's centre pixel
// (size / 2, read from the depth this pass already binds: no read-back, no stall), or where
// that pixel is background, the framed scene's distance the CPU computed
// (renderer::post::focus_fallback). Every pixel reads the same texel, so the frame has one focus.
fn dof_focus() -> f32 {
    if post_params.focus_distance > 0.0 {
        return post_params.focus_distance;
    }
    let s = gbuffer_load(vec2<i32>(textureDimensions(post_src) / 2u));
    if !s.valid {
        return post_params.focus_fallback;
    }
    return max(-s.position.z, 1e-6);
}

// Circle of confusion (diameter, px) of a pixel focused at `focus`: 0 for the background (not
// blurred).
fn coc_at(p: vec2<i32>, focus: f32) -> f32 {
    let size = vec2<i32>(textureDimensions(post_src));
    let s = gbuffer_load(clamp(p, vec2<i32>(0), size - 1));
    if !s.valid {
        return 0.0;
    }
    let z = max(-s.position.z, 1e-6);
    return min(post_params.aperture * abs(z - focus) / z, LS_MAX_COC);
}

@fragment
fn fs_dof(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(floor(frag.xy));
    let c = textureLoad(post_src, p, 0).rgb;
    let focus = dof_focus();
    let coc = coc_at(p, focus);
    if coc < 0.5 {
        return vec4<f32>(c, 1.0);
    }
    // 32 taps on a golden-angle spiral filling the disc of diameter `coc`; a tap counts if its
    // own CoC reaches back to this pixel.
    var sum = c;
    var weight = 1.0;
    for (var i = 0u; i < 32u; i++) {
        let r = 0.5 * coc * sqrt((f32(i) + 0.5) / 32.0);
        let a = f32(i) * 2.39996323;
        let q = p + vec2<i32>(round(r * vec2<f32>(cos(a), sin(a))));
        let reach = 0.5 * coc_at(q, focus);
        if reach >= r {
            sum += post_src_at(q);
            weight += 1.0;
        }
    }
    return vec4<f32>(sum / weight, 1.0);
}

@fragment
fn fs_view_coc(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let coc = coc_at(vec2<i32>(floor(frag.xy)), dof_focus());
    let t = coc / LS_MAX_COC;
    return vec4<f32>(select(vec3<f32>(t), vec3<f32>(0.0, 0.25, 0.0), coc < 0.5), 1.0);
}

@fragment
fn fs_vignette(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(floor(frag.xy));
    let size = vec2<f32>(textureDimensions(post_src));
    // 0 at the centre, 1 at the corners.
    let r = length((frag.xy / size - 0.5) * 2.0) / sqrt(2.0);
    let k = 1.0 - post_params.vignette * smoothstep(0.3, 1.0, r);
    return vec4<f32>(textureLoad(post_src, p, 0).rgb * k, 1.0);
}

// Seed 002's edge strength at p: the second difference of 1/depth across the pixel (zero on any
// plane, since 1/z is affine in screen space over a plane), relative to 1/depth, and the
// largest turn of the normal to a neighbour; background next to geometry is an edge.
fn edge_strength(p: vec2<i32>) -> f32 {
    let size = vec2<i32>(textureDimensions(post_src));
    let s = gbuffer_load(p);
    let l = gbuffer_load(clamp(p - vec2<i32>(1, 0), vec2<i32>(0), size - 1));
    let r = gbuffer_load(clamp(p + vec2<i32>(1, 0), vec2<i32>(0), size - 1));
    let u = gbuffer_load(clamp(p - vec2<i32>(0, 1), vec2<i32>(0), size - 1));
    let d = gbuffer_load(clamp(p + vec2<i32>(0, 1), vec2<i32>(0), size - 1));
    let any_valid = s.valid || l.valid || r.valid || u.valid || d.valid;
    let all_valid = s.valid && l.valid && r.valid && u.valid && d.valid;
    if !all_valid {
        return select(0.0, 1.0, any_valid);
    }
    let w = 1.0 / max(-s.position.z, 1e-6);
    let wl = 1.0 / max(-l.position.z, 1e-6);
    let wr = 1.0 / max(-r.position.z, 1e-6);
    let wu = 1.0 / max(-u.position.z, 1e-6);
    let wd = 1.0 / max(-d.position.z, 1e-6);
    let depth_edge = max(abs(wl + wr - 2.0 * w), abs(wu + wd - 2.0 * w)) / w;
    let turn = 1.0 - min(min(dot(s.normal, l.normal), dot(s.normal, r.normal)), min(dot(s.normal, u.normal), dot(s.normal, d.normal)));
    return clamp(max((depth_edge - 0.02) * 20.0, (turn - 0.1) * 4.0), 0.0, 1.0);
}

// FXAA's thresholds (Lottes) are for gamma-encoded luma; the chain holds linear colour, so the
// luma is taken from sqrt of each channel (gamma 2, FXAA 3.11's own approximation).
fn luma(c: vec3<f32>) -> f32 {
    return dot(sqrt(max(c, vec3<f32>(0.0))), vec3<f32>(0.299, 0.587, 0.114));
}

// FXAA's contrast test (Lottes): the local luma range against its thresholds.
fn fxaa_edge(p: vec2<i32>) -> bool {
    let m = luma(post_src_at(p));
    let n = luma(post_src_at(p + vec2<i32>(0, -1)));
    let s = luma(post_src_at(p + vec2<i32>(0, 1)));
    let e = luma(post_src_at(p + vec2<i32>(1, 0)));
    let w = luma(post_src_at(p + vec2<i32>(-1, 0)));
    let hi = max(m, max(max(n, s), max(e, w)));
    let lo = min(m, min(min(n, s), min(e, w)));
    return hi - lo >= max(0.0312, hi * 0.125);
}

// Bilinear read of post_src at pixel-space position `x` (pixel centres at .5).
fn post_bilinear(x: vec2<f32>) -> vec3<f32> {
    let t = x - 0.5;
    let i = vec2<i32>(floor(t));
    let f = t - floor(t);
    let a = mix(post_src_at(i), post_src_at(i + vec2<i32>(1, 0)), f.x);
    let b = mix(post_src_at(i + vec2<i32>(0, 1)), post_src_at(i + vec2<i32>(1, 1)), f.x);
    return mix(a, b, f.y);
}

@fragment
fn fs_aa(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(floor(frag.xy));
    let c = textureLoad(post_src, p, 0).rgb;
    if post_params.aa == LS_AA_EDGE {
        let k = edge_strength(p);
        if k <= 0.0 {
            return vec4<f32>(c, 1.0);
        }
        let blur = (post_src_at(p + vec2<i32>(1, 0)) + post_src_at(p - vec2<i32>(1, 0)) + post_src_at(p + vec2<i32>(0, 1)) + post_src_at(p - vec2<i32>(0, 1))) * 0.25;
        return vec4<f32>(mix(c, 0.5 * (c + blur), k), 1.0);
    }
    // FXAA, the minimal console form (FXAA_REDUCE_MIN 1/128, REDUCE_MUL 1/8, SPAN_MAX 8).
    if !fxaa_edge(p) {
        return vec4<f32>(c, 1.0);
    }
    let nw = luma(post_src_at(p + vec2<i32>(-1, -1)));
    let ne = luma(post_src_at(p + vec2<i32>(1, -1)));
    let sw = luma(post_src_at(p + vec2<i32>(-1, 1)));
    let se = luma(post_src_at(p + vec2<i32>(1, 1)));
    let m = luma(c);
    var dir = vec2<f32>(-((nw + ne) - (sw + se)), (nw + sw) - (ne + se));
    let reduce = max((nw + ne + sw + se) * 0.25 * 0.125, 1.0 / 128.0);
    let rcp_min = 1.0 / (min(abs(dir.x), abs(dir.y)) + reduce);
    dir = clamp(dir * rcp_min, vec2<f32>(-8.0), vec2<f32>(8.0));
    let x = frag.xy;
    let a = 0.5 * (post_bilinear(x + dir * (1.0 / 3.0 - 0.5)) + post_bilinear(x + dir * (2.0 / 3.0 - 0.5)));
    let b = a * 0.5 + 0.25 * (post_bilinear(x - dir * 0.5) + post_bilinear(x + dir * 0.5));
    let lb = luma(b);
    let lo = min(m, min(min(nw, ne), min(sw, se)));
    let hi = max(m, max(max(nw, ne), max(sw, se)));
    return vec4<f32>(select(b, a, lb < lo || lb > hi), 1.0);
}

@fragment
fn fs_view_edges(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(floor(frag.xy));
    let base = clamp(textureLoad(post_src, p, 0).rgb, vec3<f32>(0.0), vec3<f32>(1.0)) * 0.3;
    var k = 0.0;
    if post_params.aa == LS_AA_FXAA {
        k = select(0.0, 1.0, fxaa_edge(p));
    } else {
        k = edge_strength(p);
    }
    // Mask pixels have full green (the dimmed picture never reaches it): white at full strength,
    // green where the edge is faint.
    return vec4<f32>(select(base, vec3<f32>(k, 1.0, k), k > 0.0), 1.0);
}

// Seed 002's distortion buffer (`post::distortion`): a distorting surface's view-space normal's
// x and y (normal map applied) times its strength (GpuObject.pbr.w), in fractions of the screen
// height, summed by the blend; 1 / view depth in .a, the nearest kept (max blend).
@fragment
fn fs_distortion(in: GeometryOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var s: Surface;
    let o = objects[in.object];
    if material_surface(in, front, &s) < o.material.y {
        discard;
    }
    return vec4<f32>(s.normal.xy * o.pbr.w, 0.0, 1.0 / max(-in.view_pos.z, 1e-6));
}

// Seed 002's distortion: the picture at the pixel plus the buffer's offset (view-space y up,
// screen y down), the nearest texel. A source pixel whose surface is nearer to the eye than
// the nearest distorting surface here (1 / .a) lies in front of it and is not what the glass
// shows: the pixel keeps its own colour. No offset: copied unchanged.
@fragment
fn fs_distort(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(floor(frag.xy));
    let own = textureLoad(post_src, p, 0).rgb;
    let d = textureLoad(post_aux, p, 0);
    if !(d.a > 0.0) {
        return vec4<f32>(own, 1.0);
    }
    let size = vec2<i32>(textureDimensions(post_src));
    let shift = vec2<i32>(round(vec2<f32>(d.x, -d.y) * f32(size.y)));
    let q = clamp(p + shift, vec2<i32>(0), size - 1);
    let sq = gbuffer_load(q);
    if sq.valid && -sq.position.z * d.a < 1.0 {
        return vec4<f32>(own, 1.0);
    }
    return vec4<f32>(textureLoad(post_src, q, 0).rgb, 1.0);
}
