// The z-binned culling mode (Drobot 2017; culling::zbin). With tile_params.mode == 2:
// - tile_lists: [first, end) of sorted positions per depth bin (tile_params.slices bins), then
//   the sorted lights' indices (from tile_params.order_base), then each sorted light's tile
//   rectangle, x0 | x1 << 16 and y0 | y1 << 16 (from tile_params.rect_base);
// - tile_counts: the lights' pair counters (1 + i), then from tile_params.mask_base one mask
//   per tile, tile_params.words words, bit j set when sorted light j's rectangle holds the tile.

// One invocation per sorted light: its bit in every tile of its rectangle.
@compute @workgroup_size(64)
fn cs_zbin_mask(@builtin(global_invocation_id) gid: vec3<u32>) {
    let j = gid.x + gid.y * 65535u * 64u;
    if j >= tile_params.capacity {
        return;
    }
    let rx = tile_lists[tile_params.rect_base + 2u * j];
    let ry = tile_lists[tile_params.rect_base + 2u * j + 1u];
    let bit = 1u << (j & 31u);
    let word = tile_params.mask_base + (j >> 5u);
    for (var ty = ry & 0xffffu; ty <= ry >> 16u; ty++) {
        let row = ty * tile_params.tiles_x;
        for (var tx = rx & 0xffffu; tx <= rx >> 16u; tx++) {
            atomicOr(&tile_counts[word + (row + tx) * tile_params.words], bit);
        }
    }
}

// The pixel's tile.
fn zbin_tile(p: vec2<i32>) -> u32 {
    let t = vec2<u32>(p) / tile_params.tile_size;
    return min(t.y, tile_params.tiles_y - 1u) * tile_params.tiles_x + min(t.x, tile_params.tiles_x - 1u);
}

// The bin of view depth `depth` (as tiles::ClusterGrid::slice).
fn zbin_bin(depth: f32) -> u32 {
    let k = floor(log(max(depth, 1e-30)) * tile_params.slice_scale + tile_params.slice_bias);
    return u32(clamp(k, 0.0, f32(tile_params.slices - 1u)));
}

// Bin k's sorted positions [first, end), cut to draw `chunk`'s stretch of tile_params.chunk.
fn zbin_range(k: u32, chunk: u32) -> vec2<u32> {
    let lo = chunk * tile_params.chunk;
    let hi = lo + min(tile_params.chunk, tile_params.capacity - min(lo, tile_params.capacity));
    return vec2<u32>(max(tile_lists[2u * k], lo), min(tile_lists[2u * k + 1u], hi));
}

// The bits of word w inside positions [r.x, r.y). (insertBits, not 1 << b - 1: a shift by 32
// is undefined in SPIR-V, and a driver may fold it into the select's other arm.)
fn zbin_word_bits(w: u32, r: vec2<u32>) -> u32 {
    let a = max(r.x, w << 5u) - (w << 5u);
    let b = min(r.y, (w << 5u) + 32u) - (w << 5u);
    return insertBits(0u, 0xffffffffu, a, b - a);
}

// Tile `tile`'s mask bits over positions [r.x, r.y) in word w.
fn zbin_word(tile: u32, w: u32, r: vec2<u32>) -> u32 {
    return atomicLoad(&tile_counts[tile_params.mask_base + tile * tile_params.words + w]) & zbin_word_bits(w, r);
}

@fragment
fn fs_zbin(in: TiledVarying) -> LightTargets {
    return zbin_shade(in.clip, in.chunk, false);
}

@fragment
fn fs_zbin_counted(in: TiledVarying) -> LightTargets {
    return zbin_shade(in.clip, in.chunk, true);
}

// As tiled_shade (tiled.wgsl), walking the set bits of the tile's mask within the pixel's bin:
// the reach test first, the per-light clamp, and with LS_CASTERS_APART the casting lights in a
// second walk over the positions between the first and the last of them.
fn zbin_shade(frag: vec4<f32>, chunk: u32, counted: bool) -> LightTargets {
    let p = vec2<i32>(frag.xy);
    let s = gbuffer_load(p);
    var d = vec3<f32>(0.0);
    var sp = vec3<f32>(0.0);
    if s.valid {
        let view = view_dir(s);
        let tile = zbin_tile(p);
        let r = zbin_range(zbin_bin(-s.position.z), chunk);
        var casters = vec2<u32>(r.y, 0u);
        for (var w = r.x >> 5u; r.x < r.y && w <= (r.y - 1u) >> 5u; w++) {
            var m = zbin_word(tile, w, r);
            while m != 0u {
                let j = (w << 5u) | countTrailingZeros(m);
                m &= m - 1u;
                let i = tile_lists[tile_params.order_base + j];
                if counted {
                    atomicAdd(&tile_counts[1u + i], 1u);
                }
                let l = light_at(i);
                let to_light = l.position - s.position;
                if dot(to_light, to_light) > l.radius * l.radius * 1.0001 {
                    continue;
                }
                if LS_CASTERS_APART && l.shadow.x != LS_NO_SHADOW {
                    casters = vec2<u32>(min(casters.x, j), j + 1u);
                    continue;
                }
                let lit = shade_light_view(s, view, l, !LS_CASTERS_APART);
                d += min(lit.diffuse, vec3<f32>(l.clamp));
                sp += min(lit.specular, vec3<f32>(l.clamp));
            }
        }
        for (var w = casters.x >> 5u; LS_CASTERS_APART && casters.x < casters.y && w <= (casters.y - 1u) >> 5u; w++) {
            var m = zbin_word(tile, w, casters);
            while m != 0u {
                let j = (w << 5u) | countTrailingZeros(m);
                m &= m - 1u;
                let l = light_at(tile_lists[tile_params.order_base + j]);
                let to_light = l.position - s.position;
                if l.shadow.x == LS_NO_SHADOW || dot(to_light, to_light) > l.radius * l.radius * 1.0001 {
                    continue;
                }
                let lit = shade_light_view(s, view, l, true);
                d += min(lit.diffuse, vec3<f32>(l.clamp));
                sp += min(lit.specular, vec3<f32>(l.clamp));
            }
        }
    }
    return light_targets(s, d, sp);
}

// The debug views' walk: of the lights the pixel's tile and bin hold (every draw's stretch),
// how many (`waste` false), or how many whose true shape does not hold the surface point
// (`waste` true, restricted to tile_params.selected unless that is 0xffffffff).
fn zbin_count(p: vec2<i32>, s: Surface, depth: f32, waste: bool) -> u32 {
    let tile = zbin_tile(p);
    let k = zbin_bin(depth);
    let r = vec2<u32>(tile_lists[2u * k], tile_lists[2u * k + 1u]);
    var n = 0u;
    for (var w = r.x >> 5u; r.x < r.y && w <= (r.y - 1u) >> 5u; w++) {
        var m = zbin_word(tile, w, r);
        if !waste {
            n += countOneBits(m);
            continue;
        }
        while m != 0u {
            let j = (w << 5u) | countTrailingZeros(m);
            m &= m - 1u;
            let i = tile_lists[tile_params.order_base + j];
            let counted = tile_params.selected == 0xffffffffu || tile_params.selected == i;
            n += u32(counted && !inside_light(s, light_at(i)));
        }
    }
    return n;
}
