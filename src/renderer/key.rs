//! The pipeline configuration a frame's settings ask for (`PipelineKey`), or why the adapter
//! cannot give it: asks only the capability table, so `support` answers without a device.

use super::kit::adapter::AdapterCaps;
use super::kit::{self, gbuffer, PipelineKey};
use super::options::culling::CullingMode as M;
use super::options::{BlendedMode, DebugView, DepthRead, Msaa, RenderPath};
use super::settings::Settings;
use super::{post, program};
use crate::scene::Scene;
use anyhow::Result;

/// The pipeline configuration `settings` ask for with G-buffer `layout` for `scene` (its
/// shader features; `None` before the renderer is handed one), or why the adapter cannot
/// give it. Asks only the capability table: `support` calls it without a device.
pub fn pipeline_key(
    scene: Option<&Scene>,
    settings: &Settings,
    layout: gbuffer::GBufferLayout,
    caps: &AdapterCaps,
    (output_format, features): (wgpu::TextureFormat, program::ShaderFeatures),
) -> Result<PipelineKey> {
    // The light pre-pass's pass 1 writes its own thin buffer, whatever `--layout` says.
    let prepass = settings.path == RenderPath::LightPrepass;
    let layout = if prepass && layout.name != gbuffer::PREPASS_LAYOUT { gbuffer::prepass_layout() } else { layout };
    let layout = layout.for_caps(caps);
    let depth_format = settings.depth_format.format(caps.features);
    let layout = match depth_read_refusal(settings, caps) {
        None => layout.reading_depth_buffer(),
        Some(_) => layout,
    };
    layout.validate().map_err(anyhow::Error::msg)?;
    layout.check_caps(caps)?;
    let accum_format = settings.accumulation.format(caps)?;
    let samples = if prepass && settings.msaa == Msaa::X4 { 4 } else { 1 };
    // `--msaa 4` multisamples the light pre-pass's pass 3 and the forward paths: their HDR
    // colour and depth.
    let forward = !settings.path.keeps_gbuffer();
    if settings.msaa == Msaa::X4 && (prepass || forward) && !caps.multisample_x4(kit::HDR_FORMAT) {
        return Err(caps.refuse("--msaa 4", &format!("4-sample {:?} targets", kit::HDR_FORMAT), "use --msaa 1"));
    }
    // A layout without an emissive target (seed 000's, `packed`) carries the surfaces'
    // emission in the accumulation the G-buffer pass starts (`gbuffer_store`): that pass
    // must write ambient + sun, whatever `ambient_in_gbuffer` says, or the emission is lost.
    let fits = kit::ambient_fits(&layout, accum_format, &caps.limits);
    let emission_in_accumulation = !prepass && !layout.has(gbuffer::Attr::Emissive);
    if emission_in_accumulation && !fits {
        return Err(caps.refuse(
            &format!("layout {} (no emissive target: emission goes into the light accumulation)", layout.name),
            &format!(
                "{} colour attachments of {} bytes per sample in all",
                layout.targets.len() + 2,
                layout.bytes_per_pixel() + 2 * accum_format.block_copy_size(None).unwrap_or(16)
            ),
            "choose a layout with an emissive target (compact)",
        ));
    }
    // Seed 004's lightmaps are read at the surface's second texture coordinates, which only
    // the G-buffer pass has: on the deferred path it must start the accumulation.
    let lightmapped = !prepass && !forward && settings.lightmaps && scene.is_some_and(crate::scene::lightmap::any);
    if lightmapped && !fits {
        return Err(caps.refuse(
            "lightmaps on the deferred path (the G-buffer pass applies them as it starts the light accumulation)",
            &format!(
                "{} colour attachments of {} bytes per sample in all",
                layout.targets.len() + 2,
                layout.bytes_per_pixel() + 2 * accum_format.block_copy_size(None).unwrap_or(16)
            ),
            "use --lightmaps off, or the light-prepass or forward paths",
        ));
    }
    let reuse_buffers = crate::renderer::stochastic::reuse::STORAGE_BUFFERS;
    if settings.stochastic_options().reuse() && caps.limits.max_storage_buffers_per_shader_stage < reuse_buffers {
        return Err(caps.refuse(
            "RIS reuse (ris-spatial, ris-temporal)",
            &format!("{reuse_buffers} storage buffers a shader stage"),
            "use ris-spatial 0 and ris-temporal off",
        ));
    }
    Ok(PipelineKey {
        ambient_in_gbuffer: !prepass
            && (settings.ambient_in_gbuffer || emission_in_accumulation || lightmapped)
            && fits,
        prepass,
        samples,
        layout,
        depth_format,
        output_format,
        reversed_z: settings.reversed_z,
        accum_format,
        post_format: post::post_format(caps),
        depth_clamp: settings.depth_clamp && caps.has(wgpu::Features::DEPTH_CLIP_CONTROL),
        features,
        additive_blended: settings.blended == BlendedMode::Additive,
        peeled_blended: settings.blended == BlendedMode::Peeled,
    })
}
/// Why a frame drawn with `settings` on `caps`' adapter keeps
/// the R32Float depth copy; `None` when it reads the depth buffer instead. The passes that read
/// the G-buffer while the depth-stencil buffer is attached (the light pass, the measurement
/// passes) must attach it read-only, depth and stencil both, so:
/// - `--depth-read copy` asks for the copy;
/// - the adapter must allow a read-only depth-stencil attachment (wgpu's GL backend does not);
/// - any depth format will do: a 24-bit buffer holds depth to 2^-24 where the copy keeps the
///   fragment's f32, but the volumes' depth tests compare with the buffer itself, so the lights
///   and brute force then shade the very depth the tests saw (`kit::VOLUME_BIAS_UNITS` covers
///   the copy's half unit of difference, which reading the buffer removes);
/// - the light pass must not write the stencil: not the stencil methods, not `auto` (it picks a
///   stencil method per light), not the stencil and complexity views (they draw stencil marks).
pub fn depth_read_refusal(settings: &Settings, caps: &AdapterCaps) -> Option<String> {
    if settings.depth_read == DepthRead::Copy {
        return Some("--depth-read copy".into());
    }
    if !caps.has_downlevel(wgpu::DownlevelFlags::READ_ONLY_DEPTH_STENCIL) {
        return Some("the adapter has no read-only depth-stencil attachments".into());
    }
    if matches!(settings.culling, M::StencilTwoPass | M::StencilInvert | M::StencilReplace | M::Auto) {
        let what = if settings.culling == M::Auto { "auto picks stencil methods per light, which" } else { "it" };
        return Some(format!(
            "culling {}: {what} writes the stencil beside the depth the lights read",
            settings.culling.name()
        ));
    }
    if matches!(settings.debug_view, DebugView::Stencil | DebugView::Complexity) {
        return Some(format!("the {} view draws stencil marks", settings.debug_view.name()));
    }
    None
}
