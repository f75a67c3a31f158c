//! The pixel probe, the view-space positions, the light volumes' planes and the shadow atlas of the last frame.

use crate::gpu::Gpu;
use crate::renderer::frame::last::Last;
use crate::renderer::inspect::*;
use crate::renderer::kit::gbuffer::{Attr, GBufferTargets, NormalEncoding};
use crate::renderer::volumes::{self, VolumeKind};
use crate::scene::Brdf;
use anyhow::{bail, Result};
use glam::{DVec4, Vec2, Vec3};

impl<'a> Last<'a> {
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
        let (comps, raw) = read_channels(gpu, &t.gbuffer, x, y)?;
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
            if crate::renderer::kit::log_accum(t.diffuse.format()) {
                v.map(crate::renderer::settings::log_accum_decode)
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
        let exponent = 2f32.powf(get(Attr::SpecExp, 0, 0.0) * crate::renderer::kit::gbuffer::SPEC_EXP_LOG_RANGE);
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
                crate::renderer::kit::gbuffer::level_from_reflectance(get(Attr::SpecLevel, 0, 0.0), exponent)
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

/// A pixel's G-buffer channels by (attribute, component), decoded as `gbuffer_load` decodes
/// them (signed attributes remapped from normalised channels, packed channels unpacked, the
/// emission from its scale of the albedo).
type Channels = std::collections::HashMap<(Attr, u8), f32>;

/// A target's texel as read: (the target's name, its format, the value).
type RawTexel = (String, String, [f32; 4]);

/// Pixel (`x`, `y`)'s channels in `gbuffer`'s targets ([`Channels`]), and each target's raw
/// texel.
fn read_channels(gpu: &Gpu, gbuffer: &GBufferTargets, x: u32, y: u32) -> Result<(Channels, Vec<RawTexel>)> {
    let mut comps: Channels = Default::default();
    let mut raw = Vec::new();
    let layout = &gbuffer.layout;
    for (i, (desc, tex)) in layout.targets.iter().zip(&gbuffer.textures).enumerate() {
        let v = read_texel_aspect(gpu, tex, gbuffer.aspect(i), x, y)?;
        raw.push((desc.name.to_string(), format!("{:?}", desc.format), v));
        // Signed attributes are remapped in normalised channels only (as the WGSL does).
        let float = crate::renderer::kit::gbuffer::is_float(desc.format);
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
    Ok((comps, raw))
}

impl<'a> Last<'a> {
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
        if plan.params.sun[0] != crate::renderer::records::NO_SHADOW {
            claim(plan.params.sun[0], plan.params.sun[1], TileOwner::Sun);
        }
        for (i, &(first, count)) in plan.lights.iter().enumerate() {
            if first != crate::renderer::records::NO_SHADOW && count > 0 {
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
                    orthographic: t.info[0] == crate::renderer::shadows::TILE_ORTHOGRAPHIC,
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
            self.passes.build(&self.passes.atlas_view.declared(empty));
            let scratch = (self.frame, &self.scratch.atlas_view);
            self.passes.atlas_view.encode(self.device, self.queue, &mut encoder, scratch, target, side, empty);
            self.queue.submit([encoder.finish()]);
            self.scratch.atlas_view.read(gpu)
        })
    }
}
