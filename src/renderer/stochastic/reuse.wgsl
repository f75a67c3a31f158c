// ReSTIR's reuse of RIS samples (Bitterli et al. 2020, "Spatiotemporal reservoir resampling for
// real-time ray tracing with dynamic direct lighting"; stochastic/reuse.rs): three passes over
// two buffers of reservoirs. `reuse` starts with the header (REUSE_HEADER vec4s):
//   [0, 4)  the current view space to the last frame's view space (f32 bits, columns),
//   [4, 8)  the last frame's projection,
//   [8]     (temporal reuse with a history, spatial neighbours, radius in pixels, temporal cap),
//   [9]     (width, height, K, 0),
// then holds region 0, this frame's candidates after temporal reuse; `reuse_final` holds region
// 1, the final reservoirs (after spatial reuse), which the next frame's temporal reuse reads;
// each K reservoirs a pixel.
// A reservoir is two vec4<u32>: (light, W, M, depth) and (octahedral normal, p^ at its pixel,
// 0, 0), W its contribution weight, M the candidates it stands for, depth and normal its
// pixel's (view space). Reservoir r's weight in a combination at pixel q is p^_q(y_r) W_r M_r.

const REUSE_HEADER: u32 = 10u;
const REUSE_NONE: u32 = 0xffffffffu;

struct Reservoir {
    light: u32,
    weight: f32,
    m: f32,
    depth: f32,
    normal: vec3<f32>,
    // p^ of `light` at the reservoir's own pixel.
    goal: f32,
};

fn reuse_matrix(at: u32) -> mat4x4<f32> {
    return mat4x4<f32>(
        bitcast<vec4<f32>>(reuse[at]),
        bitcast<vec4<f32>>(reuse[at + 1u]),
        bitcast<vec4<f32>>(reuse[at + 2u]),
        bitcast<vec4<f32>>(reuse[at + 3u]),
    );
}

// Where sample k of pixel p starts in region `region` (0 after the header of `reuse`, 1 in
// `reuse_final`).
fn reuse_slot(region: u32, p: vec2<i32>, k: u32) -> u32 {
    let size = reuse[9u];
    return select(0u, REUSE_HEADER, region == 0u) + 2u * ((u32(p.y) * size.x + u32(p.x)) * size.z + k);
}

fn reuse_load(region: u32, at: u32) -> Reservoir {
    var a: vec4<u32>;
    var b: vec4<u32>;
    if region == 0u {
        a = reuse[at];
        b = reuse[at + 1u];
    } else {
        a = reuse_final[at];
        b = reuse_final[at + 1u];
    }
    let n = oct_decode(unpack2x16snorm(b.x));
    return Reservoir(a.x, bitcast<f32>(a.y), bitcast<f32>(a.z), bitcast<f32>(a.w), n, bitcast<f32>(b.y));
}

fn reuse_store(region: u32, at: u32, r: Reservoir) {
    let a = vec4<u32>(r.light, bitcast<u32>(r.weight), bitcast<u32>(r.m), bitcast<u32>(r.depth));
    let b = vec4<u32>(pack2x16snorm(oct_encode(r.normal)), bitcast<u32>(r.goal), 0u, 0u);
    if region == 0u {
        reuse[at] = a;
        reuse[at + 1u] = b;
    } else {
        reuse_final[at] = a;
        reuse_final[at + 1u] = b;
    }
}

// Whether a reservoir of a surface at `depth` with `normal` may be reused at one at `depth_here`
// with `normal_here`: depths within 10% and normals within 25 degrees (ReSTIR's heuristic; it
// keeps the reuse among like surfaces, and decides no weight: the spatial pass's 1/Z weights
// are unbiased whichever neighbours it takes).
fn reuse_alike(depth: f32, normal: vec3<f32>, depth_here: f32, normal_here: vec3<f32>) -> bool {
    return abs(depth - depth_here) <= 0.1 * depth_here && dot(normal, normal_here) >= 0.9;
}

// The candidates pass: K fresh RIS samples a pixel (`ris_pick`), each combined with the last
// frame's final sample k at the reprojected point when the header allows and the surfaces are
// alike. Temporal reuse weighs the two with ReSTIR's 1/M weights, the history's M capped at
// `cap` x M: unbiased where the two pixels' targets are the same function (a still camera over
// still lights), biased where they differ.
fn reuse_candidates(p: vec2<i32>, s: Surface, c: RisCell) {
    let size = reuse[9u];
    let mode = reuse[8u];
    let m = max(camera.noise.y, 1u);
    var state = ris_stream(p, 0u);
    let view = view_dir(s);
    let depth = -s.position.z;
    var prev = vec2<i32>(-1);
    var prev_depth = 0.0;
    var prev_normal = vec3<f32>(0.0);
    if s.valid && mode.x == 1u {
        let at = reuse_matrix(0u) * vec4<f32>(s.position, 1.0);
        let clip = reuse_matrix(4u) * at;
        if clip.w > 0.0 {
            let ndc = clip.xy / clip.w;
            let uv = vec2<f32>(0.5 * ndc.x + 0.5, 0.5 - 0.5 * ndc.y);
            let q = vec2<i32>(floor(uv * vec2<f32>(size.xy)));
            if all(q >= vec2<i32>(0)) && all(q < vec2<i32>(size.xy)) {
                prev = q;
                prev_depth = -at.z;
                prev_normal = normalize((reuse_matrix(0u) * vec4<f32>(s.normal, 0.0)).xyz);
            }
        }
    }
    for (var k = 0u; k < size.z; k++) {
        var r = Reservoir(REUSE_NONE, 0.0, 0.0, depth, s.normal, 0.0);
        if s.valid {
            let pick = ris_pick(s, view, c, m, &state);
            r = Reservoir(pick.light, pick.weight, f32(m), depth, s.normal, pick.goal);
        }
        let u = ris_unit(&state);
        if prev.x >= 0 {
            let h = reuse_load(1u, reuse_slot(1u, prev, k));
            if h.m > 0.0 && reuse_alike(h.depth, h.normal, prev_depth, prev_normal) {
                let hm = min(h.m, f32(mode.w) * f32(m));
                let own = r.goal * r.weight * r.m;
                let goal = ris_light_target(s, view, h.light);
                let theirs = goal * h.weight * hm;
                let total = own + theirs;
                if theirs > 0.0 && u * total < theirs {
                    r.light = h.light;
                    r.goal = goal;
                }
                r.m += hm;
                r.weight = select(0.0, total / (r.m * r.goal), r.goal > 0.0);
            }
        }
        reuse_store(0u, reuse_slot(0u, p, k), r);
    }
}

// The candidates pass at invocation `id`, from the z-bins (`zbin`) or the tile and cluster
// lists.
fn reuse_candidates_at(id: vec3<u32>, zbin: bool) {
    if id.x >= reuse[9u].x || id.y >= reuse[9u].y {
        return;
    }
    let p = vec2<i32>(id.xy);
    let s = gbuffer_load(p);
    var c = RisCell(0u, 0u, 0u, 0u);
    if s.valid && zbin {
        c = ris_zbin_cell(p, s);
    } else if s.valid {
        c = ris_list_cell(p, s);
    }
    reuse_candidates(p, s, c);
}

@compute @workgroup_size(8, 8)
fn cs_ris_candidates(@builtin(global_invocation_id) id: vec3<u32>) {
    reuse_candidates_at(id, false);
}

@compute @workgroup_size(8, 8)
fn cs_ris_candidates_zbin(@builtin(global_invocation_id) id: vec3<u32>) {
    reuse_candidates_at(id, true);
}

// The spatial pass: each of the pixel's K samples combined with those of `mode.y` neighbours
// (at most 16) drawn uniformly in a disc of `mode.z` pixels, those unlike the pixel's surface
// left out, with ReSTIR's unbiased weights (Bitterli et al. 2020, Algorithm 6): W = (sum of
// the weights) / (Z p^(y)), Z the M of every reservoir taken whose own pixel's target is
// above 0 at the sample kept. The result is the frame's final reservoir (region 1).
@compute @workgroup_size(8, 8)
fn cs_ris_spatial(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = reuse[9u];
    let mode = reuse[8u];
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = vec2<i32>(id.xy);
    let s = gbuffer_load(p);
    let view = view_dir(s);
    var state = ris_stream(p, 0x5bd1e995u);
    let n = min(mode.y, 16u);
    for (var k = 0u; k < size.z; k++) {
        let own = reuse_load(0u, reuse_slot(0u, p, k));
        if !s.valid || n == 0u {
            reuse_store(1u, reuse_slot(1u, p, k), own);
            continue;
        }
        var out = own;
        var total = own.goal * own.weight * own.m;
        var taken: array<vec2<i32>, 16>;
        var taken_m: array<f32, 16>;
        var count = 0u;
        for (var j = 0u; j < n; j++) {
            let angle = 6.2831853 * ris_unit(&state);
            let radius = f32(mode.z) * sqrt(ris_unit(&state));
            let u = ris_unit(&state);
            let q = p + vec2<i32>(round(radius * vec2<f32>(cos(angle), sin(angle))));
            if any(q < vec2<i32>(0)) || any(q >= vec2<i32>(size.xy)) || all(q == p) {
                continue;
            }
            let r = reuse_load(0u, reuse_slot(0u, q, k));
            if r.m <= 0.0 || !reuse_alike(r.depth, r.normal, own.depth, own.normal) {
                continue;
            }
            taken[count] = q;
            taken_m[count] = r.m;
            count += 1u;
            let goal = ris_light_target(s, view, r.light);
            let w = goal * r.weight * r.m;
            total += w;
            out.m += r.m;
            if w > 0.0 && u * total < w {
                out.light = r.light;
                out.goal = goal;
            }
        }
        out.weight = 0.0;
        if out.goal > 0.0 {
            // Z: the pixel's own M (its target is above 0 at the sample kept), and each taken
            // neighbour's whose own surface's target is.
            var z = own.m;
            for (var j = 0u; j < count; j++) {
                let t = gbuffer_load(taken[j]);
                if ris_light_target(t, view_dir(t), out.light) > 0.0 {
                    z += taken_m[j];
                }
            }
            out.weight = total / (z * out.goal);
        }
        reuse_store(1u, reuse_slot(1u, p, k), out);
    }
}

// The resolve: each of the pixel's final samples shaded with its shadow and weighted by W, the
// K averaged.
@fragment
fn fs_ris_resolve(in: TiledVarying) -> LightTargets {
    let p = vec2<i32>(in.clip.xy);
    let s = gbuffer_load(p);
    var out = Lighting(vec3<f32>(0.0), vec3<f32>(0.0));
    if s.valid {
        let view = view_dir(s);
        let k = reuse[9u].z;
        for (var j = 0u; j < k; j++) {
            let r = reuse_load(1u, reuse_slot(1u, p, j));
            let lit = ris_shade_light(s, view, r.light, r.weight);
            out.diffuse += lit.diffuse;
            out.specular += lit.specular;
        }
        out.diffuse /= f32(max(k, 1u));
        out.specular /= f32(max(k, 1u));
    }
    return light_targets(s, out.diffuse, out.specular);
}
