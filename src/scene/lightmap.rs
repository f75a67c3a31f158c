//! Seed 004's lightmaps, baked: "Lightmaps are also applied in the final pass. Close to the
//! camera, realtime lighting is used, and only baked indirect lighting is added. This
//! crossfades into fully baked lighting further away from the camera."
//!
//! [`bake`] computes, for every opaque object whose mesh has a second texture coordinate set
//! (the built-in cube lays its faces out for one, [`super::cube_lightmap_uv`]), the diffuse
//! irradiance at each texel's surface point from the scene's two distant lights:
//! - the ambient, a uniform sky of radiance `ambient`, seen through the point's occlusion
//!   (cosine-weighted rays, `rays` of them, blocked by any opaque triangle within
//!   `occlusion_distance`): `ambient x AO`, the "baked indirect lighting";
//! - the sun, `colour x intensity x max(N.L, 0)` where a ray towards it is not blocked (the
//!   project's CPU ray check, `scene::occluders::Occluders`).
//!
//! These are the renderer's own terms for a Lambert surface (`ambient_diffuse`, `sun_light`),
//! so on an unoccluded, unshadowed surface the baked and the realtime lighting agree up to the
//! texture's rounding. Stored in linear RGBA8 ([`super::Lightmap`]): RGB the irradiance over
//! a per-object `scale` (its largest channel), A the occlusion. The rounding is at most half
//! a step, `scale / 510` per channel, and bilinear filtering between texels blends
//! neighbouring points' values.
//!
//! [`save`] writes `lightmaps.json` and one PNG per object to a folder; [`load`] reads them
//! back for the same scene and [`apply`] gives each baked object its lightmap (a copy of its
//! material with the map).

use super::{Lightmap, Scene, Texture, Topology};
use anyhow::{bail, Context, Result};
use glam::{DMat3, DVec2, DVec3};
use serde::{Deserialize, Serialize};

/// What a bake computes, and how finely.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct BakeOptions {
    /// Texels along a cube face's cell; the map is `3 texels x 2 texels`.
    pub texels: u32,
    /// Occlusion rays per texel.
    pub rays: u32,
    /// How far an occluder may be and still shade the ambient (world units).
    pub occlusion_distance: f64,
}

impl Default for BakeOptions {
    fn default() -> Self {
        Self { texels: 16, rays: 64, occlusion_distance: 4.0 }
    }
}

/// One object's baked map.
#[derive(Clone, Debug)]
pub struct BakedObject {
    pub object: usize,
    pub texture: Texture,
    pub scale: f32,
}

/// A scene's bake.
#[derive(Clone, Debug)]
pub struct Baked {
    pub scene: String,
    pub options: BakeOptions,
    pub objects: Vec<BakedObject>,
    /// Objects left out, and why (no second texture coordinate set, blended, not triangles).
    pub skipped: Vec<(usize, String)>,
}

/// The `i`-th of `n` directions of a cosine-weighted hemisphere around +Z (Hammersley points,
/// Malley's method: uniform points on the disc projected up).
fn cosine_direction(i: u32, n: u32) -> DVec3 {
    let u = (i as f64 + 0.5) / n as f64;
    let v = (i.reverse_bits() as f64) / (u32::MAX as f64 + 1.0);
    let r = u.sqrt();
    let phi = std::f64::consts::TAU * v;
    DVec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u).max(0.0).sqrt())
}

/// Bakes every object that can hold a lightmap; `progress(done, total)` after each.
pub fn bake(scene: &Scene, options: &BakeOptions, mut progress: impl FnMut(usize, usize)) -> Result<Baked> {
    scene.validate().map_err(anyhow::Error::msg)?;
    if options.texels == 0 || options.texels > 256 || options.rays == 0 || options.rays > 4096 {
        bail!("bake: texels must be 1..=256 and rays 1..=4096 (got {} and {})", options.texels, options.rays);
    }
    if !(options.occlusion_distance.is_finite() && options.occlusion_distance > 0.0) {
        bail!("bake: the occlusion distance must be a positive number");
    }
    let occluders = super::occluders::Occluders::of(scene);
    let (w, h) = (3 * options.texels, 2 * options.texels);
    let mut baked = Baked { scene: scene.name.clone(), options: *options, objects: Vec::new(), skipped: Vec::new() };
    let total = scene.objects.len();
    for (k, o) in scene.objects.iter().enumerate() {
        progress(k, total);
        let mesh = &scene.meshes[o.mesh];
        let material = &scene.materials[o.material];
        let why = if mesh.topology != Topology::Triangles {
            Some("not triangles")
        } else if material.is_blended() {
            Some("blended")
        } else if mesh.vertices.iter().all(|v| v.uv1 == [0.0, 0.0]) {
            Some("no second texture coordinate set")
        } else {
            None
        };
        if let Some(why) = why {
            baked.skipped.push((k, why.into()));
            continue;
        }
        let normal_matrix = DMat3::from_mat4(o.transform).inverse().transpose();
        // Each texel's surface point and normal: the triangles rasterised in TEXCOORD_1 space
        // at texel centres.
        let mut points: Vec<Option<(DVec3, DVec3)>> = vec![None; (w * h) as usize];
        for t in mesh.indices.chunks_exact(3) {
            let v = [t[0], t[1], t[2]].map(|i| &mesh.vertices[i as usize]);
            let uv = v.map(|v| DVec2::new(v.uv1[0] as f64 * w as f64, v.uv1[1] as f64 * h as f64));
            let area = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]);
            if area.abs() < 1e-12 {
                continue;
            }
            let lo = uv[0].min(uv[1]).min(uv[2]).floor().max(DVec2::ZERO);
            let hi = uv[0].max(uv[1]).max(uv[2]).ceil().min(DVec2::new(w as f64, h as f64));
            for y in lo.y as u32..hi.y as u32 {
                for x in lo.x as u32..hi.x as u32 {
                    let c = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                    let b0 = (uv[1] - c).perp_dot(uv[2] - c) / area;
                    let b1 = (uv[2] - c).perp_dot(uv[0] - c) / area;
                    let b2 = 1.0 - b0 - b1;
                    if b0 < -1e-9 || b1 < -1e-9 || b2 < -1e-9 {
                        continue;
                    }
                    let p = |a: [f32; 3]| DVec3::from(a.map(f64::from));
                    let local = p(v[0].position) * b0 + p(v[1].position) * b1 + p(v[2].position) * b2;
                    let n = p(v[0].normal) * b0 + p(v[1].normal) * b1 + p(v[2].normal) * b2;
                    let world = o.transform.transform_point3(local);
                    let normal = (normal_matrix * n).normalize_or_zero();
                    if normal != DVec3::ZERO {
                        points[(y * w + x) as usize] = Some((world, normal));
                    }
                }
            }
        }
        let mut texels: Vec<Option<[f64; 4]>> =
            points.iter().map(|p| p.map(|(p, n)| irradiance(scene, &occluders, options, p, n))).collect();
        dilate(&mut texels, w, h);
        let scale = texels.iter().flatten().flat_map(|t| t[..3].to_vec()).fold(1e-6f64, f64::max);
        let mut rgba = Vec::with_capacity((w * h * 4) as usize);
        for t in &texels {
            let t = t.unwrap_or([0.0; 4]);
            let q = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
            rgba.extend([q(t[0] / scale), q(t[1] / scale), q(t[2] / scale), q(t[3])]);
        }
        let texture = Texture { name: format!("lightmap of object {k}"), width: w, height: h, srgb: false, rgba };
        baked.objects.push(BakedObject { object: k, texture, scale: scale as f32 });
    }
    progress(total, total);
    Ok(baked)
}

/// Irradiance (RGB) and occlusion (A) at `p` with normal `n`.
fn irradiance(scene: &Scene, occluders: &super::occluders::Occluders, o: &BakeOptions, p: DVec3, n: DVec3) -> [f64; 4] {
    // Off the surface by more than the f64 hit test's tolerance, as the shadow tests' rays.
    let from = p + n * 1e-4 * (1.0 + p.length());
    let (t1, t2) = {
        let t = n.any_orthonormal_vector();
        (t, n.cross(t))
    };
    let open = (0..o.rays)
        .filter(|&i| {
            let d = cosine_direction(i, o.rays);
            let dir = t1 * d.x + t2 * d.y + n * d.z;
            !occluders.blocked(from, from + dir * o.occlusion_distance)
        })
        .count();
    let ao = open as f64 / o.rays as f64;
    let mut e = scene.ambient.as_dvec3() * ao;
    if let Some(sun) = scene.sun {
        let l = (-sun.direction.as_dvec3()).normalize_or_zero();
        let ndl = n.dot(l);
        if ndl > 0.0 && !occluders.blocked(from, from + l * 1e4) {
            e += (sun.color * sun.intensity).as_dvec3() * ndl;
        }
    }
    [e.x, e.y, e.z, ao]
}

/// Fills texels no triangle covers (the gutters between faces) from covered neighbours, so
/// bilinear filtering at a face's edge never reads an empty texel.
fn dilate(texels: &mut [Option<[f64; 4]>], w: u32, h: u32) {
    for _ in 0..4 {
        let before = texels.to_vec();
        for y in 0..h as i64 {
            for x in 0..w as i64 {
                if before[(y * w as i64 + x) as usize].is_some() {
                    continue;
                }
                let near = [(-1, 0), (1, 0), (0, -1), (0, 1)].iter().find_map(|(dx, dy)| {
                    let (a, b) = (x + dx, y + dy);
                    (a >= 0 && b >= 0 && a < w as i64 && b < h as i64)
                        .then(|| before[(b * w as i64 + a) as usize])
                        .flatten()
                });
                texels[(y * w as i64 + x) as usize] = near;
            }
        }
    }
}

/// `lightmaps.json`: what [`save`] writes beside the PNGs.
#[derive(Serialize, Deserialize)]
struct Index {
    scene: String,
    objects: usize,
    options: BakeOptions,
    maps: Vec<IndexEntry>,
}

#[derive(Serialize, Deserialize)]
struct IndexEntry {
    object: usize,
    file: String,
    scale: f32,
}

/// Writes `baked` to `dir` (made if absent): `lightmaps.json` and `object_K.png` per map.
pub fn save(baked: &Baked, objects: usize, dir: &std::path::Path) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let mut maps = Vec::new();
    for b in &baked.objects {
        let file = format!("object_{}.png", b.object);
        let image = image::RgbaImage::from_raw(b.texture.width, b.texture.height, b.texture.rgba.clone())
            .context("internal: a lightmap's size and bytes disagree")?;
        image.save(dir.join(&file)).with_context(|| format!("cannot write {}", dir.join(&file).display()))?;
        maps.push(IndexEntry { object: b.object, file, scale: b.scale });
    }
    let index = Index { scene: baked.scene.clone(), objects, options: baked.options, maps };
    let path = dir.join("lightmaps.json");
    std::fs::write(&path, serde_json::to_string_pretty(&index)?)
        .with_context(|| format!("cannot write {}", path.display()))
}

/// Reads a bake [`save`] wrote for `scene`: the scene's name and object count must be the
/// bake's, and every map a readable PNG of an object with a second texture coordinate set.
pub fn load(dir: &std::path::Path, scene: &Scene) -> Result<Baked> {
    let path = dir.join("lightmaps.json");
    let text = std::fs::read_to_string(&path).with_context(|| format!("cannot read {}", path.display()))?;
    let index: Index =
        serde_json::from_str(&text).with_context(|| format!("{} is not a lightmap index", path.display()))?;
    if index.scene != scene.name || index.objects != scene.objects.len() {
        bail!(
            "{}: baked for scene '{}' with {} objects, not '{}' with {}; bake it again (`lampshade bake`)",
            path.display(),
            index.scene,
            index.objects,
            scene.name,
            scene.objects.len()
        );
    }
    let mut objects = Vec::new();
    for e in index.maps {
        let Some(o) = scene.objects.get(e.object) else {
            bail!("{}: object {} does not exist", path.display(), e.object)
        };
        if scene.meshes[o.mesh].vertices.iter().all(|v| v.uv1 == [0.0, 0.0]) {
            bail!("{}: object {} has no second texture coordinate set", path.display(), e.object);
        }
        if !(e.scale.is_finite() && e.scale > 0.0) {
            bail!("{}: object {}'s scale {} is not a positive number", path.display(), e.object, e.scale);
        }
        let file = dir.join(&e.file);
        let image = image::open(&file).with_context(|| format!("cannot read {}", file.display()))?.to_rgba8();
        let texture = Texture {
            name: format!("lightmap {}", e.file),
            width: image.width(),
            height: image.height(),
            srgb: false,
            rgba: image.into_raw(),
        };
        objects.push(BakedObject { object: e.object, texture, scale: e.scale });
    }
    Ok(Baked { scene: index.scene, options: index.options, objects, skipped: Vec::new() })
}

/// Gives each baked object its map: a copy of its material with the lightmap, the texture
/// added to the scene.
pub fn apply(scene: &mut Scene, baked: &Baked) {
    for b in &baked.objects {
        scene.textures.push(std::sync::Arc::new(b.texture.clone()));
        let texture = scene.textures.len() - 1;
        let Some(o) = scene.objects.get(b.object) else { continue };
        let mut m = scene.materials[o.material];
        m.lightmap = Some(Lightmap { texture, scale: b.scale });
        scene.materials.push(m);
        let material = scene.materials.len() - 1;
        scene.objects[b.object].material = material;
    }
}

/// Whether any material of `scene` has a lightmap.
pub fn any(scene: &Scene) -> bool {
    scene.materials.iter().any(|m| m.lightmap.is_some())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Camera, Material, Mesh, Object, Sun};
    use glam::{DMat4, Vec2, Vec3};

    /// A 20 x 20 floor (top at y = 0) with a 2-unit cube on it at the origin, a sun from the
    /// +x side, some ambient.
    fn yard() -> Scene {
        let mut s = Scene::new("yard", Camera::looking_at(DVec3::new(0.0, 5.0, 10.0), DVec3::ZERO));
        s.meshes.push(Mesh::cube());
        s.materials.push(Material::default());
        s.ambient = Vec3::splat(0.2);
        s.sun = Some(Sun { direction: Vec3::new(-1.0, -1.0, 0.0).normalize(), color: Vec3::ONE, intensity: 0.5 });
        let boxed = |min: DVec3, max: DVec3| Object {
            mesh: 0,
            material: 0,
            transform: DMat4::from_translation((min + max) * 0.5) * DMat4::from_scale(max - min),
            layer: 0,
        };
        s.objects.push(boxed(DVec3::new(-10.0, -1.0, -10.0), DVec3::new(10.0, 0.0, 10.0)));
        s.objects.push(boxed(DVec3::new(-1.0, 0.0, -1.0), DVec3::new(1.0, 2.0, 1.0)));
        s
    }

    #[test]
    fn the_bake_holds_ambient_through_occlusion_and_the_sun_through_visibility() {
        let scene = yard();
        let o = BakeOptions { texels: 16, rays: 256, occlusion_distance: 4.0 };
        let occ = crate::scene::occluders::Occluders::of(&scene);
        let up = DVec3::Y;
        let open = DVec3::new(7.0, 0.0, 7.0);
        // Open floor: the whole sky, and the sun at N.L = cos 45 degrees.
        let e = irradiance(&scene, &occ, &o, open, up);
        let expected = 0.2 + 0.5 * std::f64::consts::FRAC_1_SQRT_2;
        assert!((e[0] - expected).abs() < 1e-6 && e[3] == 1.0, "open floor: {e:?}");
        // In the cube's shadow (the sun comes from +x, down at 45 degrees; the cube's top edge
        // at x = 1, y = 2 shadows the floor to x = -3): no sun, and part of the sky hidden.
        let shadowed = irradiance(&scene, &occ, &o, DVec3::new(-2.0, 0.0, 0.0), up);
        assert!(shadowed[3] < 1.0 && (shadowed[0] - 0.2 * shadowed[3]).abs() < 1e-6, "in shadow: {shadowed:?}");
        // At the cube's foot about a quarter of the sky is the cube's side.
        let foot = irradiance(&scene, &occ, &o, DVec3::new(1.05, 0.0, 0.0), up);
        assert!(foot[3] > 0.4 && foot[3] < 0.8, "at the foot: occlusion {}", foot[3]);
        // The baked texel over the open point decodes to its irradiance within half a step.
        let baked = bake(&scene, &o, |_, _| {}).expect("bake");
        assert_eq!(baked.objects.len(), 2);
        let floor = &baked.objects[0];
        let (w, h) = (floor.texture.width, floor.texture.height);
        assert_eq!((w, h), (48, 32));
        // The floor's top face: +Y, face 2; its u runs along x, v along z over 20 units.
        let uv =
            crate::scene::cube_lightmap_uv(2, Vec2::new((open.x / 20.0 + 0.5) as f32, (open.z / 20.0 + 0.5) as f32));
        let (x, y) = ((uv.x * w as f32) as u32, (uv.y * h as f32) as u32);
        let t = &floor.texture.rgba[((y * w + x) * 4) as usize..][..4];
        let decoded = t[0] as f64 / 255.0 * floor.scale as f64;
        assert!((decoded - expected).abs() <= floor.scale as f64 / 510.0 + 1e-9, "texel {t:?} decodes to {decoded}");
        assert_eq!(t[3], 255, "open floor's occlusion");
        // Every texel is written (the gutters dilated) and the scale is the brightest value.
        let brightest = floor.texture.rgba.chunks_exact(4).map(|p| p[0].max(p[1]).max(p[2])).max();
        assert_eq!(brightest, Some(255));
    }

    #[test]
    fn the_occlusion_rays_are_cosine_weighted_over_the_hemisphere() {
        // The mean of cos(theta) over a cosine-weighted hemisphere is 2/3; every ray is above
        // the surface and of unit length.
        let n = 4096;
        let mean: f64 = (0..n).map(|i| cosine_direction(i, n).z).sum::<f64>() / n as f64;
        assert!((mean - 2.0 / 3.0).abs() < 1e-3, "mean cos {mean}");
        assert!((0..n).all(|i| {
            let d = cosine_direction(i, n);
            d.z > 0.0 && (d.length() - 1.0).abs() < 1e-9
        }));
    }
}
