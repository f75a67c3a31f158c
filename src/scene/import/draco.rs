//! `KHR_draco_mesh_compression`: a triangle primitive whose attributes and indices are one
//! Draco bitstream in a buffer view, decoded by `draco-core` (a pure-Rust Draco decoder). The
//! extension maps each glTF attribute to a Draco attribute id; the primitive's accessors give
//! the types. What is left of the load's element budget (`ImportOptions::max_elements`) bounds
//! the points and faces a stream may declare, and the decoded ones count against it like any
//! other primitive's.

use super::geometry::Attributes;
use super::*;

pub(super) const NAME: &str = "KHR_draco_mesh_compression";

impl Importer<'_> {
    /// The primitive's attributes and indices from its Draco stream, or `None` when it has none.
    pub(super) fn draco(&mut self, prim: &gltf::Primitive<'_>) -> Result<Option<(Attributes, Vec<u32>)>> {
        let Some(ext) = prim.extension_value(NAME) else { return Ok(None) };
        let what = || format!("{NAME} data");
        if !matches!(prim.mode(), gltf::mesh::Mode::Triangles) {
            bail!("{}: only triangle lists may be Draco-compressed, not {:?}", what(), prim.mode());
        }
        let view_index = ext
            .get("bufferView")
            .and_then(|v| v.as_u64())
            .ok_or_else(|| anyhow!("{}: bufferView is missing", what()))? as usize;
        let Some(view) = self.doc.views().nth(view_index) else {
            bail!("{}: buffer view {view_index} does not exist", what());
        };
        // `check_views` has put every view inside its buffer.
        let data = &self.buffers[view.buffer().index()].0[view.offset()..view.offset() + view.length()];
        // What is left of the load's element budget bounds what the stream may declare.
        let left = self.options.max_elements.saturating_sub(self.decoded) as u64;
        let limits = draco_core::DecodeLimits::default().with_max_points(left).with_max_faces(left / 3);
        let mut mesh = draco_core::Mesh::new();
        draco_core::MeshDecoder::new()
            .decode(&mut draco_core::DecoderBuffer::new(data).with_limits(limits), &mut mesh)
            .map_err(|e| anyhow!("{}: buffer view {view_index} does not decode: {e}", what()))?;
        let n = mesh.num_points();
        let faces = mesh.num_faces();
        self.decoded = self.decoded.saturating_add(n).saturating_add(faces.saturating_mul(3));
        if self.decoded > self.options.max_elements {
            bail!("the primitives add up to more than {} vertices and indices", self.options.max_elements);
        }
        if n == 0 || faces == 0 {
            bail!("{}: buffer view {view_index} decodes to no triangles", what());
        }
        let ids = ext.get("attributes").and_then(|a| a.as_object());
        let read = |semantic: &str, components: usize| -> Result<Option<Vec<f32>>> {
            let Some(id) = ids.and_then(|a| a.get(semantic)) else { return Ok(None) };
            let id = id.as_u64().ok_or_else(|| anyhow!("{}: the id of {semantic} is not a number", what()))?;
            let att = u32::try_from(id)
                .ok()
                .and_then(|id| mesh.attribute_by_unique_id(id))
                .ok_or_else(|| anyhow!("{}: the stream has no attribute {id} for {semantic}", what()))?;
            let mut values = att.read_f32s(n, components);
            // Integer texture coordinates the accessor declares normalized.
            let normalized = prim.attributes().any(|(s, acc)| s.to_string() == semantic && acc.normalized());
            let scale = match att.data_type() {
                draco_core::DataType::Uint8 if normalized => 1.0 / 255.0,
                draco_core::DataType::Uint16 if normalized => 1.0 / 65535.0,
                _ => 1.0,
            };
            if scale != 1.0 {
                values.iter_mut().for_each(|v| *v *= scale);
            }
            Ok(Some(values))
        };
        let pairs = |v: Vec<f32>| v.chunks_exact(2).map(|c| [c[0], c[1]]).collect::<Vec<_>>();
        let triples = |v: Vec<f32>| v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect::<Vec<_>>();
        let positions = read("POSITION", 3)?.map(triples).ok_or_else(|| anyhow!("{}: no POSITION", what()))?;
        if let Some(i) = positions.iter().position(|p| !p.iter().all(|v| v.is_finite())) {
            bail!("vertex {i} has a non-finite position {:?}", positions[i]);
        }
        let attributes = Attributes {
            positions,
            normals: read("NORMAL", 3)?.map(triples),
            tangents: read("TANGENT", 4)?.map(|v| v.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect()),
            uvs: read("TEXCOORD_0", 2)?.map(pairs),
            uvs1: read("TEXCOORD_1", 2)?.map(pairs),
        };
        let indices: Vec<u32> = mesh.faces().iter().flat_map(|f| f.map(|p| p.0)).collect();
        if let Some((k, &bad)) = indices.iter().enumerate().find(|(_, &i)| i as usize >= n) {
            bail!("{}: index {k} is {bad}, out of range for {n} points", what());
        }
        Ok(Some((attributes, indices)))
    }
}
