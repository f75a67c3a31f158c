//! The WGSL a layout generates: its constants, the bindings of its targets, `GBufferOut`,
//! `gbuffer_store` and `gbuffer_load`, so the encoding lives in the table alone.

use super::{is_bits, is_depth_buffer, is_float, Attr, GBufferLayout, NormalEncoding, Slot, TargetDesc};
use std::fmt::Write;

/// The components of a target's texel, in WGSL.
const COMPS: [&str; 4] = ["x", "y", "z", "w"];

impl GBufferLayout {
    /// WGSL: bindings of the targets for reading (group `group`), the `GBufferOut` struct,
    /// `gbuffer_store(Surface) -> GBufferOut` and `gbuffer_load(vec2<i32>) -> Surface`. With
    /// `ambient`, `GBufferOut` also has the two light accumulation targets after the layout's
    /// (`light_diffuse`, `light_specular`), which `gbuffer_store` fills with ambient + sun
    /// (`ambient_sun`, seed 000's RT1 starting value).
    pub fn wgsl(&self, group: u32, ambient: bool) -> String {
        let mut w = String::new();
        self.wgsl_constants(&mut w);
        for (i, t) in self.targets.iter().enumerate() {
            let _ = writeln!(w, "@group({group}) @binding({i}) var gbuf{i}: texture_2d<{}>;", scalar(t.format));
        }
        self.wgsl_out(&mut w, ambient);
        self.wgsl_store(&mut w, ambient);
        self.wgsl_depth_only(&mut w);
        self.wgsl_load(&mut w);
        w
    }

    /// The layout's facts as WGSL constants, for the shaders' branches.
    fn wgsl_constants(&self, w: &mut String) {
        let _ = writeln!(w, "// Generated from G-buffer layout '{}'.", self.name);
        let _ = writeln!(w, "const GBUFFER_NORMAL_OCTAHEDRAL: bool = {};", self.normal == NormalEncoding::Octahedral);
        let _ = writeln!(w, "const GBUFFER_NORMAL_LAMBERT: bool = {};", self.normal == NormalEncoding::Lambert);
        let _ = writeln!(w, "const GBUFFER_HAS_DEPTH: bool = {};", self.has(Attr::Depth));
        let _ = writeln!(w, "const GBUFFER_WORLD: bool = {};", self.world);
        let _ = writeln!(w, "const GBUFFER_ONE_ACCUM: bool = {};", self.one_accumulation);
        let _ = writeln!(w, "const GBUFFER_POSITION_ROUNDING: f32 = {:?};", self.position_rounding() as f32);
        let _ = writeln!(w, "const GBUFFER_SPEC_LEVEL_RAW: bool = {};", self.spec_level_raw());
        // The material ID: per pixel from its channel, or the scene's one model.
        let _ = writeln!(w, "const GBUFFER_HAS_MATERIAL: bool = {};", self.uniform_brdf.is_none());
        let _ = writeln!(w, "const GBUFFER_BRDF: u32 = {}u;", self.uniform_brdf.unwrap_or_default().id());
        // The culling layer (seed 004): per pixel from its channel, or the scene's one layer.
        let _ = writeln!(w, "const GBUFFER_HAS_LAYER: bool = {};", self.uniform_layer.is_none());
        let _ = writeln!(w, "const GBUFFER_LAYER: u32 = {}u;", self.uniform_layer.unwrap_or(0));
    }

    /// The `GBufferOut` struct: a location per rendered target, the fragment's depth where a
    /// stored position sets it, and the accumulation targets with `ambient`.
    fn wgsl_out(&self, w: &mut String, ambient: bool) {
        let _ = writeln!(w, "struct GBufferOut {{");
        // The depth buffer read as a target is not an output: locations count rendered targets.
        let mut location = 0;
        for (i, t) in self.targets.iter().enumerate().filter(|(_, t)| !is_depth_buffer(t)) {
            let _ = writeln!(w, "    @location({location}) t{i}: vec4<{}>,", scalar(t.format));
            location += 1;
        }
        // A stored position is the point the lighting shades: the depth the volumes test against
        // is that point's, projected after the target's rounding, not the rasteriser's plane,
        // which can lie far from it along the ray on a grazing surface (`position_depth`).
        if self.position_depth().is_some() {
            let _ = writeln!(w, "    @builtin(frag_depth) depth: f32,");
        }
        if ambient {
            let n = location;
            let _ = writeln!(w, "    @location({n}) light_diffuse: vec4<f32>,");
            if !self.one_accumulation {
                let _ = writeln!(w, "    @location({}) light_specular: vec4<f32>,", n + 1);
            }
        }
        let _ = writeln!(w, "}};");
    }

    /// `gbuffer_store`: each rendered target's channels from the surface's packed attributes,
    /// then the stored position's depth and, with `ambient`, ambient + sun.
    fn wgsl_store(&self, w: &mut String, ambient: bool) {
        let _ = writeln!(w, "fn gbuffer_store(s: Surface) -> GBufferOut {{");
        let _ = writeln!(w, "    var o: GBufferOut;");
        let _ = writeln!(w, "    let a = attributes_of(s);");
        for (i, t) in self.targets.iter().enumerate().filter(|(_, t)| !is_depth_buffer(t)) {
            let _ = writeln!(w, "    o.t{i} = vec4<{}>();", scalar(t.format));
            for (c, slot) in t.channels.iter().enumerate() {
                if let Some(s) = slot {
                    let _ = writeln!(w, "    o.t{i}.{} = {};", COMPS[c], self.stored_value(t, s));
                }
            }
        }
        if self.position_depth().is_some() {
            let _ = writeln!(w, "    o.depth = stored_depth(a);");
        }
        if ambient {
            self.wgsl_store_ambient(w);
        }
        let _ = writeln!(w, "    return o;\n}}");
    }

    /// What `gbuffer_store` writes to slot `s` of target `t`: the attribute, remapped to [0, 1]
    /// for a signed one in a normalised format, as bits in an integer format.
    fn stored_value(&self, t: &TargetDesc, s: &Slot) -> String {
        let src = match s.attr {
            // The least-squares multiple of the albedo (fp16's largest finite value at most).
            Attr::EmissiveScale => "min(select(0.0, max(dot(a.emissive, a.albedo), 0.0) / \
                                    max(dot(a.albedo, a.albedo), 1e-30), dot(a.albedo, a.albedo) > 0.0), 65504.0)"
                .to_string(),
            Attr::MaterialExp => "a.material * 255.0 + a.spec_exp * (255.0 / 256.0)".to_string(),
            _ => format!("a.{}{}", attr_field(s.attr), self.accessor(s)),
        };
        if is_bits(t.format) {
            format!("bitcast<u32>({src})")
        } else if s.attr.signed() && !is_float(t.format) {
            format!("{src} * 0.5 + 0.5")
        } else {
            src
        }
    }

    /// The G-buffer depth pre-pass's fragment stages (`surfaces::gbuffer`): the masked
    /// surfaces' cutoff and, where a stored position sets the G-buffer pass's depth, that same
    /// depth (`stored_depth`), so the pass after it finds at each pixel exactly the depth it
    /// writes itself. `fs_geometry_depth` exists only then (the others draw without a fragment
    /// stage).
    fn wgsl_depth_only(&self, w: &mut String) {
        let cutoff = "if alpha < objects[in.object].material.y {\n        discard;\n    }\n";
        let Some(half) = self.position_depth() else {
            let _ = writeln!(
                w,
                "@fragment\nfn fs_geometry_depth_masked(in: GeometryOut, @builtin(front_facing) front: bool) {{"
            );
            let _ =
                writeln!(w, "    var s: Surface;\n    let alpha = material_surface(in, front, &s);\n    {cutoff}}}");
            return;
        };
        self.wgsl_store_depth(w, half);
        for (entry, masked) in [("fs_geometry_depth", false), ("fs_geometry_depth_masked", true)] {
            let _ = writeln!(w, "@fragment\nfn {entry}(in: GeometryOut, @builtin(front_facing) front: bool) -> @builtin(frag_depth) f32 {{");
            let _ = writeln!(w, "    var s: Surface;\n    let alpha = material_surface(in, front, &s);");
            if masked {
                let _ = write!(w, "    {cutoff}");
            }
            let _ = writeln!(w, "    return stored_depth(attributes_of(s));\n}}");
        }
    }

    /// `stored_depth`: the fragment's depth, the stored position (rounded to fp16 where
    /// `half`) projected.
    fn wgsl_store_depth(&self, w: &mut String, half: bool) {
        let _ = writeln!(w, "fn stored_depth(a: Attributes) -> f32 {{");
        let p = if half {
            "vec3<f32>(unpack2x16float(pack2x16float(a.position.xy)), unpack2x16float(pack2x16float(vec2<f32>(a.position.z, 0.0))).x)"
        } else {
            "a.position"
        };
        // As `gbuffer_load` reads it back: seed 000's world-space view vector turned to view space.
        let p = if self.world { format!("-(camera.view_rotation * vec4<f32>({p}, 0.0)).xyz") } else { p.to_string() };
        let _ = writeln!(w, "    let stored_clip = camera.proj * vec4<f32>({p}, 1.0);");
        let _ = writeln!(w, "    return clamp(stored_clip.z / stored_clip.w, 0.0, 1.0);\n}}");
    }

    /// The accumulation targets' starting value: ambient + sun (and the emission, for a layout
    /// with no emissive target).
    fn wgsl_store_ambient(&self, w: &mut String) {
        let _ = writeln!(w, "    let stored = as_stored(s);");
        let _ = writeln!(w, "    let light = ambient_sun(stored);");
        // A layout without an emissive target (seed 000's) writes the surface's emission
        // into the accumulation here: it is light, and compose adds the specular target
        // (seed 000: the one accumulation) as it is.
        let emitted = if self.has(Attr::Emissive) { "" } else { " + max(s.emissive, vec3<f32>(0.0))" };
        let diffuse = "min(light.diffuse, ambient_limit(stored))";
        let specular = format!("min(light.specular{emitted}, ambient_limit(stored))");
        if self.one_accumulation {
            let _ = writeln!(w, "    o.light_diffuse = encode_light({diffuse} * stored.albedo + {specular});");
        } else {
            let _ = writeln!(w, "    o.light_diffuse = encode_light({diffuse});");
            let _ = writeln!(w, "    o.light_specular = encode_light({specular});");
        }
    }

    /// `gbuffer_load`: every target's channels back into the attributes, then the surface.
    fn wgsl_load(&self, w: &mut String) {
        let _ = writeln!(w, "fn gbuffer_load(p: vec2<i32>) -> Surface {{");
        let _ = writeln!(w, "    var a = default_attributes();");
        let emissive_scale =
            self.targets.iter().flat_map(|t| &t.channels).flatten().any(|s| s.attr == Attr::EmissiveScale);
        if emissive_scale {
            let _ = writeln!(w, "    var emissive_scale = 0.0;");
        }
        for (i, t) in self.targets.iter().enumerate() {
            let _ = writeln!(w, "    let t{i} = textureLoad(gbuf{i}, p, 0);");
            for (c, slot) in t.channels.iter().enumerate() {
                if let Some(s) = slot {
                    self.wgsl_load_slot(w, t, s, format!("t{i}.{}", COMPS[c]));
                }
            }
        }
        if emissive_scale {
            let _ = writeln!(w, "    a.emissive = emissive_scale * a.albedo;");
        }
        let _ = writeln!(w, "    return surface_of(a, p);\n}}");
    }

    /// `gbuffer_load`'s reading of slot `s` of target `t` from `src`, its texel's component.
    fn wgsl_load_slot(&self, w: &mut String, t: &TargetDesc, s: &Slot, src: String) {
        let val = if is_bits(t.format) {
            format!("bitcast<f32>({src})")
        } else if s.attr.signed() && !is_float(t.format) {
            format!("{src} * 2.0 - 1.0")
        } else {
            src
        };
        match s.attr {
            Attr::EmissiveScale => {
                let _ = writeln!(w, "    emissive_scale = {val};");
            }
            Attr::MaterialExp => {
                let _ = writeln!(w, "    a.material = floor({val}) / 255.0;");
                let _ = writeln!(w, "    a.spec_exp = fract({val}) * (256.0 / 255.0);");
            }
            _ => {
                let _ = writeln!(w, "    a.{}{} = {val};", attr_field(s.attr), self.accessor(s));
            }
        }
    }

    /// `.x`, `.y`, ... for vector attributes, nothing for scalars.
    fn accessor(&self, s: &Slot) -> &'static str {
        if self.components(s.attr) == 1 && !matches!(s.attr, Attr::Normal) {
            ""
        } else {
            [".x", ".y", ".z", ".w"][s.comp as usize]
        }
    }
}

/// The WGSL scalar type a target is written and read as.
fn scalar(format: wgpu::TextureFormat) -> &'static str {
    if is_bits(format) {
        "u32"
    } else {
        "f32"
    }
}

fn attr_field(a: Attr) -> &'static str {
    match a {
        Attr::Albedo => "albedo",
        Attr::SpecLevel => "spec_level",
        Attr::SpecExp => "spec_exp",
        Attr::Normal => "normal",
        Attr::Emissive => "emissive",
        Attr::Depth => "depth",
        Attr::Position => "position",
        Attr::Material => "material",
        Attr::Layer => "layer",
        Attr::EmissiveScale => "emissive_scale",
        Attr::MaterialExp => "material_exp",
    }
}
