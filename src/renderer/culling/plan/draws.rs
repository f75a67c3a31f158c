//! Each object's draw: into the G-buffer or forward, in which order, and the forward pass's
//! light lists (per blended object, and per screen tile).

use super::{DrawLists, LightPlan, PlanView};
use crate::renderer::culling::stats::ForwardStats;
use crate::renderer::options::culling::{ForwardLights, FORWARD_LIST_MAX};
use crate::renderer::records::CameraRecord;
use crate::scene::{AlphaMode, Scene};
use glam::DVec3;

/// Most u32 entries the forward pass's light lists (object and tile lists together) may hold:
/// 128 MiB, the storage-buffer binding size WebGPU guarantees.
pub const MAX_FORWARD_LIST_ENTRIES: usize = (128 << 20) / 4;

/// The warnings for a frame whose forward loops may walk a list longer than
/// [`FORWARD_LIST_MAX`]: the longest list of the forward path's objects (`path`), or of the
/// blended surfaces (`blended`: a fragment walks the shorter of its object's list and its
/// tile's, so the shorter of the longest of each bounds it).
pub fn long_forward_list_warnings(path: Option<u32>, blended: Option<&ForwardStats>) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(n) = path.filter(|&n| n > FORWARD_LIST_MAX) {
        out.push(format!(
            "an object's light list holds {n} lights; the forward path shades at most {FORWARD_LIST_MAX} a pixel on lavapipe (its loop limit), the rest are lost there"
        ));
    }
    if let Some(f) = blended {
        let walked = if f.tiles > 0 { f.longest_object_list.min(f.longest_tile_list) } else { f.longest_object_list };
        if walked > FORWARD_LIST_MAX {
            out.push(format!(
                "a blended surface's light list may hold {walked} lights; the forward pass shades at most {FORWARD_LIST_MAX} a pixel on lavapipe (its loop limit), the rest are lost there"
            ));
        }
    }
    out
}

/// Size in pixels of the forward pass's screen tiles.
pub const FORWARD_TILE: u32 = 16;

/// Object `o`'s bounding sphere in world space: its mesh's sphere (`bounds`) moved by its
/// transform, the radius scaled by the transform's largest axis scale.
pub(super) fn world_sphere(o: &crate::scene::Object, bounds: &[(DVec3, f64)]) -> (DVec3, f64) {
    let (c, r) = bounds.get(o.mesh).copied().unwrap_or((DVec3::ZERO, 0.0));
    let scale = (0..3).map(|k| o.transform.col(k).truncate().length()).fold(0.0, f64::max);
    (o.transform.transform_point3(c), r * scale)
}

/// The forward pass's screen tiles ([`FORWARD_TILE`] pixels) at `size`: (tiles across, down,
/// each tile's lights in light order), a light in every tile its screen rectangle, widened by a
/// pixel against rounding, covers; only the lights `wanted` marks.
pub(super) fn forward_tiles(plans: &[LightPlan], wanted: &[bool], (w, h): (u32, u32)) -> (u32, u32, Vec<Vec<u32>>) {
    let (tx, ty) = (w.div_ceil(FORWARD_TILE), h.div_ceil(FORWARD_TILE));
    let mut tiles: Vec<Vec<u32>> = vec![Vec::new(); (tx * ty) as usize];
    for (k, p) in plans.iter().enumerate() {
        let Some((lo, hi)) = p.screen_rect.filter(|_| wanted[k]) else { continue };
        // NDC to pixels (y down), widened by a pixel; a fragment's centre lies inside.
        let px = |x: f32| ((x + 1.0) * 0.5 * w as f32).floor();
        let py = |y: f32| ((1.0 - y) * 0.5 * h as f32).floor();
        let tile = |v: f32, max: u32| (v.max(0.0) as u32).min(max - 1) / FORWARD_TILE;
        let (x0, x1) = (px(lo.x) - 1.0, px(hi.x) + 1.0);
        let (y0, y1) = (py(hi.y) - 1.0, py(lo.y) + 1.0);
        if x1 < 0.0 || y1 < 0.0 || x0 >= w as f32 || y0 >= h as f32 {
            continue;
        }
        for y in tile(y0, h)..=tile(y1, h) {
            for x in tile(x0, w)..=tile(x1, w) {
                tiles[(y * tx + x) as usize].push(k as u32);
            }
        }
    }
    (tx, ty, tiles)
}

/// Sorts the objects into the G-buffer pass (opaque, masked) and the forward pass (blended,
/// back to front by the view depth of their bounding sphere's centre), and builds the forward
/// pass's light lists (see [`ForwardLights`]):
/// - per blended object, the lights whose sphere reaches its bounding sphere (`tiled` also
///   drops lights off screen; `all` lists every light);
/// - with `tiled`, per [`FORWARD_TILE`]-pixel screen tile, the lights of those lists whose
///   screen rectangle ([`LightPlan::screen_rect`], widened by a pixel against rounding) covers
///   the tile; `camera.forward_tiles` tells the shader where they are.
///
/// A light is left out of a list only where it cannot reach: every list is in light order, so
/// a fragment sums the same non-zero terms in the same order whichever list it walks.
pub(super) fn plan_draws(
    scene: &Scene,
    objects: &mut [crate::renderer::records::ObjectRecord],
    camera: &mut CameraRecord,
    bounds: &[(DVec3, f64)],
    plans: &[LightPlan],
    view: &PlanView,
) -> (DrawLists, Vec<u32>, Option<ForwardStats>) {
    let mode = view.forward_lights;
    let mut lists = Vec::new();
    let mut draws = DrawLists::default();
    let mut forward: Vec<(f64, usize, usize, usize)> = Vec::new();
    // Each opaque draw's nearest view depth, for front-to-back order.
    let mut nearest: Vec<f64> = vec![0.0; if view.front_to_back { scene.objects.len() } else { 0 }];
    let mut stats = ForwardStats { lights: mode, ..Default::default() };
    // Lights in at least one blended object's list: the only ones a tile needs.
    let mut reaches_glass = vec![false; scene.lights.len()];
    // The light pre-pass's buffer shades the layers its lights treat alike.
    let shared_layers = if view.prepass_models.is_some() { scene.shared_layers().1 } else { u32::MAX };
    for (i, o) in scene.objects.iter().enumerate() {
        let m = &scene.materials[o.material];
        if let Some(d) = nearest.get_mut(i) {
            let (centre, radius) = world_sphere(o, bounds);
            *d = -scene.camera.to_view(centre).z - radius;
        }
        let topology = scene.meshes.get(o.mesh).map_or(Default::default(), |mesh| mesh.topology);
        if topology != crate::scene::Topology::Triangles {
            // Lines and points go into the G-buffer whatever their alpha mode (the importer
            // warns about blended ones).
            let masked = matches!(m.alpha_mode, AlphaMode::Mask { .. });
            let p = crate::renderer::kit::pipeline::topology_pipeline_index(topology, masked, m.double_sided);
            draws.gbuffer.push((i, p, o.material));
            continue;
        }
        // Toon and Phong under the light pre-pass (`Brdf::prepass_lit`), and objects on a layer
        // some light tells apart from the buffer's (`Scene::shared_layers`): its depth in pass
        // 1, its shading forward (a light list, as a blended object's).
        let toon_forward = view.prepass_models.is_some_and(|force| {
            let apart = !force.unwrap_or(m.brdf).prepass_lit() || shared_layers & (1 << (o.layer & 31)) == 0;
            apart && m.alpha_mode != AlphaMode::Blend
        });
        if m.distortion > 0.0 {
            draws.distorting.push((i, m.double_sided as usize, o.material));
        }
        match m.alpha_mode {
            _ if toon_forward || m.alpha_mode == AlphaMode::Blend => {
                let (centre, radius) = world_sphere(o, bounds);
                let first = lists.len() as u32;
                object_lights(scene, (centre, radius), plans, mode, &mut lists, &mut reaches_glass);
                let count = lists.len() as u32 - first;
                objects[i].info[1] = first;
                objects[i].info[2] = count;
                stats.objects += 1;
                stats.object_list_entries += count as u64;
                stats.longest_object_list = stats.longest_object_list.max(count);
                if toon_forward {
                    // Alpha-masked ones discard in pass 1 and again in their forward draw.
                    let masked = matches!(m.alpha_mode, AlphaMode::Mask { .. });
                    draws.gbuffer.push((
                        i,
                        crate::renderer::kit::pipeline::pipeline_index(masked, m.double_sided),
                        o.material,
                    ));
                    draws.forward_opaque.push((i, m.double_sided as usize + 2 * masked as usize, o.material));
                } else {
                    let depth = scene.camera.to_view(centre).z;
                    forward.push((depth, i, m.double_sided as usize, o.material));
                }
            }
            mode => {
                let masked = matches!(mode, AlphaMode::Mask { .. });
                draws.gbuffer.push((
                    i,
                    crate::renderer::kit::pipeline::pipeline_index(masked, m.double_sided),
                    o.material,
                ));
            }
        }
    }
    camera.forward_tiles = [0; 4];
    if mode == ForwardLights::Tiled && !forward.is_empty() {
        camera.forward_tiles = tile_lists(plans, &reaches_glass, view.size, &mut lists, &mut stats);
    }
    // View space looks down -z: the farthest has the most negative z and is drawn first.
    // Added surfaces (seed 003's additive blending) need no order: they stay in scene order.
    if view.sort_blended {
        forward.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    draws.forward = forward.into_iter().map(|(_, i, p, m)| (i, p, m)).collect();
    order_gbuffer(&mut draws, &nearest, view.front_to_back);
    let stats = (!draws.forward.is_empty()).then_some(stats);
    (draws, lists, stats)
}

/// The lights whose sphere reaches an object's bounding sphere `(centre, radius)`, in light
/// order, appended to `lists` and marked in `reaches_glass` (`mode`: `tiled` also drops lights
/// off screen; `all` lists every light).
fn object_lights(
    scene: &Scene,
    (centre, radius): (DVec3, f64),
    plans: &[LightPlan],
    mode: ForwardLights,
    lists: &mut Vec<u32>,
    reaches_glass: &mut [bool],
) {
    for (k, l) in scene.lights.iter().enumerate() {
        let keep = match mode {
            ForwardLights::All => true,
            ForwardLights::Object => (l.position() - centre).length() < radius + l.radius() as f64,
            ForwardLights::Tiled => {
                plans.get(k).is_some_and(|p| p.screen_rect.is_some())
                    && (l.position() - centre).length() < radius + l.radius() as f64
            }
        };
        if keep {
            lists.push(k as u32);
            reaches_glass[k] = true;
        }
    }
}

/// The tiles' light lists of the lights `wanted` marks, appended to `lists` after a header of
/// (first, count) per tile, and their counts in `stats`; what `camera.forward_tiles` says of
/// them (all 0 when there are none, or too many entries for one storage buffer).
fn tile_lists(
    plans: &[LightPlan],
    wanted: &[bool],
    size: (u32, u32),
    lists: &mut Vec<u32>,
    stats: &mut ForwardStats,
) -> [u32; 4] {
    let (tx, ty, mut tiles) = forward_tiles(plans, wanted, size);
    let entries: usize = tiles.iter().map(Vec::len).sum();
    if lists.len() + 2 * tiles.len() + entries > MAX_FORWARD_LIST_ENTRIES {
        // Too many to upload in one storage buffer: the pass walks the object lists alone
        // (the same picture, slower), and the stats show no tiles.
        log::warn!(
            "forward tile lists would hold {entries} entries (most {MAX_FORWARD_LIST_ENTRIES}); using the object lists"
        );
        tiles.clear();
    }
    let header = lists.len() as u32;
    let mut first = header + 2 * tiles.len() as u32;
    for t in &tiles {
        lists.extend([first, t.len() as u32]);
        first += t.len() as u32;
        stats.tile_list_entries += t.len() as u64;
        stats.longest_tile_list = stats.longest_tile_list.max(t.len() as u32);
    }
    for t in &tiles {
        lists.extend_from_slice(t);
    }
    stats.tiles = tiles.len() as u64;
    if tiles.is_empty() {
        [0; 4]
    } else {
        [FORWARD_TILE, tx, ty, header]
    }
}

/// The G-buffer pass's order: nearest sphere first where `front_to_back` (`nearest`: each
/// object's nearest view depth), else by pipeline and material; and, where some objects are
/// shaded forward apart from the buffer, the draws the light passes light.
fn order_gbuffer(draws: &mut DrawLists, nearest: &[f64], front_to_back: bool) {
    if front_to_back {
        // Nearest sphere first (seed 002's front-to-back z-only pass); ties by material.
        draws.gbuffer.sort_by(|a, b| nearest[a.0].total_cmp(&nearest[b.0]).then((a.1, a.2).cmp(&(b.1, b.2))));
    } else {
        // Fewer pipeline and material switches in the G-buffer pass.
        draws.gbuffer.sort_by_key(|&(_, p, m)| (p, m));
    }
    if !draws.forward_opaque.is_empty() {
        let apart: std::collections::HashSet<usize> = draws.forward_opaque.iter().map(|d| d.0).collect();
        draws.lit = draws.gbuffer.iter().copied().filter(|d| !apart.contains(&d.0)).collect();
    }
}
