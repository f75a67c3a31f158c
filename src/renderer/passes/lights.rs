//! The light accumulation (seeds 000-002): ambient + sun full-screen, then every light with the
//! method its plan chose, additively into the diffuse and specular targets.
//!
//! Each culling method is one [`StencilMethod`] literal below, to be held against the seeds'
//! tables: the marking draw (if any) and the shading draw, each as faces, depth test and
//! stencil. Depth is written for standard depth (near = 0) and flipped under reversed Z.

use super::{face, stencil, DrawState, Faces, FrameInputs, LightPipe, Out, Shared, Vs, NO_STENCIL};
use crate::renderer::plan::Method;
use crate::renderer::stats::{light_pass_ranges, Stamp, LIGHTS_PER_QUERY_SET};
use wgpu::{CompareFunction as Cmp, StencilOperation as Op};

/// A culling method's draws.
#[derive(Clone, Debug)]
pub struct StencilMethod {
    /// Drawn first with colour writes off, to mark the stencil.
    pub mark: Option<DrawState>,
    /// Drawn with the lighting shader.
    pub shade: DrawState,
    /// Replaces `shade` for lights whose volume crosses the near plane (its front faces are
    /// clipped away there).
    pub shade_crossing_near: Option<DrawState>,
    /// The stencil reference: zero, or a value per light (1..=255, cleared every 255 lights).
    pub reference: Reference,
    /// Whether the shading draw is the light's volume or a full-screen triangle.
    pub fullscreen: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reference {
    Zero,
    PerLight,
}

/// No culling: every light shades every pixel (the reference picture).
pub const FULLSCREEN: StencilMethod = StencilMethod {
    mark: None,
    shade: DrawState { faces: Faces::Both, depth: Cmp::Always, stencil: NO_STENCIL },
    shade_crossing_near: None,
    reference: Reference::Zero,
    fullscreen: true,
};

/// Back faces at or behind the scene point: the point is in front of the volume's far side.
pub const VOLUME: StencilMethod = StencilMethod {
    mark: None,
    shade: DrawState { faces: Faces::Back, depth: Cmp::GreaterEqual, stencil: NO_STENCIL },
    shade_crossing_near: None,
    reference: Reference::Zero,
    fullscreen: false,
};

/// Seed 000. Pass 1: front faces, no colour, Z LessEqual, Z-fail increments (saturating).
/// Pass 2: back faces, Z GreaterEqual, stencil Equal 0, every outcome writes zero (clearing the
/// mark for the next light).
pub const STENCIL_TWO_PASS: StencilMethod = StencilMethod {
    mark: Some(DrawState {
        faces: Faces::Front,
        depth: Cmp::LessEqual,
        stencil: stencil(face(Cmp::Always, Op::Keep, Op::IncrementClamp, Op::Keep), super::KEEP),
    }),
    shade: DrawState {
        faces: Faces::Back,
        depth: Cmp::GreaterEqual,
        stencil: stencil(
            face(Cmp::Equal, Op::Zero, Op::Zero, Op::Zero),
            face(Cmp::Equal, Op::Zero, Op::Zero, Op::Zero),
        ),
    },
    shade_crossing_near: None,
    reference: Reference::Zero,
    fullscreen: false,
};

/// Seed 001. Mark: both faces, Z Less, Z-fail inverts: a scene point inside the volume fails
/// only against the back face, an odd count, non-zero stencil. Shade: back faces, depth test
/// off, stencil NotEqual 0, pass op Zero clears for the next light.
pub const STENCIL_INVERT: StencilMethod = StencilMethod {
    mark: Some(DrawState {
        faces: Faces::Both,
        depth: Cmp::Less,
        stencil: stencil(
            face(Cmp::Always, Op::Keep, Op::Invert, Op::Keep),
            face(Cmp::Always, Op::Keep, Op::Invert, Op::Keep),
        ),
    }),
    shade: DrawState {
        faces: Faces::Back,
        depth: Cmp::Always,
        stencil: stencil(
            face(Cmp::NotEqual, Op::Keep, Op::Keep, Op::Zero),
            face(Cmp::NotEqual, Op::Keep, Op::Keep, Op::Zero),
        ),
    },
    shade_crossing_near: None,
    reference: Reference::Zero,
    fullscreen: false,
};

/// Seed 002 with REPLACE. Mark: back faces, Z Less, so Z fails (REPLACE X) exactly where the
/// scene point is at or in front of the far side. Shade: front faces, Z LessEqual, stencil
/// Equal X: the point is also at or behind the near side, i.e. inside. Where no front face
/// exists (camera inside, volume crossing the near plane) the shade draws back faces with the
/// depth test off instead; stencil Equal X alone is then exact. X = 1..255 differs per light, so
/// the stencil is cleared only once every 255 lights.
pub const STENCIL_REPLACE: StencilMethod = StencilMethod {
    mark: Some(DrawState {
        faces: Faces::Back,
        depth: Cmp::Less,
        stencil: stencil(
            face(Cmp::Always, Op::Keep, Op::Replace, Op::Keep),
            face(Cmp::Always, Op::Keep, Op::Replace, Op::Keep),
        ),
    }),
    shade: DrawState { faces: Faces::Front, depth: Cmp::LessEqual, stencil: EQUAL_REFERENCE },
    shade_crossing_near: Some(DrawState { faces: Faces::Back, depth: Cmp::Always, stencil: EQUAL_REFERENCE }),
    reference: Reference::PerLight,
    fullscreen: false,
};

const EQUAL_REFERENCE: wgpu::StencilState =
    stencil(face(Cmp::Equal, Op::Keep, Op::Keep, Op::Keep), face(Cmp::Equal, Op::Keep, Op::Keep, Op::Keep));

/// The table of methods, in the order of [`Method`]'s drawn variants.
pub fn stencil_method(m: Method) -> Option<&'static StencilMethod> {
    match m {
        Method::Fullscreen => Some(&FULLSCREEN),
        Method::Volume => Some(&VOLUME),
        Method::StencilTwoPass => Some(&STENCIL_TWO_PASS),
        Method::StencilInvert => Some(&STENCIL_INVERT),
        Method::StencilReplace => Some(&STENCIL_REPLACE),
        Method::Skipped => None,
    }
}

/// The methods that draw something, for building their pipelines.
pub const DRAWN: [Method; 5] =
    [Method::Fullscreen, Method::Volume, Method::StencilTwoPass, Method::StencilInvert, Method::StencilReplace];

/// One method's pipelines.
struct MethodPipelines {
    method: &'static StencilMethod,
    mark: Option<wgpu::RenderPipeline>,
    shade: wgpu::RenderPipeline,
    shade_crossing_near: Option<wgpu::RenderPipeline>,
}

pub struct LightPass {
    ambient: wgpu::RenderPipeline,
    /// By [`DRAWN`]'s order.
    methods: Vec<MethodPipelines>,
    /// Zeroes the stencil (REPLACE, every 255 lights).
    stencil_clear: wgpu::RenderPipeline,
}

impl LightPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let pipe = |label, vs, fs, state, out| shared.light_pipeline(device, LightPipe { label, vs, fs, state, out });
        let fullscreen = DrawState { faces: Faces::Both, depth: Cmp::Always, stencil: NO_STENCIL };
        let methods = DRAWN
            .iter()
            .filter_map(|&m| stencil_method(m).map(|s| (m, s)))
            .map(|(m, s)| {
                let (label, mark_label, near_label) = match m {
                    Method::Fullscreen => ("light fullscreen", "", ""),
                    Method::Volume => ("light volume", "", ""),
                    Method::StencilTwoPass => ("two-pass shade", "two-pass mark", ""),
                    Method::StencilInvert => ("invert shade", "invert mark", ""),
                    _ => ("replace shade (front faces)", "replace mark", "replace shade (back faces)"),
                };
                let vs = if s.fullscreen { Vs::Fullscreen } else { Vs::Volume };
                MethodPipelines {
                    method: s,
                    mark: s.mark.clone().map(|d| pipe(mark_label, Vs::Volume, "fs_no_color", d, Out::NoColor)),
                    shade: pipe(label, vs, "fs_light", s.shade.clone(), Out::Accumulate),
                    shade_crossing_near: s
                        .shade_crossing_near
                        .clone()
                        .map(|d| pipe(near_label, Vs::Volume, "fs_light", d, Out::Accumulate)),
                }
            })
            .collect();
        let clear = face(Cmp::Always, Op::Zero, Op::Zero, Op::Zero);
        Self {
            ambient: pipe("ambient+sun", Vs::FullscreenPlain, "fs_ambient", fullscreen.clone(), Out::Replace),
            methods,
            stencil_clear: pipe(
                "stencil clear",
                Vs::FullscreenPlain,
                "fs_no_color",
                DrawState { stencil: stencil(clear, clear), ..fullscreen },
                Out::NoColor,
            ),
        }
    }

    fn pipelines(&self, m: Method) -> Option<&MethodPipelines> {
        DRAWN.iter().position(|&d| d == m).and_then(|i| self.methods.get(i))
    }

    /// Records the accumulation: one render pass per range of lights (within one occlusion
    /// query set of 4096, and small enough for llvmpipe when counting: see
    /// `stats::light_pass_ranges`), the first starting with ambient + sun.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) {
        let t = f.targets;
        let chunk = LIGHTS_PER_QUERY_SET;
        let triangles = (f.volumes.sphere.indices.len() as u64 / 3, f.volumes.cone.indices.len() as u64 / 3);
        let ranges = light_pass_ranges(&f.plan.lights, (t.width, t.height), f.counts, triangles);
        let mut replace_counter = 0u32;
        for (k, lights) in ranges.iter().enumerate() {
            let (first, last) = (k == 0, k + 1 == ranges.len());
            let b = lights.start / chunk;
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("lights"),
                color_attachments: &t.accumulation(first),
                depth_stencil_attachment: Some(t.depth_attachment(true)),
                timestamp_writes: if first || last {
                    f.timestamps(first.then_some(Stamp::LightsBegin), last.then_some(Stamp::LightsEnd))
                } else {
                    None
                },
                occlusion_query_set: if f.counts { f.queries.occlusion.get(b) } else { None },
                multiview_mask: None,
            });
            f.bind_light_inputs(&mut pass);
            if first {
                pass.push_debug_group("ambient + sun");
                pass.set_pipeline(&self.ambient);
                pass.draw(0..3, 0..1);
                pass.pop_debug_group();
            }
            for i in lights.clone() {
                let plan = f.plan.lights[i];
                let li = i as u32..i as u32 + 1;
                let (range, base) = f.volumes.range(plan.volume);
                let query = (i - b * chunk) as u32;
                let Some(m) = self.pipelines(plan.method) else {
                    // Skipped (outside the frustum): nothing to shade, the count is zero.
                    if f.counts {
                        pass.begin_occlusion_query(query);
                        pass.end_occlusion_query();
                    }
                    continue;
                };
                if m.method.reference == Reference::PerLight {
                    if replace_counter == 255 {
                        pass.set_pipeline(&self.stencil_clear);
                        pass.draw(0..3, 0..1);
                        replace_counter = 0;
                    }
                    replace_counter += 1;
                    pass.set_stencil_reference(replace_counter);
                }
                if let Some(mark) = &m.mark {
                    pass.set_pipeline(mark);
                    pass.draw_indexed(range.clone(), base, li.clone());
                    if m.method.reference == Reference::Zero {
                        pass.set_stencil_reference(0);
                    }
                }
                // The occlusion query counts the shading draw's samples only.
                let shade = match &m.shade_crossing_near {
                    Some(near) if plan.crosses_near => near,
                    _ => &m.shade,
                };
                pass.set_pipeline(shade);
                if f.counts {
                    pass.begin_occlusion_query(query);
                }
                if m.method.fullscreen {
                    pass.draw(0..3, li);
                } else {
                    pass.draw_indexed(range, base, li);
                }
                if f.counts {
                    pass.end_occlusion_query();
                }
            }
        }
    }
}
