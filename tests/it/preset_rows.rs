//! Every row of every seed preset proven by its effect: each preset is rendered, and what each
//! row's seed line names is checked on that frame — its stats, the pipelines its passes declared
//! (their colour targets, blending, faces, depth and stencil states) or its picture — against
//! the seed's words, never against the row table. A row without a check fails, so a new row
//! comes with its proof; changing a row's value to one its seed line contradicts fails the
//! row's check, named `PRESET/KNOB` in the message. Values a seed leaves open ("no level
//! given") are checked for the effect the seed names and held by the preset's stored picture
//! (`images::presets_match_their_references`).

use crate::common::*;
use lampshade::headless::render_image;
use lampshade::renderer::kit::description::RenderDescription;
use lampshade::renderer::presets::Preset;
use lampshade::renderer::{FrameStats, Renderer, Settings, OUTPUT_FORMAT};
use wgpu::CompareFunction as Cmp;
use wgpu::StencilOperation as Op;

const W: u32 = 96;
const H: u32 = 54;

/// One frame of a preset: its settings, stats and declared render pipelines, and a renderer to
/// draw variations with.
struct Seen {
    preset: Preset,
    settings: Settings,
    stats: FrameStats,
    pipes: Vec<RenderDescription>,
    scene: lampshade::Scene,
}

type Check = fn(&Seen) -> Result<(), String>;

/// `materials` (the six models and a blended pane) with a point light at the camera, crossing
/// the near plane, and a spot light.
fn preset_scene() -> lampshade::Scene {
    use lampshade::scene::{Light, PointLight, SpotLight, ALL_LAYERS};
    let mut s = scene("materials");
    let eye = s.camera.position;
    let lights = s.lights_mut();
    let (color, intensity) = (glam::Vec3::new(1.0, 0.9, 0.8), 2.0);
    lights.push(Light::Point(PointLight {
        position: eye,
        color,
        intensity,
        radius: 1.5,
        cookie: None,
        mask: ALL_LAYERS,
        cast_shadows: true,
    }));
    lights.push(Light::Spot(SpotLight {
        position: eye + glam::DVec3::new(0.0, 3.0, -2.0),
        direction: glam::Vec3::new(0.0, -1.0, -1.0).normalize(),
        color,
        intensity,
        radius: 12.0,
        inner_angle: 0.3,
        outer_angle: 0.5,
        cast_shadows: true,
        cookie: None,
        mask: ALL_LAYERS,
    }));
    s
}

fn seen(preset: Preset, scene: &lampshade::Scene) -> Seen {
    let gpu = gpu();
    let settings = Settings { count_ideal: false, ..preset.apply(&Settings::default()).expect("the preset applies") };
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &settings).expect("renderer");
    let (_, stats) = render_image(gpu, &mut r, scene, &settings, W, H).expect("render");
    let pipes = r
        .describe_pipelines(scene, &settings, (W, H))
        .expect("the frame's pipelines")
        .into_iter()
        .filter_map(|p| p.render().cloned())
        .collect();
    Seen { preset, settings, stats, pipes, scene: scene.clone() }
}

/// The picture of `scene` with `s`.
fn picture(scene: &lampshade::Scene, s: &Settings) -> image::RgbaImage {
    let gpu = gpu();
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, s).expect("renderer");
    render_image(gpu, &mut r, scene, s, W * 2, H * 2).expect("render").0
}

fn ensure(ok: bool, what: impl FnOnce() -> String) -> Result<(), String> {
    if ok {
        Ok(())
    } else {
        Err(what())
    }
}

fn fs(p: &RenderDescription) -> &str {
    p.fragment.as_deref().unwrap_or("")
}

/// The light pass's shading pipelines (volumes and full-screen).
fn shading(s: &Seen) -> Vec<&RenderDescription> {
    s.pipes.iter().filter(|p| fs(p).starts_with("fs_light")).collect()
}

/// The light pass's stencil-marking pipelines (no colour written).
fn marks(s: &Seen) -> Vec<&RenderDescription> {
    s.pipes.iter().filter(|p| p.vertex == "vs_volume" && !p.writes_colour() && p.uses_stencil()).collect()
}

/// The G-buffer pass's shading pipelines (the light pre-pass's pass 1 included).
fn gbuffer(s: &Seen) -> Vec<&RenderDescription> {
    s.pipes.iter().filter(|p| fs(p).starts_with("fs_geometry") && !fs(p).starts_with("fs_geometry_depth")).collect()
}

fn volumes(s: &Seen) -> Vec<&RenderDescription> {
    shading(s).into_iter().filter(|p| p.vertex == "vs_volume").collect()
}

fn depth_state(p: &RenderDescription) -> Option<&wgpu::DepthStencilState> {
    p.depth_stencil.as_ref()
}

fn compare(p: &RenderDescription) -> Option<Cmp> {
    depth_state(p).and_then(|d| d.depth_compare)
}

fn writes_depth(p: &RenderDescription) -> bool {
    depth_state(p).and_then(|d| d.depth_write_enabled) == Some(true)
}

fn faces(p: &RenderDescription) -> &'static str {
    match p.primitive.cull_mode {
        Some(wgpu::Face::Back) => "front",
        Some(wgpu::Face::Front) => "back",
        None => "both",
    }
}

fn stencil_face(p: &RenderDescription, back: bool) -> Option<wgpu::StencilFaceState> {
    depth_state(p).map(|d| if back { d.stencil.back } else { d.stencil.front })
}

fn format_of(p: &RenderDescription) -> Vec<wgpu::TextureFormat> {
    p.colour_targets().map(|t| t.format).collect()
}

// ---- the checks, by what the seeds say ----

fn deferred(s: &Seen) -> Result<(), String> {
    // "rendered into several buffers (in a single pass, using multiple render targets) which
    // are then sampled by the light shader"
    let g = gbuffer(s);
    ensure(s.stats.path == lampshade::renderer::RenderPath::Deferred && s.stats.prepass.is_none(), || {
        format!("the frame was drawn on the {:?} path", s.stats.path)
    })?;
    ensure(!g.is_empty() && g.iter().all(|p| p.colour_targets().count() >= 2), || {
        format!("the G-buffer pass binds {:?}", g.iter().map(|p| format_of(p)).collect::<Vec<_>>())
    })?;
    ensure(!shading(s).is_empty(), || "no light shader read the G-buffer".into())
}

fn light_prepass(s: &Seen) -> Result<(), String> {
    // Seed 003's three passes (normals + exponent, the lights, the geometry again) / seed
    // 004's base, lighting and final passes.
    let pp = s.stats.prepass.as_ref().ok_or("no pre-pass figures: not the light pre-pass")?;
    let again = s.pipes.iter().any(|p| fs(p).starts_with("fs_prepass"));
    ensure(pp.final_draw_calls > 0 && again, || "the geometry is not drawn again after the lights".into())?;
    // "a 24-bit normal and a scaled 8-bit specular exponent": one 32-bit target.
    ensure(pp.normal_exp_bytes_per_pixel == 4, || format!("pass 1 writes {} B/px", pp.normal_exp_bytes_per_pixel))
}

fn no_shadows(s: &Seen) -> Result<(), String> {
    ensure(s.stats.shadow.is_none() && !s.pipes.iter().any(|p| p.label.contains("shadow")), || {
        format!("the frame cast shadows: {:?}", s.stats.shadow.as_ref().map(|x| x.casting))
    })
}

fn all_shadows(s: &Seen) -> Result<(), String> {
    // "All lights can have Shadows." / "Shadow maps work very well with deferred shading"
    let sh = s.stats.shadow.as_ref().ok_or("no shadow atlas")?;
    let lights = s.scene.lights.len() as u32;
    ensure(sh.casting >= lights, || format!("{} of {lights} lights cast", sh.casting))
}

fn one_pass_per_light(s: &Seen) -> Result<(), String> {
    // Each light drawn by itself ("Each light volume is rendered it two passes" / "render the
    // cone again"): as many batches as lights the light pass draws.
    let drawn = s
        .stats
        .per_light
        .iter()
        .filter(|l| !l.method.listed() && l.method != lampshade::renderer::Method::Skipped)
        .count() as u64;
    ensure(drawn > 1 && s.stats.light_batches == drawn, || {
        format!("{} batches for {drawn} drawn lights", s.stats.light_batches)
    })
}

fn bloom(s: &Seen) -> Result<(), String> {
    ensure(s.stats.post.as_ref().is_some_and(|p| p.bloom), || "no bloom pass ran".into())
}

fn effect(s: &Seen, name: &str) -> Result<(), String> {
    ensure(s.stats.post.as_ref().is_some_and(|p| p.ran(name)), || {
        format!("the post chain did not run {name}: {:?}", s.stats.post.as_ref().map(|p| &p.effects))
    })
}

fn no_aa(s: &Seen) -> Result<(), String> {
    // "No hardware antialiasing." / "No real anti-aliasing support.": one sample, no AA pass.
    let samples = s.pipes.iter().map(|p| p.samples).max().unwrap_or(1);
    ensure(samples == 1 && !s.stats.post.as_ref().is_some_and(|p| p.ran("aa")), || {
        format!("{samples} samples; post {:?}", s.stats.post.as_ref().map(|p| &p.effects))
    })
}

fn alpha_blended_last(s: &Seen) -> Result<(), String> {
    // "Blend into final image, sort back-to-front as always" / "sorted from back to front":
    // blended surfaces drawn forward, alpha blended.
    let f = s.stats.forward.as_ref().ok_or("no forward pass of blended surfaces")?;
    let alpha = s.pipes.iter().any(|p| {
        fs(p) == "fs_forward" && p.colour_targets().any(|t| t.blend == Some(wgpu::BlendState::ALPHA_BLENDING))
    });
    ensure(f.objects > 0 && alpha, || format!("{} blended objects, alpha blending {alpha}", f.objects))
}

fn material_ids(s: &Seen) -> Result<(), String> {
    // The scene's own models, chosen per pixel: the material-ID view shows more than one.
    let ids = Settings { debug_view: lampshade::renderer::DebugView::MaterialId, ..s.settings.clone() };
    let img = picture(&s.scene, &ids);
    let colours: std::collections::HashSet<[u8; 3]> =
        img.pixels().filter(|p| p[0] > 8 || p[1] > 8 || p[2] > 8).map(|p| [p[0], p[1], p[2]]).collect();
    ensure(colours.len() >= 4, || format!("the material-ID view shows {} colours", colours.len()))
}

/// Every surface of the material-ID view in model `brdf`'s colour.
fn one_model(s: &Seen, brdf: lampshade::scene::Brdf) -> Result<(), String> {
    let ids = Settings { debug_view: lampshade::renderer::DebugView::MaterialId, ..s.settings.clone() };
    let img = picture(&s.scene, &ids);
    let want = brdf.debug_color();
    let shade = |c: f32| (255.0 * c.clamp(0.0, 1.0).powf(1.0 / 2.2)).round() as i32;
    let want = [shade(want[0]), shade(want[1]), shade(want[2])];
    let lit: Vec<_> = img.pixels().filter(|p| p[0] > 8 || p[1] > 8 || p[2] > 8).collect();
    let off = lit.iter().filter(|p| (0..3).any(|c| (p[c] as i32 - want[c]).abs() > 24)).count();
    ensure(!lit.is_empty() && off * 20 < lit.len(), || {
        format!("{off} of {} surface pixels are not {brdf:?}'s colour {want:?}", lit.len())
    })
}

fn rgba16_accumulation(s: &Seen) -> Result<(), String> {
    // "16-bit floating point enables HDR" / seed 000's fp16 RT1: the lights add into fp16.
    let v = volumes(s);
    ensure(
        !v.is_empty()
            && v.iter()
                .all(|p| p.colour_targets().all(|t| t.format == wgpu::TextureFormat::Rgba16Float && t.blend.is_some())),
        || format!("the lights write {:?}", v.iter().map(|p| format_of(p)).collect::<Vec<_>>()),
    )
}

/// The G-buffer pass binds exactly `n` colour targets, every one Rgba16Float.
fn fp16_targets(s: &Seen, n: usize) -> Result<(), String> {
    let g = gbuffer(s);
    let fp16 = |p: &&RenderDescription| {
        let f = format_of(p);
        f.len() == n && f.iter().all(|f| *f == wgpu::TextureFormat::Rgba16Float)
    };
    ensure(!g.is_empty() && g.iter().all(fp16), || {
        format!("the G-buffer pass binds {:?}", g.iter().map(|p| format_of(p)).collect::<Vec<_>>())
    })
}

fn seed000_layout(s: &Seen) -> Result<(), String> {
    // "four fp16 textures with this layout": RT0, RT2 and RT3 and RT1, the accumulation.
    fp16_targets(s, 4)
}

fn ambient_in_rt1(s: &Seen) -> Result<(), String> {
    // "RT1 starts off with light contribution from main ambient and directional sources (sun)."
    let ambient = s.pipes.iter().any(|p| fs(p) == "fs_ambient");
    ensure(s.stats.ambient_in_gbuffer && !ambient, || {
        format!("ambient in the G-buffer pass: {}; a pass of its own: {ambient}", s.stats.ambient_in_gbuffer)
    })
}

fn two_pass_stencil(s: &Seen) -> Result<(), String> {
    // Pass 1: "Front faces only; Colour write disabled; No Z-write; Z function = Less/Equal;
    // Z-Fail writes non-zero value to stencil buffer (increment-saturate); Stencil pass & fail
    // don't modify stencil buffer". Pass 2: "Back-faces only; Colour write enabled; No Z-write;
    // Z function = Greater/Equal; Stencil function = Equal (stencil ref = zero); Always writes
    // zeo to stencil".
    let m = marks(s);
    let one = m.iter().any(|p| {
        let f = stencil_face(p, false).unwrap_or_default();
        faces(p) == "front"
            && !writes_depth(p)
            && compare(p) == Some(Cmp::LessEqual)
            && (f.depth_fail_op, f.pass_op, f.fail_op) == (Op::IncrementClamp, Op::Keep, Op::Keep)
    });
    let two = volumes(s).iter().any(|p| {
        let b = stencil_face(p, true).unwrap_or_default();
        faces(p) == "back"
            && p.writes_colour()
            && !writes_depth(p)
            && compare(p) == Some(Cmp::GreaterEqual)
            && b.compare == Cmp::Equal
            && (b.pass_op, b.fail_op, b.depth_fail_op) == (Op::Zero, Op::Zero, Op::Zero)
    });
    ensure(one && two, || format!("pass 1 as the seed writes it: {one}; pass 2: {two}"))
}

fn invert_stencil(s: &Seen) -> Result<(), String> {
    // Mark: "DepthFunc = D3D11_COMPARISON_LESS", "StencilDepthFailOp = D3D11_STENCIL_OP_INVERT"
    // on both faces, "back face culling off". Shade: "depth testing is off", back faces with
    // "D3D11_COMPARISON_NOT_EQUAL" and "StencilPassOp … D3D_STENCIL_OP_ZERO", front faces culled.
    let one = marks(s).iter().any(|p| {
        let (f, b) = (stencil_face(p, false).unwrap_or_default(), stencil_face(p, true).unwrap_or_default());
        faces(p) == "both"
            && compare(p) == Some(Cmp::Less)
            && !writes_depth(p)
            && [f, b].iter().all(|x| x.compare == Cmp::Always && x.depth_fail_op == Op::Invert && x.pass_op == Op::Keep)
    });
    let two = volumes(s).iter().any(|p| {
        let b = stencil_face(p, true).unwrap_or_default();
        faces(p) == "back" && compare(p) == Some(Cmp::Always) && b.compare == Cmp::NotEqual && b.pass_op == Op::Zero
    });
    ensure(one && two, || format!("the INVERT mark as the seed writes it: {one}; the shading draw: {two}"))
}

fn replace_stencil(s: &Seen) -> Result<(), String> {
    // "1. Render light volume with color write disabled; Depth Func = LESS, Stencil Func =
    // ALWAYS; Stencil Z-FAIL = REPLACE (with value X); Rest of stencil ops set to KEEP. 2.
    // Render with lighting shader … Stencil Func = EQUAL, all ops = KEEP". The shading draw's
    // depth test is a listed departure (docs/presets.md): front faces, LessEqual.
    let one = marks(s).iter().any(|p| {
        let f = stencil_face(p, true).unwrap_or_default();
        compare(p) == Some(Cmp::Less)
            && f.compare == Cmp::Always
            && (f.depth_fail_op, f.pass_op, f.fail_op) == (Op::Replace, Op::Keep, Op::Keep)
    });
    let two = volumes(s).iter().any(|p| {
        let f = stencil_face(p, false).unwrap_or_default();
        f.compare == Cmp::Equal && (f.pass_op, f.fail_op, f.depth_fail_op) == (Op::Keep, Op::Keep, Op::Keep)
    });
    ensure(one && two, || format!("the REPLACE mark as the seed writes it: {one}; the EQUAL shading: {two}"))
}

fn plain_volumes(s: &Seen) -> Result<(), String> {
    // "rendered using 3-d sphere geometry, taking advantage of the z-buffer" / "rendered as 3D
    // shapes, with Z buffer test against scene enabled": depth-tested volumes, no stencil.
    let v = volumes(s);
    ensure(!v.is_empty() && marks(s).is_empty() && v.iter().all(|p| p.depth_tested() && !p.uses_stencil()), || {
        format!("{} volume pipelines, {} stencil marks", v.len(), marks(s).len())
    })
}

fn standard_depth(s: &Seen) -> Result<(), String> {
    // "Z function = Less/Equal": standard depth, the G-buffer's test Less.
    let g = gbuffer(s);
    ensure(!g.is_empty() && g.iter().all(|p| matches!(compare(p), Some(Cmp::Less | Cmp::LessEqual))), || {
        format!("the G-buffer's depth test: {:?}", g.iter().map(|p| compare(p)).collect::<Vec<_>>())
    })
}

fn low_poly_spheres(s: &Seen) -> Result<(), String> {
    // "rendered as low-poly spheres": an icosahedron split once, 80 triangles, at most.
    ensure(s.stats.sphere_triangles > 0 && s.stats.sphere_triangles <= 80, || {
        format!("the sphere has {} triangles", s.stats.sphere_triangles)
    })
}

fn lambert_normals(s: &Seen) -> Result<(), String> {
    // "reconstructs the view space normal from two channels (using Lambert azimuthal
    // equal-area projection": the layout stores the normal in two channels, Lambert-encoded.
    use lampshade::renderer::kit::gbuffer::{Attr, NormalEncoding};
    let layout = lampshade::renderer::LayoutChoice::parse(&s.stats.gbuffer_layout)?.layout();
    let normal =
        layout.targets.iter().flat_map(|t| t.channels.iter().flatten()).filter(|c| c.attr == Attr::Normal).count();
    ensure(layout.normal == NormalEncoding::Lambert && normal == 2, || {
        format!("{}: normal {:?} in {normal} channels", layout.name, layout.normal)
    })
}

fn seed002_layout(s: &Seen) -> Result<(), String> {
    // "Three 16-bit Float MRTs": Position + Emissive, Diffuse + Specular, Normal + Free.
    fp16_targets(s, 3)
}

fn sun_as_quad(s: &Seen) -> Result<(), String> {
    // "Keep MRT usage to 3 or fewer render targets" and "Directional Light = Quad": the G-buffer
    // pass binds at most 3 targets, and ambient + sun are a full-screen draw of their own.
    let most = gbuffer(s).iter().map(|p| p.colour_targets().count()).max().unwrap_or(0);
    let quad = s.pipes.iter().any(|p| fs(p) == "fs_ambient");
    ensure(most <= 3 && quad && !s.stats.ambient_in_gbuffer, || {
        format!("{most} G-buffer targets; the sun a full-screen draw: {quad}")
    })
}

fn three_targets_on_lightmaps(s: &Seen) -> Result<(), String> {
    // "Keep MRT usage to 3 or fewer render targets": on the lightmapped courtyard too, where
    // lightmaps on the deferred path start the accumulation in the G-buffer pass.
    let courtyard = scene("courtyard");
    let mut r = Renderer::new(gpu(), OUTPUT_FORMAT, &s.settings).expect("renderer");
    let pipes = r.describe_pipelines(&courtyard, &s.settings, (W, H)).map_err(|e| format!("{e:#}"))?;
    let most = pipes
        .iter()
        .filter_map(|p| p.render())
        .filter(|p| fs(p) == "fs_geometry" || fs(p) == "fs_geometry_masked")
        .map(|p| p.colour_targets().count())
        .max()
        .unwrap_or(0);
    ensure(most > 0 && most <= 3, || format!("the courtyard's G-buffer pass binds {most} targets"))
}

fn zonly_first(s: &Seen) -> Result<(), String> {
    // "Do an initial front-to-back-sorted z-only pass.": depth-only pipelines that write depth,
    // then the G-buffer shaded only where that depth is (LessEqual, not written).
    let zonly =
        s.pipes.iter().any(|p| p.colour_targets().count() == 0 && writes_depth(p) && p.label.starts_with("geometry"));
    let g = gbuffer(s);
    ensure(zonly && !g.is_empty() && g.iter().all(|p| !writes_depth(p) && compare(p) == Some(Cmp::LessEqual)), || {
        format!(
            "a z-only pass: {zonly}; the G-buffer then written without depth: {}",
            g.iter().all(|p| !writes_depth(p))
        )
    })
}

fn front_to_back(s: &Seen) -> Result<(), String> {
    // "front-to-back-sorted": the opaque draws nearest first. With the order reversed (farthest
    // first) by material order's worst case, the same frame writes more G-buffer samples
    // without the z-only pass; here the sorted order's count is at most the material order's.
    let base = Settings { gbuffer_depth_prepass: false, ..s.settings.clone() };
    let material = Settings { draw_order: lampshade::renderer::DrawOrder::Material, ..base.clone() };
    let count = |x: &Settings| {
        let gpu = gpu();
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, x).expect("renderer");
        render_image(gpu, &mut r, &scene("demo"), x, W, H).expect("render").1.gbuffer_fragments.unwrap_or(0)
    };
    let (sorted, unsorted) = (count(&base), count(&material));
    ensure(sorted > 0 && sorted < unsorted, || {
        format!("{sorted} G-buffer samples in the preset's order, {unsorted} in material order")
    })
}

fn anisotropic(s: &Seen) -> Result<(), String> {
    // "Use aniso filtering during G-buffer pass (no level given)": on a textured floor seen at a
    // grazing angle the preset's picture differs from trilinear filtering's.
    let room = crate::presets::room();
    let trilinear = Settings { anisotropy: 1, ..s.settings.clone() };
    let (a, b) = (picture(&room, &s.settings), picture(&room, &trilinear));
    let changed = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
    ensure(changed > 0, || "the preset's filtering draws the textured room as trilinear does".into())
}

fn indirect_cube(s: &Seen) -> Result<(), String> {
    // "Unrolls a shadow cube map into a 2D depth texture … G16R16 cubemap efficiently maps
    // XYZ->ST": a 2-D atlas and an indirection cube.
    let sh = s.stats.shadow.as_ref().ok_or("no shadows")?;
    ensure(sh.cube == lampshade::renderer::shadows::ShadowCube::Indirect && sh.indirection_side > 0, || {
        format!("cube {:?}, indirection {} texels a side", sh.cube, sh.indirection_side)
    })
}

fn pcf_2x2(s: &Seen) -> Result<(), String> {
    // "Enable bilinear filtering to get 4-sample PCF".
    let sh = s.stats.shadow.as_ref().ok_or("no shadows")?;
    ensure(sh.filter == lampshade::renderer::shadows::ShadowFilter::Pcf2x2, || format!("filter {:?}", sh.filter))
}

fn d24_shadows(s: &Seen) -> Result<(), String> {
    // "Use D16 or D24X8 format for shadow maps".
    let sh = s.stats.shadow.as_ref().ok_or("no shadows")?;
    let ok = matches!(
        sh.format,
        lampshade::renderer::shadows::ShadowFormat::Depth24 | lampshade::renderer::shadows::ShadowFormat::Depth16
    );
    ensure(ok, || format!("shadow format {:?}", sh.format))
}

fn edge_aa(s: &Seen) -> Result<(), String> {
    // "\"Intelligent Blur\" : Only filter object edges": the edge blur in the post chain, one
    // sample per pixel.
    effect(s, "aa")?;
    let samples = s.pipes.iter().map(|p| p.samples).max().unwrap_or(1);
    ensure(samples == 1, || format!("{samples} samples"))
}

fn rgba8_additive(s: &Seen) -> Result<(), String> {
    // "A second g-buffer containing a 24-bit diffuse color (rgb) and 8-bit specular value is
    // updated by each light. … glBlendFunc(GL_ONE, GL_ONE)": an 8-bit RGBA light buffer, added.
    let one = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    };
    let v = shading(s);
    ensure(
        !v.is_empty()
            && v.iter().all(|p| {
                p.colour_targets().all(|t| {
                    matches!(t.format, wgpu::TextureFormat::Rgba8Unorm | wgpu::TextureFormat::Bgra8Unorm)
                        && t.blend.is_some_and(|b| b.color == one && b.alpha == one)
                })
            }),
        || format!("the lights write {:?}", v.iter().map(|p| &p.targets).collect::<Vec<_>>()),
    )
}

fn log_light_buffer(s: &Seen) -> Result<(), String> {
    // "Lighting buffer is single ARGB32 Render Texture … encoded using logarithmic encoding":
    // 8 bits a channel, each light multiplied in (2^-x stored, so the sum's log is added).
    let v = shading(s);
    ensure(
        !v.is_empty()
            && v.iter().all(|p| {
                p.colour_targets().all(|t| {
                    t.format == wgpu::TextureFormat::Rgba8Unorm
                        && t.blend.is_some_and(|b| {
                            (b.color.src_factor, b.color.dst_factor)
                                == (wgpu::BlendFactor::Dst, wgpu::BlendFactor::Zero)
                        })
                })
            }),
        || format!("the lights write {:?}", v.iter().map(|p| &p.targets).collect::<Vec<_>>()),
    )
}

fn crossing_full_screen(s: &Seen) -> Result<(), String> {
    // "Point/Spot lights that cross the near plane are rendered as fullscreen quads."
    let crossing: Vec<_> = s.stats.per_light.iter().filter(|l| l.crosses_near).collect();
    ensure(!crossing.is_empty() && crossing.iter().all(|l| l.method == lampshade::renderer::Method::Fullscreen), || {
        format!(
            "{} lights cross the near plane, drawn {:?}",
            crossing.len(),
            crossing.iter().map(|l| l.method).collect::<Vec<_>>()
        )
    })
}

fn deferred_lit_or_forward(s: &Seen) -> Result<(), String> {
    // "Lighting model is fixed to Blinn-Phong." and "Objects with shaders that can't handle
    // Deferred Lighting are rendered after this process is done, using
    // RenderTech-ForwardRendering path.": the light pass shades Blinn-Phong terms whatever the
    // material, and every object whose model the buffer cannot shade, or that is blended, goes
    // forward.
    let cannot = s
        .scene
        .objects
        .iter()
        .filter(|o| {
            let m = &s.scene.materials[o.material];
            m.is_blended() || !m.brdf.prepass_lit()
        })
        .count();
    let f = s.stats.forward.as_ref().ok_or("nothing drawn forward")?;
    ensure(cannot > 1 && f.objects == cannot, || {
        format!("{} objects drawn forward, {cannot} the buffer cannot shade", f.objects)
    })
}

fn lightmapped(s: &Seen) -> Result<(), String> {
    // "Lightmaps are also applied in the final pass.": on the lightmapped courtyard the
    // preset's picture differs from the same without lightmaps.
    let courtyard = scene("courtyard");
    let off = Settings { lightmaps: false, ..s.settings.clone() };
    let (a, b) = (picture(&courtyard, &s.settings), picture(&courtyard, &off));
    ensure(a != b, || "the lightmaps changed no pixel of the courtyard".into())
}

fn reads_depth_buffer(s: &Seen) -> Result<(), String> {
    // "If platform & hardware supports reading Z buffer as a texture, then depth is not
    // explicitly rendered." / seed 003's lights read "the 24-bit z-buffer": no depth copy.
    let pp = s.stats.prepass.as_ref().ok_or("not the light pre-pass")?;
    ensure(pp.depth_copy_bytes_per_pixel == 0 && s.stats.depth_read.starts_with("depth buffer"), || {
        format!("depth read from {} ({} B/px copy)", s.stats.depth_read, pp.depth_copy_bytes_per_pixel)
    })
}

fn d24_depth(s: &Seen) -> Result<(), String> {
    // "with the 24-bit z-buffer": a 24-bit depth buffer.
    ensure(s.stats.depth_stencil_format == "Depth24PlusStencil8", || s.stats.depth_stencil_format.clone())
}

fn checks(p: Preset) -> Vec<(&'static str, Check)> {
    match p {
        Preset::Default => Vec::new(),
        Preset::Seed000 => vec![
            ("path", deferred),
            ("layout", seed000_layout),
            ("accumulation", rgba16_accumulation),
            ("ambient-in-gbuffer", ambient_in_rt1),
            ("culling", two_pass_stencil),
            ("light-batching", one_pass_per_light),
            ("sphere-subdivisions", low_poly_spheres),
            ("reversed-z", standard_depth),
            ("brdf", |s| one_model(s, lampshade::scene::Brdf::Phong)),
            ("shadows", no_shadows),
            ("bloom", bloom),
            ("aa", no_aa),
        ],
        Preset::Seed001 => vec![
            ("path", deferred),
            ("layout", lambert_normals),
            ("culling", invert_stencil),
            ("light-batching", one_pass_per_light),
            ("brdf", |s| one_model(s, lampshade::scene::Brdf::BlinnPhong)),
            ("shadows", no_shadows),
        ],
        Preset::Seed002 => vec![
            ("path", deferred),
            ("layout", seed002_layout),
            ("accumulation", rgba16_accumulation),
            ("ambient-in-gbuffer", sun_as_quad),
            ("culling", replace_stencil),
            ("brdf", material_ids),
            ("material-branch", |s| {
                // "Reasonably coherent dynamic branching": the light shader branches on the ID.
                ensure(
                    s.settings.material_branch == lampshade::renderer::settings::MaterialBranch::Branch
                        && s.stats.shader_lookups.iter().any(|l| l == "branch on the material"),
                    || format!("lookups compiled in: {:?}", s.stats.shader_lookups),
                )
            }),
            ("gbuffer-depth-prepass", zonly_first),
            ("lightmaps", three_targets_on_lightmaps),
            ("draw-order", front_to_back),
            ("anisotropy", anisotropic),
            ("shadows", all_shadows),
            ("shadow-cube", indirect_cube),
            ("shadow-filter", pcf_2x2),
            ("shadow-format", d24_shadows),
            ("bloom", bloom),
            ("auto-exposure", |s| {
                ensure(s.stats.post.as_ref().is_some_and(|p| p.auto_exposure), || "no auto-exposure".into())
            }),
            ("distortion", |s| effect(s, "distortion")),
            ("fog", |s| effect(s, "fog")),
            ("aa", edge_aa),
            ("blended", alpha_blended_last),
        ],
        Preset::Seed003 => vec![
            ("path", light_prepass),
            ("accumulation", rgba8_additive),
            ("culling", plain_volumes),
            ("depth-format", d24_depth),
            ("depth-read", reads_depth_buffer),
            ("blended", alpha_blended_last),
            ("shadows", no_shadows),
            ("lut", |s| effect(s, "grading")),
            ("dof", |s| effect(s, "dof")),
            ("vignette", |s| effect(s, "vignette")),
        ],
        Preset::Seed004 => vec![
            ("path", light_prepass),
            ("accumulation", log_light_buffer),
            ("culling", plain_volumes),
            ("near-lights", crossing_full_screen),
            ("brdf", deferred_lit_or_forward),
            ("shadows", all_shadows),
            ("lightmaps", lightmapped),
            ("aa", no_aa),
            ("depth-read", reads_depth_buffer),
        ],
    }
}

/// Preset `p`'s rows, each checked on its frame; the failures named `PRESET/KNOB`.
fn check_rows(p: Preset) {
    let seen = seen(p, &preset_scene());
    assert_eq!(seen.preset, p);
    let table = checks(p);
    let mut failures = Vec::new();
    for row in p.rows() {
        let Some((_, check)) = table.iter().find(|(k, _)| *k == row.knob) else {
            failures.push(format!("{}/{}: the row has no check", p.name(), row.knob));
            continue;
        };
        if let Err(e) = check(&seen) {
            failures.push(format!("{}/{} ({}): {e}", p.name(), row.knob, row.seed));
        }
    }
    // A check whose row is gone is a check of nothing.
    for (knob, _) in &table {
        if !p.rows().iter().any(|r| r.knob == *knob) {
            failures.push(format!("{}/{knob}: checked, but the preset has no such row", p.name()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn seed000_rows_hold_on_the_frame() {
    check_rows(Preset::Seed000);
}

#[test]
fn seed001_rows_hold_on_the_frame() {
    check_rows(Preset::Seed001);
}

#[test]
fn seed002_rows_hold_on_the_frame() {
    check_rows(Preset::Seed002);
}

#[test]
fn seed003_rows_hold_on_the_frame() {
    check_rows(Preset::Seed003);
}

#[test]
fn seed004_rows_hold_on_the_frame() {
    check_rows(Preset::Seed004);
}
