//! The depth-peeling targets of blended surfaces (allocated per size).

use crate::renderer::kit::{bindings, texture, Shared, HDR_FORMAT};

/// The format the peeled layers are composited in.
pub(crate) const PEELED_FORMAT: wgpu::TextureFormat = HDR_FORMAT;

/// The layers' depth: 32-bit float whatever the frame's depth format, so that a fragment's depth
/// as stored is its depth as shaded, and `fs_peel_depth`'s "behind the previous layer" never
/// takes a layer again (a 24-bit buffer rounds it). The opaque depth is compared as stored:
/// with 24-bit depth, a blended fragment within one 24-bit step in front of an opaque surface
/// may be hidden where the hardware test, rounding it first, would keep it.
pub(crate) const PEEL_DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Depth peeling's size-dependent targets (`Targets::peel`): two depth buffers the layers
/// alternate between (one written, the other read as the previous layer), the layers'
/// composite, and the bind groups reading them.
pub struct PeelTargets {
    /// Attachment and sampled (depth aspect) views of each depth buffer.
    pub(crate) depth: [(wgpu::TextureView, wgpu::TextureView); 2],
    pub(crate) peeled: wgpu::TextureView,
    /// Group 2 of layer k is `groups[k % 2]`: the opaque depth and depth buffer `(k + 1) % 2`.
    pub(crate) groups: [wgpu::BindGroup; 2],
    pub(crate) peeled_group: wgpu::BindGroup,
}

impl PeelTargets {
    /// `opaque`: the frame's depth buffer (made with `TEXTURE_BINDING` when peeling).
    pub fn new(device: &wgpu::Device, shared: &Shared, opaque: &wgpu::Texture, size: (u32, u32)) -> Self {
        use wgpu::TextureUsages as U;
        let depth_only = wgpu::TextureViewDescriptor { aspect: wgpu::TextureAspect::DepthOnly, ..Default::default() };
        let usage = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING;
        let depth = [0, 1].map(|_| {
            let t = texture(device, "peel depth", PEEL_DEPTH, size, usage);
            (t.create_view(&Default::default()), t.create_view(&depth_only))
        });
        let peeled = texture(device, "peeled layers", PEELED_FORMAT, size, usage).create_view(&Default::default());
        let opaque = opaque.create_view(&depth_only);
        let groups = [1, 0].map(|previous| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("peel"),
                layout: &shared.peel_bgl,
                entries: &bindings::PEEL.entries(vec![
                    wgpu::BindingResource::TextureView(&opaque),
                    wgpu::BindingResource::TextureView(&depth[previous].1),
                ]),
            })
        });
        let peeled_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("peeled layers"),
            layout: &shared.peeled_bgl,
            entries: &bindings::PEELED.entries(vec![wgpu::BindingResource::TextureView(&peeled)]),
        });
        Self { depth, peeled, groups, peeled_group }
    }
}
