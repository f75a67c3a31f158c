// Reservoir-resampled lighting on the list modes (stochastic/mod.rs): per pixel, K = camera.noise.z
// samples, each kept by weighted reservoir sampling (Chao 1982) from M = camera.noise.y candidates
// drawn uniformly from the pixel's list, with the candidate's unshadowed, clamped contribution's
// luminance as the target p^ (Talbot et al. 2005). Sample y is shaded with its shadow, f(y), and
// weighted by W = (1 / p^(y)) x (1 / M) x sum of the candidates' w = p^ / p, p = 1 / n for a list
// of n: the estimate f(y) W is unbiased for the sum of f over the list wherever p^ > 0 where
// f > 0, which holds as f is p^'s contribution times the shadow. The K estimates, each from its
// own candidates, are averaged. Lights of odd index are weighted by camera.stochastic.y (the
// planted bias of the unbiasedness tests; 1 otherwise).

// Where a pixel's candidates come from: kind 0, entries [first, first + count) of tile_lists; 1,
// every light (a list the GPU had no room for); 2, the z-bin's sorted positions [first, first +
// count), of which those the pixel's tile's mask leaves out are no light (they reach no point
// of the tile, so their contribution is zero: drawing them keeps the proposal uniform).
struct RisCell {
    kind: u32,
    first: u32,
    count: u32,
    tile: u32,
};

// The PCG hash (Jarzynski and Olano 2020, "Hash Functions for GPU Rendering").
fn ris_pcg(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The pixel's stream: a 32-bit LCG of full period (PCG's multiplier and increment), each state
// put through PCG's output permutation.
fn ris_next(state: ptr<function, u32>) -> u32 {
    *state = *state * 747796405u + 2891336453u;
    let s = *state;
    let word = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return (word >> 22u) ^ word;
}

// Uniform in [0, 1), 24 bits.
fn ris_unit(state: ptr<function, u32>) -> f32 {
    return f32(ris_next(state) >> 8u) * (1.0 / 16777216.0);
}

// Uniform in [0, n), n > 0, by rejection (Lemire 2019): draws below 2^32 mod n are redrawn, so
// every value has the same number of draws mapping to it. After four rejections in a row
// (probability below (n / 2^32)^4) the last draw is kept.
fn ris_below(state: ptr<function, u32>, n: u32) -> u32 {
    let reject = (~n + 1u) % n;
    var r = ris_next(state);
    for (var t = 0u; t < 3u && r < reject; t++) {
        r = ris_next(state);
    }
    return r % n;
}

// Candidate j of cell c: a light's index, or 0xffffffff for none.
fn ris_candidate(c: RisCell, j: u32) -> u32 {
    if c.kind == 0u {
        return tile_lists[c.first + j];
    }
    if c.kind == 1u {
        return j;
    }
    let at = c.first + j;
    let word = zbin_word(c.tile, at >> 5u, vec2<u32>(c.first, c.first + c.count));
    if ((word >> (at & 31u)) & 1u) == 0u {
        return 0xffffffffu;
    }
    return tile_lists[tile_params.order_base + at];
}

fn ris_target(d: vec3<f32>, sp: vec3<f32>) -> f32 {
    return dot(d + sp, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// p^ of light i at surface s: the luminance of its unshadowed, clamped contribution; 0 for no
// light (0xffffffff), an index past the lights, or a light that does not reach s.
fn ris_light_target(s: Surface, view: vec3<f32>, i: u32) -> f32 {
    if i >= tile_params.light_count {
        return 0.0;
    }
    let l = light_at(i);
    let to_light = l.position - s.position;
    if dot(to_light, to_light) > l.radius * l.radius * 1.0001 {
        return 0.0;
    }
    let lit = shade_light_view(s, view, l, false);
    return ris_target(min(lit.diffuse, vec3<f32>(l.clamp)), min(lit.specular, vec3<f32>(l.clamp)));
}

// One RIS sample: the light kept, its p^, and its contribution weight W = (1 / p^) (1 / M) x
// the sum of the candidates' p^ / p.
struct RisPick {
    light: u32,
    goal: f32,
    weight: f32,
};

// One sample from M candidates of cell c, streamed through a weighted reservoir (Chao 1982).
fn ris_pick(s: Surface, view: vec3<f32>, c: RisCell, m: u32, state: ptr<function, u32>) -> RisPick {
    var pick = RisPick(0xffffffffu, 0.0, 0.0);
    if c.count == 0u {
        return pick;
    }
    let n = f32(c.count);
    var total = 0.0;
    for (var j = 0u; j < m; j++) {
        let i = ris_candidate(c, ris_below(state, c.count));
        let u = ris_unit(state);
        let w = ris_light_target(s, view, i) * n;
        total += w;
        if w > 0.0 && u * total < w {
            pick.light = i;
            pick.goal = w / n;
        }
    }
    if pick.goal > 0.0 {
        pick.weight = total / (f32(m) * pick.goal);
    }
    return pick;
}

// Light i shaded at s with its shadow, clamped, times `weight` (the planted bias on lights of
// odd index).
fn ris_shade_light(s: Surface, view: vec3<f32>, i: u32, weight: f32) -> Lighting {
    var out = Lighting(vec3<f32>(0.0), vec3<f32>(0.0));
    if i >= tile_params.light_count || weight <= 0.0 {
        return out;
    }
    let l = light_at(i);
    let lit = shade_light_view(s, view, l, true);
    var w = weight;
    if (i & 1u) == 1u {
        w *= camera.stochastic.y;
    }
    out.diffuse = min(lit.diffuse, vec3<f32>(l.clamp)) * w;
    out.specular = min(lit.specular, vec3<f32>(l.clamp)) * w;
    return out;
}

// The pixel's stream of random numbers under the frame's seed; `salt` separates the passes'.
fn ris_stream(p: vec2<i32>, salt: u32) -> u32 {
    return ris_pcg(camera.noise.x ^ salt ^ ris_pcg(u32(p.x) ^ ris_pcg(u32(p.y))));
}

fn ris_shade(s: Surface, view: vec3<f32>, c: RisCell, p: vec2<i32>) -> Lighting {
    var out = Lighting(vec3<f32>(0.0), vec3<f32>(0.0));
    if c.count == 0u {
        return out;
    }
    let m = max(camera.noise.y, 1u);
    let k = max(camera.noise.z, 1u);
    var state = ris_stream(p, 0u);
    for (var r = 0u; r < k; r++) {
        let pick = ris_pick(s, view, c, m, &state);
        let lit = ris_shade_light(s, view, pick.light, pick.weight);
        out.diffuse += lit.diffuse;
        out.specular += lit.specular;
    }
    out.diffuse /= f32(k);
    out.specular /= f32(k);
    return out;
}

// The candidates of a pixel of the tile and cluster lists.
fn ris_list_cell(p: vec2<i32>, s: Surface) -> RisCell {
    let cell = tile_cell(p, s);
    var c = RisCell(0u, tile_lists[2u * cell], tile_lists[2u * cell + 1u], 0u);
    if c.count == LS_TILE_ALL {
        c = RisCell(1u, 0u, tile_params.light_count, 0u);
    }
    return c;
}

// The candidates of a pixel of the z-bins.
fn ris_zbin_cell(p: vec2<i32>, s: Surface) -> RisCell {
    let k = zbin_bin(-s.position.z);
    let first = tile_lists[2u * k];
    let end = max(tile_lists[2u * k + 1u], first);
    return RisCell(2u, first, end - first, zbin_tile(p));
}

@fragment
fn fs_tiled_ris(in: TiledVarying) -> LightTargets {
    let p = vec2<i32>(in.clip.xy);
    let s = gbuffer_load(p);
    var r = Lighting(vec3<f32>(0.0), vec3<f32>(0.0));
    if s.valid {
        r = ris_shade(s, view_dir(s), ris_list_cell(p, s), p);
    }
    return light_targets(s, r.diffuse, r.specular);
}

@fragment
fn fs_zbin_ris(in: TiledVarying) -> LightTargets {
    let p = vec2<i32>(in.clip.xy);
    let s = gbuffer_load(p);
    var r = Lighting(vec3<f32>(0.0), vec3<f32>(0.0));
    if s.valid {
        r = ris_shade(s, view_dir(s), ris_zbin_cell(p, s), p);
    }
    return light_targets(s, r.diffuse, r.specular);
}
