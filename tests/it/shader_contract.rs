//! One contract between Rust and WGSL: the final shader source (generated constants, bindings
//! and G-buffer layout, then the WGSL files), parsed with naga, must declare every record with
//! the members, offsets and size of its Rust twin, every binding the Rust tables list, and no
//! uniform buffer but the light planes, which are read only at an index computed at run time.

use lampshade::renderer::kit::bindings::{Kind, GROUPS};
use lampshade::renderer::program::shader_source;
use lampshade::renderer::records::{self, RecordLayout};
use lampshade::renderer::LayoutChoice;

/// The differences between `record` and the WGSL struct of the same name in `module`.
fn mismatches(module: &naga::Module, record: &RecordLayout) -> Vec<String> {
    let mut layouter = naga::proc::Layouter::default();
    if let Err(e) = layouter.update(module.to_ctx()) {
        return vec![format!("layout of the module failed: {e}")];
    }
    let found = module.types.iter().find(|(_, t)| t.name.as_deref() == Some(record.wgsl));
    let Some((handle, ty)) = found else { return vec![format!("no WGSL struct named {}", record.wgsl)] };
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        return vec![format!("{} is not a struct in WGSL", record.wgsl)];
    };
    let mut out = Vec::new();
    let wgsl: Vec<(String, usize)> =
        members.iter().map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize)).collect();
    let rust: Vec<(String, usize)> = record.fields.iter().map(|(n, o)| (n.to_string(), *o)).collect();
    if wgsl != rust {
        out.push(format!("{}: WGSL members {wgsl:?} but Rust fields {rust:?}", record.wgsl));
    }
    if *span as usize != record.size || layouter[handle].size as usize != record.size {
        out.push(format!("{}: WGSL size {span} but Rust size {}", record.wgsl, record.size));
    }
    out
}

fn parse(source: &str) -> naga::Module {
    naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)))
}

#[test]
fn every_record_has_the_layout_of_its_wgsl_twin_in_every_shader_configuration() {
    for layout in LayoutChoice::ALL.into_iter().filter(|l| *l != LayoutChoice::Fit) {
        for accum in [wgpu::TextureFormat::Rgba16Float, wgpu::TextureFormat::Rgba8Unorm] {
            for ambient_in_gbuffer in [true, false] {
                let module = parse(&shader_source(&layout.layout(), accum, ambient_in_gbuffer));
                for record in records::layouts() {
                    let bad = mismatches(&module, &record);
                    assert!(bad.is_empty(), "{layout:?}, {accum:?}, {ambient_in_gbuffer}: {bad:#?}");
                }
            }
        }
    }
}

#[test]
fn a_field_added_on_one_side_only_breaks_the_contract() {
    // The check itself must be able to fail: add a member to the WGSL light record only, then
    // a field to the Rust side only.
    let source = shader_source(&LayoutChoice::Compact.layout(), wgpu::TextureFormat::Rgba16Float, true);
    let light = records::LightRecord::layout();
    assert!(mismatches(&parse(&source), &light).is_empty());
    let extra = source.replacen("struct GpuLight {\n", "struct GpuLight {\n    extra: vec4<f32>,\n", 1);
    assert_ne!(extra, source, "the WGSL light record was not found to edit");
    let bad = mismatches(&parse(&extra), &light);
    assert!(bad.iter().any(|m| m.contains("WGSL members")) && bad.iter().any(|m| m.contains("size")), "{bad:?}");
    let mut rust_only = records::LightRecord::layout();
    rust_only.fields.push(("shadow_index", rust_only.size));
    rust_only.size += 16;
    let bad = mismatches(&parse(&source), &rust_only);
    assert_eq!(bad.len(), 2, "{bad:?}");
}

#[test]
fn every_binding_is_declared_as_the_rust_tables_say_and_only_the_light_planes_are_uniforms() {
    let module = parse(&shader_source(&LayoutChoice::Compact.layout(), wgpu::TextureFormat::Rgba16Float, true));
    let planes: Vec<&str> = GROUPS
        .iter()
        .flat_map(|g| g.bindings.iter())
        .filter(|b| matches!(b.kind, Kind::LightPlane))
        .map(|b| b.name)
        .collect();
    assert_eq!(planes.len(), records::LIGHT_PLANE_COUNT);
    for (_, g) in module.global_variables.iter() {
        if matches!(g.space, naga::AddressSpace::Uniform) {
            assert!(
                g.name.as_deref().is_some_and(|n| planes.contains(&n)),
                "{:?} is a uniform buffer: lavapipe recompiles (and leaks) shaders whose branches read one at a \
                 constant offset; use storage (only the light planes, read at a light's index, are uniforms)",
                g.name
            );
        }
    }
    for group in GROUPS {
        for b in group.bindings {
            let found = module.global_variables.iter().find(|(_, g)| g.name.as_deref() == Some(b.name));
            let Some((_, g)) = found else { panic!("{} is not declared", b.name) };
            let rb = g.binding.as_ref().map(|r| (r.group, r.binding));
            assert_eq!(rb, Some((group.index, b.slot)), "{}", b.name);
        }
    }
}

/// Where a light plane is read at an index fixed in the source: lavapipe inlines uniform values
/// read at constant offsets into the shader and recompiles it whenever the buffer changes
/// (the soak's old leak), so the planes may only be read at an index computed at run time.
fn constant_plane_reads(module: &naga::Module) -> Vec<String> {
    let planes: Vec<naga::Handle<naga::GlobalVariable>> = module
        .global_variables
        .iter()
        .filter(|(_, g)| g.name.as_deref().is_some_and(|n| n.starts_with("light_plane")))
        .map(|(h, _)| h)
        .collect();
    assert_eq!(planes.len(), records::LIGHT_PLANE_COUNT);
    let functions = module.functions.iter().map(|(_, f)| f).chain(module.entry_points.iter().map(|e| &e.function));
    let mut found = Vec::new();
    for f in functions {
        let is_plane = |e: naga::Handle<naga::Expression>| matches!(f.expressions[e], naga::Expression::GlobalVariable(g) if planes.contains(&g));
        for (_, e) in f.expressions.iter() {
            let constant = match *e {
                naga::Expression::AccessIndex { base, .. } => is_plane(base),
                naga::Expression::Access { base, index } => {
                    is_plane(base)
                        && matches!(
                            f.expressions[index],
                            naga::Expression::Literal(_)
                                | naga::Expression::Constant(_)
                                | naga::Expression::ZeroValue(_)
                        )
                }
                _ => false,
            };
            if constant {
                found.push(f.name.clone().unwrap_or_default());
            }
        }
    }
    found
}

#[test]
fn the_light_planes_are_only_read_at_an_index_computed_at_run_time() {
    let source = shader_source(&LayoutChoice::Compact.layout(), wgpu::TextureFormat::Rgba16Float, true);
    assert_eq!(constant_plane_reads(&parse(&source)), Vec::<String>::new());
    // A read at a fixed index is caught.
    let bad = format!("{source}\nfn first_light_radius() -> u32 {{\n    return light_plane0[0u].w;\n}}\n");
    assert_eq!(constant_plane_reads(&parse(&bad)), ["first_light_radius"]);
    let bad = format!(
        "{source}\nconst FIRST: u32 = 2u;\nfn third_light() -> u32 {{\n    return light_plane3[FIRST].w;\n}}\n"
    );
    assert_eq!(constant_plane_reads(&parse(&bad)), ["third_light"]);
}

#[test]
fn every_shared_constant_is_generated_from_rust_not_copied_into_a_shader_file() {
    // A constant both sides use is written by `wgsl_constants` from its Rust twin; a `const LS_`
    // declared in a WGSL file is a copy that only a comment keeps in step.
    fn wgsl_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
        for entry in std::fs::read_dir(dir).expect("a source folder").flatten() {
            let path = entry.path();
            if path.is_dir() {
                wgsl_files(&path, out);
            } else if path.extension().is_some_and(|e| e == "wgsl") {
                out.push(path);
            }
        }
    }
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    wgsl_files(&root.join("src"), &mut files);
    assert!(files.len() >= 10, "{} shader files found", files.len());
    let mut copied = Vec::new();
    for path in &files {
        let text = std::fs::read_to_string(path).expect("a shader file");
        for line in text.lines().filter(|l| l.trim_start().starts_with("const LS_")) {
            copied.push(format!("{}: {}", path.display(), line.trim()));
        }
    }
    assert!(copied.is_empty(), "hand-copied constants:\n{}", copied.join("\n"));
    // And the generated ones are there, with their Rust values.
    let source = shader_source(&LayoutChoice::Compact.layout(), wgpu::TextureFormat::Rgba16Float, true);
    for want in [
        format!("const LS_TILE_ALL: u32 = {}u;", lampshade::renderer::tiles::ALL_LIGHTS),
        format!("const LS_TILE_MAX_LIGHTS: u32 = {}u;", lampshade::renderer::tiles::GPU_LIST_MAX_LIGHTS),
        "const LS_LUMINANCE: vec3<f32> = vec3<f32>(0.2126, 0.7152, 0.0722);".to_string(),
    ] {
        assert!(source.contains(&want), "{want} is not in the shader source");
    }
}
