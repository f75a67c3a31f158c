// The viewer's shadow-atlas panel (`shadows::atlas_view`): the last frame's shadow
// atlas (any depth format, linear depth -z / far per tile, cleared to 1.0) as a grey image, its
// depth stretched over the range actually present.
//
// 1. `cs_atlas_range` finds the least and greatest stored depth below the clear value (1.0):
//    each invocation reads an ATLAS_BLOCK x ATLAS_BLOCK block, a workgroup folds its blocks
//    with workgroup atomics, then one global atomicMin/atomicMax per workgroup. Depths are
//    non-negative floats, whose bit patterns order as the floats do, so u32 atomics compare
//    them exactly.
// 2. `fs_atlas_view` draws each image pixel from the atlas texel under it (point sampled):
//    near white, far black over [least, greatest]; texels at the clear value (nothing cast
//    there) dark blue.

const ATLAS_BLOCK: u32 = 4u;
const ATLAS_EMPTY: vec3<f32> = vec3<f32>(0.02, 0.03, 0.10);

var<workgroup> atlas_wg_lo: atomic<u32>;
var<workgroup> atlas_wg_hi: atomic<u32>;

@compute @workgroup_size(8, 8)
fn cs_atlas_range(@builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    if li == 0u {
        atomicStore(&atlas_wg_lo, 0xffffffffu);
        atomicStore(&atlas_wg_hi, 0u);
    }
    workgroupBarrier();
    let size = textureDimensions(shadow_atlas);
    var lo = 0xffffffffu;
    var hi = 0u;
    for (var dy = 0u; dy < ATLAS_BLOCK; dy++) {
        for (var dx = 0u; dx < ATLAS_BLOCK; dx++) {
            let p = id.xy * ATLAS_BLOCK + vec2<u32>(dx, dy);
            if p.x < size.x && p.y < size.y {
                let d = textureLoad(shadow_atlas, vec2<i32>(p), 0);
                if d < 1.0 {
                    let b = bitcast<u32>(max(d, 0.0));
                    lo = min(lo, b);
                    hi = max(hi, b);
                }
            }
        }
    }
    if hi >= lo {
        atomicMin(&atlas_wg_lo, lo);
        atomicMax(&atlas_wg_hi, hi);
    }
    workgroupBarrier();
    if li == 0u {
        let wlo = atomicLoad(&atlas_wg_lo);
        let whi = atomicLoad(&atlas_wg_hi);
        if whi >= wlo {
            atomicMin(&atlas_range[0], wlo);
            atomicMax(&atlas_range[1], whi);
        }
    }
}

@fragment
fn fs_atlas_view(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let size = textureDimensions(shadow_atlas);
    let side = max(atomicLoad(&atlas_range[2]), 1u);
    let t = min(vec2<u32>(floor(frag.xy * f32(size.x) / f32(side))), size - vec2<u32>(1u));
    let d = textureLoad(shadow_atlas, vec2<i32>(t), 0);
    if d >= 1.0 {
        return vec4<f32>(ATLAS_EMPTY, 1.0);
    }
    let lo = bitcast<f32>(atomicLoad(&atlas_range[0]));
    let hi = bitcast<f32>(atomicLoad(&atlas_range[1]));
    let v = select(0.5, clamp((d - lo) / (hi - lo), 0.0, 1.0), hi > lo);
    // The target is sRGB: the grey is given linear, so near (v = 0) shows white and the bytes
    // step evenly in perceived brightness from near to far.
    let g = pow(1.0 - v, 2.2);
    return vec4<f32>(g, g, g, 1.0);
}
