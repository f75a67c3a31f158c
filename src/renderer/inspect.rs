//! Looking inside a frame: the values at one pixel (the viewer's hover probe) and the
//! screen-space wireframe of a light's bounding volume.

use super::kit::gbuffer::{Attr, NormalEncoding};
use super::records::{LightRecord, LIGHT_KIND_SPOT};
use super::volumes::{self, VolumeKind};
use super::Renderer;
use crate::gpu::Gpu;
use crate::scene::{Brdf, Scene};
use anyhow::{bail, Context, Result};
use glam::{DVec4, Vec2, Vec3};

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

fn read_texel(gpu: &Gpu, texture: &wgpu::Texture, x: u32, y: u32) -> Result<[f32; 4]> {
    read_texel_aspect(gpu, texture, wgpu::TextureAspect::All, x, y)
}

/// Texel (`x`, `y`) of `aspect` of `texture` (a depth-stencil texture's depth: Depth32Float,
/// read whole: a copy out of a depth-stencil texture must cover the whole subresource).
fn read_texel_aspect(
    gpu: &Gpu,
    texture: &wgpu::Texture,
    aspect: wgpu::TextureAspect,
    x: u32,
    y: u32,
) -> Result<[f32; 4]> {
    let format = texture.format().aspect_specific_format(aspect).unwrap_or(texture.format());
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

fn oct_decode(e: Vec2) -> Vec3 {
    let mut n = Vec3::new(e.x, e.y, 1.0 - e.x.abs() - e.y.abs());
    let t = (-n.z).clamp(0.0, 1.0);
    n.x += if n.x >= 0.0 { -t } else { t };
    n.y += if n.y >= 0.0 { -t } else { t };
    n.normalize_or(Vec3::Z)
}

/// As `lambert_decode` in `kit/common.wgsl`.
fn lambert_decode(e: Vec2) -> Vec3 {
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

impl Renderer {
    /// The view-space point of every pixel of the last frame (None for background), as the
    /// lighting shaders reconstruct it: from the depth copy, or the stored position.
    pub fn view_positions(&self, gpu: &Gpu) -> Result<Vec<Option<Vec3>>> {
        let Some(t) = &self.targets else { bail!("nothing rendered yet") };
        let layout = &t.gbuffer.layout;
        let find = |attr| layout.targets.iter().position(|d| d.channels.iter().flatten().any(|s| s.attr == attr));
        let far_depth = if self.passes.key().reversed_z { 0.0 } else { 1.0 };
        if let Some(i) = find(Attr::Depth) {
            let format = layout.targets[i].format;
            let bpp = format.block_copy_size(None).unwrap_or(4) as usize;
            let bytes = gpu.read_texture(&t.gbuffer.textures[i], t.gbuffer.aspect(i))?;
            let mut out = Vec::with_capacity(bytes.len() / bpp);
            let inv_proj = self.last.proj.inverse();
            for (k, c) in bytes.chunks_exact(bpp).enumerate() {
                let d = texel(format, c)?[0];
                let (x, y) = ((k as u32 % t.width) as f64, (k as u32 / t.width) as f64);
                out.push((d != far_depth).then(|| {
                    let ndc = DVec4::new(
                        (x + 0.5) / t.width as f64 * 2.0 - 1.0,
                        1.0 - (y + 0.5) / t.height as f64 * 2.0,
                        d as f64,
                        1.0,
                    );
                    let v = inv_proj * ndc;
                    (v.truncate() / v.w).as_vec3()
                }));
            }
            return Ok(out);
        }
        let Some(i) = find(Attr::Position) else { bail!("layout {} stores no position", layout.name) };
        let format = layout.targets[i].format;
        let bpp = format.block_copy_size(None).unwrap_or(8) as usize;
        let bytes = gpu.read_texture(&t.gbuffer.textures[i], t.gbuffer.aspect(i))?;
        bytes
            .chunks_exact(bpp)
            .map(|c| {
                let v = texel(format, c)?;
                Ok((v[2] < 0.0).then(|| Vec3::new(v[0], v[1], v[2])))
            })
            .collect()
    }

    /// The faces of light `i`'s bounding mesh in view space, as (point, outward normal) planes.
    pub fn volume_planes(&self, i: usize) -> Option<Vec<(Vec3, Vec3)>> {
        let raw = self.last.lights.get(i)?;
        let mesh = self.volumes.mesh(VolumeKind::of(raw));
        let pts: Vec<Vec3> = mesh.vertices.iter().map(|v| volumes::place_light(*v, raw)).collect();
        Some(
            mesh.indices
                .chunks(3)
                .map(|t| {
                    let [a, b, c] = [pts[t[0] as usize], pts[t[1] as usize], pts[t[2] as usize]];
                    (a, (b - a).cross(c - a).normalize_or_zero())
                })
                .collect(),
        )
    }

    /// Decodes pixel (`x`, `y`) of the last frame on the CPU, following the layout table.
    pub fn probe(&self, gpu: &Gpu, x: u32, y: u32) -> Result<PixelProbe> {
        let Some(t) = &self.targets else { bail!("nothing rendered yet") };
        self.last.gbuffer("pixel to probe")?;
        if x >= t.width || y >= t.height {
            bail!("pixel ({x}, {y}) is outside the {}x{} frame", t.width, t.height);
        }
        let layout = &t.gbuffer.layout;
        let mut comps: std::collections::HashMap<(Attr, u8), f32> = Default::default();
        let mut raw = Vec::new();
        for (i, (desc, tex)) in layout.targets.iter().zip(&t.gbuffer.textures).enumerate() {
            let v = read_texel_aspect(gpu, tex, t.gbuffer.aspect(i), x, y)?;
            raw.push((desc.name.to_string(), format!("{:?}", desc.format), v));
            // Signed attributes are remapped in normalised channels only (as the WGSL does).
            let float = super::kit::gbuffer::is_float(desc.format);
            for (c, slot) in desc.channels.iter().enumerate() {
                if let Some(s) = slot {
                    let val = if s.attr.signed() && !float { v[c] * 2.0 - 1.0 } else { v[c] };
                    // Packed channels, as `gbuffer_load` unpacks them.
                    match s.attr {
                        Attr::MaterialExp => {
                            comps.insert((Attr::Material, 0), val.floor() / 255.0);
                            comps.insert((Attr::SpecExp, 0), val.fract() * (256.0 / 255.0));
                        }
                        _ => {
                            comps.insert((s.attr, s.comp), val);
                        }
                    }
                }
            }
        }
        if let Some(&e) = comps.get(&(Attr::EmissiveScale, 0)) {
            for c in 0..3 {
                let a = comps.get(&(Attr::Albedo, c)).copied().unwrap_or(0.0);
                comps.insert((Attr::Emissive, c), e * a);
            }
        }
        let get = |a: Attr, c: u8, default: f32| comps.get(&(a, c)).copied().unwrap_or(default);
        let v3 = |a: Attr| Vec3::new(get(a, 0, 0.0), get(a, 1, 0.0), get(a, 2, 0.0));
        let normal = match layout.normal {
            NormalEncoding::Octahedral => oct_decode(Vec2::new(get(Attr::Normal, 0, 0.0), get(Attr::Normal, 1, 0.0))),
            NormalEncoding::Lambert => lambert_decode(Vec2::new(get(Attr::Normal, 0, 0.0), get(Attr::Normal, 1, 0.0))),
            NormalEncoding::Xyz => v3(Attr::Normal).normalize_or(Vec3::Z),
        };
        // World-space layouts (seed 000) store the normal and the view vector (surface to eye)
        // in world space, as `surface_of` turns them back.
        let rot = self.last.view_rotation.as_mat3();
        let normal = if layout.world { (rot * normal).normalize_or(Vec3::Z) } else { normal };
        let far_depth = if self.passes.key().reversed_z { 0.0 } else { 1.0 };
        let (position, valid) = if layout.has(Attr::Depth) {
            let d = get(Attr::Depth, 0, far_depth);
            let ndc = DVec4::new(
                (x as f64 + 0.5) / t.width as f64 * 2.0 - 1.0,
                1.0 - (y as f64 + 0.5) / t.height as f64 * 2.0,
                d as f64,
                1.0,
            );
            let v = self.last.proj.inverse() * ndc;
            ((v.truncate() / v.w).as_vec3(), d != far_depth)
        } else {
            let p = if layout.world { -(rot * v3(Attr::Position)) } else { v3(Attr::Position) };
            (p, p.z < 0.0)
        };
        let decode = |v: [f32; 4]| {
            if super::kit::log_accum(t.diffuse.format()) {
                v.map(super::settings::log_accum_decode)
            } else {
                v
            }
        };
        let diffuse = decode(read_texel(gpu, &t.diffuse, x, y)?);
        // The light pre-pass has one light buffer (its `specular` target is a 1x1 stand-in):
        // the mono specular (A) as grey.
        // Seed 000's one RT1 holds all light (`diffuse_light`, the lit colour).
        let specular = if t.prepass {
            [diffuse[3]; 4]
        } else if t.one_target {
            [0.0; 4]
        } else {
            decode(read_texel(gpu, &t.specular, x, y)?)
        };
        let diffuse_light = Vec3::new(diffuse[0], diffuse[1], diffuse[2]);
        let specular_light = Vec3::new(specular[0], specular[1], specular[2]);
        let albedo = v3(Attr::Albedo);
        let exponent = 2f32.powf(get(Attr::SpecExp, 0, 0.0) * super::kit::gbuffer::SPEC_EXP_LOG_RANGE);
        let emissive = v3(Attr::Emissive);
        // As `surface_of` decodes it.
        let material_id =
            layout.has(Attr::Material).then(|| (get(Attr::Material, 0, 0.0).clamp(0.0, 1.0) * 255.0).round() as u32);
        let brdf = match material_id {
            Some(id) => Brdf::ALL.into_iter().find(|b| b.id() == id).unwrap_or_default(),
            None => layout.uniform_brdf.unwrap_or_default(),
        };
        // As `surface_of` decodes it.
        let layer = match layout.uniform_layer {
            Some(l) => l,
            None => ((get(Attr::Layer, 0, 0.0).clamp(0.0, 1.0) * 255.0).round() as u32) & 31,
        };
        let lights = if valid {
            self.last.lights.iter().enumerate().filter(|(_, l)| inside_light(l, position)).map(|(i, _)| i).collect()
        } else {
            Vec::new()
        };
        Ok(PixelProbe {
            x,
            y,
            valid,
            albedo,
            specular_level: if layout.spec_level_raw() {
                get(Attr::SpecLevel, 0, 0.0)
            } else {
                super::kit::gbuffer::level_from_reflectance(get(Attr::SpecLevel, 0, 0.0), exponent)
            },
            specular_exponent: exponent,
            normal,
            emissive,
            position,
            diffuse_light,
            specular_light,
            // The light pre-pass's lit colour is pass 3's (its buffer holds no albedo).
            lit: match (&t.hdr_texture, valid) {
                (_, false) => Vec3::ZERO,
                (Some(hdr), true) if t.prepass => Vec3::from_slice(&read_texel(gpu, hdr, x, y)?[..3]),
                (_, true) if t.one_target => diffuse_light,
                _ => diffuse_light * albedo + specular_light + emissive,
            },
            lights,
            raw,
            brdf,
            material_id,
            layer,
        })
    }
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

impl Renderer {
    /// The last frame's shadow-atlas tiles with their owners, in the plan's tile
    /// order, and the atlas's side in texels. Lights that cast elsewhere (not in the atlas)
    /// have no tile here.
    pub fn shadow_atlas_tiles(&self) -> (u32, Vec<AtlasTile>) {
        let plan = &self.last.shadows;
        let mut owner: Vec<Option<(TileOwner, u32)>> = vec![None; plan.tiles.len()];
        let mut claim = |first: u32, count: u32, o: TileOwner| {
            for k in 0..count {
                if let Some(slot) = owner.get_mut(first.saturating_add(k) as usize) {
                    *slot = Some((o, k));
                }
            }
        };
        if plan.params.sun[0] != super::records::NO_SHADOW {
            claim(plan.params.sun[0], plan.params.sun[1], TileOwner::Sun);
        }
        for (i, &(first, count)) in plan.lights.iter().enumerate() {
            if first != super::records::NO_SHADOW && count > 0 {
                claim(first, count, if count == 1 { TileOwner::Spot(i) } else { TileOwner::Cube(i) });
            }
        }
        // Faces in the cube array (`--shadow-cube array`) are not in the atlas: left out, so
        // their lights show as shadowed outside it.
        let tiles = plan
            .draws
            .iter()
            .filter(|d| d.layer.is_none())
            .filter_map(|d| {
                let (o, face) = owner.get(d.tile as usize).copied().flatten()?;
                let t = plan.tiles.get(d.tile as usize)?;
                Some(AtlasTile {
                    owner: o,
                    face,
                    x: d.x,
                    y: d.y,
                    size: d.size,
                    texel: t.info[1],
                    orthographic: t.info[0] == super::shadows::TILE_ORTHOGRAPHIC,
                })
            })
            .collect();
        (plan.side, tiles)
    }

    /// Draws the last frame's shadow atlas into `target` (the output format, `side` pixels
    /// square; `shadows::atlas_view`): each pixel the atlas texel under it, the stored linear
    /// depth stretched over the range present, near white, far black; texels nothing was cast
    /// into dark blue. Returns that range (least, greatest stored depth, as fractions of each
    /// tile's far distance), `None` when no texel was drawn.
    pub fn draw_shadow_atlas(&self, gpu: &Gpu, target: &wgpu::TextureView, side: u32) -> Result<Option<(f32, f32)>> {
        if side == 0 {
            bail!("cannot draw the shadow atlas into a 0-pixel image");
        }
        self.passes.atlas_view.prepare()?;
        crate::renderer::scoped(&self.device, || {
            let mut encoder =
                self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("atlas view") });
            let empty = self.last.shadows.draws.is_empty();
            let scratch = (&self.frame, &self.scratch.atlas_view);
            self.passes.atlas_view.encode(&self.device, &self.queue, &mut encoder, scratch, target, side, empty);
            self.queue.submit([encoder.finish()]);
            self.scratch.atlas_view.read(gpu)
        })
    }
}
