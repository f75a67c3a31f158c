//! `EXT_meshopt_compression`: buffer views whose bytes are stored compressed by meshoptimizer's
//! codecs. Each such view names the compressed bytes (a range of another buffer), how many
//! elements of what stride they decode to, the codec (`ATTRIBUTES`, `TRIANGLES`, `INDICES`) and
//! a filter (`NONE`, `OCTAHEDRAL`, `QUATERNION`, `EXPONENTIAL`, `COLOR`). The view's own buffer
//! is usually a "fallback" buffer with no data (`fallback: true`, no `uri`): it is allocated
//! zeroed here and every compressed view is decoded into its place, so that everything after
//! this (the `gltf` crate's readers, `check_views`) reads plain bytes.
//!
//! Decoding is the `meshopt` crate's (bindings to meshoptimizer's own decoders, which are
//! written to be safe on untrusted input); every constraint those decoders assert is checked
//! here first, so a bad file is an error, never an abort.

use super::*;
use serde_json::Value;

/// The most bytes all fallback buffers of one file may ask for (their size is not bounded by
/// the file's: a 1 KB file could declare gigabytes).
pub const MAX_FALLBACK_BYTES: usize = 1 << 30;

pub(super) const NAME: &str = "EXT_meshopt_compression";

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Codec {
    Attributes,
    Triangles,
    Indices,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Filter {
    None,
    Octahedral,
    Quaternion,
    Exponential,
    Color,
}

/// One compressed buffer view, its fields checked against the constraints of the codec.
#[derive(Clone, Debug)]
struct View {
    index: usize,
    source: usize,
    offset: usize,
    length: usize,
    stride: usize,
    count: usize,
    codec: Codec,
    filter: Filter,
}

/// What the file's JSON says about the extension: which buffers are fallbacks and which views
/// are compressed.
#[derive(Debug, Default)]
pub(super) struct Meshopt {
    /// Per buffer: a fallback buffer, allocated zeroed instead of read.
    pub fallback: Vec<bool>,
    views: Vec<View>,
}

impl Meshopt {
    /// Reads the extension's objects from the file's JSON (`bytes` is the whole file: a .glb
    /// or JSON). Files that do not use the extension are not parsed again.
    pub(super) fn read(bytes: &[u8], doc: &gltf::Document) -> Result<Self> {
        let mut out = Meshopt { fallback: vec![false; doc.buffers().len()], views: Vec::new() };
        if !doc.extensions_used().any(|e| e == NAME) {
            return Ok(out);
        }
        let json: Value = if bytes.starts_with(b"glTF") {
            let glb = gltf::binary::Glb::from_slice(bytes).map_err(|e| anyhow!("not a valid glTF file: {e}"))?;
            serde_json::from_slice(&glb.json)
        } else {
            serde_json::from_slice(bytes)
        }
        .map_err(|e| anyhow!("not a valid glTF file: {e}"))?;
        let ext = |v: &Value| v.get("extensions").and_then(|e| e.get(NAME)).cloned();
        for (i, b) in json.get("buffers").and_then(Value::as_array).into_iter().flatten().enumerate() {
            if let (Some(e), Some(slot)) = (ext(b), out.fallback.get_mut(i)) {
                *slot = e.get("fallback").and_then(Value::as_bool).unwrap_or(false);
            }
        }
        let views: Vec<gltf::buffer::View<'_>> = doc.views().collect();
        for (i, v) in json.get("bufferViews").and_then(Value::as_array).into_iter().flatten().enumerate() {
            let Some(e) = ext(v) else { continue };
            let Some(view) = views.get(i) else { continue };
            out.views.push(parse_view(view, &e).with_context(|| format!("buffer view {i} ({NAME})"))?);
        }
        Ok(out)
    }

    pub(super) fn is_empty(&self) -> bool {
        self.views.is_empty()
    }

    /// Decodes every compressed view into its place in its own buffer.
    pub(super) fn decode(&self, doc: &gltf::Document, buffers: &mut [gltf::buffer::Data]) -> Result<()> {
        for v in &self.views {
            let what = || format!("buffer view {} ({NAME})", v.index);
            let src = buffers.get(v.source).map(|b| b.0.as_slice()).unwrap_or_default();
            let Some(compressed) = v.offset.checked_add(v.length).and_then(|end| src.get(v.offset..end)) else {
                bail!(
                    "{}: its compressed data (offset {}, length {}) reaches past the end of buffer {} ({} bytes)",
                    what(),
                    v.offset,
                    v.length,
                    v.source,
                    src.len()
                );
            };
            let decoded = decode_view(v, compressed).with_context(what)?;
            let Some(view) = doc.views().nth(v.index) else { continue };
            let dst = &mut buffers[view.buffer().index()].0;
            let start = view.offset();
            let Some(target) = start.checked_add(decoded.len()).and_then(|end| dst.get_mut(start..end)) else {
                bail!(
                    "{}: {} decoded bytes from offset {start} do not fit in buffer {} ({} bytes)",
                    what(),
                    decoded.len(),
                    view.buffer().index(),
                    dst.len()
                );
            };
            target.copy_from_slice(&decoded);
        }
        Ok(())
    }
}

fn parse_view(view: &gltf::buffer::View<'_>, e: &Value) -> Result<View> {
    let num = |key: &str, default: Option<u64>| -> Result<usize> {
        match e.get(key) {
            Some(v) => v.as_u64().map(|n| n as usize).ok_or_else(|| anyhow!("{key} is not a non-negative integer")),
            None => default.map(|n| n as usize).ok_or_else(|| anyhow!("{key} is missing")),
        }
    };
    let codec = match e.get("mode").and_then(Value::as_str) {
        Some("ATTRIBUTES") => Codec::Attributes,
        Some("TRIANGLES") => Codec::Triangles,
        Some("INDICES") => Codec::Indices,
        other => bail!("mode {other:?} is not ATTRIBUTES, TRIANGLES or INDICES"),
    };
    let filter = match e.get("filter").and_then(Value::as_str) {
        None | Some("NONE") => Filter::None,
        Some("OCTAHEDRAL") => Filter::Octahedral,
        Some("QUATERNION") => Filter::Quaternion,
        Some("EXPONENTIAL") => Filter::Exponential,
        Some("COLOR") => Filter::Color,
        Some(other) => bail!("filter '{other}' is not one meshoptimizer knows"),
    };
    let v = View {
        index: view.index(),
        source: num("buffer", None)?,
        offset: num("byteOffset", Some(0))?,
        length: num("byteLength", None)?,
        stride: num("byteStride", None)?,
        count: num("count", None)?,
        codec,
        filter,
    };
    if v.count == 0 || v.count > MAX_ACCESSOR_COUNT {
        bail!("count {} is outside 1..={MAX_ACCESSOR_COUNT}", v.count);
    }
    let stride_ok = match codec {
        Codec::Attributes => v.stride.is_multiple_of(4) && (4..=256).contains(&v.stride),
        Codec::Triangles | Codec::Indices => v.stride == 2 || v.stride == 4,
    };
    if !stride_ok {
        bail!(
            "byteStride {} is not allowed for {codec:?} (4 to 256 in steps of 4 for attributes, 2 or 4 for indices)",
            v.stride
        );
    }
    if codec == Codec::Triangles && !v.count.is_multiple_of(3) {
        bail!("TRIANGLES data of {} indices is not whole triangles", v.count);
    }
    let filter_ok = match filter {
        Filter::None => true,
        _ if codec != Codec::Attributes => false,
        Filter::Octahedral | Filter::Color => v.stride == 4 || v.stride == 8,
        Filter::Quaternion => v.stride == 8,
        Filter::Exponential => v.stride.is_multiple_of(4),
    };
    if !filter_ok {
        bail!("filter {filter:?} cannot apply to {codec:?} data of stride {}", v.stride);
    }
    if v.count * v.stride > view.length() {
        bail!("{} elements of {} bytes do not fit the view's {} bytes", v.count, v.stride, view.length());
    }
    if view.stride().is_some_and(|s| s != v.stride) {
        bail!("byteStride {} differs from the view's {}", v.stride, view.stride().unwrap_or(0));
    }
    Ok(v)
}

/// Decodes one view's compressed bytes to `count * stride` bytes.
fn decode_view(v: &View, compressed: &[u8]) -> Result<Vec<u8>> {
    use ::meshopt::ffi;
    let bytes = v.count * v.stride;
    // u32 storage: the filters read 16- and 32-bit values in place.
    let mut out = vec![0u32; bytes.div_ceil(4)];
    let dst = out.as_mut_ptr().cast::<std::ffi::c_void>();
    // SAFETY: `out` holds at least `count * stride` bytes, 4-byte aligned; the strides, counts
    // and filters are the ones `parse_view` allows (what meshoptimizer asserts), and its
    // decoders read at most `compressed.len()` bytes from `compressed`.
    let code = unsafe {
        match v.codec {
            Codec::Attributes => {
                ffi::meshopt_decodeVertexBuffer(dst, v.count, v.stride, compressed.as_ptr(), compressed.len())
            }
            Codec::Triangles => {
                ffi::meshopt_decodeIndexBuffer(dst, v.count, v.stride, compressed.as_ptr(), compressed.len())
            }
            Codec::Indices => {
                ffi::meshopt_decodeIndexSequence(dst, v.count, v.stride, compressed.as_ptr(), compressed.len())
            }
        }
    };
    if code != 0 {
        bail!("the compressed data does not decode (meshoptimizer error {code})");
    }
    // SAFETY: as above: the buffer holds `count` elements of `stride` bytes, which the filter
    // rewrites in place; `parse_view` checked the stride each filter allows.
    unsafe {
        match v.filter {
            Filter::None => {}
            Filter::Octahedral => ffi::meshopt_decodeFilterOct(dst, v.count, v.stride),
            Filter::Quaternion => ffi::meshopt_decodeFilterQuat(dst, v.count, v.stride),
            Filter::Exponential => ffi::meshopt_decodeFilterExp(dst, v.count, v.stride),
            Filter::Color => ffi::meshopt_decodeFilterColor(dst, v.count, v.stride),
        }
    }
    let mut bytes_out: Vec<u8> = bytemuck::cast_slice(&out).to_vec();
    bytes_out.truncate(bytes);
    Ok(bytes_out)
}
