//! Material textures on the GPU: upload with a mip chain, the 1x1 stand-ins for absent maps,
//! and one bind group per material.

use crate::scene::{Scene, Texture};
use wgpu::util::DeviceExt;

/// 1x1 textures that make an absent map a no-op: white for colour and metallic-roughness
/// (factors pass through), the flat normal (0.5, 0.5, 1) for normal maps.
pub struct DefaultTextures {
    white_srgb: wgpu::TextureView,
    white_linear: wgpu::TextureView,
    flat_normal: wgpu::TextureView,
    _textures: [wgpu::Texture; 3],
}

fn one_pixel(device: &wgpu::Device, queue: &wgpu::Queue, rgba: [u8; 4], format: wgpu::TextureFormat) -> wgpu::Texture {
    device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("default material texture"),
            size: wgpu::Extent3d { width: 1, height: 1, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &rgba,
    )
}

impl DefaultTextures {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        use wgpu::TextureFormat::{Rgba8Unorm, Rgba8UnormSrgb};
        let t = [
            one_pixel(device, queue, [255; 4], Rgba8UnormSrgb),
            one_pixel(device, queue, [255; 4], Rgba8Unorm),
            one_pixel(device, queue, [128, 128, 255, 255], Rgba8Unorm),
        ];
        let v = |i: usize| t[i].create_view(&Default::default());
        Self { white_srgb: v(0), white_linear: v(1), flat_normal: v(2), _textures: t }
    }
}

/// Number of mip levels down to 1x1.
pub fn mip_levels(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

/// Uploads a texture with its mip chain (box-filtered on the CPU by the `image` crate; sRGB
/// textures are filtered in their encoded values, which darkens high-contrast detail slightly in
/// the smallest levels).
pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue, t: &Texture) -> wgpu::Texture {
    let levels = mip_levels(t.width, t.height);
    let format = if t.srgb { wgpu::TextureFormat::Rgba8UnormSrgb } else { wgpu::TextureFormat::Rgba8Unorm };
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(&t.name),
        size: wgpu::Extent3d { width: t.width, height: t.height, depth_or_array_layers: 1 },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let write = |level: u32, w: u32, h: u32, data: &[u8]| {
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: level,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            data,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(4 * w), rows_per_image: Some(h) },
            wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        );
    };
    write(0, t.width, t.height, &t.rgba);
    let Some(mut image) = image::RgbaImage::from_raw(t.width, t.height, t.rgba.clone()) else {
        // `Scene::validate` checked the size; nothing more to upload.
        return texture;
    };
    for level in 1..levels {
        let (w, h) = ((t.width >> level).max(1), (t.height >> level).max(1));
        image = image::imageops::resize(&image, w, h, image::imageops::FilterType::Triangle);
        write(level, w, h, image.as_raw());
    }
    texture
}

/// One bind group per material: its four maps (or the stand-ins) and the sampler.
pub fn bind_groups(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    scene: &Scene,
    views: &[wgpu::TextureView],
    defaults: &DefaultTextures,
    sampler: &wgpu::Sampler,
) -> Vec<wgpu::BindGroup> {
    scene
        .materials
        .iter()
        .map(|m| {
            let pick = |k: Option<usize>, fallback: &'_ wgpu::TextureView| -> wgpu::TextureView {
                k.and_then(|k| views.get(k)).unwrap_or(fallback).clone()
            };
            let t = m.textures;
            let maps = [
                pick(t.base_color, &defaults.white_srgb),
                pick(t.normal, &defaults.flat_normal),
                pick(t.emissive, &defaults.white_srgb),
                pick(t.metallic_roughness, &defaults.white_linear),
            ];
            let lightmap = pick(m.lightmap.map(|l| l.texture), &defaults.white_linear);
            // In the order of `bindings::MATERIAL`: base colour, normal, emissive, metal-rough,
            // sampler, lightmap.
            let mut resources: Vec<wgpu::BindingResource<'_>> =
                maps.iter().map(wgpu::BindingResource::TextureView).collect();
            resources.push(wgpu::BindingResource::Sampler(sampler));
            resources.push(wgpu::BindingResource::TextureView(&lightmap));
            let entries = super::kit::bindings::MATERIAL.entries(resources);
            device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("material"), layout, entries: &entries })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #[test]
    fn mip_chain_ends_at_one_pixel() {
        assert_eq!(super::mip_levels(1, 1), 1);
        assert_eq!(super::mip_levels(256, 64), 9);
        assert_eq!(super::mip_levels(257, 3), 9);
    }
}
