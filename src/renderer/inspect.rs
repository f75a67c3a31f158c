//! Looking inside a frame: the values at one pixel (the viewer's hover probe) and the
//! screen-space wireframe of a light's bounding volume.

use super::records::{LightRecord, LIGHT_KIND_SPOT};
use super::volumes::{self, VolumeKind};
use crate::gpu::Gpu;
use crate::scene::{Brdf, Scene};
use anyhow::{bail, Context, Result};
use glam::{Vec2, Vec3};

/// What the G-buffer and the light buffers hold at one pixel of the last frame, decoded.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct PixelProbe {
    pub x: u32,
    pub y: u32,
    /// False where no geometry was drawn (background).
    pub valid: bool,
    pub albedo: Vec3,
    pub specular_level: f32,
    pub specular_exponent: f32,
    /// View-space normal.
    pub normal: Vec3,
    pub emissive: Vec3,
    /// View-space position.
    pub position: Vec3,
    pub diffuse_light: Vec3,
    pub specular_light: Vec3,
    /// diffuse x albedo + specular + emissive, linear, before tonemapping.
    pub lit: Vec3,
    /// Lights whose true shape contains the pixel's point.
    pub lights: Vec<usize>,
    /// Raw channel values per G-buffer target: (target name, format, RGBA).
    pub raw: Vec<(String, String, [f32; 4])>,
    /// The reflectance model: from the material ID channel, or the layout's one model.
    pub brdf: Brdf,
    /// The stored material ID when the layout has the channel (an unknown one is shaded as
    /// `blinn-phong`, as the shaders do).
    pub material_id: Option<u32>,
    /// The object's culling layer (seed 004): from the layer channel, or the layout's one layer.
    pub layer: u32,
}

fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Decodes one texel of the colour formats Lampshade renders to, as linear RGBA.
pub fn texel(format: wgpu::TextureFormat, bytes: &[u8]) -> Result<[f32; 4]> {
    use wgpu::TextureFormat as F;
    let mut out = [0.0f32; 4];
    match format {
        F::Rgba8Unorm | F::Rg8Unorm | F::R8Unorm => {
            bytes.iter().take(4).enumerate().for_each(|(i, b)| out[i] = *b as f32 / 255.0)
        }
        F::Bgra8Unorm => bytes.iter().take(4).enumerate().for_each(|(i, b)| out[[2, 1, 0, 3][i]] = *b as f32 / 255.0),
        F::Rgba8UnormSrgb => bytes.iter().take(4).enumerate().for_each(|(i, b)| {
            let v = *b as f32 / 255.0;
            out[i] = if i < 3 { srgb_to_linear(v) } else { v };
        }),
        F::Rgba16Unorm | F::Rg16Unorm | F::R16Unorm => {
            for (i, c) in bytes.chunks_exact(2).take(4).enumerate() {
                out[i] = u16::from_le_bytes([c[0], c[1]]) as f32 / 65535.0;
            }
        }
        F::Rgba16Float | F::Rg16Float | F::R16Float => {
            for (i, c) in bytes.chunks_exact(2).take(4).enumerate() {
                out[i] = half::f16::from_le_bytes([c[0], c[1]]).to_f32();
            }
        }
        F::Rg11b10Ufloat => {
            let v = u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
            // Unsigned small floats: 5-bit exponent, 6/6/5-bit mantissa.
            let small = |bits: u32, mantissa_bits: u32| {
                let m = bits & ((1 << mantissa_bits) - 1);
                let e = bits >> mantissa_bits;
                let scale = (1 << mantissa_bits) as f32;
                match e {
                    0 => m as f32 / scale * 2f32.powi(-14),
                    31 => {
                        if m == 0 {
                            f32::INFINITY
                        } else {
                            f32::NAN
                        }
                    }
                    e => (1.0 + m as f32 / scale) * 2f32.powi(e as i32 - 15),
                }
            };
            out = [small(v & 0x7ff, 6), small((v >> 11) & 0x7ff, 6), small(v >> 22, 5), 0.0];
        }
        // R32Uint is the depth copy holding a float's bits (`gbuffer::is_bits`): the same bytes.
        F::R32Float | F::Rg32Float | F::Rgba32Float | F::R32Uint | F::Depth32Float => {
            for (i, c) in bytes.chunks_exact(4).take(4).enumerate() {
                out[i] = f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
            }
        }
        other => bail!("cannot decode texels of {other:?}"),
    }
    Ok(out)
}

pub(crate) fn read_texel(gpu: &Gpu, texture: &wgpu::Texture, x: u32, y: u32) -> Result<[f32; 4]> {
    read_texel_aspect(gpu, texture, wgpu::TextureAspect::All, x, y)
}

/// Texel (`x`, `y`) of `aspect` of `texture` (a depth-stencil texture's depth: Depth32Float,
/// read whole: a copy out of a depth-stencil texture must cover the whole subresource).
pub(crate) fn read_texel_aspect(
    gpu: &Gpu,
    texture: &wgpu::Texture,
    aspect: wgpu::TextureAspect,
    x: u32,
    y: u32,
) -> Result<[f32; 4]> {
    let format = texture.format().aspect_specific_format(aspect).unwrap_or(texture.format());
    // A depth aspect comes back as f32 texels whatever its format (`Gpu::read_texture`).
    let format = if aspect == wgpu::TextureAspect::DepthOnly { wgpu::TextureFormat::Depth32Float } else { format };
    let bpp = format.block_copy_size(None).unwrap_or(16);
    if texture.format().is_depth_stencil_format() {
        let bytes = gpu.read_texture(texture, aspect)?;
        let at = ((y * texture.width() + x) * bpp) as usize;
        let texel_bytes = bytes.get(at..at + bpp as usize).context("the depth readback is short")?;
        return texel(format, texel_bytes);
    }
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probe"),
        size: 256,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo { texture, mip_level: 0, origin: wgpu::Origin3d { x, y, z: 0 }, aspect },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: None, rows_per_image: None },
        },
        wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
    );
    gpu.queue.submit([encoder.finish()]);
    let bytes = gpu.read_buffer(&buffer)?;
    texel(format, &bytes[..bpp as usize])
}

pub(crate) fn oct_decode(e: Vec2) -> Vec3 {
    let mut n = Vec3::new(e.x, e.y, 1.0 - e.x.abs() - e.y.abs());
    let t = (-n.z).clamp(0.0, 1.0);
    n.x += if n.x >= 0.0 { -t } else { t };
    n.y += if n.y >= 0.0 { -t } else { t };
    n.normalize_or(Vec3::Z)
}

/// As `lambert_decode` in `kit/common.wgsl`.
pub(crate) fn lambert_decode(e: Vec2) -> Vec3 {
    let g = 2.0 * e;
    let f = g.length_squared().min(4.0);
    (g * (1.0 - f / 4.0).sqrt()).extend(1.0 - f / 2.0).normalize_or(Vec3::Z)
}

/// Whether view-space point `p` lies inside the light's true shape (as `inside_light` in WGSL).
pub fn inside_light(l: &LightRecord, p: Vec3) -> bool {
    let v = p - Vec3::from(l.position);
    let d = v.length();
    if d >= l.radius {
        return false;
    }
    if l.kind == LIGHT_KIND_SPOT && d > 0.0 {
        return (v / d).dot(Vec3::from(l.direction)) > l.cos_outer;
    }
    true
}

/// Screen-space segments (pixels, origin top-left) of light `light`'s bounding volume as the
/// renderer draws it under `settings` (its cut-off and tessellation), for a `width`x`height`
/// view of `scene`. Edges behind the near plane are left out.
pub fn volume_wireframe_with(
    scene: &Scene,
    light: usize,
    width: u32,
    height: u32,
    settings: &super::Settings,
) -> Vec<[Vec2; 2]> {
    let Some(l) = scene.lights.get(light) else { return Vec::new() };
    if width == 0 || height == 0 || settings.validate().is_err() {
        return Vec::new();
    }
    let raw = LightRecord::in_view(&scene.camera, l, settings.light_cutoff);
    let mesh = match VolumeKind::of(&raw) {
        VolumeKind::Sphere => volumes::VolumeMesh::sphere(settings.sphere_subdivisions),
        VolumeKind::Cone => volumes::VolumeMesh::cone(settings.cone_sides),
    };
    let proj = scene.camera.projection(width as f64 / height as f64, false).as_mat4();
    let near = scene.camera.near as f32;
    let pts: Vec<Option<Vec2>> = mesh
        .vertices
        .iter()
        .map(|v| {
            let p = volumes::place_light(*v, &raw);
            if -p.z < near {
                return None;
            }
            let c = proj * p.extend(1.0);
            let n = Vec2::new(c.x, c.y) / c.w;
            Some(Vec2::new((n.x * 0.5 + 0.5) * width as f32, (0.5 - n.y * 0.5) * height as f32))
        })
        .collect();
    let mut edges = std::collections::BTreeSet::new();
    for tri in mesh.indices.chunks(3) {
        for (a, b) in [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])] {
            edges.insert((a.min(b), a.max(b)));
        }
    }
    edges.into_iter().filter_map(|(a, b)| Some([pts[a as usize]?, pts[b as usize]?])).collect()
}

/// Who a shadow-atlas tile belongs to (the viewer's atlas panel).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TileOwner {
    /// The sun; `AtlasTile::face` is the cascade.
    Sun,
    /// A spot shadowed by one perspective tile.
    Spot(usize),
    /// A point light (or a spot wider than `shadows::CUBE_SPOT_ANGLE`) shadowed by six cube
    /// faces; `AtlasTile::face` indexes `shadows::FACES` (+x, -x, +y, -y, +z, -z, view space).
    Cube(usize),
}

impl TileOwner {
    /// The light's index, `None` for the sun.
    pub fn light(self) -> Option<usize> {
        match self {
            TileOwner::Sun => None,
            TileOwner::Spot(i) | TileOwner::Cube(i) => Some(i),
        }
    }
}

/// One tile of the last frame's shadow atlas, as the viewer's panel shows it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct AtlasTile {
    pub owner: TileOwner,
    /// The sun's cascade or the cube face (0 for a spot).
    pub face: u32,
    /// The tile's texel rectangle in the atlas: corner and side.
    pub x: u32,
    pub y: u32,
    pub size: u32,
    /// World size of one texel: at the receiver for the sun's orthographic cascades, per unit
    /// of distance from the light for perspective tiles (spot, cube face).
    pub texel: f32,
    /// The tile is orthographic (the sun): `texel` does not grow with distance.
    pub orthographic: bool,
}
