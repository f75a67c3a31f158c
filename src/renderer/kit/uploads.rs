//! Material textures uploaded on a device, shared by every renderer on it that draws a scene
//! holding the same image (`Arc<scene::Texture>`). The bench keeps a renderer per configuration
//! alive at once, each with the scene: without sharing, 8 materials with three 2048-pixel maps
//! each (0.5 GiB with their mips) were uploaded once per renderer. The device (`gpu.rs`) holds
//! the cache; a copy is let go once no scene holds its image and no renderer its texture.

use crate::scene::Texture;
use std::sync::{Arc, Mutex, Weak};

#[derive(Default)]
pub struct Uploads {
    textures: Mutex<Vec<(Weak<Texture>, wgpu::Texture)>>,
}

impl Uploads {
    /// The device's copy of `t`, uploaded by `upload` when it has none.
    pub fn texture(&self, t: &Arc<Texture>, upload: impl FnOnce() -> wgpu::Texture) -> wgpu::Texture {
        let mut held = self.textures.lock().unwrap_or_else(|e| e.into_inner());
        // Images no scene holds any more (a dropped image's address may be reused).
        held.retain(|(image, _)| image.strong_count() > 0);
        if let Some((_, texture)) = held.iter().find(|(image, _)| std::ptr::eq(image.as_ptr(), Arc::as_ptr(t))) {
            return texture.clone();
        }
        let texture = upload();
        held.push((Arc::downgrade(t), texture.clone()));
        texture
    }

    /// Images with a copy held.
    pub fn len(&self) -> usize {
        let mut held = self.textures.lock().unwrap_or_else(|e| e.into_inner());
        held.retain(|(image, _)| image.strong_count() > 0);
        held.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}
