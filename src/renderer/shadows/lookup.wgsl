// The shadow lookups every shaded light and the sun go through (`ls_shadow`, `ls_sun_shadow`):
// the atlas tiles, the cube array, the sun's cascades and the kernels (`shadows`).

// The shadow factor (1 lit .. 0 shadowed) of view-space point `p` with normal `n` in
// tile `t`, towards the light along `L`. The biases are texels (`shadow_params.bias`) times a
// texel's world size at the receiver, so they follow each tile's resolution:
// - normal offset: the lookup point moves h = (reach + knob) texels along the normal, where
//   reach is how far from the point the kernel reads depths (LS_SHADOW_REACH: 1 texel for the
//   hardware 2x2, 2 for 3x3 of them, 3 for the Poisson disc of radius 2). On a plane this alone
//   removes acne at every angle: the light ray through the moved point meets the plane h / N.L
//   beyond it, while the plane's stored depth varies by at most (reach + 1/2) texels x tan over
//   the texels the kernel reads, which is less than h / N.L when h > (reach + 1/2) sin.
// - depth bias: the compared depth is lowered by (constant + slope x tan(angle to the light),
//   tan at most 10) texels.
// - stored-position bias (`stored_position_error`): a layout that stores the position in fp16
//   (seeds 000 and 002) moves the receiver by up to e; along the light that changes its depth
//   by up to e, and sideways (the lookup lands on the receiver's plane up to e away) the
//   plane's stored depth by up to e x tan, so the compared depth is lowered by e (1 + tan) more.
// - format step (`LS_SHADOW_DEPTH_STEP`, `ShadowFormat::step`): the stored depth rounds by half
//   a step of the map's format and the compared reference by up to half a step more, so one
//   step more (1/65535 of the light's range for `depth16`).
// Points outside the tile's frustum are lit (a spot's cone and a light's radius end there).
fn shadow_tile_factor(t: ShadowTile, p: vec3<f32>, n: vec3<f32>, L: vec3<f32>, pos_err: f32) -> f32 {
    let q0 = (t.to_light * vec4<f32>(p, 1.0)).xyz;
    let w0 = select(-q0.z, 1.0, t.info.x == LS_TILE_ORTHOGRAPHIC);
    if !(w0 > 0.0) {
        return 1.0;
    }
    let texel = t.info.y * w0;
    return shadow_lookup(t, shadow_offset_point(p, n, texel), n, L, texel, pos_err);
}

// How far the G-buffer's stored position may lie from the surface's (`Surface.position_error`,
// 0 for surfaces shaded forward, whose position is the vertex stage's): each component rounds by
// at most GBUFFER_POSITION_ROUNDING of its magnitude (half an ulp: 2^-11 in fp16), which is at
// most |p|, so |error| <= sqrt(3) x rounding x |p| (seed 002: "increase shadow bias based on
// pos.z if using fp16 for G-buffer positions"). 0 for layouts that reconstruct the position
// from depth. Seed 000 stores the world-space view vector, of the same length.
fn stored_position_error(p: vec3<f32>) -> f32 {
    return sqrt(3.0) * GBUFFER_POSITION_ROUNDING * length(p);
}

// The normal offset's lookup point: `p` moved (reach + knob) texels along the normal.
fn shadow_offset_point(p: vec3<f32>, n: vec3<f32>, texel: f32) -> vec3<f32> {
    let b = shadow_params_load();
    let reach = f32(LS_SHADOW_KERNEL + 1u);
    return p + n * ((reach + b.bias.z) * texel);
}

// The lookup at the (offset) point `p1` in tile `t`; `texel` is a texel's world size at the
// receiver.
fn shadow_lookup(t: ShadowTile, p1: vec3<f32>, n: vec3<f32>, L: vec3<f32>, texel: f32, pos_err: f32) -> f32 {
    let ortho = t.info.x == LS_TILE_ORTHOGRAPHIC;
    let q = (t.to_light * vec4<f32>(p1, 1.0)).xyz;
    let w = select(-q.z, 1.0, ortho);
    if !(w > 0.0) {
        return 1.0;
    }
    let ndc = q.xy * t.proj.xy / w;
    if any(abs(ndc) > vec2<f32>(1.0)) {
        return 1.0;
    }
    return shadow_compare(t, ndc, -q.z, n, L, texel, pos_err, 0.0);
}

// The comparison in tile `t` at `ndc` for a point `dist` along the tile's axis (-q.z), within
// `lateral` texels of its true projection: the lookup may land that far sideways on the
// receiver's plane, where the stored depths differ by up to lateral x tan texels, so the depth
// bias's slope term grows by that (0 for the tiles' own projection).
fn shadow_compare(t: ShadowTile, ndc: vec2<f32>, dist: f32, n: vec3<f32>, L: vec3<f32>, texel: f32, pos_err: f32, lateral: f32) -> f32 {
    let shadow_params = shadow_params_load();
    let ndl = clamp(dot(n, L), 0.0, 1.0);
    let kernel = LS_SHADOW_KERNEL;
    let tan_angle = min(sqrt(max(1.0 - ndl * ndl, 0.0)) / max(ndl, 1e-4), 10.0);
    let slope = shadow_params.bias.y + lateral;
    let bias = ((shadow_params.bias.x + slope * tan_angle) * texel + pos_err * (1.0 + tan_angle)) * t.proj.z
        + LS_SHADOW_DEPTH_STEP;
    let depth = dist * t.proj.z + t.proj.w - bias;
    if depth >= 1.0 {
        return 1.0;
    }
    let uv = t.rect.xy + vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * t.rect.zw;
    // Taps stay half a texel inside the tile: never a neighbour's depths.
    let px = shadow_params.bias.w;
    let lo = t.rect.xy + vec2<f32>(0.5 * px);
    let hi = t.rect.xy + t.rect.zw - vec2<f32>(0.5 * px);
    if kernel == LS_SHADOW_FILTER_PCF2X2 {
        return textureSampleCompareLevel(shadow_atlas, shadow_sampler, clamp(uv, lo, hi), depth);
    }
    var sum = 0.0;
    if kernel == LS_SHADOW_FILTER_PCF3X3 {
        for (var y = -1; y <= 1; y++) {
            for (var x = -1; x <= 1; x++) {
                let o = vec2<f32>(f32(x), f32(y)) * px;
                sum += textureSampleCompareLevel(shadow_atlas, shadow_sampler, clamp(uv + o, lo, hi), depth);
            }
        }
        return sum / 9.0;
    }
    for (var k = 0; k < 16; k++) {
        let o = SHADOW_POISSON[k] * (2.0 * px);
        sum += textureSampleCompareLevel(shadow_atlas, shadow_sampler, clamp(uv + o, lo, hi), depth);
    }
    return sum / 16.0;
}

// 16 points of a Poisson disc of radius 1 (the widely used set from "Fast soft shadows").
const SHADOW_POISSON = array<vec2<f32>, 16>(
    vec2<f32>(-0.94201624, -0.39906216), vec2<f32>(0.94558609, -0.76890725),
    vec2<f32>(-0.094184101, -0.92938870), vec2<f32>(0.34495938, 0.29387760),
    vec2<f32>(-0.91588581, 0.45771432), vec2<f32>(-0.81544232, -0.87912464),
    vec2<f32>(-0.38277543, 0.27676845), vec2<f32>(0.97484398, 0.75648379),
    vec2<f32>(0.44323325, -0.97511554), vec2<f32>(0.53742981, -0.47373420),
    vec2<f32>(-0.26496911, -0.41893023), vec2<f32>(0.79197514, 0.19090188),
    vec2<f32>(-0.24188840, 0.99706507), vec2<f32>(-0.81409955, 0.91437590),
    vec2<f32>(0.19984126, 0.78641367), vec2<f32>(0.14383161, -0.14100790),
);

// The cube face of the major axis of the light-to-point vector `d` (view-space axes,
// `shadows::FACES`: +x, -x, +y, -y, +z, -z).
fn cube_face(d: vec3<f32>) -> u32 {
    let a = abs(d);
    var face = 0u;
    if a.x >= a.y && a.x >= a.z {
        face = select(1u, 0u, d.x > 0.0);
    } else if a.y >= a.z {
        face = select(3u, 2u, d.y > 0.0);
    } else {
        face = select(5u, 4u, d.z > 0.0);
    }
    return face;
}

// THE shadow lookup of a light: every place that shades a light calls it through
// `shade_light` (light volumes, the tiled/clustered loop, the forward pass). 1 when the light
// casts no shadow this frame.
// Only the lookups the configuration compiles in (`program::ShaderFeatures`): a light of a kind
// the scene has no caster of never has a shadow.
fn ls_shadow(l: GpuLight, p: vec3<f32>, n: vec3<f32>, pos_err: f32) -> f32 {
    if !(LS_TILE_SHADOWS || LS_CUBE_SHADOWS) || l.shadow.x == LS_NO_SHADOW {
        return 1.0;
    }
    let L = safe_normalize(l.position - p, n);
    if LS_TILE_SHADOWS && (!LS_CUBE_SHADOWS || l.shadow.y < 6u) {
        return shadow_tile_factor(shadow_tile_load(l.shadow.x), p, n, L, pos_err);
    }
    if !LS_CUBE_SHADOWS {
        return 1.0;
    }
    // A cube: every face has the texel size of the distance along the major axis; the face is
    // picked for the offset lookup point, so the lookup always lies in its face's frustum and
    // the taps within the border (a point near a face edge offset into the next face reads
    // that face, not the first face's border, where the projection stretches).
    let d = p - l.position;
    let a = abs(d);
    let first = shadow_tile_load(l.shadow.x);
    let texel = first.info.y * max(a.x, max(a.y, a.z));
    let p1 = shadow_offset_point(p, n, texel);
    if LS_CUBE_ARRAY {
        return shadow_cube_lookup(first, p1 - l.position, n, L, texel, pos_err);
    }
    if LS_CUBE_INDIRECT {
        return shadow_cube_indirect(l.shadow.x, p1 - l.position, n, L, texel, pos_err);
    }
    let face = shadow_tile_load(l.shadow.x + cube_face(p1 - l.position));
    return shadow_lookup(face, p1, n, L, texel, pos_err);
}

// `--shadow-cube indirect`: seed 002's indirection. One nearest fetch of the indirection cube
// by the (offset) light-to-point vector `d` gives the face the hardware picks for `d` and the
// face coordinates (u, v) of that texel's centre (`shadows::indirection_texels`: (face + u) / 6
// and v, 16 bits each, split over two bytes); the tile's ndc follows from them (the faces lie
// in the cube-map orientation, `shadows::cube_face_space`), and the depth is the axial
// distance, the largest component of |d|, the unrolled face's -q.z. The lookup lands within
// `shadows::indirection_error` texels (per axis) of the face pick's, so up to sqrt(2) times
// that sideways; `shadow_compare` widens the bias by it. `first` is the cube's first face.
fn shadow_cube_indirect(first: u32, d: vec3<f32>, n: vec3<f32>, L: vec3<f32>, texel: f32, pos_err: f32) -> f32 {
    let a = abs(d);
    let ma = max(a.x, max(a.y, a.z));
    if !(ma > 0.0) {
        return 1.0;
    }
    let c = round(textureSampleLevel(shadow_indirection, indirection_sampler, d, 0.0) * 255.0);
    let r = (c.x * 256.0 + c.y) / 65535.0 * 6.0;
    let v = (c.z * 256.0 + c.w) / 65535.0;
    let f = min(floor(r), 5.0);
    let t = shadow_tile_load(first + u32(f));
    let ndc = vec2<f32>(2.0 * (r - f) - 1.0, 1.0 - 2.0 * v) * t.proj.xy;
    let side = f32(textureDimensions(shadow_indirection).x);
    // The face frustum's span in texels: the tile less its borders (`shadows::BORDER`).
    let inner = t.proj.x * t.info.z;
    let lateral = sqrt(2.0) * inner * ((0.5 + 1.0 / 16.0) / side + 3.0 / 65535.0);
    return shadow_compare(t, ndc, ma, n, L, texel, pos_err, lateral);
}

// `--shadow-cube array`: the lookup of a cube in the cube array, for the (offset) light-to-point
// vector `d`; `first` is the cube's first face (rect.x its layer, proj.z 1 / far, info.z the
// face side); `texel` a texel's world size at the receiver. The same test as `shadow_lookup`
// on an unrolled face, stored differently: the faces hold |q| / far (`fs_shadow`), so the
// reference is the axial one (ma / far - bias, ma = d's major component, the unrolled face's
// depth) times |d'| / ma for a tap along d' (d' - d lies in the face's plane, so d' has the
// same axial distance ma, and along one ray radial = axial x |d'| / ma: the comparison is the
// axial one, exactly). The hardware picks the face and filters 2x2 across face edges
// (seamless), so no border; the wider kernels move d in the plane of its major face by whole
// texels (2 ma / side a texel at that face's distance), as the atlas kernels move uv.
fn shadow_cube_lookup(first: ShadowTile, d: vec3<f32>, n: vec3<f32>, L: vec3<f32>, texel: f32, pos_err: f32) -> f32 {
    let shadow_params = shadow_params_load();
    let kernel = LS_SHADOW_KERNEL;
    let a = abs(d);
    let ma = max(a.x, max(a.y, a.z));
    if !(ma > 0.0) {
        return 1.0;
    }
    let ndl = clamp(dot(n, L), 0.0, 1.0);
    let tan_angle = min(sqrt(max(1.0 - ndl * ndl, 0.0)) / max(ndl, 1e-4), 10.0);
    let bias = ((shadow_params.bias.x + shadow_params.bias.y * tan_angle) * texel + pos_err * (1.0 + tan_angle)) * first.proj.z
        + LS_SHADOW_DEPTH_STEP;
    let axial = ma * first.proj.z - bias;
    if axial >= 1.0 {
        return 1.0;
    }
    let cube = i32(first.rect.x) / 6;
    // The face's plane: the two axes other than the major one, a texel long at distance ma.
    var tu = vec3<f32>(0.0, 1.0, 0.0);
    var tv = vec3<f32>(0.0, 0.0, 1.0);
    if a.y >= a.x && a.y >= a.z {
        tu = vec3<f32>(1.0, 0.0, 0.0);
    } else if a.z > a.x && a.z > a.y {
        tu = vec3<f32>(1.0, 0.0, 0.0);
        tv = vec3<f32>(0.0, 1.0, 0.0);
    }
    let step = 2.0 * ma / first.info.z;
    tu *= step;
    tv *= step;
    let k = axial / ma;
    if kernel == LS_SHADOW_FILTER_PCF2X2 {
        return textureSampleCompareLevel(shadow_cubes, shadow_sampler, d, cube, k * length(d));
    }
    var sum = 0.0;
    if kernel == LS_SHADOW_FILTER_PCF3X3 {
        for (var y = -1; y <= 1; y++) {
            for (var x = -1; x <= 1; x++) {
                let dt = d + f32(x) * tu + f32(y) * tv;
                sum += textureSampleCompareLevel(shadow_cubes, shadow_sampler, dt, cube, k * length(dt));
            }
        }
        return sum / 9.0;
    }
    for (var i = 0; i < 16; i++) {
        let o = SHADOW_POISSON[i] * 2.0;
        let dt = d + o.x * tu + o.y * tv;
        sum += textureSampleCompareLevel(shadow_cubes, shadow_sampler, dt, cube, k * length(dt));
    }
    return sum / 16.0;
}

// The sun's cascade for view-space point `p` (its count when beyond the last: unshadowed).
fn sun_cascade(p: vec3<f32>) -> u32 {
    let shadow_params = shadow_params_load();
    let d = -p.z;
    var i = 0u;
    while i < shadow_params.sun.y && d > shadow_params.splits[i] {
        i++;
    }
    return i;
}

// The sun's shadow factor (ambient + sun, in the G-buffer pass, its own pass and the forward
// pass).
fn ls_sun_shadow(p: vec3<f32>, n: vec3<f32>, pos_err: f32) -> f32 {
    let shadow_params = shadow_params_load();
    if !LS_SUN_SHADOW || shadow_params.sun.x == LS_NO_SHADOW {
        return 1.0;
    }
    let i = sun_cascade(p);
    if i >= shadow_params.sun.y {
        return 1.0;
    }
    return shadow_tile_factor(shadow_tile_load(shadow_params.sun.x + i), p, n, camera.sun_dir.xyz, pos_err);
}

// The shadow table (`records::FrameBuffers::shadow_table`): row 0 the ShadowParams, row 1 + i
// tile i, each as the bytes of its Rust record (Rgba32Uint texels).
fn shadow_params_load() -> ShadowParams {
    var r: ShadowParams;
    r.sun = textureLoad(shadow_table, vec2<i32>(0, 0), 0);
    r.splits = bitcast<vec4<f32>>(textureLoad(shadow_table, vec2<i32>(1, 0), 0));
    r.bias = bitcast<vec4<f32>>(textureLoad(shadow_table, vec2<i32>(2, 0), 0));
    r.counts = textureLoad(shadow_table, vec2<i32>(3, 0), 0);
    return r;
}

fn shadow_texel(x: i32, y: i32) -> vec4<f32> {
    return bitcast<vec4<f32>>(textureLoad(shadow_table, vec2<i32>(x, y), 0));
}

fn shadow_tile_load(i: u32) -> ShadowTile {
    let y = i32(i) + 1;
    var t: ShadowTile;
    t.to_light = mat4x4<f32>(shadow_texel(0, y), shadow_texel(1, y), shadow_texel(2, y), shadow_texel(3, y));
    t.proj = shadow_texel(4, y);
    t.rect = shadow_texel(5, y);
    t.info = shadow_texel(6, y);
    return t;
}

