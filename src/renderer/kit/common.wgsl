// Shared by every pass: frame uniforms, the light record, G-buffer attribute packing and the
// lighting model. Constants prefixed LS_ are generated from Rust (see renderer::program::wgsl_constants).

struct Camera {
    proj: mat4x4<f32>,
    inv_proj: mat4x4<f32>,
    // World to view rotation: world-space layouts (GBUFFER_WORLD) store normals and view vectors
    // turned back by its transpose.
    view_rotation: mat4x4<f32>,
    // width, height, 1/width, 1/height
    screen: vec4<f32>,
    ambient: vec4<f32>,
    // View-space direction towards the sun; w = 1 when the scene has a sun.
    sun_dir: vec4<f32>,
    sun_color: vec4<f32>,
    background: vec4<f32>,
    exposure: f32,
    // Depth value of the far plane: 1, or 0 with reversed Z.
    far_depth: f32,
    // The most ambient + sun may add to a channel (`overlap::clamps`); each light has its own.
    light_clamp: f32,
    pad0: f32,
    // The forward pass's screen tiles: tile size in pixels (0: no tile lists), tiles across,
    // tiles down, and where the tiles' (first, count) pairs start in `light_lists`.
    forward_tiles: vec4<u32>,
    // Seed 004's lightmap crossfade: realtime up to x, fully baked from y (view distance);
    // z = 1 when lightmaps apply.
    lightmap_fade: vec4<f32>,
    // The stochastic estimators: the noise seed, RIS's candidates M and samples K (0: exact), 0.
    noise: vec4<u32>,
    // Stochastic culling's attenuation threshold (0: off), the planted bias on lights of odd
    // index (1: none), 0, 0.
    stochastic: vec4<f32>,
};

// A light in view space. `color` is colour x intensity.
struct GpuLight {
    position: vec3<f32>,
    radius: f32,
    color: vec3<f32>,
    kind: u32,
    direction: vec3<f32>,
    cos_outer: f32,
    cos_inner: f32,
    tan_outer: f32,
    // Where the attenuation reaches zero; `radius` is where the light is cut off (the same, or
    // less under a cut-off threshold) and what its volume bounds.
    falloff: f32,
    // The most this light may add to a channel (`overlap::clamps`).
    clamp: f32,
    // A spot cookie's up in view space (right = direction x up).
    cookie_up: vec3<f32>,
    // Where the cookie's first face starts in `cookie_texels`, or LS_NO_COOKIE.
    cookie: u32,
    // Culling mask (seed 004): bit k set = lights objects on layer k.
    mask: u32,
    // The cookie's face side in texels.
    cookie_size: u32,
    // The tangent of the bounding cone's half-angle (`LightRecord::volume_tan`).
    volume_tan: f32,
    // How far the bounding volume is grown all round (`LightRecord::volume_pad`).
    volume_pad: f32,
    // X, the first shadow tile (LS_NO_SHADOW: unshadowed); y, the tile count (1, or
    // 6 cube faces).
    shadow: vec4<u32>,
};

// One shadow-map tile of the atlas (`shadows::plan`): view space -> light space (the light
// looks down -z); ndc.xy = q.xy * proj.xy / w, w = -q.z (perspective) or 1 (orthographic);
// stored depth -q.z * proj.z + proj.w.
struct ShadowTile {
    to_light: mat4x4<f32>,
    proj: vec4<f32>,
    // The tile in atlas uv: corner, size.
    rect: vec4<f32>,
    // LS_TILE_PERSPECTIVE / LS_TILE_ORTHOGRAPHIC (atlas tiles) or LS_TILE_CUBE_FACE (a face of
    // the cube array, rect.x its layer), a texel's world size at w = 1, resolution, near plane.
    info: vec4<f32>,
};

struct ShadowParams {
    // The sun's first cascade tile (LS_NO_SHADOW: none), cascades, filter (LS_SHADOW_FILTER_*;
    // the lookups use the compiled-in LS_SHADOW_KERNEL, the same value), objects (the shadow pass's instance is tile * objects + object).
    sun: vec4<u32>,
    // View depth (-z) where each cascade ends.
    splits: vec4<f32>,
    // Constant bias, slope bias, normal offset (texels), 1 / atlas side.
    bias: vec4<f32>,
    // The frame's light count, 0, 0, 0.
    counts: vec4<u32>,
};

struct GpuObject {
    model_view: mat4x4<f32>,
    normal_view: mat4x4<f32>,
    albedo_spec: vec4<f32>,
    emissive_exp: vec4<f32>,
    // alpha factor, alpha cutoff (mask), normal scale, culling layer (0..31, seed 004)
    material: vec4<f32>,
    // metallic, roughness, dielectric f0 (used per pixel with a metallic-roughness texture),
    // distortion strength (seed 002's post distortion)
    pbr: vec4<f32>,
    // flags (LS_MAT_*), first entry in light_lists, count (forward-shaded objects), 0
    info: vec4<u32>,
    // per map (base colour, normal, emissive, metal-rough) two rows of its uv transform;
    // the first row's w is the texture coordinate set
    uv_transform: array<vec4<f32>, 8>,
    // The lightmap's scale (with LS_MAT_LIGHTMAP), 0, 0, 0.
    lightmap: vec4<f32>,
};

// The bindings (group 0, the frame's storage buffers) are declared from Rust: renderer::bindings.

// What a G-buffer pixel describes, decoded.
struct Surface {
    albedo: vec3<f32>,
    spec_level: f32,
    spec_exp: f32,
    normal: vec3<f32>,
    emissive: vec3<f32>,
    // View-space position.
    position: vec3<f32>,
    // How far `position` may lie from the surface's true one (`stored_position_error`): a
    // layout's fp16 stored position; 0 from depth or the vertex stage.
    position_error: f32,
    depth: f32,
    valid: bool,
    // The reflectance model (LS_BRDF_*, seed 002's material ID): from the ID channel, or the
    // scene's one model (GBUFFER_BRDF).
    brdf: u32,
    // The object's culling layer (seed 004): from the layer channel, or the scene's one
    // layer (GBUFFER_LAYER).
    layer: u32,
    // Seed 004's lightmap at the point (surfaces drawn from their material only): baked
    // irradiance in rgb, ambient occlusion in a; `lightmapped` when there is one.
    baked: vec4<f32>,
    lightmapped: bool,
};

// Seed 004's crossfade (Unity's dual lightmaps): the share of a lightmapped point's ambient and
// sun taken from the lightmap at view-space position `p`: 0 (realtime, plus the baked
// occlusion on the ambient) up to `lightmap_fade.x`, 1 (fully baked) from `lightmap_fade.y`,
// linear between; 0 when lightmaps are off. Non-decreasing in the distance.
fn baked_weight(p: vec3<f32>) -> f32 {
    let f = camera.lightmap_fade;
    if f.z < 0.5 {
        return 0.0;
    }
    return clamp((length(p) - f.x) / max(f.y - f.x, 1e-6), 0.0, 1.0);
}

// The models a lightmap's diffuse irradiance applies to: those whose ambient is the ambient
// itself (`ambient_diffuse`), not a metal (no diffuse) or an unlit surface.
fn takes_lightmap(s: Surface) -> bool {
    return s.lightmapped && s.brdf != LS_BRDF_METAL && s.brdf != LS_BRDF_UNLIT;
}

// The stored (encoded) form: what the layout table distributes over channels.
struct Attributes {
    albedo: vec3<f32>,
    spec_level: f32,
    spec_exp: f32,
    // Octahedral and Lambert layouts use .xy.
    normal: vec3<f32>,
    emissive: vec3<f32>,
    depth: f32,
    position: vec3<f32>,
    // The material ID / 255 (exact in 8-bit unorm and in fp16).
    material: f32,
    // The culling layer / 255 (the same).
    layer: f32,
};

fn safe_normalize(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let l2 = dot(v, v);
    if !(l2 > 1e-20) || l2 > 1e30 {
        return fallback;
    }
    return v * inverseSqrt(l2);
}

// Octahedral normal encoding (Cigolle et al., "A Survey of Efficient Representations for
// Independent Unit Vectors", JCGT 2014).
fn oct_wrap(v: vec2<f32>) -> vec2<f32> {
    let s = select(vec2<f32>(-1.0), vec2<f32>(1.0), v >= vec2<f32>(0.0));
    return (1.0 - abs(v.yx)) * s;
}

fn oct_encode(n: vec3<f32>) -> vec2<f32> {
    let p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    if n.z < 0.0 {
        return oct_wrap(p);
    }
    return p;
}

fn oct_decode(e: vec2<f32>) -> vec3<f32> {
    var n = vec3<f32>(e, 1.0 - abs(e.x) - abs(e.y));
    let t = clamp(-n.z, 0.0, 1.0);
    n.x += select(t, -t, n.x >= 0.0);
    n.y += select(t, -t, n.y >= 0.0);
    return safe_normalize(n, vec3<f32>(0.0, 0.0, 1.0));
}

// Lambert azimuthal equal-area projection (seed 001; Pranckevičius 2009, "Compact Normal
// Storage for small G-Buffers", method #4), scaled to the unit disc: e = n.xy / sqrt(2 + 2 n.z).
// n = -z, the one direction with no single point, goes to the rim at (1, 0).
fn lambert_encode(n: vec3<f32>) -> vec2<f32> {
    let d = 2.0 + 2.0 * n.z;
    if d <= 1e-12 {
        return vec2<f32>(1.0, 0.0);
    }
    return n.xy * inverseSqrt(d);
}

// g = 2e, f = |g|^2 in [0, 4] (clamped: rounding can step just past the rim):
// n = (g sqrt(1 - f/4), 1 - f/2), unit length by construction.
fn lambert_decode(e: vec2<f32>) -> vec3<f32> {
    let g = 2.0 * e;
    let f = min(dot(g, g), 4.0);
    return safe_normalize(vec3<f32>(g * sqrt(1.0 - f / 4.0), 1.0 - f / 2.0), vec3<f32>(0.0, 0.0, 1.0));
}

fn attributes_of(s: Surface) -> Attributes {
    var a: Attributes;
    a.albedo = clamp(s.albedo, vec3<f32>(0.0), vec3<f32>(1.0));
    a.spec_exp = clamp(log2(max(s.spec_exp, 1.0)) / LS_SPEC_EXP_LOG_RANGE, 0.0, 1.0);
    // The specular channel holds the reflectance f0 = level x 8 / (exponent + 8), which lies in
    // [0, 1] for every physical material, and `surface_of` multiplies the normalisation back:
    // the level itself reaches (2048 + 8) / 8 for a polished metal and would not fit.
    a.spec_level = clamp(s.spec_level * 8.0 / (exp2(a.spec_exp * LS_SPEC_EXP_LOG_RANGE) + 8.0), 0.0, 1.0);
    if GBUFFER_SPEC_LEVEL_RAW {
        // A float channel holds the level itself (seed 000's RT0 alpha).
        a.spec_level = max(s.spec_level, 0.0);
    }
    var n = safe_normalize(s.normal, vec3<f32>(0.0, 0.0, 1.0));
    a.position = s.position;
    if GBUFFER_WORLD {
        // Seed 000: world-space normal and the world-space, not normalised, view vector (from
        // the surface to the eye).
        let to_world = transpose(camera.view_rotation);
        n = (to_world * vec4<f32>(n, 0.0)).xyz;
        a.position = (to_world * vec4<f32>(-s.position, 0.0)).xyz;
    }
    if GBUFFER_NORMAL_OCTAHEDRAL {
        a.normal = vec3<f32>(oct_encode(n), 0.0);
    } else if GBUFFER_NORMAL_LAMBERT {
        a.normal = vec3<f32>(lambert_encode(n), 0.0);
    } else {
        a.normal = n;
    }
    a.emissive = max(s.emissive, vec3<f32>(0.0));
    a.depth = s.depth;
    a.material = f32(s.brdf) / 255.0;
    a.layer = f32(s.layer) / 255.0;
    return a;
}

fn default_attributes() -> Attributes {
    var a: Attributes;
    a.albedo = vec3<f32>(0.0);
    a.spec_level = 0.0;
    a.spec_exp = 0.0;
    a.normal = vec3<f32>(0.0, 0.0, 1.0);
    a.emissive = vec3<f32>(0.0);
    a.depth = camera.far_depth;
    a.position = vec3<f32>(0.0);
    a.material = f32(GBUFFER_BRDF) / 255.0;
    a.layer = f32(GBUFFER_LAYER) / 255.0;
    return a;
}

// Pixel centre to view space, from hardware depth (seed 001: position from depth).
fn view_position_from_depth(p: vec2<i32>, depth: f32) -> vec3<f32> {
    let uv = (vec2<f32>(p) + 0.5) * camera.screen.zw;
    let ndc = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, depth, 1.0);
    let v = camera.inv_proj * ndc;
    return v.xyz / v.w;
}

fn surface_of(a: Attributes, p: vec2<i32>) -> Surface {
    var s: Surface;
    s.albedo = a.albedo;
    s.spec_exp = exp2(a.spec_exp * LS_SPEC_EXP_LOG_RANGE);
    s.spec_level = a.spec_level * (s.spec_exp + 8.0) / 8.0;
    if GBUFFER_SPEC_LEVEL_RAW {
        s.spec_level = a.spec_level;
    }
    if GBUFFER_NORMAL_OCTAHEDRAL {
        s.normal = oct_decode(a.normal.xy);
    } else if GBUFFER_NORMAL_LAMBERT {
        s.normal = lambert_decode(a.normal.xy);
    } else {
        s.normal = safe_normalize(a.normal, vec3<f32>(0.0, 0.0, 1.0));
    }
    var position = a.position;
    var valid = a.position.z < 0.0;
    if GBUFFER_WORLD {
        s.normal = safe_normalize((camera.view_rotation * vec4<f32>(s.normal, 0.0)).xyz, vec3<f32>(0.0, 0.0, 1.0));
        position = -(camera.view_rotation * vec4<f32>(a.position, 0.0)).xyz;
        // Cleared to zero where no surface was drawn; a surface is in front of the eye.
        valid = position.z < 0.0;
    }
    s.emissive = a.emissive;
    if LS_PREPASS {
        // The light pre-pass's buffer has no reflectance: its light pass shades Blinn-Phong with
        // unit reflectance f0 = 1 (level (n + 8) / 8), and pass 3 multiplies in the material's.
        s.spec_level = (s.spec_exp + 8.0) / 8.0;
    }
    s.brdf = GBUFFER_BRDF;
    if GBUFFER_HAS_MATERIAL {
        s.brdf = u32(round(clamp(a.material, 0.0, 1.0) * 255.0));
    }
    s.layer = GBUFFER_LAYER;
    if GBUFFER_HAS_LAYER {
        s.layer = u32(round(clamp(a.layer, 0.0, 1.0) * 255.0)) & 31u;
    }
    if GBUFFER_HAS_DEPTH {
        s.depth = a.depth;
        s.valid = a.depth != camera.far_depth;
        s.position = view_position_from_depth(p, a.depth);
    } else {
        s.position = position;
        s.position_error = stored_position_error(position);
        s.valid = valid;
        s.depth = 0.0;
    }
    return s;
}

struct Lighting {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
};

// Smooth window that reaches exactly zero (with zero slope) at the radius.
fn distance_attenuation(d: f32, radius: f32) -> f32 {
    let x = d / radius;
    let w = clamp(1.0 - x * x, 0.0, 1.0);
    return w * w;
}

fn spot_attenuation(l: GpuLight, light_to_surface: vec3<f32>) -> f32 {
    if l.kind != LS_LIGHT_SPOT {
        return 1.0;
    }
    let c = dot(light_to_surface, l.direction);
    if l.cos_inner - l.cos_outer < 1e-6 {
        return select(0.0, 1.0, c >= l.cos_outer);
    }
    return smoothstep(l.cos_outer, l.cos_inner, c);
}

// Whether the surface point lies inside the light's true shape (radius and cone).
fn inside_light(s: Surface, l: GpuLight) -> bool {
    let v = s.position - l.position;
    let d = length(v);
    if !(d < l.radius) {
        return false;
    }
    if l.kind == LS_LIGHT_SPOT && d > 0.0 {
        return dot(v / d, l.direction) > l.cos_outer;
    }
    return true;
}

// The reflectance models (seed 002's material ID, `scene::Brdf`; mirrored by
// `reference::shade`). Diffuse is light before the albedo (compose multiplies it in), specular
// is light as it leaves the surface:
// - blinn-phong: diffuse N.L, specular N.L x the normalised lobe (N.H)^n x level, in white;
// - lambert: diffuse N.L only;
// - phong (seed 000's "standard Phong function"): diffuse N.L, specular (R.V)^n x level in
//   white, R = reflect(-L, N), no N.L on the highlight;
// - metal: no diffuse; the blinn-phong specular tinted by the albedo channel, which holds the
//   metal's specular colour F0 (`Material::metal_from_pbr`);
// - toon: diffuse N.L in three bands (ceil(3 N.L) / 3), specular the flat level where the
//   lobe exceeds half its peak;
// - unlit: nothing from lights (ambient gives it its base colour, `ambient_diffuse`).
// `color` is the light's colour x intensity, `att` its distance and spot attenuation.
fn brdf_light(s: Surface, L: vec3<f32>, ndl: f32, color: vec3<f32>, att: f32) -> Lighting {
    var r = brdf_light_view(s, view_dir(s), L, ndl, color, att);
    r.diffuse = select(r.diffuse, vec3<f32>(0.0), ndl <= 0.0);
    r.specular = select(r.specular, vec3<f32>(0.0), ndl <= 0.0);
    return r;
}

// The unit vector from view-space surface point `s` to the eye.
fn view_dir(s: Surface) -> vec3<f32> {
    return safe_normalize(-s.position, vec3<f32>(0.0, 0.0, 1.0));
}

// `brdf_light` for ndl > 0 with the view vector `V` given, so a loop over lights computes it
// once. Straight-line code: each model's terms are chosen with `select`, not branches, because
// lavapipe runs every branch of a fragment shader under a lane mask (the branchy form cost
// every pixel all the models' arithmetic). Each model's expression is the same, operation for
// operation, as the branchy form's, so for finite inputs the picture is unchanged (a term a
// model leaves out is colour x 0, so an infinite colour now gives NaN there, not 0).
fn brdf_light_view(s: Surface, V: vec3<f32>, L: vec3<f32>, ndl: f32, color: vec3<f32>, att: f32) -> Lighting {
    if LS_BRDF_BRANCH {
        return brdf_light_branch(s, V, L, ndl, color, att);
    }
    let H = safe_normalize(L + V, s.normal);
    let lobe = pow(max(dot(s.normal, H), 0.0), s.spec_exp);
    let toon = s.brdf == LS_BRDF_TOON;
    let metal = s.brdf == LS_BRDF_METAL;
    let lambert = s.brdf == LS_BRDF_LAMBERT;
    let unlit = s.brdf == LS_BRDF_UNLIT;
    let phong = s.brdf == LS_BRDF_PHONG;
    // Phong's lobe: the light mirrored about the normal, against the view.
    let phong_lobe = pow(max(dot(reflect(-L, s.normal), V), 0.0), s.spec_exp);
    // Diffuse: att x ndl (Blinn-Phong, Lambert), in three bands (toon), none (metal, unlit).
    var dw = select(att * ndl, att * (ceil(ndl * 3.0) / 3.0), toon);
    dw = select(dw, 0.0, metal || unlit);
    // Specular: att x ndl x lobe x level (Blinn-Phong, metal, tinted by the albedo below), the
    // level where the lobe passes 1/2 (toon), none (Lambert, unlit).
    var sw = select(att * ndl * (lobe * s.spec_level), att * select(0.0, s.spec_level, lobe >= 0.5), toon);
    sw = select(sw, att * (phong_lobe * s.spec_level), phong);
    sw = select(sw, 0.0, lambert || unlit);
    var r: Lighting;
    r.diffuse = color * dw;
    r.specular = select(color * sw, color * sw * s.albedo, metal);
    return r;
}

// The same terms as `brdf_light_view`, the model picked by branching on the material ID
// (LS_BRDF_BRANCH; seed 002: "store multiple BRDFs in light shader, choose per-pixel …
// reasonably coherent dynamic branching"): each model computes only its own terms, with the
// same arithmetic, so both give the same values.
fn brdf_light_branch(s: Surface, V: vec3<f32>, L: vec3<f32>, ndl: f32, color: vec3<f32>, att: f32) -> Lighting {
    var r: Lighting;
    if s.brdf == LS_BRDF_UNLIT {
        return r;
    }
    if s.brdf == LS_BRDF_LAMBERT {
        r.diffuse = color * (att * ndl);
        return r;
    }
    if s.brdf == LS_BRDF_PHONG {
        r.diffuse = color * (att * ndl);
        r.specular = color * (att * (pow(max(dot(reflect(-L, s.normal), V), 0.0), s.spec_exp) * s.spec_level));
        return r;
    }
    let H = safe_normalize(L + V, s.normal);
    let lobe = pow(max(dot(s.normal, H), 0.0), s.spec_exp);
    if s.brdf == LS_BRDF_TOON {
        r.diffuse = color * (att * (ceil(ndl * 3.0) / 3.0));
        r.specular = color * (att * select(0.0, s.spec_level, lobe >= 0.5));
        return r;
    }
    let sw = att * ndl * (lobe * s.spec_level);
    if s.brdf == LS_BRDF_METAL {
        r.specular = color * sw * s.albedo;
        return r;
    }
    r.diffuse = color * (att * ndl);
    r.specular = color * sw;
    return r;
}

// The diffuse light a uniform ambient A gives: A, none for a metal, and exactly 1 for an unlit
// surface (so compose's diffuse x albedo is its base colour; no light adds to it).
fn ambient_diffuse(s: Surface) -> vec3<f32> {
    if s.brdf == LS_BRDF_METAL {
        return vec3<f32>(0.0);
    }
    if s.brdf == LS_BRDF_UNLIT {
        return vec3<f32>(1.0);
    }
    return camera.ambient.rgb;
}

// The specular light a uniform ambient A reflects: the normalised Blinn-Phong lobe
// (level = f0 (n + 8) / 8) integrates over the hemisphere to f0, so the result is A f0 (the
// uniform-environment limit of image-based lighting; without it a metal, which has no diffuse
// term, is black away from its highlights), tinted by the specular colour for a metal; none
// for lambert and unlit. Mirrored by `reference::shade`.
fn ambient_specular(s: Surface) -> vec3<f32> {
    if s.brdf == LS_BRDF_LAMBERT || s.brdf == LS_BRDF_UNLIT {
        return vec3<f32>(0.0);
    }
    let a = camera.ambient.rgb * (s.spec_level * 8.0 / (s.spec_exp + 8.0));
    if s.brdf == LS_BRDF_METAL {
        return a * s.albedo;
    }
    return a;
}

// The most ambient + sun may add to a channel: `camera.light_clamp`, or 1 for an unlit
// surface, whose 1 is all the light it gets (no light adds to it, so it cannot overflow).
fn ambient_limit(s: Surface) -> vec3<f32> {
    if s.brdf == LS_BRDF_UNLIT {
        return vec3<f32>(max(camera.light_clamp, 1.0));
    }
    return vec3<f32>(camera.light_clamp);
}

// Light `i` as the per-pixel light loops read it: from the light planes
// (`records::light_planes`) when LS_LIGHT_PLANES, else from `lights`. On lavapipe a storage
// load at an index that varies by pixel is a loop over the lanes, one per scalar (about 17 a
// light); a uniform load is a gather. The planes leave out `tan_outer` and the cookie's fields:
// LS_LIGHT_PLANES is off when a light has a cookie, and the volumes' shapes read `lights`.
fn light_at(i: u32) -> GpuLight {
    if !LS_LIGHT_PLANES {
        return lights[i];
    }
    let a = light_plane0[i];
    let b = light_plane1[i];
    let c = light_plane2[i];
    let e = light_plane3[i];
    var l: GpuLight;
    l.position = bitcast<vec3<f32>>(a.xyz);
    l.radius = bitcast<f32>(a.w);
    l.color = bitcast<vec3<f32>>(b.xyz);
    l.clamp = bitcast<f32>(b.w);
    l.direction = bitcast<vec3<f32>>(c.xyz);
    l.cos_outer = bitcast<f32>(c.w);
    l.cos_inner = bitcast<f32>(e.x);
    l.falloff = bitcast<f32>(e.y);
    l.mask = e.z;
    l.kind = e.w & 15u;
    let first = e.w >> 8u;
    l.shadow = vec4<u32>(select(first, LS_NO_SHADOW, first == 0xffffffu), (e.w >> 4u) & 15u, 0u, 0u);
    l.cookie = LS_NO_COOKIE;
    return l;
}

// Seed 004's light culling mask: whether light `l` lights a surface on `layer` (0..31).
fn ls_light_reaches(l: GpuLight, layer: u32) -> bool {
    return (l.mask & (1u << (layer & 31u))) != 0u;
}

// Texel (x, y) of a cookie face starting at word `base`, clamped to the edge.
fn ls_cookie_texel(base: u32, size: u32, x: i32, y: i32) -> vec3<f32> {
    let n = i32(size) - 1;
    let i = base + u32(clamp(y, 0, n)) * size + u32(clamp(x, 0, n));
    return textureLoad(cookie_texels, vec2<u32>(i % LS_COOKIE_ROW, i / LS_COOKIE_ROW), 0).rgb;
}

// Bilinear sample of a cookie face at `uv` (texel centres at (k + 0.5) / size, clamp to
// edge): `CookieImage::sample` is its f64 twin.
fn ls_cookie_sample(base: u32, size: u32, uv: vec2<f32>) -> vec3<f32> {
    let s = f32(size);
    let t = clamp(uv * s - 0.5, vec2<f32>(-1.0), vec2<f32>(s));
    let i = floor(t);
    let f = t - i;
    let x = i32(i.x);
    let y = i32(i.y);
    let a = mix(ls_cookie_texel(base, size, x, y), ls_cookie_texel(base, size, x + 1, y), f.x);
    let b = mix(ls_cookie_texel(base, size, x, y + 1), ls_cookie_texel(base, size, x + 1, y + 1), f.x);
    return mix(a, b, f.y);
}

// Seed 004's cookie: the factor light `l` is filtered by at view-space point `p` (1 without
// a cookie). A spot projects its 2D cookie through its cone (`scene::cookie::spot_uv`); a
// point light its cube, addressed by the world-space direction from the light
// (`scene::cookie::cube_face_uv`, faces +X -X +Y -Y +Z -Z).
fn ls_cookie(l: GpuLight, p: vec3<f32>) -> vec3<f32> {
    if !LS_COOKIES || l.cookie == LS_NO_COOKIE {
        return vec3<f32>(1.0);
    }
    let v = p - l.position;
    if l.kind == LS_LIGHT_SPOT {
        let z = dot(v, l.direction);
        if !(z > 0.0) {
            return vec3<f32>(0.0);
        }
        let right = cross(l.direction, l.cookie_up);
        let k = 0.5 / (z * max(abs(l.tan_outer), 1e-6));
        let uv = vec2<f32>(dot(v, right) * k + 0.5, 0.5 - dot(v, l.cookie_up) * k);
        return ls_cookie_sample(l.cookie, l.cookie_size, uv);
    }
    let d = (transpose(camera.view_rotation) * vec4<f32>(v, 0.0)).xyz;
    let a = abs(d);
    var face = 0u;
    var ma = a.x;
    var sc = -d.z;
    var tc = -d.y;
    if a.x >= a.y && a.x >= a.z {
        if d.x < 0.0 {
            face = 1u;
            sc = d.z;
        }
    } else if a.y >= a.z {
        ma = a.y;
        sc = d.x;
        if d.y >= 0.0 {
            face = 2u;
            tc = d.z;
        } else {
            face = 3u;
            tc = -d.z;
        }
    } else {
        ma = a.z;
        if d.z >= 0.0 {
            face = 4u;
            sc = d.x;
        } else {
            face = 5u;
            sc = -d.x;
        }
    }
    ma = max(ma, 1e-30);
    let uv = vec2<f32>(0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0));
    return ls_cookie_sample(l.cookie + face * l.cookie_size * l.cookie_size, l.cookie_size, uv);
}

// One light at a surface point, in the pixel's reflectance model (`brdf_light`), attenuated
// smoothly to zero and by its shadow; diffuse and specular kept apart (seed 002). Every path
// that shades a light calls it, so each gets seed 004's culling mask (`ls_light_reaches`) and
// cookie (`ls_cookie`), and the shadow (`ls_shadow`).
fn shade_light(s: Surface, l: GpuLight) -> Lighting {
    return shade_light_as(s, l, true);
}

// `shade_light` with (`lookups`) or without the light's shadow lookup. Called with a literal,
// so the driver's inlining drops the lookup from the `false` call: the tiled and clustered
// passes shade the lights that cast no shadow this way (`LS_CASTERS_APART`).
fn shade_light_as(s: Surface, l: GpuLight, lookups: bool) -> Lighting {
    return shade_light_view(s, view_dir(s), l, lookups);
}

// `shade_light_as` with the view vector `V` given (`view_dir`), for loops over lights. Like
// `brdf_light_view`, straight-line: everything is computed and a light that does not reach
// the point (layer, radius, cone, back face, shadow) is zeroed at the end; on lavapipe the
// early returns cost as much and added mask work. A NaN attenuation, N.L or shadow factor
// now gives no light (the early returns let it through as NaN). The cookie lookup runs for
// every light the loop reaches, lit or not (scenes with cookies only).
fn shade_light_view(s: Surface, V: vec3<f32>, l: GpuLight, lookups: bool) -> Lighting {
    let to_light = l.position - s.position;
    let d = length(to_light);
    // A light exactly on the surface lights it head-on.
    let L = select(s.normal, to_light / d, d > 1e-6 * l.falloff);
    // Stochastic light culling (Tokuyoshi and Harada 2016): the light's range was drawn for the
    // frame so that it reaches distance d with probability min(1, a(d) / t), t =
    // camera.stochastic.x; where it reaches, max(a(d), t) keeps the expectation a(d). With t = 0
    // (off) this is a(d).
    let att = max(distance_attenuation(d, l.falloff), camera.stochastic.x) * spot_attenuation(l, -L);
    let ndl = max(dot(s.normal, L), 0.0);
    var lit = ls_light_reaches(l, s.layer) && d < l.radius && att > 0.0 && ndl > 0.0;
    var shadow = 1.0;
    if lookups {
        if lit {
            shadow = ls_shadow(l, s.position, s.normal, s.position_error);
        }
        lit = lit && shadow > 0.0;
    }
    var color = l.color;
    if LS_COOKIES && l.cookie != LS_NO_COOKIE {
        color = l.color * ls_cookie(l, s.position);
    }
    var r = brdf_light_view(s, V, L, ndl, color, att * shadow);
    r.diffuse = select(vec3<f32>(0.0), r.diffuse, lit);
    r.specular = select(vec3<f32>(0.0), r.specular, lit);
    return r;
}

// Seed 004's logarithmic Rgba8 accumulation (LS_ACCUM_LOG): a light is stored as exp2(-light)
// and blended multiplicatively, so the product encodes the sum; decoded with -log2. A stored 0
// (saturated) decodes to the top of the range, never infinity.
fn encode_light(v: vec3<f32>) -> vec4<f32> {
    if LS_ACCUM_LOG {
        return vec4<f32>(exp2(-max(v, vec3<f32>(0.0))), 1.0);
    }
    return vec4<f32>(v, 0.0);
}

// The light pre-pass's one light buffer (seeds 003/004): RGB diffuse, and in A the mono
// specular, the luminance of the specular light (seed 004: "monochrome specular lighting in A").
// Encoded as the accumulation is (fp16 additive, or seed 004's log encoding, all four channels).
// LS_LUMINANCE: Rec. 709 luma weights, generated from `scene::LUMINANCE`.

fn encode_light_buffer(diffuse: vec3<f32>, specular: vec3<f32>) -> vec4<f32> {
    let v = max(vec4<f32>(diffuse, dot(specular, LS_LUMINANCE)), vec4<f32>(0.0));
    if LS_ACCUM_LOG {
        return exp2(-v);
    }
    return v;
}

fn decode_light_buffer(v: vec4<f32>) -> vec4<f32> {
    if LS_ACCUM_LOG {
        return min(-log2(max(v, vec4<f32>(1.0 / 255.0))), vec4<f32>(LS_LOG_ACCUM_MAX));
    }
    return v;
}

fn decode_light(v: vec3<f32>) -> vec3<f32> {
    if LS_ACCUM_LOG {
        return min(-log2(max(v, vec3<f32>(1.0 / 255.0))), vec3<f32>(LS_LOG_ACCUM_MAX));
    }
    return v;
}

fn fullscreen_position(vi: u32) -> vec4<f32> {
    let x = f32((vi << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(vi & 2u) * 2.0 - 1.0;
    return vec4<f32>(x, y, 0.5, 1.0);
}
