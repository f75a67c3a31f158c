// The tiled (Andersson 2011) and clustered (Olsson et al. 2012) culling modes: light lists per
// screen tile (between the tile's depth bounds) or per view-space cluster, then ONE full-screen
// pass shading each pixel with its list. Bindings (group 2, `tile_*`) are declared from Rust:
// renderer::bindings::TILES. `tile_lists` holds a (first, count) pair per tile or cluster, then
// the entries; `tile_counts[0]` is the list allocator, `tile_counts[1 + i]` light i's pairs.

struct TileParams {
    // 0: tiled, 1: clustered, 2: z-binned.
    mode: u32,
    tile_size: u32,
    tiles_x: u32,
    tiles_y: u32,
    slices: u32,
    light_count: u32,
    // Entries the list region (after the headers) holds.
    capacity: u32,
    // Clustered: slice = floor(ln(view depth) * slice_scale + slice_bias).
    slice_scale: f32,
    slice_bias: f32,
    // Clustered: the view depths the slices span.
    near: f32,
    far: f32,
    // The tile-lights view's slice depth (0: each pixel's own surface).
    view_depth: f32,
    // The waste view's one light (0xffffffff: every light).
    selected: u32,
    // Z-binned (zbin.wgsl): mask words per tile, the masks' start in tile_counts, the sorted
    // lights' and their rectangles' starts in tile_lists, sorted lights per shading draw.
    words: u32,
    mask_base: u32,
    order_base: u32,
    rect_base: u32,
    chunk: u32,
};

// Generated from Rust: LS_TILE_ALL, a list count meaning "every light" (`tiles::ALL_LIGHTS`);
// LS_TILE_MAX_LIGHTS, the lights the compute pass keeps a bit for at once, a batch
// (`tiles::GPU_LIST_MAX_LIGHTS`).

var<workgroup> wg_min: atomic<u32>;
var<workgroup> wg_max: atomic<u32>;
var<workgroup> wg_valid: atomic<u32>;
var<workgroup> wg_total: atomic<u32>;
var<workgroup> wg_mask: array<atomic<u32>, 2048>;
var<workgroup> wg_scan: array<u32, 256>;

// Inclusive prefix sum of the workgroup's 256 `value`s into `wg_scan` (Hillis and Steele):
// afterwards `wg_scan[li]` is the sum of the values of invocations 0..=li. Called by every
// invocation of the workgroup (uniform control flow: it holds barriers).
fn wg_inclusive_scan(li: u32, value: u32) {
    wg_scan[li] = value;
    workgroupBarrier();
    for (var off = 1u; off < 256u; off *= 2u) {
        var v = 0u;
        if li >= off {
            v = wg_scan[li - off];
        }
        workgroupBarrier();
        wg_scan[li] += v;
        workgroupBarrier();
    }
}
// Plain copies for workgroupUniformLoad (barriers need uniform control flow).
var<workgroup> wg_base: u32;
var<workgroup> wg_count: u32;
var<workgroup> wg_sum: u32;

// Whether light l's sphere can reach a point of the tile whose pixels span [lo, hi) (pixel
// edges, y down) between view depths dmin and dmax: the sphere meets each of the tile
// frustum's four side planes' inner half-spaces and the depth slab. Conservative: a light
// reaching a point of the tile always passes (the sphere meets the intersection, so each part).
fn light_meets_tile(l: GpuLight, lo: vec2<f32>, hi: vec2<f32>, dmin: f32, dmax: f32) -> bool {
    let c = l.position;
    let r = l.radius;
    let d = -c.z;
    if d + r < dmin || d - r > dmax {
        return false;
    }
    let p00 = camera.proj[0][0];
    let p11 = camera.proj[1][1];
    let p20 = camera.proj[2][0];
    let p21 = camera.proj[2][1];
    let ndc_lo = vec2<f32>(lo.x * camera.screen.z * 2.0 - 1.0, 1.0 - hi.y * camera.screen.w * 2.0);
    let ndc_hi = vec2<f32>(hi.x * camera.screen.z * 2.0 - 1.0, 1.0 - lo.y * camera.screen.w * 2.0);
    // Inside the left edge x = ndc_lo.x: P00 x + (ndc + P20) z >= 0 (z = -d), and so on.
    let left = normalize(vec3<f32>(p00, 0.0, ndc_lo.x + p20));
    let right = normalize(vec3<f32>(-p00, 0.0, -(ndc_hi.x + p20)));
    let bottom = normalize(vec3<f32>(0.0, p11, ndc_lo.y + p21));
    let top = normalize(vec3<f32>(0.0, -p11, -(ndc_hi.y + p21)));
    if dot(left, c) < -r || dot(right, c) < -r || dot(bottom, c) < -r || dot(top, c) < -r {
        return false;
    }
    // And the box around the tile's frustum piece between the depth bounds (tighter than the
    // planes where the depth range is narrow): the sphere meets it if its nearest point is
    // within the radius.
    let xs = vec4<f32>(ndc_lo.x + p20, ndc_hi.x + p20, ndc_lo.x + p20, ndc_hi.x + p20) / p00
        * vec4<f32>(dmin, dmin, dmax, dmax);
    let ys = vec4<f32>(ndc_lo.y + p21, ndc_hi.y + p21, ndc_lo.y + p21, ndc_hi.y + p21) / p11
        * vec4<f32>(dmin, dmin, dmax, dmax);
    let lo3 = vec3<f32>(min(min(xs.x, xs.y), min(xs.z, xs.w)), min(min(ys.x, ys.y), min(ys.z, ys.w)), -dmax);
    let hi3 = vec3<f32>(max(max(xs.x, xs.y), max(xs.z, xs.w)), max(max(ys.x, ys.y), max(ys.z, ys.w)), -dmin);
    let e = c - clamp(c, lo3, hi3);
    return dot(e, e) <= r * r * 1.0001;
}

// Marks in `wg_mask` the lights of batch `b` (lights b x LS_TILE_MAX_LIGHTS onwards, as many
// as the mask holds bits for) that meet tile `t`; returns the mask words the batch fills. A light
// whose rectangle of tiles (two words from `tile_params.rect_base`, `x0 | x1 << 16` and
// `y0 | y1 << 16`: the tiles of the pixels it can reach a visible point at) leaves the tile out
// is not tested. Called by every invocation of the workgroup (it holds barriers).
fn tile_mark(li: u32, b: u32, t: vec2<u32>, lo: vec2<f32>, hi: vec2<f32>, dmin: f32, dmax: f32) -> u32 {
    let first = b * LS_TILE_MAX_LIGHTS;
    let count = min(tile_params.light_count - first, LS_TILE_MAX_LIGHTS);
    let words = (count + 31u) / 32u;
    // A frame within one batch cleared the mask and the count with the depth bounds.
    if tile_params.light_count > LS_TILE_MAX_LIGHTS {
        tile_clear(li, words);
        workgroupBarrier();
    }
    for (var i = li; i < count; i += 256u) {
        let rx = tile_lists[tile_params.rect_base + 2u * (first + i)];
        let ry = tile_lists[tile_params.rect_base + 2u * (first + i) + 1u];
        if t.x < (rx & 0xffffu) || t.x > (rx >> 16u) || t.y < (ry & 0xffffu) || t.y > (ry >> 16u) {
            continue;
        }
        if light_meets_tile(light_at(first + i), lo, hi, dmin, dmax) {
            atomicOr(&wg_mask[i / 32u], 1u << (i % 32u));
        }
    }
    workgroupBarrier();
    return words;
}

// Clears the mask's first `words` words and the count's total (their last readers passed a
// barrier since).
fn tile_clear(li: u32, words: u32) {
    if li == 0u {
        atomicStore(&wg_total, 0u);
    }
    for (var w = li; w < words; w += 256u) {
        atomicStore(&wg_mask[w], 0u);
    }
}

// The set bits of the mask's first `words` words, summed over the workgroup after
// `tile_mark` (every invocation gets the sum; it holds barriers: two, where a prefix sum would
// take seventeen, and lavapipe pays for each barrier in every invocation).
fn tile_mask_count(li: u32, words: u32) -> u32 {
    var mine = 0u;
    for (var w = li; w < words; w += 256u) {
        mine += countOneBits(atomicLoad(&wg_mask[w]));
    }
    atomicAdd(&wg_total, mine);
    workgroupBarrier();
    if li == 0u {
        wg_sum = atomicLoad(&wg_total);
    }
    return workgroupUniformLoad(&wg_sum);
}

// Writes the marked lights of batch `b` (the mask's first `words` words) at `tile_lists[at]`
// onwards, in light order: word by word, each round of 256 words placed by a prefix sum.
fn tile_write(li: u32, b: u32, words: u32, at: u32) {
    var done = 0u;
    for (var round = 0u; round < words; round += 256u) {
        let w = round + li;
        var bits = 0u;
        if w < words {
            bits = atomicLoad(&wg_mask[w]);
        }
        let c = countOneBits(bits);
        wg_inclusive_scan(li, c);
        var k = at + done + wg_scan[li] - c;
        let round_total = wg_scan[255];
        workgroupBarrier();
        while bits != 0u {
            let bit = firstTrailingBit(bits);
            tile_lists[k] = b * LS_TILE_MAX_LIGHTS + w * 32u + bit;
            k += 1u;
            bits &= bits - 1u;
        }
        done += round_total;
    }
}

// One workgroup per 16x16 tile: the tile's depth bounds over its valid G-buffer pixels, a bit
// per light that meets the tile, then the set bits written out in light order. The mask holds
// LS_TILE_MAX_LIGHTS bits (its 2048 words are most of the 32 KiB of workgroup memory WebGPU
// guarantees); past that many lights the tile's lights are found in batches of that many, in two
// sweeps: the first counts them, so that the tile's list is one allocation, the second tests
// each batch again and writes it after the last. A frame within one batch tests once.
@compute @workgroup_size(16, 16, 1)
fn cs_tile_lists(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
    @builtin(global_invocation_id) gid: vec3<u32>,
) {
    let n = tile_params.light_count;
    let batches = (n + LS_TILE_MAX_LIGHTS - 1u) / LS_TILE_MAX_LIGHTS;
    if li == 0u {
        atomicStore(&wg_min, 0x7f7fffffu);
        atomicStore(&wg_max, 0u);
        atomicStore(&wg_valid, 0u);
    }
    if batches == 1u {
        tile_clear(li, (n + 31u) / 32u);
    }
    workgroupBarrier();
    let size = vec2<u32>(camera.screen.xy);
    if all(gid.xy < size) {
        let s = gbuffer_load(vec2<i32>(gid.xy));
        let d = -s.position.z;
        if s.valid && d > 0.0 && d < 3.0e38 {
            // Positive floats order as their bit patterns.
            atomicMin(&wg_min, bitcast<u32>(d));
            atomicMax(&wg_max, bitcast<u32>(d));
            atomicAdd(&wg_valid, 1u);
        }
    }
    workgroupBarrier();
    let tile = wg.y * tile_params.tiles_x + wg.x;
    if li == 0u {
        wg_count = atomicLoad(&wg_valid);
    }
    let valid = workgroupUniformLoad(&wg_count);
    if valid == 0u || batches == 0u {
        if li == 0u {
            tile_lists[2u * tile] = 0u;
            tile_lists[2u * tile + 1u] = 0u;
        }
        return;
    }
    // Widened against rounding: the shading pass reconstructs the same depths, but another
    // compilation may round differently; a pixel around the tile's edges.
    let dmin = bitcast<f32>(atomicLoad(&wg_min)) * (1.0 - 1e-4);
    let dmax = bitcast<f32>(atomicLoad(&wg_max)) * (1.0 + 1e-4);
    let lo = vec2<f32>(wg.xy * tile_params.tile_size) - 1.0;
    let hi = vec2<f32>((wg.xy + 1u) * tile_params.tile_size) + 1.0;
    // One batch: marked once, counted, written, in straight-line code (lavapipe keeps more of
    // an invocation's state across a barrier inside a loop).
    if batches == 1u {
        let words = tile_mark(li, 0u, wg.xy, lo, hi, dmin, dmax);
        let total = tile_mask_count(li, words);
        let at = tile_allot(li, tile, total);
        if at != LS_TILE_ALL {
            tile_write(li, 0u, words, at);
        }
        return;
    }
    var total = 0u;
    for (var b = 0u; b < batches; b++) {
        total += tile_mask_count(li, tile_mark(li, b, wg.xy, lo, hi, dmin, dmax));
    }
    let at = tile_allot(li, tile, total);
    if at == LS_TILE_ALL {
        return;
    }
    var done = 0u;
    for (var b = 0u; b < batches; b++) {
        let w = tile_mark(li, b, wg.xy, lo, hi, dmin, dmax);
        let c = tile_mask_count(li, w);
        tile_write(li, b, w, at + done);
        done += c;
    }
}

// Room for `total` entries of tile `tile`'s list: where they start in `tile_lists`, its header
// written; or LS_TILE_ALL when the list region is out of room (the tile then walks every light:
// the right picture, at a higher cost). Called by every invocation (it holds a barrier).
fn tile_allot(li: u32, tile: u32, total: u32) -> u32 {
    if li == 0u {
        wg_base = atomicAdd(&tile_counts[0], total);
    }
    let base = workgroupUniformLoad(&wg_base);
    let header = 2u * tile_params.tiles_x * tile_params.tiles_y;
    let full = base + total > tile_params.capacity;
    if li == 0u {
        tile_lists[2u * tile] = select(header + base, 0u, full);
        tile_lists[2u * tile + 1u] = select(total, LS_TILE_ALL, full);
    }
    return select(header + base, LS_TILE_ALL, full);
}

// The pixel's tile (tiled) or cluster (clustered).
fn tile_cell(p: vec2<i32>, s: Surface) -> u32 {
    let t = vec2<u32>(p) / tile_params.tile_size;
    let tile = min(t.y, tile_params.tiles_y - 1u) * tile_params.tiles_x + min(t.x, tile_params.tiles_x - 1u);
    if tile_params.mode == 0u {
        return tile;
    }
    let k = floor(log(max(-s.position.z, 1e-30)) * tile_params.slice_scale + tile_params.slice_bias);
    let slice = u32(clamp(k, 0.0, f32(tile_params.slices - 1u)));
    return slice * tile_params.tiles_x * tile_params.tiles_y + tile;
}

// One full-screen pass: each valid pixel walks its list, every light through `shade_light`
// and the per-light clamp, summed, and added once into the accumulation. Two entry points:
// `fs_tiled_counted` also counts each light's pairs (`tile_counts`). `counted` is a literal at
// each call, so the driver's inlining folds the branch away: lavapipe runs a branch's body
// under a lane mask whether or not a lane takes it, and the uncounted frame would pay for the
// atomic at every pair (2 of 47 ms on `demo`, clustered).
// Instance k walks entries k x LS_TILE_CHUNK onwards of each list (`tiles::SHADE_CHUNK`:
// lavapipe ends a shader's loops after 65,535 iterations between them).
struct TiledVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) chunk: u32,
};

@vertex
fn vs_tiled(@builtin(vertex_index) vi: u32, @builtin(instance_index) chunk: u32) -> TiledVarying {
    var out: TiledVarying;
    out.clip = fullscreen_position(vi);
    out.chunk = chunk;
    return out;
}

@fragment
fn fs_tiled(in: TiledVarying) -> LightTargets {
    return tiled_shade(in.clip, in.chunk, false);
}

@fragment
fn fs_tiled_counted(in: TiledVarying) -> LightTargets {
    return tiled_shade(in.clip, in.chunk, true);
}

// One listed light `i` at surface `s`, the step the tile and cluster walk and the z-bin walk
// share: counted when `counted` (every visited pair counts as evaluated, whether or not the
// light reaches), then skipped unless its sphere holds the point. The reach test comes first:
// most listed lights miss most of a cell's pixels, and the lanes they miss are masked off for
// the rest of the iteration (on lavapipe the loop body runs for 8 lanes together); its 1e-4
// margin over `shade_light`'s own (d < radius) skips only lights that add exactly zero. A
// casting light is put aside when casters are shaded apart (returns true: the caller keeps its
// place for the casters' loop); any other is added to `d` and `sp` under its own clamp
// (`overlap.rs`: what can overlap its pixels).
fn list_light_step(
    s: Surface,
    view: vec3<f32>,
    i: u32,
    counted: bool,
    d: ptr<function, vec3<f32>>,
    sp: ptr<function, vec3<f32>>,
) -> bool {
    if counted {
        atomicAdd(&tile_counts[1u + i], 1u);
    }
    let l = light_at(i);
    let to_light = l.position - s.position;
    if dot(to_light, to_light) > l.radius * l.radius * 1.0001 {
        return false;
    }
    if LS_CASTERS_APART && l.shadow.x != LS_NO_SHADOW {
        return true;
    }
    let r = shade_light_view(s, view, l, !LS_CASTERS_APART);
    *d += min(r.diffuse, vec3<f32>(l.clamp));
    *sp += min(r.specular, vec3<f32>(l.clamp));
    return false;
}

fn tiled_shade(frag: vec4<f32>, chunk: u32, counted: bool) -> LightTargets {
    let p = vec2<i32>(frag.xy);
    let s = gbuffer_load(p);
    var d = vec3<f32>(0.0);
    var sp = vec3<f32>(0.0);
    if s.valid {
        let cell = tile_cell(p, s);
        let view = view_dir(s);
        let first = tile_lists[2u * cell];
        var count = tile_lists[2u * cell + 1u];
        let all = count == LS_TILE_ALL;
        if all {
            count = tile_params.light_count;
        }
        // With LS_CASTERS_APART, the casting lights the pixel's light reaches are left to a
        // second loop over the part of the list between the first and the last of them, the
        // only one that runs the shadow lookups.
        // This instance's stretch of the list.
        let lo = chunk * LS_TILE_CHUNK;
        let hi = min(count, lo + LS_TILE_CHUNK);
        var casters = vec2<u32>(hi, 0u);
        for (var k = lo; k < hi; k++) {
            var i = k;
            if !all {
                i = tile_lists[first + k];
            }
            if list_light_step(s, view, i, counted, &d, &sp) {
                casters = vec2<u32>(min(casters.x, k), k + 1u);
            }
        }
        for (var k = casters.x; LS_CASTERS_APART && k < casters.y; k++) {
            var i = k;
            if !all {
                i = tile_lists[first + k];
            }
            let l = light_at(i);
            if l.shadow.x == LS_NO_SHADOW {
                continue;
            }
            let r = shade_light_view(s, view, l, true);
            d += min(r.diffuse, vec3<f32>(l.clamp));
            sp += min(r.specular, vec3<f32>(l.clamp));
        }
    }
    return light_targets(s, d, sp);
}

// Debug: the ledger's waste at the pixel, the entries of its list whose light's true shape does
// not hold its point (every entry the shading loop visits there counts as evaluated).
@fragment
fn fs_tile_waste(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(frag.xy);
    let s = gbuffer_load(p);
    if !s.valid {
        return vec4<f32>(0.0);
    }
    if tile_params.mode == 2u {
        return vec4<f32>(f32(zbin_count(p, s, -s.position.z, true)), 0.0, 0.0, 0.0);
    }
    let cell = tile_cell(p, s);
    let first = tile_lists[2u * cell];
    var count = tile_lists[2u * cell + 1u];
    let all = count == LS_TILE_ALL;
    if all {
        count = tile_params.light_count;
    }
    var wasted = 0u;
    for (var k = 0u; k < count; k++) {
        var i = k;
        if !all {
            i = tile_lists[first + k];
        }
        let counted = tile_params.selected == 0xffffffffu || tile_params.selected == i;
        wasted += u32(counted && !inside_light(s, light_at(i)));
    }
    return vec4<f32>(f32(wasted), 0.0, 0.0, 0.0);
}

// Debug: the length of the pixel's list (every pixel with a G-buffer point; z-binned, the
// bits of its tile's mask within its bin). In a clustered or z-binned frame with `tile_params.view_depth` > 0, the length of its tile's list at that view depth
// instead, at every pixel (a slice through the clusters, as Unity HDRP's cluster display).
@fragment
fn fs_tile_count(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(frag.xy);
    var s = gbuffer_load(p);
    let slice = tile_params.mode >= 1u && tile_params.view_depth > 0.0;
    if slice {
        s.position = vec3<f32>(0.0, 0.0, -tile_params.view_depth);
    } else if !s.valid {
        return vec4<f32>(0.0);
    }
    if tile_params.mode == 2u {
        return vec4<f32>(f32(zbin_count(p, s, -s.position.z, false)), 0.0, 0.0, 1.0);
    }
    let cell = tile_cell(p, s);
    var count = tile_lists[2u * cell + 1u];
    if count == LS_TILE_ALL {
        count = tile_params.light_count;
    }
    return vec4<f32>(f32(count), 0.0, 0.0, 1.0);
}

// ---- Clustered lists built on the GPU (tiles::ClusterBuild::Gpu). The CPU's twin is
// tiles::cluster_lists: the same tests in f32, axis by axis, over the same span of cells per
// light (tiles::Span, 4 words per light after the list region of `tile_lists`). Four passes:
// count each cell's lights (the counters after the lights' in `tile_counts`),
// a prefix sum into the headers, fill each cell's list at its cursor, then sort each list into
// light order (the fill's atomics leave it in arrival order; sorted, a pixel sums its lights
// in the same order as the CPU's lists and every run gives the same picture).

// View x (or y) over view depth at pixel edge `px` (x) or `py` (y, down).
fn cluster_ax(px: f32) -> f32 {
    let ndc = px * camera.screen.z * 2.0 - 1.0;
    return (ndc + camera.proj[2][0]) / camera.proj[0][0];
}

fn cluster_ay(py: f32) -> f32 {
    let ndc = 1.0 - py * camera.screen.w * 2.0;
    return (ndc + camera.proj[2][1]) / camera.proj[1][1];
}

// Squared distance from c to the extent d * a, d in depths, a in span (tiles::gap2).
fn cluster_gap2(c: f32, span: vec2<f32>, depths: vec2<f32>) -> f32 {
    let lo = min(depths.x * span.x, depths.y * span.x);
    let hi = max(depths.x * span.y, depths.y * span.y);
    let g = max(max(lo - c, c - hi), 0.0);
    return g * g;
}

// Column tx's extent (tiles::CellBounds::columns), widened by a pixel.
fn cluster_column(tx: u32) -> vec2<f32> {
    let t = f32(tile_params.tile_size);
    return vec2<f32>(cluster_ax(f32(tx) * t - 1.0), cluster_ax(f32(tx + 1u) * t + 1.0));
}

fn cluster_row(ty: u32) -> vec2<f32> {
    let t = f32(tile_params.tile_size);
    return vec2<f32>(cluster_ay(f32(ty + 1u) * t + 1.0), cluster_ay(f32(ty) * t - 1.0));
}

// Slice k's depths (tiles::ClusterGrid::slice_depths), widened by 0.1%.
fn cluster_slice(k: u32) -> vec2<f32> {
    let d0 = exp((f32(k) - tile_params.slice_bias) / tile_params.slice_scale);
    let d1 = exp((f32(k + 1u) - tile_params.slice_bias) / tile_params.slice_scale);
    return vec2<f32>(d0 * 0.999, d1 * 1.001);
}

// Cell c's counter (after the allocator and the lights' pair counts).
fn cluster_counter(c: u32) -> u32 {
    return 1u + tile_params.light_count + c;
}

// Light i's cells (tiles::light_cells): counted (`fill` false) or written at their cell's
// cursor.
fn cluster_assign(i: u32, fill: bool) {
    let at_span = 2u * tile_params.tiles_x * tile_params.tiles_y * tile_params.slices + tile_params.capacity + 4u * i;
    let span = vec3<u32>(tile_lists[at_span], tile_lists[at_span + 1u], tile_lists[at_span + 2u]);
    for (var k = span.z & 0xffffu; k < (span.z >> 16u); k++) {
        cluster_assign_slice(i, k, span, fill);
    }
}

fn cluster_assign_slice(i: u32, k: u32, span: vec3<u32>, fill: bool) {
    let tx0 = span.x & 0xffffu;
    let tx1 = span.x >> 16u;
    let ty0 = span.y & 0xffffu;
    let ty1 = span.y >> 16u;
    let l = light_at(i);
    let c = l.position;
    let r = l.radius;
    let r2 = r * r * 1.0001;
    let depths = cluster_slice(k);
    let dz = max(max(depths.x + c.z, -c.z - depths.y), 0.0);
    let dz2 = dz * dz;
    if dz2 > r2 {
        return;
    }
    // The run of columns within reach at this slice.
    var a = tx1 + 1u;
    for (var tx = tx0; tx <= tx1; tx++) {
        if dz2 + cluster_gap2(c.x, cluster_column(tx), depths) <= r2 {
            a = tx;
            break;
        }
    }
    if a > tx1 {
        return;
    }
    var b = a;
    for (var tx = tx1; tx > a; tx--) {
        if dz2 + cluster_gap2(c.x, cluster_column(tx), depths) <= r2 {
            b = tx;
            break;
        }
    }
    let per_slice = tile_params.tiles_x * tile_params.tiles_y;
    for (var ty = ty0; ty <= ty1; ty++) {
        let dyz2 = dz2 + cluster_gap2(c.y, cluster_row(ty), depths);
        if dyz2 > r2 {
            continue;
        }
        for (var tx = a; tx <= b; tx++) {
            if dyz2 + cluster_gap2(c.x, cluster_column(tx), depths) <= r2 {
                let cell = k * per_slice + ty * tile_params.tiles_x + tx;
                if fill {
                    let count = tile_lists[2u * cell + 1u];
                    let at = atomicAdd(&tile_counts[cluster_counter(cell)], 1u);
                    if count != LS_TILE_ALL {
                        tile_lists[tile_lists[2u * cell] + at] = i;
                    }
                } else {
                    atomicAdd(&tile_counts[cluster_counter(cell)], 1u);
                }
            }
        }
    }
}

// One invocation per light (lavapipe pays per workgroup: a light's slices are a loop, not a
// dispatch dimension).
@compute @workgroup_size(64, 1, 1)
fn cs_cluster_count(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x < tile_params.light_count {
        cluster_assign(gid.x, false);
    }
}

@compute @workgroup_size(64, 1, 1)
fn cs_cluster_fill(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x < tile_params.light_count {
        cluster_assign(gid.x, true);
    }
}

// One workgroup: each invocation sums a run of cells' counts, a prefix sum over the runs,
// then each writes its cells' headers (a cell past the list region's room walks every light,
// as in the tiled mode) and resets their counters to serve as the fill's cursors.
@compute @workgroup_size(256, 1, 1)
fn cs_cluster_scan(@builtin(local_invocation_index) li: u32) {
    let cells = tile_params.tiles_x * tile_params.tiles_y * tile_params.slices;
    let run = (cells + 255u) / 256u;
    let start = min(li * run, cells);
    let end = min(start + run, cells);
    var mine = 0u;
    for (var c = start; c < end; c++) {
        mine += atomicLoad(&tile_counts[cluster_counter(c)]);
    }
    wg_inclusive_scan(li, mine);
    let header = 2u * cells;
    var at = wg_scan[li] - mine;
    for (var c = start; c < end; c++) {
        let n = atomicLoad(&tile_counts[cluster_counter(c)]);
        if at + n > tile_params.capacity {
            tile_lists[2u * c] = 0u;
            tile_lists[2u * c + 1u] = LS_TILE_ALL;
        } else {
            tile_lists[2u * c] = header + at;
            tile_lists[2u * c + 1u] = n;
        }
        at += n;
        atomicStore(&tile_counts[cluster_counter(c)], 0u);
    }
}

// One invocation per cell: its list into light order (insertion sort; the fill leaves lists
// nearly ordered, and they are short).
@compute @workgroup_size(64, 1, 1)
fn cs_cluster_sort(@builtin(global_invocation_id) gid: vec3<u32>) {
    let cells = tile_params.tiles_x * tile_params.tiles_y * tile_params.slices;
    let cell = gid.y * 65535u * 64u + gid.x;
    if cell >= cells {
        return;
    }
    let count = tile_lists[2u * cell + 1u];
    if count == LS_TILE_ALL || count < 2u {
        return;
    }
    let first = tile_lists[2u * cell];
    for (var j = first + 1u; j < first + count; j++) {
        let v = tile_lists[j];
        var m = j;
        while m > first && tile_lists[m - 1u] > v {
            tile_lists[m] = tile_lists[m - 1u];
            m -= 1u;
        }
        tile_lists[m] = v;
    }
}
