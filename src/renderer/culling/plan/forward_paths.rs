//! The forward paths' per-object light lists, and the multi-pass path's (object, light) pairs.

use super::draws::{world_sphere, MAX_FORWARD_LIST_ENTRIES};
use super::{Draw, LightPlan};
use crate::scene::Scene;
use glam::{DVec3, Vec2};

/// One (object, light) draw of the forward multi-pass path: the object's draw, the light, and
/// the scissor rectangle (x, y, width, height in pixels) of the light's screen rectangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForwardPair {
    pub draw: Draw,
    pub light: u32,
    pub scissor: [u32; 4],
}

/// The forward paths' lists (seed 002), appended to the frame's light lists.
#[derive(Clone, Debug, Default)]
pub struct ForwardPathLists {
    /// Objects drawn (opaque and masked: the G-buffer list's), their list entries summed, and
    /// the longest list.
    pub objects: usize,
    pub list_entries: u64,
    pub longest_list: u32,
    /// Multi-pass only: one draw per (object, light) pair whose scissor rectangle is not
    /// empty, in object order.
    pub pairs: Vec<ForwardPair>,
    /// Instance index of the first pair: pair `j` is `light_lists[2 (pair_base + j)]` (object)
    /// and `light_lists[2 (pair_base + j) + 1]` (light).
    pub pair_base: u32,
    /// Each drawn object's list: (object, first entry in the frame's light lists, count).
    pub spans: Vec<(usize, u32, u32)>,
    /// Entries the per-object cap left out (`Settings::lights_per_object`).
    pub capped: u64,
}

/// A light's screen rectangle in pixels (x, y, width, height; y down), widened by a pixel
/// against rounding as the forward tiles' (`plan_draws`) and clipped to the screen; `None` when
/// it covers no pixel.
pub fn scissor_rect(rect: Option<(Vec2, Vec2)>, (w, h): (u32, u32)) -> Option<[u32; 4]> {
    let (lo, hi) = rect?;
    let px = |x: f32| ((x + 1.0) * 0.5 * w as f32).floor() - 1.0;
    let py = |y: f32| ((1.0 - y) * 0.5 * h as f32).floor() - 1.0;
    let (x0, x1) = (px(lo.x).max(0.0), (px(hi.x) + 3.0).min(w as f32));
    let (y0, y1) = (py(hi.y).max(0.0), (py(lo.y) + 3.0).min(h as f32));
    if !(x1 > x0 && y1 > y0) {
        return None;
    }
    Some([x0 as u32, y0 as u32, (x1 - x0) as u32, (y1 - y0) as u32])
}

/// The forward paths' per-object light lists (seed 002: "each object's light list"): for every
/// object in `opaque` (the G-buffer draw list), the lights whose sphere reaches the object's
/// bounding sphere and that reach the screen at all (`screen_rect`), in light order, appended to
/// `lists`; the object's record gets their offset and count (`info.y`, `info.z`, as blended
/// objects'). This list is the forward paths' light culling: a light is left out of an object
/// only where it cannot reach it, so the culling mode, which picks how deferred draws light
/// volumes, changes nothing here. With `pairs` (multi-pass) the (object, light) pairs follow,
/// two entries each, for the additive draws. With `all` (`ForwardLights::All`) nothing is
/// culled: every light is in every object's list, and every pair draws full screen, the
/// unculled reference the culling oracle holds the lists against. Errors when the lists
/// outgrow one storage buffer.
#[allow(clippy::too_many_arguments)]
pub fn forward_path_lists(
    scene: &Scene,
    objects: &mut [crate::renderer::records::ObjectRecord],
    bounds: &[(DVec3, f64)],
    plans: &[LightPlan],
    opaque: &[Draw],
    size: (u32, u32),
    lists: &mut Vec<u32>,
    (pairs, all): (bool, bool),
    (cap, order): (u32, crate::renderer::caps::CapOrder),
) -> Result<ForwardPathLists, String> {
    let mut out = ForwardPathLists::default();
    let screen = [0, 0, size.0.max(1), size.1.max(1)];
    let scissors: Vec<Option<[u32; 4]>> =
        plans.iter().map(|p| if all { Some(screen) } else { scissor_rect(p.screen_rect, size) }).collect();
    let mut pair_list: Vec<ForwardPair> = Vec::new();
    for &draw in opaque {
        let i = draw.0;
        let (Some(o), Some(record)) = (scene.objects.get(i), objects.get_mut(i)) else { continue };
        let (centre, radius) = world_sphere(o, bounds);
        let first = lists.len() as u32;
        for (k, l) in scene.lights.iter().enumerate() {
            if scissors.get(k).copied().flatten().is_none() {
                continue;
            }
            if all || (l.position() - centre).length() < radius + l.radius() as f64 {
                lists.push(k as u32);
            }
        }
        if cap > 0 && lists.len() - first as usize > cap as usize {
            // The per-object cap (`caps`): the object's `cap` nearest or brightest lights, or
            // its first, measured at its bounding sphere's centre.
            let at = |i: u32| {
                let l = &scene.lights[i as usize];
                (l.position().as_vec3(), l.radius(), crate::renderer::caps::peak(l))
            };
            let kept = crate::renderer::caps::keep_nearest_or_brightest(
                &lists[first as usize..],
                cap as usize,
                order,
                centre.as_vec3(),
                at,
            );
            out.capped += (lists.len() - first as usize - kept.len()) as u64;
            lists.truncate(first as usize);
            lists.extend(kept);
        }
        if pairs {
            for &k in &lists[first as usize..] {
                if let Some(scissor) = scissors.get(k as usize).copied().flatten() {
                    pair_list.push(ForwardPair { draw, light: k, scissor });
                }
            }
        }
        let count = lists.len() as u32 - first;
        out.spans.push((i, first, count));
        record.info[1] = first;
        record.info[2] = count;
        out.objects += 1;
        out.list_entries += count as u64;
        out.longest_list = out.longest_list.max(count);
        if lists.len() > MAX_FORWARD_LIST_ENTRIES {
            return Err(format!(
                "the forward light lists would hold more than {MAX_FORWARD_LIST_ENTRIES} entries; use fewer lights or --path deferred"
            ));
        }
    }
    if pairs {
        if lists.len() % 2 == 1 {
            lists.push(0);
        }
        out.pair_base = (lists.len() / 2) as u32;
        if lists.len() + 2 * pair_list.len() > MAX_FORWARD_LIST_ENTRIES {
            return Err(format!(
                "the forward multi-pass path would draw {} (object, light) pairs, more than one storage buffer lists; \
                 use fewer lights or --path forward",
                pair_list.len()
            ));
        }
        for p in &pair_list {
            lists.extend([p.draw.0 as u32, p.light]);
        }
        out.pairs = pair_list;
    }
    Ok(out)
}
