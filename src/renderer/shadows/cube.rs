//! Seed 002's unrolled cube: the indirection cube that maps a direction to its face's tile
//! (its side, its texels in 16-bit fixed point, their decoding and error).

/// The indirection cube's side for an atlas of `side` texels: the largest tile a cube face can
/// be granted (a quarter of the side), at most [`MAX_INDIRECTION`], at least [`MIN_TILE`].
pub fn indirection_side(side: u32) -> u32 {
    (side / 4).clamp(MIN_TILE, MAX_INDIRECTION)
}

/// The largest indirection cube: 1024² x 6 texels of 4 bytes, 24 MiB.
pub const MAX_INDIRECTION: u32 = 1024;

/// How far (in texels of the face's tile, along each axis) the indirection's lookup point may
/// lie from the face pick's, for a face tile whose frustum spans `inner` texels and an
/// indirection cube of side `n`. Sampled nearest, the texel read is the one holding the
/// direction, whose centre's face coordinate is within half a texel (1 / 2n of the face) of
/// the direction's, plus the hardware's rounding of the texel coordinate (Vulkan guarantees
/// `subTexelPrecisionBits` >= 4: 1/16 texel); the face coordinate is then stored as
/// (face + u) / 6 in 16 bits, read back within 1/2 of 1/65535, so u within 3/65535 (v within
/// 1/2 of that). A face coordinate error du is du x inner texels of the tile.
/// Bilinear filtering would be exact inside a face ("free bilinear filtering" in the seed,
/// written for Direct3D 9's cube maps, which clamp at face edges), but Vulkan, Direct3D 11+ and
/// Metal filter cube maps across face edges (seamless), blending two faces' coordinates in
/// the band half a texel wide along every edge, so it is sampled nearest.
pub fn indirection_error(inner: f64, n: u32) -> f64 {
    inner * ((0.5 + 1.0 / 16.0) / n as f64 + 3.0 / 65535.0)
}

/// The indirection cube's texels, layer by layer (+x, -x, +y, -y, +z, -z: the cube-map face
/// order, [`FACES`]), row by row, 4 bytes each: the face's 16-bit (face + u) / 6 and 16-bit v at
/// the texel's centre (u = (i + 1/2) / n, v = (j + 1/2) / n: the face coordinates of the
/// cube-map face selection table, [`cube_face_space`]), each split high byte first into two
/// channels of an Rgba8Unorm texel. The bits of seed 002's G16R16, in a format every adapter
/// samples (Rg16Unorm needs the native-only `TEXTURE_FORMAT_16BIT_NORM`); nearest sampling
/// returns them exactly.
pub fn indirection_texels(n: u32) -> Vec<u8> {
    let unorm16 = |x: f64| (x * 65535.0).round().clamp(0.0, 65535.0) as u16;
    let mut out = Vec::with_capacity(6 * 4 * n as usize * n as usize);
    for face in 0..6u32 {
        for j in 0..n {
            let v = unorm16((j as f64 + 0.5) / n as f64);
            for i in 0..n {
                let r = unorm16((face as f64 + (i as f64 + 0.5) / n as f64) / 6.0);
                out.extend_from_slice(&[(r >> 8) as u8, r as u8, (v >> 8) as u8, v as u8]);
            }
        }
    }
    out
}

/// Decodes an indirection texel (`indirection_texels`) into (face, u, v), as the shader does.
pub fn indirection_decode(t: [u8; 4]) -> (u32, f64, f64) {
    let r = (t[0] as u32 * 256 + t[1] as u32) as f64 / 65535.0;
    let v = (t[2] as u32 * 256 + t[3] as u32) as f64 / 65535.0;
    let f = ((r * 6.0).floor() as u32).min(5);
    (f, r * 6.0 - f as f64, v)
}

/// Smallest tile side in texels.
pub const MIN_TILE: u32 = 32;
