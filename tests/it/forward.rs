//! The forward pass of blended surfaces: its light lists only skip work, never light (the
//! picture is the same whichever lists it walks), the tile lists are tighter than the objects'
//! where they must be, and the pass is timed and counted on its own.

use crate::common::*;
use lampshade::renderer::{ForwardLights, Settings};
use lampshade::scene::builtin::{self, BuiltinOptions};
use lampshade::Scene;

fn glass(lights: usize) -> Scene {
    builtin::build("glass", BuiltinOptions { lights: Some(lights), time: 0.0 }).expect("glass")
}

/// Pixels that differ at all, and the largest step.
fn differences(a: &image::RgbaImage, b: &image::RgbaImage) -> (usize, u8) {
    let mut n = 0;
    let mut max = 0;
    for (p, q) in a.pixels().zip(b.pixels()) {
        let d = (0..4).map(|k| p[k].abs_diff(q[k])).max().unwrap_or(0);
        if d > 0 {
            n += 1;
            max = max.max(d);
        }
    }
    (n, max)
}

#[test]
fn every_light_list_gives_the_same_picture() {
    // The exact radius, and a hard cut-off (a light ends in a visible step at its radius, so a
    // light wrongly left out of a tile or an object shows); a size that is no multiple of the
    // tile, so the last row and column of tiles are partial.
    let scene = glass(256);
    for cutoff in [0.0, 1.0 / 16.0] {
        for (w, h) in [(160, 90), (203, 117)] {
            let at = |forward_lights| {
                let s = Settings { forward_lights, light_cutoff: cutoff, ..Settings::default() };
                render(&scene, &s, w, h)
            };
            let all = at(ForwardLights::All);
            assert!(lit_share(&all.image) > 0.3, "the glass scene is mostly black");
            for mode in [ForwardLights::Object, ForwardLights::Tiled] {
                let f = at(mode);
                let (n, max) = differences(&all.image, &f.image);
                assert_eq!(
                    n,
                    0,
                    "cut-off {cutoff}, {w}x{h}: '{}' lists change {n} pixels (up to {max} steps) against every light",
                    mode.name()
                );
            }
        }
    }
}

#[test]
fn tile_lists_are_tighter_than_object_lists_on_glass_walls() {
    // Each 120-unit wall's bounding sphere reaches nearly every light, so its object list is
    // nearly all of them; a 16-pixel tile is covered by the screen rectangles of a few.
    let scene = glass(256);
    let n = scene.lights.len() as u32;
    let stats = |forward_lights| render(&scene, &Settings { forward_lights, ..Settings::default() }, 160, 90).stats;
    let (all, object, tiled) = (stats(ForwardLights::All), stats(ForwardLights::Object), stats(ForwardLights::Tiled));
    let (all, object, tiled) = (all.forward.unwrap(), object.forward.unwrap(), tiled.forward.unwrap());
    assert_eq!(all.objects, 17, "five walls and twelve boxes");
    assert_eq!(all.object_list_entries, 17 * n as u64);
    assert_eq!(all.longest_object_list, n);
    assert!(object.longest_object_list > n * 9 / 10, "a wall's list holds {} of {n}", object.longest_object_list);
    assert_eq!((object.tiles, all.tiles), (0, 0), "only 'tiled' builds tile lists");
    assert_eq!(tiled.tiles, 10 * 6, "160x90 in 16-pixel tiles");
    assert!(
        tiled.longest_tile_list * 4 < object.longest_object_list,
        "the longest tile list ({}) is not a quarter of the longest object list ({})",
        tiled.longest_tile_list,
        object.longest_object_list
    );
    // Every fragment walks at most the longest tile list; the mean tile is shorter still.
    assert!(tiled.tile_list_entries < tiled.tiles * tiled.longest_tile_list as u64);
    // The lists change the work per fragment, not the fragments.
    let fragments = all.fragments.expect("the forward pass is counted");
    assert!(fragments > 1000, "the glass covers only {fragments} samples");
    assert_eq!(object.fragments, Some(fragments));
    assert_eq!(tiled.fragments, Some(fragments));
}

#[test]
fn the_forward_pass_is_timed_and_counted_as_its_own_pass() {
    let blended = render(&glass(64), &Settings::default(), 160, 90).stats;
    assert!(blended.gpu_ms.forward.is_some(), "no forward time: {:?}", blended.gpu_ms);
    assert!(blended.gpu_ms.compose.is_some());
    assert!(blended.forward.as_ref().is_some_and(|f| f.fragments.is_some()));
    // Without blended surfaces there is no forward pass to report.
    let demo = render(&scene("demo"), &Settings::default(), 160, 90).stats;
    assert_eq!(demo.gpu_ms.forward, None);
    assert!(demo.forward.is_none());
    assert!(demo.gpu_ms.compose.is_some());
    // Counting off: lists reported, fragments not.
    let quiet = Settings { count_fragments: false, ..Settings::default() };
    let f = render(&glass(64), &quiet, 160, 90).stats.forward.expect("lists are reported");
    assert_eq!(f.fragments, None);
}

/// A glass cube (side 2, bounding sphere radius sqrt 3) seen corner-on, and a point light of
/// radius 1 beyond each corner, on the diagonal at sqrt 3 + 0.92 from the centre: each light's
/// sphere reaches 0.08 into its corner and no further. `reaching` false leaves the lights out.
fn corner_lights(reaching: bool) -> Scene {
    use glam::{DMat4, DVec3, Vec3};
    use lampshade::scene::{AlphaMode, Camera, Light, Material, Mesh, Object, PointLight};
    let camera = Camera::looking_at(DVec3::new(3.2, 2.6, 4.0), DVec3::ZERO);
    let mut s = Scene { meshes: vec![Mesh::cube()], ..Scene::new("corner lights", camera) };
    s.ambient = Vec3::splat(0.02);
    s.materials.push(Material { alpha: 0.6, alpha_mode: AlphaMode::Blend, ..Material::diffuse(Vec3::splat(0.9)) });
    s.objects.push(Object { mesh: 0, material: 0, transform: DMat4::from_scale(DVec3::splat(2.0)), layer: 0 });
    if reaching {
        for k in 0..8 {
            let corner = DVec3::new([-1.0, 1.0][k & 1], [-1.0, 1.0][(k >> 1) & 1], [-1.0, 1.0][k >> 2]);
            let position = corner.normalize() * (3f64.sqrt() + 0.92);
            s.lights_mut().push(Light::Point(PointLight {
                position,
                color: Vec3::ONE,
                intensity: 60.0,
                radius: 1.0,
                cast_shadows: true,
                cookie: None,
                mask: lampshade::scene::ALL_LAYERS,
            }));
        }
    }
    s
}

#[test]
fn lights_that_just_reach_a_corner_are_kept() {
    let scene = corner_lights(true);
    let at = |forward_lights| render(&scene, &Settings { forward_lights, ..Settings::default() }, 160, 90);
    let all = at(ForwardLights::All);
    // The lights matter: without them the corners are darker.
    let dark = render(&corner_lights(false), &Settings::default(), 160, 90);
    let (lit, _) = differences(&all.image, &dark.image);
    assert!(lit >= 10, "the corner lights change only {lit} pixels");
    for mode in [ForwardLights::Object, ForwardLights::Tiled] {
        let f = at(mode);
        let lists = f.stats.forward.clone().unwrap();
        assert_eq!(lists.object_list_entries, 8, "'{}': every light reaches the cube's bounds", mode.name());
        let (n, max) = differences(&all.image, &f.image);
        assert_eq!(n, 0, "'{}' lists change {n} pixels (up to {max} steps)", mode.name());
    }
}

/// Every visible point a light can reach lies in a tile whose list holds the light (checked on
/// the CPU against the plan's lists, at sampled points inside each light's true shape: the
/// cut-off radius, and the cone for spots).
#[test]
fn every_point_a_light_reaches_is_in_a_tile_that_lists_it() {
    use glam::{Vec2, Vec3, Vec4Swizzles};
    use lampshade::renderer::plan::{FramePlan, PlanView};
    use lampshade::renderer::records::FrameRecords;
    use lampshade::renderer::volumes::Volumes;
    use lampshade::renderer::CullingMode;
    let scene = glass(256);
    let (w, h) = (203u32, 117u32);
    for cutoff in [0.0, 1.0 / 16.0] {
        let settings = Settings { light_cutoff: cutoff, ..Settings::default() };
        let mut records = FrameRecords::new(&scene, &settings.options(), (w, h), wgpu::TextureFormat::Rgba16Float);
        let proj = records.proj.as_mat4();
        let view = PlanView {
            proj,
            near: scene.camera.near as f32,
            far: scene.camera.far as f32,
            size: (w, h),
            mode: CullingMode::Volume,
            depth_clamp: true,
            forward_lights: ForwardLights::Tiled,
            light_batching: true,
            cluster_build: lampshade::renderer::settings::ClusterBuilder::Cpu,
            grid: Default::default(),
            object_cap: (0, Default::default()),
            loop_limit: None,
            near_fullscreen: false,
            front_to_back: false,
            sort_blended: true,
            prepass_models: None,
            costs: Default::default(),
        };
        let bounds: Vec<(glam::DVec3, f64)> = scene
            .meshes
            .iter()
            .map(|m| {
                let r = m.vertices.iter().map(|v| Vec3::from(v.position).length() as f64).fold(0.0, f64::max);
                (glam::DVec3::ZERO, r)
            })
            .collect();
        let volumes = Volumes::new(&gpu().device, (settings.sphere_subdivisions, settings.cone_sides));
        let plan = FramePlan::new(&scene, &mut records, &bounds, &volumes, &view);
        let [tile, tx, _, header] = records.camera.forward_tiles;
        assert_eq!(tile, 16);
        let lists = &plan.light_lists;
        let in_objects: std::collections::HashSet<u32> = records
            .objects
            .iter()
            .filter(|o| o.info[2] > 0)
            .flat_map(|o| lists[o.info[1] as usize..(o.info[1] + o.info[2]) as usize].iter().copied())
            .collect();
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 40) as f32) / (1u64 << 24) as f32
        };
        let mut checked = 0;
        for (k, l) in records.lights.iter().enumerate() {
            if !in_objects.contains(&(k as u32)) {
                continue;
            }
            let centre = Vec3::from(l.position);
            for _ in 0..400 {
                let d = Vec3::new(rnd() * 2.0 - 1.0, rnd() * 2.0 - 1.0, rnd() * 2.0 - 1.0);
                if d.length() > 1.0 || d.length() < 1e-3 {
                    continue;
                }
                // Mostly near the surface, where a list's edge would show.
                let p = centre + d.normalize() * l.radius * (0.9 + 0.0999 * rnd());
                if l.kind == lampshade::renderer::LIGHT_KIND_SPOT
                    && (p - centre).normalize().dot(Vec3::from(l.direction)) <= l.cos_outer
                {
                    continue;
                }
                let c = proj * p.extend(1.0);
                if -p.z <= view.near || c.w <= 0.0 {
                    continue;
                }
                let ndc = c.xy() / c.w;
                if ndc.abs().max_element() >= 1.0 {
                    continue;
                }
                let px = Vec2::new((ndc.x + 1.0) * 0.5 * w as f32, (1.0 - ndc.y) * 0.5 * h as f32);
                let t = (px.y as u32 / tile) * tx + px.x as u32 / tile;
                let at = (header + 2 * t) as usize;
                let list = &lists[lists[at] as usize..(lists[at] + lists[at + 1]) as usize];
                assert!(
                    list.contains(&(k as u32)),
                    "cut-off {cutoff}: light {k} reaches pixel {px} but tile {t} leaves it out"
                );
                checked += 1;
            }
        }
        assert!(checked > 10_000, "only {checked} points checked");
    }
}
