//! The effects after tone mapping, as one table. Each is one full-screen pass from the chain's
//! last image into the next (or into the output when it is the last that runs), in the
//! table's order, and each is one fragment function in `post.wgsl`. The order is the seeds':
//! seed 002 lists "Glow, Auto-Exposure, Distortion, Edge-smoothing, Fog" (glow and exposure
//! run before tone mapping), seed 003's fifth pass "color grading, depth of field, vignetting".
//! Grading first, on the tone-mapped colour LUTs are made for; then seed 002's distortion,
//! edge smoothing and fog; then seed 003's depth of field and vignette.
//! Adding one is a row here, its function there, its option in `Settings` and `PostOptions`, and its knob row.
//!
//! - **grading** (seed 003's fifth pass): the tonemapped colour through a 3D LUT
//!   (`--lut FILE.cube`, or `identity`), trilinear, in the sRGB encoding LUTs are made for.
//! - **distortion** (seed 002's chain): each pixel reads the picture at its own position plus
//!   the distortion buffer's offset (`post::distortion`: the distorting surfaces' view-space
//!   normals times their strength), nearest texel; a source pixel nearer to the eye than the
//!   nearest distorting surface at the pixel (something in front of the glass) is not taken:
//!   the pixel keeps its own colour. Pixels without an offset are copied unchanged.
//! - **aa**: seed 002's edge-detect "intelligent blur" (edges where the second difference
//!   of 1/depth — zero across any plane — or the turn of the normal to a neighbour is large;
//!   the pixel blended with its four neighbours by the edge's strength) or FXAA (Lottes; the
//!   minimal console form: a luma contrast test, then a blend along the edge). Pixels off the
//!   mask are copied unchanged. Its view: the edges.
//! - **fog** (seed 002's chain): distance fog with an exponential height falloff towards the
//!   background colour, by `post::fog_amount`'s formula from the G-buffer's view-space point.
//!   Background pixels are left as they are.
//! - **dof**, depth of field (seed 003): each pixel's circle of confusion from its view depth,
//!   CoC = aperture × |z − focus| / z px (at most `post::MAX_COC`; focus: `Focus`, by default
//!   the view depth at the screen's centre, read on the GPU), and a gather over a 32-tap
//!   disc of that diameter, taking only neighbours whose own CoC reaches the pixel (a sharp
//!   foreground does not smear over what is behind it). A CoC under half a pixel copies the
//!   pixel. Its view: the CoC.
//! - **vignette** (seed 003): darkened towards the corners by `vignette` (a smoothstep in the
//!   distance from the centre, 1 - strength at the corners).

use super::post_draw;
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::Shared;
use crate::renderer::options::post::PostOptions;
use crate::renderer::options::DebugView;
use crate::renderer::post::Aa;
use crate::renderer::stats::Span;

/// One effect after tone mapping.
pub struct Effect {
    /// The pass's label (its debug view's with " view") and its timing span (`gpu_ms`).
    pub name: &'static str,
    /// Its name in the viewer's figures.
    pub title: &'static str,
    /// Its fragment function in `post.wgsl`.
    pub fs: &'static str,
    /// Whether it runs (in the lit view; the other views stop before it).
    pub on: fn(&PostOptions) -> bool,
    /// Its own debug view and the fragment function that draws it.
    pub view: Option<(DebugView, &'static str)>,
    /// Its second texture is drawn right before it (the distortion buffer,
    /// `post::distortion`), and that draw opens the effect's span.
    pub buffer_first: bool,
    /// Its parameters, as its fragment function reads them: `post_params.effect[i]` for the
    /// row's index `i`, named `LS_EFFECT_<NAME>` in the shaders (`program::wgsl_constants`). The
    /// effects whose parameters have fields of their own in `PostParams` leave it zero.
    pub params: fn(&PostOptions) -> [f32; 4],
}

pub use crate::renderer::records::MAX_EFFECTS;
const _: () = assert!(EFFECTS.len() <= MAX_EFFECTS);

/// No parameters of its own in `PostParams::effect`.
const NONE: fn(&PostOptions) -> [f32; 4] = |_| [0.0; 4];

/// The effects after tone mapping, in the chain's order.
pub const EFFECTS: &[Effect] = &[
    Effect {
        name: "grading",
        title: "grading",
        fs: "fs_grade",
        on: |s| s.lut.is_some(),
        view: None,
        buffer_first: false,
        params: NONE,
    },
    Effect {
        name: "distortion",
        title: "distortion",
        fs: "fs_distort",
        on: |s| s.distortion,
        view: None,
        buffer_first: true,
        params: NONE,
    },
    Effect {
        name: "aa",
        title: "anti-aliasing",
        fs: "fs_aa",
        on: |s| s.aa != Aa::Off,
        view: Some((DebugView::Edges, "fs_view_edges")),
        buffer_first: false,
        params: NONE,
    },
    Effect { name: "fog", title: "fog", fs: "fs_fog", on: |s| s.fog, view: None, buffer_first: false, params: NONE },
    Effect {
        name: "dof",
        title: "depth of field",
        fs: "fs_dof",
        on: |s| s.dof,
        view: Some((DebugView::Coc, "fs_view_coc")),
        buffer_first: false,
        params: NONE,
    },
    Effect {
        name: "vignette",
        title: "vignette",
        fs: "fs_vignette",
        on: |s| s.vignette > 0.0,
        view: None,
        buffer_first: false,
        params: NONE,
    },
];

/// Whether effect `name` runs under `s`.
pub fn runs(name: &str, s: &PostOptions) -> bool {
    EFFECTS.iter().any(|e| e.name == name && (e.on)(s))
}

/// Each effect's pipelines: into the chain's next image, into the output, and its view's.
pub struct EffectsPass {
    pipelines: Vec<(
        crate::renderer::kit::RenderPipe,
        crate::renderer::kit::RenderPipe,
        Option<crate::renderer::kit::RenderPipe>,
    )>,
}

impl EffectsPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let (layout, out) = (&shared.post_layout, shared.key.output_format);
        let pipelines = EFFECTS
            .iter()
            .map(|e| {
                let view = e
                    .view
                    .map(|(_, fs)| shared.fullscreen_pipeline(device, &format!("{} view", e.name), layout, fs, out));
                (
                    shared.fullscreen_pipeline(device, e.name, layout, e.fs, shared.key.post_format),
                    shared.fullscreen_pipeline(device, e.name, layout, e.fs, out),
                    view,
                )
            })
            .collect();
        Self { pipelines }
    }

    /// Effect `i`'s pipeline into the output (`last`) or into the chain's next image.
    pub fn pipeline(&self, i: usize, last: bool) -> Option<&crate::renderer::kit::RenderPipe> {
        self.pipelines.get(i).map(|(to_post, to_output, _)| if last { to_output } else { to_post })
    }

    /// The pipeline of the effect whose view `debug_view` is.
    pub fn view_pipeline(&self, debug_view: DebugView) -> Option<&crate::renderer::kit::RenderPipe> {
        EFFECTS
            .iter()
            .zip(&self.pipelines)
            .find_map(|(e, (_, _, pipeline))| e.view.filter(|(v, _)| *v == debug_view).and(pipeline.as_ref()))
    }

    /// Records effect `i` of [`EFFECTS`] from `group`'s source into `view` (`last`: the output).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        i: usize,
        group: &wgpu::BindGroup,
        view: &wgpu::TextureView,
        last: bool,
    ) {
        let (e, (to_post, to_output, _)) = (&EFFECTS[i], &self.pipelines[i]);
        draw(encoder, f, e, e.name, if last { to_output } else { to_post }, (group, view));
    }

    /// Records the effect whose view `debug_view` is from `group`'s source into `target`;
    /// false when no effect has that view.
    pub fn encode_view(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameInputs<'_>,
        debug_view: DebugView,
        group: &wgpu::BindGroup,
        target: &wgpu::TextureView,
    ) -> bool {
        for (e, (_, _, pipeline)) in EFFECTS.iter().zip(&self.pipelines) {
            if let (Some((v, _)), Some(pipeline)) = (e.view, pipeline) {
                if v == debug_view {
                    draw(encoder, f, e, &format!("{} view", e.name), pipeline, (group, target));
                    return true;
                }
            }
        }
        false
    }
}

/// Records one draw of effect `e` with `pipeline` from `group`'s source into `target`, timed as
/// the effect's span.
fn draw(
    encoder: &mut wgpu::CommandEncoder,
    f: &FrameInputs<'_>,
    e: &Effect,
    label: &str,
    pipeline: &crate::renderer::kit::RenderPipe,
    (group, target): (&wgpu::BindGroup, &wgpu::TextureView),
) {
    // An effect whose buffer is drawn first: the span began with those draws.
    let begin = (!e.buffer_first).then_some(Span(e.name));
    let stamps = f.timestamps(begin, Some(Span(e.name)));
    post_draw(encoder, f, label, pipeline, target, group, stamps);
}
