//! The size-dependent render targets: G-buffer, depth-stencil, light accumulation, the debug
//! target, the HDR scene colour (scenes with blended surfaces only), and their bind groups.

use super::kit::bindings;
use super::kit::gbuffer::GBufferTargets;
use crate::renderer::kit::{texture, texture_2d, Shared, DEBUG_FORMAT, HDR_FORMAT};

pub struct Targets {
    pub width: u32,
    pub height: u32,
    pub depth_format: wgpu::TextureFormat,
    pub gbuffer: GBufferTargets,
    pub depth: wgpu::TextureView,
    pub diffuse: wgpu::Texture,
    pub specular: wgpu::Texture,
    pub diffuse_view: wgpu::TextureView,
    pub specular_view: wgpu::TextureView,
    pub debug_view: wgpu::TextureView,
    pub debug_texture: wgpu::Texture,
    /// The G-buffer as the lighting passes read it (group 1).
    pub gbuffer_group: wgpu::BindGroup,
    /// Accumulation, debug target and compose parameters (group 2).
    pub compose_group: wgpu::BindGroup,
    /// HDR scene colour and its bind group (group 3); only for scenes with blended surfaces.
    pub hdr: Option<(wgpu::TextureView, wgpu::BindGroup)>,
    pub hdr_texture: Option<wgpu::Texture>,
    /// The post chain's images and buffers (frames that run it only; `post::chain_active`).
    pub post: Option<super::post::PostTargets>,
    /// The light pre-pass's configuration: `diffuse` is its one light buffer (RGB diffuse, mono
    /// specular in A) and `specular` a 1x1 stand-in the compose group binds, never attached.
    pub prepass: bool,
    /// One accumulation target (`PipelineKey::one_target`): the pre-pass's light buffer or
    /// seed 000's RT1; `specular` is then the 1x1 stand-in.
    pub one_target: bool,
    /// The light pre-pass's multisampled pass 3 (`--msaa 4`): its colour and depth samples.
    pub msaa: Option<MsaaTargets>,
    /// Depth peeling's depth buffers and layers (`BlendedMode::Peeled` frames with an HDR colour).
    pub peel: Option<crate::renderer::surfaces::peel::PeelTargets>,
}

/// Multisampled HDR colour and depth-stencil (the light pre-pass's pass 3 and forward pass),
/// resolved into the single-sample HDR colour.
pub struct MsaaTargets {
    pub color: wgpu::TextureView,
    pub depth: wgpu::TextureView,
    pub samples: u32,
}

impl MsaaTargets {
    fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        depth: wgpu::TextureFormat,
        size: (u32, u32),
        samples: u32,
    ) -> Self {
        let make = |label, format| {
            texture_2d(device, label, (format, &[]), size, samples, wgpu::TextureUsages::RENDER_ATTACHMENT)
                .create_view(&Default::default())
        };
        Self { color: make("hdr colour (multisampled)", format), depth: make("depth (multisampled)", depth), samples }
    }

    /// The multisampled colour, cleared or loaded, resolved into `resolve`.
    pub fn color_attachment<'a>(
        &'a self,
        resolve: &'a wgpu::TextureView,
        clear: Option<wgpu::Color>,
    ) -> Option<wgpu::RenderPassColorAttachment<'a>> {
        Some(wgpu::RenderPassColorAttachment {
            view: &self.color,
            depth_slice: None,
            resolve_target: Some(resolve),
            ops: wgpu::Operations {
                load: clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear),
                store: wgpu::StoreOp::Store,
            },
        })
    }
}

impl Targets {
    pub fn new(
        device: &wgpu::Device,
        shared: &Shared,
        size: (u32, u32),
        hdr: bool,
        post: bool,
        compose_params: &wgpu::Buffer,
    ) -> Self {
        use wgpu::TextureUsages as U;
        let key = &shared.key;
        // Depth peeling reads the opaque depth in its layer passes; a layout that reads the
        // depth buffer instead of a copy binds it as a G-buffer target (read back like one).
        let depth_usage = if key.layout.reads_depth_buffer() {
            U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC
        } else if key.peeled_blended {
            U::RENDER_ATTACHMENT | U::TEXTURE_BINDING
        } else {
            U::RENDER_ATTACHMENT
        };
        let depth_texture = texture(device, "depth-stencil", key.depth_format, size, depth_usage);
        let depth = depth_texture.create_view(&Default::default());
        let gbuffer = GBufferTargets::new(device, &key.layout, size.0, size.1, &depth_texture);
        let read = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC;
        let diffuse = texture(device, "light diffuse", key.accum_format, size, read);
        let specular_size = if key.one_target() { (1, 1) } else { size };
        let specular = texture(device, "light specular", key.accum_format, specular_size, read);
        let debug = texture(device, "debug", DEBUG_FORMAT, size, read);
        let diffuse_view = diffuse.create_view(&Default::default());
        let specular_view = specular.create_view(&Default::default());
        let debug_view = debug.create_view(&Default::default());
        let gbuffer_group = gbuffer.bind_group(device, &shared.gbuffer_bgl);
        let compose_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("compose"),
            layout: &shared.compose_bgl,
            entries: &bindings::COMPOSE.entries(vec![
                wgpu::BindingResource::TextureView(&diffuse_view),
                wgpu::BindingResource::TextureView(&specular_view),
                wgpu::BindingResource::TextureView(&debug_view),
                wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: compose_params,
                    offset: 0,
                    size: wgpu::BufferSize::new(bindings::COMPOSE_PARAMS_SIZE),
                }),
            ]),
        });
        // Only scenes with blended surfaces need the HDR scene colour (model what the scene needs).
        let hdr_texture = (hdr || post).then(|| texture(device, "hdr colour", HDR_FORMAT, size, read));
        let hdr = hdr_texture.as_ref().map(|t| {
            let view = t.create_view(&Default::default());
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("hdr colour"),
                layout: &shared.hdr_bgl,
                entries: &bindings::HDR.entries(vec![wgpu::BindingResource::TextureView(&view)]),
            });
            (view, group)
        });
        let post =
            hdr.as_ref().filter(|_| post).map(|(view, _)| super::post::PostTargets::new(device, shared, size, view));
        let peel = (hdr.is_some() && key.peeled_blended)
            .then(|| crate::renderer::surfaces::peel::PeelTargets::new(device, shared, &depth_texture, size));
        let msaa = (hdr.is_some() && key.samples > 1)
            .then(|| MsaaTargets::new(device, HDR_FORMAT, key.depth_format, size, key.samples));
        Self {
            width: size.0,
            height: size.1,
            depth_format: key.depth_format,
            gbuffer,
            depth,
            diffuse,
            specular,
            diffuse_view,
            specular_view,
            debug_view,
            debug_texture: debug.clone(),
            gbuffer_group,
            compose_group,
            hdr,
            hdr_texture,
            post,
            prepass: key.prepass,
            one_target: key.one_target(),
            msaa,
            peel,
        }
    }

    /// Whether these targets serve a frame of `size` drawn with `shared`'s configuration.
    pub fn fit(&self, shared: &Shared, size: (u32, u32), hdr: bool, post: bool) -> bool {
        (self.width, self.height) == size
            && self.depth_format == shared.key.depth_format
            && self.gbuffer.layout == shared.key.layout
            && self.diffuse.format() == shared.key.accum_format
            && self.hdr.is_some() == (hdr || post)
            && self.post.is_some() == post
            && self.prepass == shared.key.prepass
            && self.one_target == shared.key.one_target()
            && self.peel.is_some() == (shared.key.peeled_blended && (hdr || post))
    }

    /// The depth-stencil buffer as the G-buffer pass left its depth; the stencil cleared to zero
    /// or kept. Read-only, depth and stencil, where the G-buffer reads the depth buffer
    /// (`GBufferLayout::reads_depth_buffer`): the passes that attach it here also bind it for
    /// reading, and no pipeline of a frame that allows it writes either.
    pub fn depth_attachment(&self, clear_stencil: bool) -> wgpu::RenderPassDepthStencilAttachment<'_> {
        if self.gbuffer.layout.reads_depth_buffer() {
            return wgpu::RenderPassDepthStencilAttachment { view: &self.depth, depth_ops: None, stencil_ops: None };
        }
        let store = wgpu::StoreOp::Store;
        wgpu::RenderPassDepthStencilAttachment {
            view: &self.depth,
            depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store }),
            stencil_ops: Some(wgpu::Operations {
                load: if clear_stencil { wgpu::LoadOp::Clear(0) } else { wgpu::LoadOp::Load },
                store,
            }),
        }
    }

    /// The diffuse and specular accumulation as colour attachments, loaded or cleared.
    pub fn accumulation(&self, clear: bool) -> [Option<wgpu::RenderPassColorAttachment<'_>>; 2] {
        // Cleared to no light: 0, or exp2(-0) = 1 in seed 004's logarithmic encoding.
        let none =
            if super::kit::log_accum(self.diffuse.format()) { wgpu::Color::WHITE } else { wgpu::Color::TRANSPARENT };
        let ops = wgpu::Operations {
            load: if clear { wgpu::LoadOp::Clear(none) } else { wgpu::LoadOp::Load },
            store: wgpu::StoreOp::Store,
        };
        let one = self.one_target;
        // The light pre-pass's one light buffer and seed 000's one RT1: no second target.
        [Some(&self.diffuse_view), Some(&self.specular_view).filter(|_| !one)].map(|v| {
            v.map(|view| wgpu::RenderPassColorAttachment { view, depth_slice: None, resolve_target: None, ops })
        })
    }
}

/// One colour attachment, cleared to `clear` or loaded.
pub fn attachment(view: &wgpu::TextureView, clear: Option<wgpu::Color>) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear),
            store: wgpu::StoreOp::Store,
        },
    })
}
