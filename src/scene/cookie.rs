//! Light cookies (seed 004: "All lights can have Cookies"): a texture projected by a light. A
//! spot projects a square 2D image through its cone; a point light projects a cube (six square
//! faces). The texels are linear RGBA8 (a cookie is a filter on the light's colour, not a
//! picture: no sRGB decoding); only RGB is used.
//!
//! The shaders read the texels from one storage buffer (`cookie_texels`, every cookie's faces
//! one after the other, one `u32` per texel) and filter them themselves, bilinearly with
//! clamp-to-edge addressing at texel centres (`ls_cookie` in `kit/common.wgsl`). The f64
//! reference ([`CookieImage::sample`], [`cube_face_uv`], [`spot_uv`]) does the same arithmetic,
//! so its error against the GPU is f32 rounding only (see `tests/it/cookies_masks.rs`).
//!
//! Built-in cookies: `window` (a window frame: 2x2 panes, bright glass inside dark bars and a
//! dark outer frame) and `flashlight` (a soft disc with a brighter ring, as a torch's
//! reflector throws). For a point light each is drawn on all six faces of the cube.
//! A PNG file for a spot is one square image; for a point light a horizontal strip of six
//! squares, faces +X, -X, +Y, -Y, +Z, -Z (world axes; each face as a cube map's face is
//! addressed, `cube_face_uv`).

use glam::{DVec2, DVec3};
use std::path::Path;

/// The built-in cookies by name.
pub const BUILTIN: [&str; 2] = ["window", "flashlight"];
/// Side of the built-in cookies' faces.
pub const BUILTIN_SIZE: u32 = 64;
/// Largest side of a cookie face read from a file.
pub const MAX_SIZE: u32 = 2048;

/// One cookie: one face (a spot's) or six (a point light's cube), `size`x`size` RGBA8 each.
#[derive(Clone, Debug, PartialEq)]
pub struct CookieImage {
    /// A built-in name or the file's path.
    pub name: String,
    pub size: u32,
    /// One or six faces, row-major from the top row, RGBA8 linear.
    pub faces: Vec<Vec<u8>>,
    /// Unique per image made (built-in or read): what the renderer keys its upload on, so a
    /// new image is uploaded even where the allocator reuses an old one's address.
    id: u64,
}

fn next_id() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

impl CookieImage {
    /// This image's identity (see the field).
    pub fn id(&self) -> u64 {
        self.id
    }

    pub fn is_cube(&self) -> bool {
        self.faces.len() == 6
    }

    /// The texels as the shaders read them: one `u32` per texel, R in the low byte.
    pub fn words(&self) -> impl Iterator<Item = u32> + '_ {
        self.faces.iter().flat_map(|f| f.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])))
    }

    /// Texel (x, y) of `face`, clamped to the edge, RGB in [0, 1].
    fn texel(&self, face: usize, x: i64, y: i64) -> DVec3 {
        let n = self.size as i64 - 1;
        let (x, y) = (x.clamp(0, n) as usize, y.clamp(0, n) as usize);
        let i = (y * self.size as usize + x) * 4;
        let f = &self.faces[face];
        DVec3::new(f[i] as f64, f[i + 1] as f64, f[i + 2] as f64) / 255.0
    }

    /// Bilinear sample of `face` at `uv` (0..1 across the face, texel centres at (k + 0.5) /
    /// size), clamp-to-edge: the f64 twin of `ls_cookie_sample`.
    pub fn sample(&self, face: usize, uv: DVec2) -> DVec3 {
        let s = self.size as f64;
        let t = (uv * s - 0.5).clamp(DVec2::splat(-1.0), DVec2::splat(s));
        let i = t.floor();
        let f = t - i;
        let (x, y) = (i.x as i64, i.y as i64);
        let a = self.texel(face, x, y).lerp(self.texel(face, x + 1, y), f.x);
        let b = self.texel(face, x, y + 1).lerp(self.texel(face, x + 1, y + 1), f.x);
        a.lerp(b, f.y)
    }

    /// The largest difference of one channel between two neighbouring texels (across or
    /// down) of any face: how fast the bilinear sample can change, per texel moved.
    pub fn max_step(&self) -> f64 {
        let mut m = 0u8;
        let n = self.size as usize;
        for f in &self.faces {
            for y in 0..n {
                for x in 0..n {
                    for c in 0..3 {
                        let v = f[(y * n + x) * 4 + c];
                        if x + 1 < n {
                            m = m.max(v.abs_diff(f[(y * n + x + 1) * 4 + c]));
                        }
                        if y + 1 < n {
                            m = m.max(v.abs_diff(f[((y + 1) * n + x) * 4 + c]));
                        }
                    }
                }
            }
        }
        m as f64 / 255.0
    }

    /// A built-in cookie (`window`, `flashlight`): one face, or the same on six for a cube.
    pub fn builtin(name: &str, cube: bool) -> Option<CookieImage> {
        let n = BUILTIN_SIZE;
        let texel: fn(f64, f64) -> f64 = match name {
            // 2x2 panes: dark bars 1/8 wide through the middle, a dark frame 1/10 wide.
            "window" => |u, v| {
                let frame = u.min(v).min(1.0 - u).min(1.0 - v) < 0.1;
                let bar = (u - 0.5).abs() < 0.0625 || (v - 0.5).abs() < 0.0625;
                if frame || bar {
                    0.06
                } else {
                    1.0
                }
            },
            // A soft disc: full inside r 0.3, a brighter ring at 0.33, fading to 0 at 0.48.
            "flashlight" => |u, v| {
                let r = ((u - 0.5).powi(2) + (v - 0.5).powi(2)).sqrt();
                let disc = 1.0 - ((r - 0.3) / 0.18).clamp(0.0, 1.0);
                let disc = disc * disc * (3.0 - 2.0 * disc);
                let ring = (-((r - 0.33) / 0.03).powi(2)).exp() * 0.25;
                (0.75 * disc + ring).min(1.0)
            },
            _ => return None,
        };
        let mut face = Vec::with_capacity((n * n * 4) as usize);
        for y in 0..n {
            for x in 0..n {
                let v = texel((x as f64 + 0.5) / n as f64, (y as f64 + 0.5) / n as f64);
                let b = (v * 255.0).round() as u8;
                face.extend([b, b, b, 255]);
            }
        }
        let faces = if cube { vec![face; 6] } else { vec![face] };
        Some(CookieImage { name: name.into(), size: n, faces, id: next_id() })
    }

    /// A cookie from a PNG file: square for a spot, a strip of six squares (6n x n) for a point
    /// light's cube. Errors name the file and the problem.
    pub fn load(path: &Path, cube: bool) -> Result<CookieImage, String> {
        let shown = path.display();
        let meta = std::fs::metadata(path).map_err(|e| format!("cookie {shown}: {e}"))?;
        if !meta.is_file() || meta.len() > 256 << 20 {
            return Err(format!("cookie {shown}: not a regular file of at most 256 MiB"));
        }
        let bytes = std::fs::read(path).map_err(|e| format!("cookie {shown}: {e}"))?;
        let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes));
        reader.set_format(image::ImageFormat::Png);
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_SIZE * 6);
        limits.max_image_height = Some(MAX_SIZE);
        limits.max_alloc = Some(512 << 20);
        reader.limits(limits);
        let img = reader.decode().map_err(|e| format!("cookie {shown}: not a readable PNG image ({e})"))?.to_rgba8();
        let (w, h) = img.dimensions();
        let want = if cube {
            "a strip of six square faces (width = 6 x height) for a point light"
        } else {
            "square for a spot light"
        };
        let ok = if cube { w == 6 * h } else { w == h };
        if !ok || h == 0 {
            return Err(format!("cookie {shown}: {w}x{h} pixels; a cookie must be {want}"));
        }
        let raw = img.into_raw();
        let n = h as usize;
        let faces = if cube {
            (0..6)
                .map(|f| {
                    let mut face = Vec::with_capacity(n * n * 4);
                    for y in 0..n {
                        let row = (y * 6 * n + f * n) * 4;
                        face.extend_from_slice(&raw[row..row + n * 4]);
                    }
                    face
                })
                .collect()
        } else {
            vec![raw]
        };
        Ok(CookieImage { name: path.display().to_string(), size: h, faces, id: next_id() })
    }

    /// A built-in name or a PNG path.
    pub fn resolve(spec: &str, cube: bool) -> Result<CookieImage, String> {
        match Self::builtin(spec, cube) {
            Some(c) => Ok(c),
            None if spec.to_ascii_lowercase().ends_with(".png") => Self::load(Path::new(spec), cube),
            None => {
                Err(format!("cookie \"{spec}\": neither a built-in cookie ({}) nor a .png file", BUILTIN.join(", ")))
            }
        }
    }
}

/// The cube face (0..6: +X, -X, +Y, -Y, +Z, -Z) and its uv for direction `d`, as a cube map
/// addresses its faces (Vulkan's table; ties go to x, then y). The twin of the WGSL's.
pub fn cube_face_uv(d: DVec3) -> (usize, DVec2) {
    let a = d.abs();
    let (face, ma, sc, tc) = if a.x >= a.y && a.x >= a.z {
        if d.x >= 0.0 {
            (0, a.x, -d.z, -d.y)
        } else {
            (1, a.x, d.z, -d.y)
        }
    } else if a.y >= a.z {
        if d.y >= 0.0 {
            (2, a.y, d.x, d.z)
        } else {
            (3, a.y, d.x, -d.z)
        }
    } else if d.z >= 0.0 {
        (4, a.z, d.x, -d.y)
    } else {
        (5, a.z, -d.x, -d.y)
    };
    let ma = ma.max(1e-30);
    (face, DVec2::new(0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0)))
}

/// The spot cookie's "up" in world space for a spot shining along `direction`: world +Y made
/// orthogonal to it (+Z for a spot within 2.6 degrees of vertical). The image's top row is
/// towards it, its right edge towards direction x up.
pub fn spot_up(direction: DVec3) -> DVec3 {
    let d = direction.normalize_or(DVec3::NEG_Z);
    let r = if d.y.abs() > 0.999 { DVec3::Z } else { DVec3::Y };
    let right = d.cross(r).normalize();
    right.cross(d).normalize()
}

/// The spot cookie's uv of `v` (light to point) for a spot along `dir` with `up`
/// ([`spot_up`], in the same space) and outer half-angle tangent `tan_outer`; `None` behind the
/// light. The twin of the WGSL's.
#[allow(clippy::neg_cmp_op_on_partial_ord)] // `!(z > 0)` as the WGSL writes it: NaN is behind.
pub fn spot_uv(v: DVec3, dir: DVec3, up: DVec3, tan_outer: f64) -> Option<DVec2> {
    let z = v.dot(dir);
    if !(z > 0.0) {
        return None;
    }
    let right = dir.cross(up);
    let s = 0.5 / (z * tan_outer.abs().max(1e-6));
    Some(DVec2::new(v.dot(right) * s + 0.5, 0.5 - v.dot(up) * s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_built_ins_are_what_they_say() {
        let w = CookieImage::builtin("window", false).unwrap();
        // Glass in a pane, dark on the bars and the frame.
        assert!(w.sample(0, DVec2::new(0.25, 0.25)).x > 0.99);
        assert!(w.sample(0, DVec2::new(0.5, 0.25)).x < 0.1);
        assert!(w.sample(0, DVec2::new(0.02, 0.7)).x < 0.1);
        let f = CookieImage::builtin("flashlight", true).unwrap();
        assert!(f.is_cube());
        assert!(f.sample(3, DVec2::splat(0.5)).x > 0.7);
        assert!(f.sample(3, DVec2::new(0.99, 0.5)).x < 0.01);
        assert!(CookieImage::builtin("lamp", false).is_none());
    }

    #[test]
    fn cube_faces_follow_the_axes() {
        assert_eq!(cube_face_uv(DVec3::X).0, 0);
        assert_eq!(cube_face_uv(DVec3::NEG_Y).0, 3);
        assert_eq!(cube_face_uv(DVec3::NEG_Z), (5, DVec2::splat(0.5)));
        // +Z face: +x to the right, +y up (v down).
        let (f, uv) = cube_face_uv(DVec3::new(0.5, 0.5, 1.0));
        assert_eq!((f, uv), (4, DVec2::new(0.75, 0.25)));
    }

    #[test]
    fn bad_cookie_names_are_errors() {
        let e = CookieImage::resolve("lamp", false).unwrap_err();
        assert!(e.contains("window, flashlight"), "{e}");
        let e = CookieImage::resolve("/nonexistent/c.png", false).unwrap_err();
        assert!(e.contains("/nonexistent/c.png"), "{e}");
    }
}
