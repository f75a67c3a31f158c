//! What the importer checks before the `gltf` crate reads a value the file controls: the .glb
//! header, the JSON's indices, external URIs, buffer views and accessors against their data.

use super::*;

pub(super) fn load_buffers(
    doc: &gltf::Document,
    base: Option<&Path>,
    mut blob: Option<Vec<u8>>,
    fallback: &[bool],
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<Vec<gltf::buffer::Data>> {
    let total = doc.buffers().len();
    let mut out = Vec::with_capacity(total);
    let mut fallback_bytes = 0usize;
    for (i, buffer) in doc.buffers().enumerate() {
        progress(Progress { stage: "buffers", done: i, total });
        let what = match buffer.name() {
            Some(n) => format!("buffer {i} ('{n}')"),
            None => format!("buffer {i}"),
        };
        let data = match buffer.source() {
            // EXT_meshopt_compression's fallback: no data of its own, its views are decoded
            // into it (`meshopt::Meshopt::decode`).
            _ if fallback.get(i).copied().unwrap_or(false) => {
                fallback_bytes = fallback_bytes.saturating_add(buffer.length());
                if fallback_bytes > super::meshopt::MAX_FALLBACK_BYTES {
                    bail!(
                        "{what}: the compressed buffers decode to more than {} bytes",
                        super::meshopt::MAX_FALLBACK_BYTES
                    );
                }
                vec![0; buffer.length()]
            }
            gltf::buffer::Source::Bin => match blob.take() {
                Some(b) => b,
                None => bail!("{what} refers to the binary chunk, which the file does not have"),
            },
            gltf::buffer::Source::Uri(uri) => {
                check_external(base, uri).with_context(|| what.clone())?;
                gltf::buffer::Data::from_source(gltf::buffer::Source::Uri(uri), base)
                    .map_err(|e| anyhow!("{what}: cannot load '{}': {e}", short_uri(uri)))?
                    .0
            }
        };
        if data.len() < buffer.length() {
            bail!("{what} has {} bytes, the file declares {}", data.len(), buffer.length());
        }
        out.push(gltf::buffer::Data(data));
    }
    progress(Progress { stage: "buffers", done: total, total });
    Ok(out)
}

/// A URI for messages: a data URI shortened (it holds the whole payload), a file name in full.
pub(super) fn short_uri(uri: &str) -> String {
    if uri.starts_with("data:") && uri.len() > 48 {
        format!("{}...", &uri[..uri.char_indices().nth(40).map_or(uri.len(), |(i, _)| i)])
    } else {
        uri.to_string()
    }
}

/// An external reference must be a regular file of a sane size (not a device, not a folder).
pub(super) fn check_external(base: Option<&Path>, uri: &str) -> Result<()> {
    if uri.starts_with("data:") {
        return Ok(());
    }
    let Some(base) = base else { bail!("'{}' is an external file, which cannot be read here", short_uri(uri)) };
    let path = base.join(uri);
    if let Ok(meta) = std::fs::metadata(&path) {
        if !meta.is_file() {
            bail!("'{uri}' is not a regular file");
        }
        if meta.len() > MAX_FILE_BYTES {
            bail!("'{uri}' is {} bytes, more than the {} this loader accepts", meta.len(), MAX_FILE_BYTES);
        }
    }
    Ok(())
}

/// A .glb header whose total length is shorter than the header itself makes the `gltf` crate
/// subtract past zero (a panic in debug builds; found by the fuzzer).
pub(super) fn check_glb_header(bytes: &[u8]) -> Result<()> {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let Some(len) = bytes.get(8..12) else { bail!("not a valid glTF file: the .glb header is cut short") };
    let length = u32::from_le_bytes([len[0], len[1], len[2], len[3]]) as usize;
    if length < 20 {
        bail!("not a valid glTF file: the .glb header declares {length} bytes, less than a header and a chunk");
    }
    Ok(())
}

/// What `gltf-json`'s own validation indexes without checking (a panic otherwise; found by the
/// fuzzer): the POSITION accessor of every primitive.
pub(super) fn check_before_validation(root: &gltf::json::Root) -> Result<()> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &prim.attributes {
                if index.value() >= root.accessors.len() {
                    bail!(
                        "the glTF is invalid: meshes[{m}].primitives[{p}].attributes[{:?}] refers to accessor {}, but there are {}",
                        semantic,
                        index.value(),
                        root.accessors.len()
                    );
                }
            }
        }
    }
    Ok(())
}

/// What the `gltf` crate's accessors assume without validating (they would panic otherwise):
/// an image has a source, an image in a buffer view has a MIME type, a camera has the
/// projection its type names.
pub(super) fn check_json(doc: &gltf::Document) -> Result<()> {
    let root = doc.as_json();
    for (i, image) in root.images.iter().enumerate() {
        match (&image.buffer_view, &image.uri) {
            (Some(_), _) if image.mime_type.is_none() => bail!("image {i} is in a buffer view but has no mimeType"),
            (None, None) => bail!("image {i} has neither a uri nor a bufferView"),
            _ => {}
        }
    }
    for (i, camera) in root.cameras.iter().enumerate() {
        use gltf::json::camera::Type;
        let ok = match camera.type_ {
            gltf::json::validation::Checked::Valid(Type::Perspective) => camera.perspective.is_some(),
            gltf::json::validation::Checked::Valid(Type::Orthographic) => camera.orthographic.is_some(),
            _ => false,
        };
        if !ok {
            bail!("camera {i} lacks the projection its type names");
        }
    }
    Ok(())
}

/// Every buffer view inside its buffer and every accessor inside its view, with a stride no
/// shorter than its element: the `gltf` crate's readers slice with these numbers.
pub(super) fn check_views(doc: &gltf::Document, buffers: &[gltf::buffer::Data]) -> Result<()> {
    let view_ok = |view: &gltf::buffer::View<'_>| -> Result<()> {
        let len = buffers.get(view.buffer().index()).map_or(0, |b| b.0.len());
        let end = view.offset().checked_add(view.length());
        if end.is_none_or(|e| e > len) {
            bail!(
                "buffer view {} (offset {}, length {}) reaches past the end of buffer {} ({len} bytes)",
                view.index(),
                view.offset(),
                view.length(),
                view.buffer().index()
            );
        }
        Ok(())
    };
    for view in doc.views() {
        view_ok(&view)?;
    }
    let span = |what: String, view: &gltf::buffer::View<'_>, offset: usize, count: usize, elem: usize| -> Result<()> {
        if count == 0 {
            bail!("{what} has count 0");
        }
        let stride = view.stride().unwrap_or(elem);
        if stride < elem {
            bail!("{what}: buffer view {} has a stride of {stride} bytes for {elem}-byte elements", view.index());
        }
        let end = stride.checked_mul(count - 1).and_then(|s| s.checked_add(offset)).and_then(|s| s.checked_add(elem));
        if end.is_none_or(|e| e > view.length()) {
            bail!(
                "{what} ({count} elements of {elem} bytes from offset {offset}) reads past the end of buffer view {} ({} bytes)",
                view.index(),
                view.length()
            );
        }
        Ok(())
    };
    for acc in doc.accessors() {
        let what = format!("accessor {}", acc.index());
        // A sparse accessor without a view is zeros plus a few values: its count is not
        // bounded by the file's size, so it is bounded here. An accessor with neither a view nor
        // sparse values reads as nothing (a Draco primitive's accessors: the stream holds the
        // data, bounded by the element budget), so its count allocates nothing.
        if acc.count() > MAX_ACCESSOR_COUNT {
            bail!("{what} has {} elements, more than the {MAX_ACCESSOR_COUNT} this loader accepts", acc.count());
        }
        if acc.view().is_none() && acc.sparse().is_some() && acc.count() > MAX_SPARSE_ONLY_COUNT {
            bail!(
                "{what} is a sparse accessor without a buffer view of {} elements (at most {MAX_SPARSE_ONLY_COUNT})",
                acc.count()
            );
        }
        if let Some(view) = acc.view() {
            span(what.clone(), &view, acc.offset(), acc.count(), acc.size())?;
        } else if acc.sparse().is_none() && acc.count() > 0 {
            // No data: the gltf readers return nothing; the mesh code reports it where used.
        }
        if let Some(sparse) = acc.sparse() {
            let n = sparse.count();
            let idx = sparse.indices();
            span(format!("{what} sparse indices"), &idx.view(), idx.offset(), n, idx.index_type().size())?;
            let values = sparse.values();
            span(format!("{what} sparse values"), &values.view(), values.offset(), n, acc.size())?;
        }
    }
    Ok(())
}
