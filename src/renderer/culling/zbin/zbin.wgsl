// The z-binned culling mode (Drobot 2017; culling::zbin). With tile_params.mode == 2:
// - tile_lists: [first, end) of sorted positions per depth bin (tile_params.slices bins), then
//   the sorted lights' indices (from tile_params.order_base), then each sorted light's tile
//   rectangle, x0 | x1 << 16 and y0 | y1 << 16 (from tile_params.rect_base);
// - tile_counts: the lights' pair counters (1 + i), then from tile_params.mask_base one mask
//   per tile, tile_params.words words, bit j set when sorted light j's sphere meets the tile's
//   frustum between its depth bounds; then per tile its summary, zbin_summary_words() words,
//   bit w set when word w of its mask holds a bit (the walk loads only those words); then two
//   words a tile, its depth bounds (zbin_bounds_at).

fn zbin_summary_words() -> u32 {
    return (tile_params.words + 31u) / 32u;
}

// Where the summaries start in tile_counts, after the masks (from mask_base).
fn zbin_summary_offset() -> u32 {
    return tile_params.tiles_x * tile_params.tiles_y * tile_params.words;
}

// Where tile `tile`'s depth bounds are: ~bits(nearest), bits(farthest), both raised by
// atomicMax (positive floats order as their bits), so the cleared 0 means "no G-buffer point".
fn zbin_bounds_at(tile: u32) -> u32 {
    let summaries = tile_params.tiles_x * tile_params.tiles_y * zbin_summary_words();
    return tile_params.mask_base + zbin_summary_offset() + summaries + 2u * tile;
}

// One 16x16 workgroup per 16x16 pixels (a tile is a whole number of them): the view depths of
// its G-buffer points, nearest and farthest, into its tile's bounds.
@compute @workgroup_size(16, 16, 1)
fn cs_zbin_bounds(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
    @builtin(global_invocation_id) gid: vec3<u32>,
) {
    if li == 0u {
        atomicStore(&wg_min, 0u);
        atomicStore(&wg_max, 0u);
    }
    workgroupBarrier();
    let size = vec2<u32>(camera.screen.xy);
    if all(gid.xy < size) {
        let s = gbuffer_load(vec2<i32>(gid.xy));
        if s.valid {
            // The depth the shading pass bins this point at, kept positive and finite.
            let d = min(max(-s.position.z, 1e-30), 3.0e38);
            atomicMax(&wg_min, ~bitcast<u32>(d));
            atomicMax(&wg_max, bitcast<u32>(d));
        }
    }
    workgroupBarrier();
    if li == 0u && atomicLoad(&wg_max) != 0u {
        let at = zbin_bounds_at(zbin_tile(vec2<i32>(wg.xy * 16u)));
        atomicMax(&tile_counts[at], atomicLoad(&wg_min));
        atomicMax(&tile_counts[at + 1u], atomicLoad(&wg_max));
    }
}

// One invocation per sorted light: its bit in every tile of its rectangle whose frustum piece
// between the tile's depth bounds (widened by 0.1%) its sphere meets, tested axis by axis as
// the clustered lists test a cluster (tiles::light_cells: the piece's box along each axis, so
// never tighter than the piece itself). Tiles without a G-buffer point get no bits.
@compute @workgroup_size(64)
fn cs_zbin_mask(@builtin(global_invocation_id) gid: vec3<u32>) {
    let j = gid.x + gid.y * 65535u * 64u;
    if j >= tile_params.capacity {
        return;
    }
    let rx = tile_lists[tile_params.rect_base + 2u * j];
    let ry = tile_lists[tile_params.rect_base + 2u * j + 1u];
    let l = light_at(tile_lists[tile_params.order_base + j]);
    let c = l.position;
    let r2 = l.radius * l.radius * 1.0001;
    let bit = 1u << (j & 31u);
    let word = tile_params.mask_base + (j >> 5u);
    let swords = zbin_summary_words();
    let summary = tile_params.mask_base + zbin_summary_offset() + (j >> 10u);
    let summary_bit = 1u << ((j >> 5u) & 31u);
    for (var ty = ry & 0xffffu; ty <= ry >> 16u; ty++) {
        let row = ty * tile_params.tiles_x;
        let rows = cluster_row(ty);
        for (var tx = rx & 0xffffu; tx <= rx >> 16u; tx++) {
            let at = zbin_bounds_at(row + tx);
            let far = atomicLoad(&tile_counts[at + 1u]);
            if far == 0u {
                continue;
            }
            let depths = vec2<f32>(bitcast<f32>(~atomicLoad(&tile_counts[at])) * 0.999, bitcast<f32>(far) * 1.001);
            let dz = max(max(depths.x + c.z, -c.z - depths.y), 0.0);
            let g = dz * dz + cluster_gap2(c.x, cluster_column(tx), depths) + cluster_gap2(c.y, rows, depths);
            if g <= r2 {
                atomicOr(&tile_counts[word + (row + tx) * tile_params.words], bit);
                atomicOr(&tile_counts[summary + (row + tx) * swords], summary_bit);
            }
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

// Summary word sw of tile `tile`, cut to mask words [ws.x, ws.y].
fn zbin_summary(tile: u32, sw: u32, ws: vec2<u32>) -> u32 {
    let at = tile_params.mask_base + zbin_summary_offset() + tile * zbin_summary_words() + sw;
    return atomicLoad(&tile_counts[at]) & zbin_word_bits(sw, vec2<u32>(ws.x, ws.y + 1u));
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
        // The mask words the range covers; of them, only those the summary marks are loaded.
        let ws = vec2<u32>(r.x >> 5u, (max(r.y, 1u) - 1u) >> 5u);
        for (var sw = ws.x >> 5u; r.x < r.y && sw <= ws.y >> 5u; sw++) {
          var words = zbin_summary(tile, sw, ws);
          while words != 0u {
            let w = (sw << 5u) | countTrailingZeros(words);
            words &= words - 1u;
            var m = zbin_word(tile, w, r);
            while m != 0u {
                let j = (w << 5u) | countTrailingZeros(m);
                m &= m - 1u;
                if list_light_step(s, view, tile_lists[tile_params.order_base + j], counted, &d, &sp) {
                    casters = vec2<u32>(min(casters.x, j), j + 1u);
                }
            }
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
