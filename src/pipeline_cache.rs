//! The viewer's compiled pipelines kept between runs: a `wgpu::PipelineCache` per adapter in the
//! user's cache folder (`pipelines-<key>-<hash>.bin`, keyed as the calibration is: the
//! adapter's name, driver and driver info, and for a CPU adapter the CPU's model and core
//! count), read when the viewer starts and written when it closes. Where the device has no
//! pipeline cache (`Features::PIPELINE_CACHE`: wgpu's GL backend) there is nothing to keep.
//!
//! Lavapipe's cache holds nothing (Mesa 22.3.6: 96 bytes before and after a pipeline is made
//! through it, wgpu's header and Vulkan's), so there warm and cold runs are the same; what keeps
//! llvmpipe's compiled code between runs is Mesa's own shader cache. wgpu checks the header (its
//! version, the adapter, the driver) and, given data of another adapter or a damaged file,
//! starts an empty cache (`fallback`).

use crate::Gpu;
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

/// The cache file of `gpu`'s adapter, where the user has a cache folder.
pub fn path(gpu: &Gpu) -> Option<PathBuf> {
    let dir = crate::calibration::cache_dir()?;
    Some(crate::calibration::keyed_file(&dir, "pipelines", &crate::calibration::key(&gpu.info), "bin"))
}

/// Makes `gpu`'s pipeline cache from its file (empty when there is none) and has the pass sets
/// made on the device from now on compile through it. Returns the file and the bytes read; `None` where the
/// device has no pipeline cache or the user no cache folder.
pub fn load(gpu: &Gpu) -> Result<Option<(PathBuf, usize)>> {
    let Some(path) = path(gpu) else { return Ok(None) };
    Ok(load_from(gpu, &path)?.map(|n| (path, n)))
}

/// [`load`] from `path`: the bytes read, `None` where the device has no pipeline cache.
pub fn load_from(gpu: &Gpu, path: &Path) -> Result<Option<usize>> {
    if !gpu.has(wgpu::Features::PIPELINE_CACHE) {
        return Ok(None);
    }
    let data = match std::fs::read(path) {
        Ok(d) => Some(d),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(e).with_context(|| format!("reading the pipeline cache {}", path.display())),
    };
    // SAFETY: wgpu requires the data to come from `PipelineCache::get_data` of a cache made on
    // an adapter it validates against; it checks the header it wrote (magic, version, adapter
    // key, the data's length and hash) and with `fallback` starts empty on any mismatch, and the
    // file is this adapter's, written by `save` below.
    let cache = unsafe {
        gpu.device.create_pipeline_cache(&wgpu::PipelineCacheDescriptor {
            label: Some("lampshade pipelines"),
            data: data.as_deref(),
            fallback: true,
        })
    };
    gpu.passes.set_pipeline_cache(Some(cache));
    Ok(Some(data.map_or(0, |d| d.len())))
}

/// Writes `gpu`'s pipeline cache to its file. Returns the file and the bytes written; `None`
/// where there is no cache to write.
pub fn save(gpu: &Gpu) -> Result<Option<(PathBuf, usize)>> {
    let Some(path) = path(gpu) else { return Ok(None) };
    Ok(save_to(gpu, &path)?.map(|n| (path, n)))
}

/// [`save`] to `path`: the bytes written.
pub fn save_to(gpu: &Gpu, path: &Path) -> Result<Option<usize>> {
    let Some(cache) = gpu.passes.pipeline_cache() else { return Ok(None) };
    let Some(data) = cache.get_data() else { return Ok(None) };
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    // Written beside and renamed, so a run killed mid-write leaves the old file whole.
    let part = path.with_extension("bin.part");
    std::fs::write(&part, &data).with_context(|| format!("writing {}", part.display()))?;
    std::fs::rename(&part, path).with_context(|| format!("writing {}", path.display()))?;
    Ok(Some(data.len()))
}
