//! A glTF primitive into a `Mesh`, in three steps: read and check its attributes, turn its
//! indices into triangles (strips and fans too, zero-area ones dropped, mirrored ones turned),
//! then build the vertices (flat normals without NORMAL, broken normals replaced, MikkTSpace
//! tangents when a normal map needs them and the file has none).

use super::*;
use glam::Vec2;

/// The extension that allows integer vertex attributes.
pub(super) const QUANTIZATION: &str = "KHR_mesh_quantization";

/// An integer component as f32: divided by the type's largest value when normalized (and not
/// below -1, glTF's rule for signed types), else as it is.
fn dequantize<T: Copy + Into<f64>, const N: usize>(v: [T; N], max: f64, normalized: bool) -> [f32; N] {
    v.map(|x| {
        let f: f64 = x.into();
        (if normalized { (f / max).max(-1.0) } else { f }) as f32
    })
}

/// Reads accessor `$acc` of `$n` components of any glTF component type as f32 (`None` when it
/// cannot be read).
macro_rules! read_floats {
    ($acc:expr, $get:expr, $n:literal, $normalized:expr) => {{
        use gltf::accessor::Iter;
        let normalized = $normalized;
        let acc = $acc;
        match acc.data_type() {
            DataType::F32 => Iter::<[f32; $n]>::new(acc, $get).map(|it| it.collect::<Vec<_>>()),
            DataType::I8 => {
                Iter::<[i8; $n]>::new(acc, $get).map(|it| it.map(|v| dequantize(v, 127.0, normalized)).collect())
            }
            DataType::U8 => {
                Iter::<[u8; $n]>::new(acc, $get).map(|it| it.map(|v| dequantize(v, 255.0, normalized)).collect())
            }
            DataType::I16 => {
                Iter::<[i16; $n]>::new(acc, $get).map(|it| it.map(|v| dequantize(v, 32767.0, normalized)).collect())
            }
            DataType::U16 => {
                Iter::<[u16; $n]>::new(acc, $get).map(|it| it.map(|v| dequantize(v, 65535.0, normalized)).collect())
            }
            _ => None,
        }
    }};
}
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

/// A primitive's vertex attributes, read and checked: every present one has `positions.len()`
/// elements, and every position is finite.
pub(super) struct Attributes {
    pub positions: Vec<[f32; 3]>,
    pub normals: Option<Vec<[f32; 3]>>,
    pub tangents: Option<Vec<[f32; 4]>>,
    pub uvs: Option<Vec<[f32; 2]>>,
    pub uvs1: Option<Vec<[f32; 2]>>,
}

impl Importer<'_> {
    /// The primitive's mesh and whether it may use a normal map (it has the texture coordinates
    /// the map reads), or `None` (with a warning) when it draws nothing: no triangle with area.
    pub(super) fn primitive(&mut self, prim: &gltf::Primitive<'_>, mirrored: bool) -> Result<Option<(Mesh, bool)>> {
        let mode = prim.mode();
        let (attributes, indices) = match self.draco(prim)? {
            Some((a, indices)) => (a, indices),
            None => {
                let a = self.attributes(prim)?;
                let indices = self.indices(prim, a.positions.len())?;
                (a, indices)
            }
        };
        if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
            return self.lines_or_points(prim, &attributes, indices).map(|m| m.map(|m| (m, false)));
        }
        let Some(tris) = self.triangles(prim, &attributes.positions, indices, mirrored)? else { return Ok(None) };
        let wants_normal_map = prim.material().normal_texture().is_some();
        let uvs = materials::material_uvs(&prim.material(), "", &mut Vec::new());
        let has = |set: u32| if set == 1 { attributes.uvs1.is_some() } else { attributes.uvs.is_some() };
        let has_uv = has(uvs.normal.set);
        if wants_normal_map && !has_uv {
            self.warnings.push(format!(
                "{}: a normal map without TEXCOORD_{} is ignored",
                prim_label(prim),
                uvs.normal.set
            ));
        }
        let uses_uv1 = prim.material().index().is_some()
            && [uvs.base_color, uvs.emissive, uvs.metallic_roughness].iter().any(|t| t.set == 1);
        if uses_uv1 && attributes.uvs1.is_none() {
            self.warnings.push(format!("{}: its material reads TEXCOORD_1, which it does not have", prim_label(prim)));
        }
        let mut mesh = self.vertices(prim, &attributes, &tris, mirrored);
        let tangents_missing = mesh.vertices.iter().any(|v| v.tangent[3] == 0.0);
        if wants_normal_map && has_uv && tangents_missing {
            generate_tangents(&mut mesh, uvs.normal);
        }
        Ok(Some((mesh, has_uv)))
    }

    /// Reads POSITION, NORMAL, TANGENT, TEXCOORD_0 and TEXCOORD_1, checking their types, their counts
    /// against POSITION's, that they can be read in full, and the load's element budget.
    fn attributes(&mut self, prim: &gltf::Primitive<'_>) -> Result<Attributes> {
        let quantized = self.doc.extensions_used().any(|e| e == QUANTIZATION);
        let check =
            |sem: &gltf::Semantic, what: &str, dims: &[Dimensions], types: &[DataType]| -> Result<Option<usize>> {
                let Some(acc) = prim.get(sem) else { return Ok(None) };
                if !dims.contains(&acc.dimensions()) || !types.contains(&acc.data_type()) {
                    bail!(
                        "{what} accessor {} is {:?} {:?}, which glTF does not allow{}",
                        acc.index(),
                        acc.dimensions(),
                        acc.data_type(),
                        if quantized { "" } else { " without KHR_mesh_quantization" }
                    );
                }
                if acc.view().is_none() && acc.sparse().is_none() {
                    bail!("{what} accessor {} has no data (no buffer view)", acc.index());
                }
                Ok(Some(acc.count()))
            };
        // KHR_mesh_quantization: integer positions, normals, tangents and texture coordinates
        // (normalized or not, as each accessor says).
        use DataType::{F32, I16, I8, U16, U8};
        let (position_types, unit_types, uv_types): (&[DataType], &[DataType], &[DataType]) = if quantized {
            (&[F32, I8, U8, I16, U16], &[F32, I8, I16], &[F32, I8, U8, I16, U16])
        } else {
            (&[F32], &[F32], &[F32, U8, U16])
        };
        let Some(n) = check(&gltf::Semantic::Positions, "POSITION", &[Dimensions::Vec3], position_types)? else {
            bail!("it has no POSITION attribute");
        };
        self.decoded = self.decoded.saturating_add(n).saturating_add(prim.indices().map_or(0, |a| a.count()));
        if self.decoded > self.options.max_elements {
            bail!("the primitives add up to more than {} vertices and indices", self.options.max_elements);
        }
        let n_normals = check(&gltf::Semantic::Normals, "NORMAL", &[Dimensions::Vec3], unit_types)?;
        let n_tangents = check(&gltf::Semantic::Tangents, "TANGENT", &[Dimensions::Vec4], unit_types)?;
        let n_uv = check(&gltf::Semantic::TexCoords(0), "TEXCOORD_0", &[Dimensions::Vec2], uv_types)?;
        let n_uv1 = check(&gltf::Semantic::TexCoords(1), "TEXCOORD_1", &[Dimensions::Vec2], uv_types)?;
        for (what, count) in
            [("NORMAL", n_normals), ("TANGENT", n_tangents), ("TEXCOORD_0", n_uv), ("TEXCOORD_1", n_uv1)]
        {
            if let Some(c) = count {
                if c != n {
                    bail!("{what} has {c} elements but POSITION has {n}: the accessor counts disagree");
                }
            }
        }
        let get = |b: gltf::Buffer<'_>| self.buffers.get(b.index()).map(|d| d.0.as_slice());
        // Core glTF's integer texture coordinates are normalized whatever the accessor says
        // (as the `gltf` crate reads them); under KHR_mesh_quantization the accessor decides.
        let uv_normalized = |a: &gltf::Accessor<'_>| a.normalized() || (!quantized && a.data_type() != F32);
        let positions: Vec<[f32; 3]> = prim
            .get(&gltf::Semantic::Positions)
            .and_then(|a| read_floats!(a, get, 3, a.normalized()))
            .ok_or_else(|| anyhow!("POSITION cannot be read"))?;
        if positions.len() != n {
            bail!("POSITION yields {} of its {n} elements", positions.len());
        }
        if let Some(i) = positions.iter().position(|p| !p.iter().all(|v| v.is_finite())) {
            bail!("vertex {i} has a non-finite position {:?}", positions[i]);
        }
        let normals = prim.get(&gltf::Semantic::Normals).and_then(|a| read_floats!(a, get, 3, a.normalized()));
        let tangents = prim.get(&gltf::Semantic::Tangents).and_then(|a| read_floats!(a, get, 4, a.normalized()));
        let uvs = prim.get(&gltf::Semantic::TexCoords(0)).and_then(|a| read_floats!(a, get, 2, uv_normalized(&a)));
        let uvs1 = prim.get(&gltf::Semantic::TexCoords(1)).and_then(|a| read_floats!(a, get, 2, uv_normalized(&a)));
        for (what, len) in [
            ("NORMAL", normals.as_ref().map(|v| v.len())),
            ("TANGENT", tangents.as_ref().map(|v| v.len())),
            ("TEXCOORD_0", uvs.as_ref().map(|v| v.len())),
            ("TEXCOORD_1", uvs1.as_ref().map(|v| v.len())),
        ] {
            if len.is_some_and(|l| l != n) {
                bail!("{what} cannot be read in full");
            }
        }
        if n_normals.is_some() && normals.is_none()
            || n_uv.is_some() && uvs.is_none()
            || n_uv1.is_some() && uvs1.is_none()
        {
            bail!("an attribute's data cannot be read");
        }
        Ok(Attributes { positions, normals, tangents, uvs, uvs1 })
    }

    /// A point or line primitive as a mesh of points or line segments (strips and loops made
    /// lists). Without NORMAL its normals are zero, which the shaders light as facing the
    /// viewer; a normal map is not used (a line has no tangent frame).
    fn lines_or_points(&mut self, prim: &gltf::Primitive<'_>, a: &Attributes, raw: Vec<u32>) -> Result<Option<Mesh>> {
        let (topology, indices) = match prim.mode() {
            Mode::Points => (Topology::Points, raw),
            Mode::Lines => {
                if !raw.len().is_multiple_of(2) {
                    self.warnings
                        .push(format!("{}: a trailing index does not make a line and is ignored", prim_label(prim)));
                }
                (Topology::Lines, raw[..raw.len() / 2 * 2].to_vec())
            }
            mode => {
                let mut list: Vec<u32> = raw.windows(2).flatten().copied().collect();
                if mode == Mode::LineLoop && raw.len() > 2 {
                    list.extend([raw[raw.len() - 1], raw[0]]);
                }
                (Topology::Lines, list)
            }
        };
        if indices.is_empty() {
            // As a primitive of zero-area triangles: skipped with a word, the rest of the file drawn.
            self.warnings.push(format!(
                "{}: the {:?} primitive has too few vertices to draw anything; skipped",
                prim_label(prim),
                prim.mode()
            ));
            return Ok(None);
        }
        if prim.material().alpha_mode() == gltf::material::AlphaMode::Blend {
            self.warnings.push(format!("{}: blended points and lines are drawn opaque", prim_label(prim)));
        }
        if prim.material().normal_texture().is_some() {
            self.warnings.push(format!("{}: points and lines do not use normal maps", prim_label(prim)));
        }
        let normal_at = |i: usize| {
            a.normals.as_ref().map_or([0.0; 3], |n| {
                let v = Vec3::from(n[i]);
                if v.is_finite() && v.length_squared() > 1e-12 {
                    v.normalize().into()
                } else {
                    [0.0; 3]
                }
            })
        };
        let finite = |set: &Option<Vec<[f32; 2]>>, i: usize| {
            set.as_ref().map_or([0.0, 0.0], |u| if u[i].iter().all(|v| v.is_finite()) { u[i] } else { [0.0, 0.0] })
        };
        let vertices = (0..a.positions.len())
            .map(|i| Vertex { uv1: finite(&a.uvs1, i), ..Vertex::new(a.positions[i], normal_at(i), finite(&a.uvs, i)) })
            .collect();
        match topology {
            Topology::Points => self.stats.points += indices.len(),
            _ => self.stats.lines += indices.len() / 2,
        }
        Ok(Some(Mesh { name: prim_label(prim), vertices, indices, topology }))
    }

    /// The primitive's indices, checked against the vertex count `n` (0..n without indices).
    fn indices(&mut self, prim: &gltf::Primitive<'_>, n: usize) -> Result<Vec<u32>> {
        let reader = prim.reader(|b| self.buffers.get(b.index()).map(|d| d.0.as_slice()));
        Ok(match prim.indices() {
            Some(acc) => {
                if acc.dimensions() != Dimensions::Scalar
                    || !matches!(acc.data_type(), DataType::U8 | DataType::U16 | DataType::U32)
                {
                    bail!(
                        "index accessor {} is {:?} {:?}; indices must be unsigned scalars",
                        acc.index(),
                        acc.dimensions(),
                        acc.data_type()
                    );
                }
                let idx: Vec<u32> = reader
                    .read_indices()
                    .ok_or_else(|| anyhow!("index accessor {} cannot be read", acc.index()))?
                    .into_u32()
                    .collect();
                if idx.len() != acc.count() {
                    bail!("index accessor {} yields {} of its {} elements", acc.index(), idx.len(), acc.count());
                }
                if let Some((k, &bad)) = idx.iter().enumerate().find(|(_, &i)| i as usize >= n) {
                    bail!("index {k} is {bad}, out of range for {n} vertices");
                }
                idx
            }
            None => (0..n as u32).collect(),
        })
    }

    /// The primitive's indices (checked against the vertex count) as triangles, without the
    /// zero-area ones, wound front-facing under a mirroring transform; `None` (with a warning)
    /// when no triangle has area.
    fn triangles(
        &mut self,
        prim: &gltf::Primitive<'_>,
        positions: &[[f32; 3]],
        raw_indices: Vec<u32>,
        mirrored: bool,
    ) -> Result<Option<Vec<[u32; 3]>>> {
        let mode = prim.mode();
        let mut tris: Vec<[u32; 3]> = match mode {
            Mode::Triangles => raw_indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
            Mode::TriangleStrip => (2..raw_indices.len())
                .map(|i| {
                    let (a, b, c) = (raw_indices[i - 2], raw_indices[i - 1], raw_indices[i]);
                    if i % 2 == 0 {
                        [a, b, c]
                    } else {
                        [b, a, c]
                    }
                })
                .collect(),
            _ => (2..raw_indices.len()).map(|i| [raw_indices[0], raw_indices[i - 1], raw_indices[i]]).collect(),
        };
        if mode == Mode::Triangles && !raw_indices.len().is_multiple_of(3) {
            self.warnings
                .push(format!("{} trailing indices do not make a triangle and are ignored", raw_indices.len() % 3));
        }
        // Zero-area triangles draw nothing and break normal and tangent generation.
        let before = tris.len();
        tris.retain(|t| {
            let p = t.map(|i| glam::Vec3::from(positions[i as usize]).as_dvec3());
            let c = (p[1] - p[0]).cross(p[2] - p[0]);
            let scale = (p[1] - p[0]).length_squared().max((p[2] - p[0]).length_squared());
            c.length_squared() > 1e-24 * scale * scale && c.is_finite()
        });
        self.stats.dropped_triangles += before - tris.len();
        if tris.is_empty() {
            self.warnings.push("a primitive has no triangles with area and is skipped".into());
            return Ok(None);
        }
        if mirrored {
            // A mirroring transform turns counter-clockwise into clockwise: swap to keep the
            // front faces in front for back-face culling.
            for t in &mut tris {
                t.swap(1, 2);
            }
        }
        Ok(Some(tris))
    }

    /// The mesh's vertices and indices: flat-shaded without normals (glTF's rule), else the
    /// file's normals with unusable ones replaced by their faces' normal, and its tangents.
    fn vertices(&mut self, prim: &gltf::Primitive<'_>, a: &Attributes, tris: &[[u32; 3]], mirrored: bool) -> Mesh {
        let positions = &a.positions;
        let n = positions.len();
        let mut mesh = Mesh { name: prim_label(prim), ..Default::default() };
        let finite_at = |set: &Option<Vec<[f32; 2]>>, i: usize| {
            set.as_ref().map_or([0.0, 0.0], |u| if u[i].iter().all(|v| v.is_finite()) { u[i] } else { [0.0, 0.0] })
        };
        let uv_at = |i: usize| finite_at(&a.uvs, i);
        let vertex = |i: usize, normal: [f32; 3]| Vertex {
            uv1: finite_at(&a.uvs1, i),
            ..Vertex::new(positions[i], normal, uv_at(i))
        };
        let Some(normals) = &a.normals else {
            // glTF: without normals, flat shading. Each triangle gets its own vertices.
            for t in tris {
                let p = t.map(|i| glam::Vec3::from(positions[i as usize]));
                let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
                let n = if mirrored { -n } else { n };
                let base = mesh.vertices.len() as u32;
                for &i in t {
                    mesh.vertices.push(vertex(i as usize, n.into()));
                }
                mesh.indices.extend([base, base + 1, base + 2]);
            }
            return mesh;
        };
        let mut fixed: Vec<Vec3> = normals.iter().map(|n| Vec3::from(*n)).collect();
        let broken: Vec<bool> = fixed.iter().map(|n| !n.is_finite() || n.length_squared() < 1e-12).collect();
        if broken.iter().any(|&b| b) {
            // Replace unusable normals with the area-weighted normal of their faces.
            let mut acc = vec![Vec3::ZERO; n];
            for t in tris {
                let p = t.map(|i| glam::Vec3::from(positions[i as usize]));
                let fnorm = (p[1] - p[0]).cross(p[2] - p[0]);
                let fnorm = if mirrored { -fnorm } else { fnorm };
                for &i in t {
                    acc[i as usize] += fnorm;
                }
            }
            let mut bad = 0;
            for i in 0..n {
                if broken[i] {
                    fixed[i] = acc[i].normalize_or(Vec3::Y);
                    bad += 1;
                }
            }
            self.warnings.push(format!(
                "{}: {bad} normal(s) are zero or not finite; replaced by the faces' normal",
                prim_label(prim)
            ));
        }
        for i in 0..n {
            let mut v = vertex(i, fixed[i].normalize().into());
            if let Some(t) = &a.tangents {
                let t = glam::Vec4::from(t[i]);
                if t.is_finite() && t.truncate().length_squared() > 1e-12 {
                    v.tangent = [t.x, t.y, t.z, if t.w < 0.0 { -1.0 } else { 1.0 }];
                }
            }
            mesh.vertices.push(v);
        }
        mesh.indices = tris.iter().flatten().copied().collect();
        mesh
    }
}

fn prim_label(prim: &gltf::Primitive<'_>) -> String {
    format!("primitive {}", prim.index())
}

/// MikkTSpace tangents (what glTF's normal maps are baked against) from the normal map's
/// texture coordinates: its set, transformed by its `KHR_texture_transform` (so a rotated or
/// mirrored normal map is read in its own frame), written per vertex.
fn generate_tangents(mesh: &mut Mesh, uv: UvTransform) {
    struct Geo<'a>(&'a mut Mesh, UvTransform);
    impl bevy_mikktspace::Geometry for Geo<'_> {
        fn num_faces(&self) -> usize {
            self.0.indices.len() / 3
        }
        fn num_vertices_of_face(&self, _face: usize) -> usize {
            3
        }
        fn position(&self, face: usize, vert: usize) -> [f32; 3] {
            self.0.vertices[self.0.indices[face * 3 + vert] as usize].position
        }
        fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
            self.0.vertices[self.0.indices[face * 3 + vert] as usize].normal
        }
        fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
            let v = &self.0.vertices[self.0.indices[face * 3 + vert] as usize];
            self.1.apply(Vec2::from(if self.1.set == 1 { v.uv1 } else { v.uv })).into()
        }
        fn set_tangent(&mut self, t: Option<bevy_mikktspace::TangentSpace>, face: usize, vert: usize) {
            let i = self.0.indices[face * 3 + vert] as usize;
            let t = t.unwrap_or_default().tangent_encoded();
            if t.iter().all(|v| v.is_finite()) {
                self.0.vertices[i].tangent = t;
            }
        }
    }
    if bevy_mikktspace::generate_tangents(&mut Geo(mesh, uv)).is_err() {
        log::warn!("tangent generation failed for {}", mesh.name);
    }
    // Anything still without a tangent gets one perpendicular to its normal.
    for v in &mut mesh.vertices {
        if v.tangent[3] == 0.0 {
            let n = Vec3::from(v.normal);
            let t = n.any_orthonormal_vector();
            v.tangent = [t.x, t.y, t.z, 1.0];
        }
    }
}
