//! The per-pixel half of the ledger's waste (the `waste` debug view): at each pixel, the lights
//! the frame evaluated there whose true shape does not hold the pixel's point. For the lights
//! drawn one by one (every culling method but the lists) each light is drawn again with its
//! own method's draws: the marking draw with its stencil operations and reference, then the
//! shading draw's depth and stencil tests, so a fragment reaches `fs_waste` exactly where the
//! light pass evaluated the light (the light pass's batches are lights whose pixels never meet,
//! so one light at a time marks and tests what its batch did). `fs_waste` adds one where the
//! point is outside the light's shape, or there is no point. Frames shaded from tile or cluster
//! lists get the same count from their lists (`fs_tile_waste`, in the tiled pass).

use crate::renderer::culling::methods::{self, Reference, METHODS};
use crate::renderer::inputs::pass::{Pass, PassReport};
use crate::renderer::inputs::FrameInputs;
use crate::renderer::kit::Declared;
use crate::renderer::kit::{
    biased_in_fragment, face, stencil, DrawState, Faces, LightPipe, Out, Shared, Vs, ADDITIVE, NO_STENCIL,
};
use wgpu::{CompareFunction as Cmp, StencilOperation as Op};

/// One method's draws for the view: its mark (adding nothing), its shading draw, and the
/// shading draw of lights whose volume crosses the near plane.
struct MethodPipes {
    mark: Option<crate::renderer::kit::RenderPipe>,
    shade: crate::renderer::kit::RenderPipe,
    shade_crossing_near: Option<crate::renderer::kit::RenderPipe>,
}

pub struct WastePass {
    /// By [`METHODS`]' order; `None` for the methods the light pass does not draw.
    methods: Vec<Option<MethodPipes>>,
    /// Zeroes the stencil (REPLACE, every 255 lights).
    stencil_clear: crate::renderer::kit::RenderPipe,
}

impl WastePass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let pipe = |label, vs, fs, state, out| shared.light_pipeline(device, LightPipe { label, vs, fs, state, out });
        let out = Out::Debug(ADDITIVE);
        let methods = METHODS
            .iter()
            .map(|row| {
                let s = row.draws.as_ref()?;
                let vs = if s.fullscreen { Vs::Fullscreen } else { Vs::Volume };
                Some(MethodPipes {
                    mark: s.mark.clone().map(|d| {
                        let fs = if biased_in_fragment(&d) { "fs_waste_mark_both_faces" } else { "fs_waste_mark" };
                        pipe("waste view: mark", Vs::Volume, fs, d, out)
                    }),
                    shade: pipe("waste view", vs, "fs_waste", s.shade.clone(), out),
                    shade_crossing_near: s
                        .shade_crossing_near
                        .clone()
                        .map(|d| pipe("waste view: crossing near", Vs::Volume, "fs_waste", d, out)),
                })
            })
            .collect();
        let clear = face(Cmp::Always, Op::Zero, Op::Zero, Op::Zero);
        let fullscreen = DrawState { faces: Faces::Both, depth: Cmp::Always, stencil: NO_STENCIL };
        Self {
            methods,
            stencil_clear: pipe(
                "waste view: stencil clear",
                Vs::FullscreenPlain,
                "fs_waste_mark",
                DrawState { stencil: stencil(clear, clear), ..fullscreen },
                out,
            ),
        }
    }

    /// Each light the view draws (every light the light pass drew, or the selected one), in
    /// order, with its method's draws, REPLACE's references counted as the light pass counts
    /// them: what [`Self::record`] draws and [`Pass::declare`] declares.
    fn walk<'s>(&'s self, f: &FrameInputs<'_>, mut visit: impl FnMut(LightDraws<'s>)) {
        let mut reference = 0u32;
        for (i, plan) in f.plan.lights.iter().enumerate() {
            if f.options.frame.selected_light.is_some_and(|k| k != i) {
                continue;
            }
            let Some(Some(m)) = self.methods.get(methods::order(plan.method) as usize) else { continue };
            let Some(draws) = methods::row(plan.method).draws.as_ref() else { continue };
            let near = m.shade_crossing_near.as_ref().filter(|_| plan.crosses_near);
            let mut clear = false;
            let mark = m.mark.as_ref().filter(|_| near.is_none()).map(|mark| {
                if draws.reference != Reference::PerLight {
                    return (mark, None);
                }
                if reference == 255 {
                    clear = true;
                    reference = 0;
                }
                reference += 1;
                (mark, Some(reference))
            });
            visit(LightDraws { light: i, clear, mark, shade: near.unwrap_or(&m.shade), fullscreen: draws.fullscreen });
        }
    }

    /// Records the view into the debug target: every light the light pass drew (or the selected
    /// one), one at a time with its method's draws.
    fn record(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) {
        let mut pass = f.debug_view_pass(encoder, "waste view");
        self.walk(f, |d| {
            let li = d.light as u32..d.light as u32 + 1;
            let (range, base) = f.volumes.range(f.plan.lights[d.light].volume);
            if d.clear {
                pass.set_pipeline(&self.stencil_clear);
                pass.draw(0..3, 0..1);
            }
            if let Some((mark, reference)) = d.mark {
                if let Some(r) = reference {
                    pass.set_stencil_reference(r);
                }
                pass.set_pipeline(mark);
                pass.draw_indexed(range.clone(), base, li.clone());
                if reference.is_none() {
                    pass.set_stencil_reference(0);
                }
            }
            pass.set_pipeline(d.shade);
            if d.fullscreen {
                pass.draw(0..3, li);
            } else {
                pass.draw_indexed(range, base, li);
            }
        });
    }
}

/// One light's draws in the waste view.
struct LightDraws<'s> {
    light: usize,
    /// The stencil is cleared first (REPLACE's references wrapped past 255).
    clear: bool,
    /// The marking draw, with REPLACE's reference (`None`: reference zero).
    mark: Option<(&'s crate::renderer::kit::RenderPipe, Option<u32>)>,
    shade: &'s crate::renderer::kit::RenderPipe,
    fullscreen: bool,
}

impl Pass for WastePass {
    fn declare(&self, f: &FrameInputs<'_>, out: &mut Declared) {
        self.walk(f, |d| {
            if d.clear {
                out.add(&self.stencil_clear);
            }
            out.add_all(d.mark.map(|(mark, _)| mark));
            out.add(d.shade);
        });
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder, f: &FrameInputs<'_>) -> anyhow::Result<PassReport> {
        self.record(encoder, f);
        Ok(PassReport::default())
    }
}
