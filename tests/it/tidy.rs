//! The house checks its own floors, as rustc's `src/tools/tidy` and rust-analyzer's
//! `files_are_tidy` do: this reads `src/` (not the compiled crate) and fails, naming the file
//! and line, when
//! - a technique room (every folder of `src/renderer/` but `kit/`, `options/`, `inputs/` and
//!   `frame/`) imports
//!   `Renderer` or `Settings`, by any path: a `use`, an inline `crate::…::Renderer`,
//!   `super::super::…`, a glob or a re-export;
//! - `kit/` imports a technique room, or anything of the renderer but `kit/` and `options/`;
//! - the file-level import graph has a strongly connected set of more than
//!   [`MAX_CYCLE_FILES`] files, or one that spans more than one entry of `src/` (a top-level
//!   file is an entry of its own);
//! - a function is longer than [`MAX_FN_LINES`] without a table's reason (`// table: <why>` as
//!   its body's first line), or more than [`MAX_TABLES`] functions are tables;
//! - a `.rs` file under `src/renderer/` is longer than [`MAX_FILE_LINES`] besides its
//!   `#[cfg(test)]` items without naming its reason (`// tidy-filelength: <why>` among its first
//!   lines), or more than [`MAX_LONG_FILES`] files do.
//!
//! The graph: a node per file under `src/` that defines something (a file that only declares
//! modules and re-exports is not a node); an edge from a file to the file that defines an item
//! it names, in a `use` (a `pub use` too) or in a path anywhere in its code. Names are resolved
//! as rustc resolves them: through each module's items, child modules, imports and glob
//! imports, with re-exports followed to the item's source. Test modules (`#[cfg(test)]`) are
//! left out: they may import what they test.
//!
//! `LAMPSHADE_TIDY_SRC=/path/to/other/src cargo test --test it tidy:: -- --nocapture` prints
//! the report for another checkout's sources.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use syn::visit::Visit;

/// The largest strongly connected set of files allowed (Bevy's `bevy_pbr` has none over 7).
pub const MAX_CYCLE_FILES: usize = 10;
/// Folders of `src/renderer/` that are not technique rooms: the kit, the options and the
/// frame's inputs every room builds on, and the frame's assembly above them.
const NOT_ROOMS: &[&str] = &["kit", "options", "inputs", "frame"];
/// What a technique room never imports.
const HUB_TYPES: &[&str] = &["Renderer", "Settings"];

type ModId = usize;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Target {
    Module(ModId),
    /// An item: the module whose file defines it, and its name there.
    Item(ModId, usize),
}

#[derive(Default)]
struct Module {
    /// The file, relative to `src/`.
    file: String,
    parent: Option<ModId>,
    children: BTreeMap<String, ModId>,
    /// Names defined here (types, functions, constants, statics, traits, macros).
    items: BTreeSet<String>,
    /// `use` bindings: (name bound, path, line, a `pub use` re-export).
    uses: Vec<(String, Vec<String>, usize, bool)>,
    /// `use path::*`: (path, line).
    globs: Vec<(Vec<String>, usize)>,
    /// Paths named in code: (path, line).
    paths: Vec<(Vec<String>, usize)>,
}

/// One import of one file, resolved: which file and item it reaches.
#[derive(Clone, Debug)]
pub struct Import {
    pub from: String,
    pub line: usize,
    pub to: String,
    pub item: String,
    /// A `pub use`: routes others' imports to the source (followed through, not an edge of
    /// the graph), yet still an import for the rooms' rule.
    pub reexport: bool,
}

pub struct Tree {
    modules: Vec<Module>,
    names: Vec<String>,
    /// Files that define something (graph nodes).
    pub nodes: BTreeSet<String>,
}

fn is_cfg_test(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("cfg") && a.parse_args::<syn::Meta>().map(|m| m.path().is_ident("test")).unwrap_or(false)
    })
}

fn line_of(span: proc_macro2::Span) -> usize {
    span.start().line
}

fn flatten_use(tree: &syn::UseTree, prefix: &mut Vec<String>, line: usize, public: bool, m: &mut Module) {
    match tree {
        syn::UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            flatten_use(&p.tree, prefix, line, public, m);
            prefix.pop();
        }
        syn::UseTree::Name(n) => {
            let name = n.ident.to_string();
            if name == "self" {
                if let Some(last) = prefix.last() {
                    m.uses.push((last.clone(), prefix.clone(), line, public));
                }
            } else {
                let mut p = prefix.clone();
                p.push(name.clone());
                m.uses.push((name, p, line, public));
            }
        }
        syn::UseTree::Rename(r) => {
            let mut p = prefix.clone();
            if r.ident != "self" {
                p.push(r.ident.to_string());
            }
            m.uses.push((r.rename.to_string(), p, line, public));
        }
        syn::UseTree::Glob(_) => m.globs.push((prefix.clone(), line)),
        syn::UseTree::Group(g) => {
            for t in &g.items {
                flatten_use(t, prefix, line, public, m);
            }
        }
    }
}

/// Collects every path named in an item's code.
struct Paths<'a> {
    out: &'a mut Vec<(Vec<String>, usize)>,
}

impl<'ast> Visit<'ast> for Paths<'_> {
    fn visit_path(&mut self, p: &'ast syn::Path) {
        if p.leading_colon.is_none() {
            let segs: Vec<String> = p.segments.iter().map(|s| s.ident.to_string()).collect();
            let line = p.segments.first().map(|s| line_of(s.ident.span())).unwrap_or(0);
            self.out.push((segs, line));
        }
        syn::visit::visit_path(self, p);
    }
    fn visit_item_mod(&mut self, _: &'ast syn::ItemMod) {}
    fn visit_item_use(&mut self, _: &'ast syn::ItemUse) {}
}

impl Tree {
    /// Reads the module tree from `src/lib.rs` down.
    pub fn read(src: &Path) -> Result<Tree, String> {
        let mut t = Tree { modules: Vec::new(), names: Vec::new(), nodes: BTreeSet::new() };
        t.modules.push(Module { file: "lib.rs".into(), ..Default::default() });
        let file = parse(&src.join("lib.rs"))?;
        let defines = t.fill(src, 0, &file.items, Path::new(""))?;
        if defines {
            t.nodes.insert("lib.rs".into());
        }
        Ok(t)
    }

    fn add_child(&mut self, parent: ModId, name: &str, file: String) -> ModId {
        let id = self.modules.len();
        self.modules.push(Module { file, parent: Some(parent), ..Default::default() });
        self.modules[parent].children.insert(name.to_string(), id);
        id
    }

    /// Fills module `id` from its items; `dir` is where its child modules' files live.
    /// Returns whether the items define anything (beyond modules and imports).
    fn fill(&mut self, src: &Path, id: ModId, items: &[syn::Item], dir: &Path) -> Result<bool, String> {
        let mut defines = false;
        for item in items {
            let ident = match item {
                syn::Item::Const(i) => Some(&i.ident),
                syn::Item::Enum(i) => Some(&i.ident),
                syn::Item::Fn(i) => Some(&i.sig.ident),
                syn::Item::Static(i) => Some(&i.ident),
                syn::Item::Struct(i) => Some(&i.ident),
                syn::Item::Trait(i) => Some(&i.ident),
                syn::Item::Type(i) => Some(&i.ident),
                syn::Item::Union(i) => Some(&i.ident),
                syn::Item::Macro(i) => i.ident.as_ref(),
                _ => None,
            };
            let attrs: &[syn::Attribute] = match item {
                syn::Item::Mod(i) => &i.attrs,
                syn::Item::Use(i) => &i.attrs,
                syn::Item::Impl(i) => &i.attrs,
                syn::Item::Fn(i) => &i.attrs,
                _ => &[],
            };
            if is_cfg_test(attrs) {
                continue;
            }
            if let Some(ident) = ident {
                self.modules[id].items.insert(ident.to_string());
                defines = true;
            }
            match item {
                syn::Item::Use(u) => {
                    let line = line_of(u.use_token.span);
                    let mut prefix = Vec::new();
                    let public = !matches!(u.vis, syn::Visibility::Inherited);
                    flatten_use(&u.tree, &mut prefix, line, public, &mut self.modules[id]);
                }
                syn::Item::Mod(m) => {
                    let name = m.ident.to_string();
                    if let Some((_, content)) = &m.content {
                        let file = self.modules[id].file.clone();
                        let child = self.add_child(id, &name, file);
                        defines |= self.fill(src, child, content, &dir.join(&name))?;
                    } else {
                        let (rel, child_dir) = if src.join(dir).join(format!("{name}.rs")).exists() {
                            (dir.join(format!("{name}.rs")), dir.join(&name))
                        } else {
                            (dir.join(&name).join("mod.rs"), dir.join(&name))
                        };
                        let rel_s = rel.to_string_lossy().replace('\\', "/");
                        let child = self.add_child(id, &name, rel_s.clone());
                        let file = parse(&src.join(&rel))?;
                        if self.fill(src, child, &file.items, &child_dir)? {
                            self.nodes.insert(rel_s);
                        }
                    }
                }
                syn::Item::Macro(_) | syn::Item::Verbatim(_) | syn::Item::ExternCrate(_) => {}
                other => {
                    if matches!(other, syn::Item::Impl(_)) {
                        defines = true;
                    }
                    Paths { out: &mut self.modules[id].paths }.visit_item(other);
                }
            }
        }
        Ok(defines)
    }

    fn name_id(&mut self, name: &str) -> usize {
        if let Some(i) = self.names.iter().position(|n| n == name) {
            return i;
        }
        self.names.push(name.to_string());
        self.names.len() - 1
    }

    /// `name` as module `m` sees it.
    fn resolve_in(&mut self, m: ModId, name: &str, seen: &mut Vec<(ModId, String)>) -> Option<Target> {
        if seen.iter().any(|(s, n)| *s == m && n == name) || seen.len() > 64 {
            return None;
        }
        seen.push((m, name.to_string()));
        if let Some(&c) = self.modules[m].children.get(name) {
            return Some(Target::Module(c));
        }
        if self.modules[m].items.contains(name) {
            let n = self.name_id(name);
            return Some(Target::Item(m, n));
        }
        let uses: Vec<Vec<String>> =
            self.modules[m].uses.iter().filter(|(n, ..)| n == name).map(|(_, p, ..)| p.clone()).collect();
        for path in uses {
            if let Some(t) = self.resolve_path(m, &path, seen) {
                return Some(t);
            }
        }
        let globs: Vec<Vec<String>> = self.modules[m].globs.iter().map(|(p, _)| p.clone()).collect();
        for path in globs {
            if let Some(Target::Module(g)) = self.resolve_path(m, &path, seen) {
                if let Some(t) = self.resolve_in(g, name, seen) {
                    return Some(t);
                }
            }
        }
        None
    }

    /// A path as module `m` names it; `None` for what lies outside the crate (or a local name).
    fn resolve_path(&mut self, m: ModId, path: &[String], seen: &mut Vec<(ModId, String)>) -> Option<Target> {
        let first = path.first()?;
        let mut cur = match first.as_str() {
            "crate" | "lampshade" => Target::Module(0),
            "self" => Target::Module(m),
            "super" => Target::Module(self.modules[m].parent?),
            "Self" => return None,
            name => self.resolve_in(m, name, seen)?,
        };
        for seg in &path[1..] {
            match cur {
                Target::Item(..) => return Some(cur),
                Target::Module(x) => {
                    cur = match seg.as_str() {
                        "super" => Target::Module(self.modules[x].parent?),
                        "self" => Target::Module(x),
                        s => self.resolve_in(x, s, seen)?,
                    };
                }
            }
        }
        Some(cur)
    }

    /// Every import of every node file, resolved to the item's defining file.
    pub fn imports(&mut self) -> Vec<Import> {
        let mut out = Vec::new();
        for m in 0..self.modules.len() {
            let from = self.modules[m].file.clone();
            if !self.nodes.contains(&from) {
                continue;
            }
            let mut named: Vec<(Vec<String>, usize, bool)> =
                self.modules[m].uses.iter().map(|(_, p, l, public)| (p.clone(), *l, *public)).collect();
            named.extend(self.modules[m].paths.iter().map(|(p, l)| (p.clone(), *l, false)));
            for (path, line, reexport) in named {
                // A single name is resolved through this module's scope (its imports and
                // globs); a longer path segment by segment.
                if let Some(Target::Item(d, n)) = self.resolve_path(m, &path, &mut Vec::new()) {
                    let to = self.modules[d].file.clone();
                    if to != from {
                        out.push(Import { from: from.clone(), line, to, item: self.names[n].clone(), reexport });
                    }
                }
            }
        }
        out
    }
}

fn parse(path: &Path) -> Result<syn::File, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    syn::parse_file(&text).map_err(|e| format!("{}:{}: {e}", path.display(), e.span().start().line))
}

/// Tarjan's strongly connected components over the file graph, largest first.
pub fn strongly_connected(nodes: &BTreeSet<String>, imports: &[Import]) -> Vec<Vec<String>> {
    let names: Vec<&String> = nodes.iter().collect();
    let index_of: HashMap<&String, usize> = names.iter().enumerate().map(|(i, n)| (*n, i)).collect();
    let mut adj = vec![BTreeSet::new(); names.len()];
    for i in imports.iter().filter(|i| !i.reexport) {
        if let (Some(&a), Some(&b)) = (index_of.get(&i.from), index_of.get(&i.to)) {
            adj[a].insert(b);
        }
    }
    struct T<'a> {
        adj: &'a [BTreeSet<usize>],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        out: Vec<Vec<usize>>,
    }
    fn visit(t: &mut T, v: usize) {
        t.index[v] = Some(t.next);
        t.low[v] = t.next;
        t.next += 1;
        t.stack.push(v);
        t.on[v] = true;
        let succ: Vec<usize> = t.adj[v].iter().copied().collect();
        for w in succ {
            match t.index[w] {
                None => {
                    visit(t, w);
                    t.low[v] = t.low[v].min(t.low[w]);
                }
                Some(iw) if t.on[w] => t.low[v] = t.low[v].min(iw),
                _ => {}
            }
        }
        if Some(t.low[v]) == t.index[v] {
            let mut set = Vec::new();
            while let Some(w) = t.stack.pop() {
                t.on[w] = false;
                set.push(w);
                if w == v {
                    break;
                }
            }
            t.out.push(set);
        }
    }
    let n = names.len();
    let mut t = T {
        adj: &adj,
        index: vec![None; n],
        low: vec![0; n],
        on: vec![false; n],
        stack: Vec::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in 0..n {
        if t.index[v].is_none() {
            visit(&mut t, v);
        }
    }
    let mut sets: Vec<Vec<String>> = t
        .out
        .into_iter()
        .filter(|s| s.len() > 1)
        .map(|s| {
            let mut v: Vec<String> = s.into_iter().map(|i| names[i].clone()).collect();
            v.sort();
            v
        })
        .collect();
    sets.sort_by(|a, b| b.len().cmp(&a.len()).then(a.cmp(b)));
    sets
}

/// The entry of `src/` a file sits under: its first folder, or the file itself at the top.
fn entry(file: &str) -> &str {
    file.split('/').next().unwrap_or(file)
}

/// The technique room a file sits in, if any.
fn room(file: &str) -> Option<&str> {
    let mut parts = file.split('/');
    if parts.next()? != "renderer" {
        return None;
    }
    let second = parts.next()?;
    // A file directly in `renderer/` is not in a room.
    parts.next()?;
    (!NOT_ROOMS.contains(&second)).then_some(second)
}

/// Every violation of the house's rules, one line each (`file:line: what`), and the report
/// (each strongly connected set).
pub fn check(src: &Path) -> Result<(Vec<String>, String), String> {
    let mut tree = Tree::read(src)?;
    let imports = tree.imports();
    let mut bad = Vec::new();
    let mut seen = BTreeSet::new();
    for i in &imports {
        if room(&i.from).is_some() && HUB_TYPES.contains(&i.item.as_str()) && !room(&i.to).is_some() {
            if seen.insert((i.from.clone(), i.line, i.item.clone())) {
                bad.push(format!("src/{}:{}: the technique room imports `{}` ({})", i.from, i.line, i.item, i.to));
            }
        }
        // kit/ sits at the bottom: beside `options/`, nothing of the renderer above it.
        let above_kit = i.to.starts_with("renderer/")
            && !i.to.starts_with("renderer/kit/")
            && !i.to.starts_with("renderer/options/");
        if i.from.starts_with("renderer/kit/") && above_kit && seen.insert((i.from.clone(), i.line, i.to.clone())) {
            let what = match room(&i.to) {
                Some(r) => format!("the technique room `{r}`"),
                None => "what sits above it".to_string(),
            };
            bad.push(format!("src/{}:{}: kit/ imports {what} (`{}` in {})", i.from, i.line, i.item, i.to));
        }
    }
    let sets = strongly_connected(&tree.nodes, &imports);
    let mut report = format!("{} files, {} imports resolved\n", tree.nodes.len(), imports.len());
    for set in &sets {
        let entries: BTreeSet<&str> = set.iter().map(|f| entry(f)).collect();
        report += &format!(
            "strongly connected set of {} files ({}):\n",
            set.len(),
            entries.iter().copied().collect::<Vec<_>>().join(", ")
        );
        let members: BTreeSet<&String> = set.iter().collect();
        for f in set {
            // One import that keeps the file on the cycle.
            let why = imports.iter().find(|i| !i.reexport && &i.from == f && members.contains(&i.to));
            match why {
                Some(i) => report += &format!("  src/{}:{} -> {} ({})\n", f, i.line, i.to, i.item),
                None => report += &format!("  src/{f}\n"),
            }
        }
        if set.len() > MAX_CYCLE_FILES || entries.len() > 1 {
            for f in set {
                let why = imports.iter().find(|i| !i.reexport && &i.from == f && members.contains(&i.to));
                let line = why.map(|i| i.line).unwrap_or(0);
                let to = why.map(|i| i.to.as_str()).unwrap_or("?");
                bad.push(format!(
                    "src/{f}:{line}: on an import cycle of {} files across {} (imports {to}); at most {MAX_CYCLE_FILES}, under one entry of src/",
                    set.len(),
                    entries.iter().copied().collect::<Vec<_>>().join(", ")
                ));
            }
        }
    }
    Ok((bad, report))
}

fn src_dir() -> PathBuf {
    match std::env::var_os("LAMPSHADE_TIDY_SRC") {
        Some(s) => PathBuf::from(s),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
    }
}

#[test]
fn the_import_graph_runs_one_way() {
    let (bad, report) = match check(&src_dir()) {
        Ok(r) => r,
        Err(e) => panic!("reading src/: {e}"),
    };
    println!("{report}");
    assert!(bad.is_empty(), "{} violations:\n{}", bad.len(), bad.join("\n"));
}

/// A small `src/` of the same shape, with `files` (path, text) added or replacing the base's:
/// a renderer with a kit, a technique room and the hub types, and a scene.
fn planted(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lampshade-tidy-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut all: Vec<(String, String)> = [
        ("lib.rs", "pub mod renderer;\npub mod scene;\n"),
        (
            "renderer/mod.rs",
            "pub mod culling;\npub mod kit;\npub mod settings;\npub use settings::Settings;\n\
             use crate::scene::Scene;\npub struct Renderer;\nimpl Renderer {\n    pub fn draw(&self, _: &Scene, _: &Settings) { culling::cull(); }\n}\n",
        ),
        ("renderer/settings.rs", "pub struct Settings;\n"),
        ("renderer/kit/mod.rs", "pub fn helper() {}\n"),
        ("renderer/culling/mod.rs", "use crate::renderer::kit::helper;\npub fn cull() {\n    helper();\n}\n"),
        ("scene/mod.rs", "pub struct Scene;\n"),
    ]
    .iter()
    .map(|(p, t)| (p.to_string(), t.to_string()))
    .collect();
    for (p, t) in files {
        all.retain(|(q, _)| q != p);
        all.push((p.to_string(), t.to_string()));
    }
    for (p, t) in &all {
        let path = dir.join(p);
        std::fs::create_dir_all(path.parent().expect("a file's folder")).expect("the planted folder");
        std::fs::write(&path, t).expect("a planted file");
    }
    dir
}

fn violations(name: &str, files: &[(&str, &str)]) -> Vec<String> {
    let dir = planted(name, files);
    let out = check(&dir).unwrap_or_else(|e| panic!("{name}: {e}")).0;
    let _ = std::fs::remove_dir_all(&dir);
    out
}

#[test]
fn the_planted_tree_is_clean_without_a_planted_violation() {
    assert_eq!(violations("clean", &[]), Vec::<String>::new());
}

#[test]
fn a_room_importing_settings_or_renderer_by_any_path_is_named_with_its_line() {
    let cases = [
        ("use", "use crate::renderer::settings::Settings;\npub fn cull(_: &Settings) {}\n", "Settings"),
        ("re-exported", "use crate::renderer::Settings;\npub fn cull(_: &Settings) {}\n", "Settings"),
        ("inline", "pub fn cull() {}\n\npub fn f(_: &crate::renderer::Renderer) {}\n", "Renderer"),
        ("super", "pub fn cull() {}\npub fn f(_: &super::Renderer) {}\n", "Renderer"),
        ("glob", "use crate::renderer::*;\npub fn cull() {}\npub fn f(_: &Settings) {}\n", "Settings"),
        ("pub use", "pub use crate::renderer::Renderer as Hub;\npub fn cull() {}\n", "Renderer"),
    ];
    for (name, text, item) in cases {
        let v = violations(name, &[("renderer/culling/mod.rs", text)]);
        assert!(
            v.iter().any(|l| l.starts_with("src/renderer/culling/mod.rs:") && l.contains(&format!("`{item}`"))),
            "{name}: {v:?}"
        );
        let line = v[0].split(':').nth(1).and_then(|n| n.parse::<usize>().ok());
        assert!(line.is_some_and(|n| n >= 1 && n <= text.lines().count()), "{name}: a line of the file: {v:?}");
    }
}

#[test]
fn kit_importing_a_technique_is_named() {
    let v = violations(
        "kit",
        &[("renderer/kit/mod.rs", "pub fn helper() {}\npub fn both() {\n    crate::renderer::culling::cull();\n}\n")],
    );
    assert!(v.iter().any(|l| l.starts_with("src/renderer/kit/mod.rs:3:") && l.contains("`culling`")), "{v:?}");
    let settings = "pub fn helper() {}\npub fn f(_: &crate::renderer::settings::Settings) {}\n";
    let v = violations("kit-settings", &[("renderer/kit/mod.rs", settings)]);
    assert!(v.iter().any(|l| l.starts_with("src/renderer/kit/mod.rs:2:") && l.contains("above it")), "{v:?}");
}

#[test]
fn a_cycle_of_more_than_ten_files_or_across_two_entries_is_named() {
    // Eleven files in a ring under one entry.
    let n = MAX_CYCLE_FILES + 1;
    let mut files: Vec<(String, String)> = (0..n)
        .map(|i| {
            (
                format!("renderer/ring/r{i}.rs"),
                format!("pub fn f{i}() {{\n    super::r{}::f{}();\n}}\n", (i + 1) % n, (i + 1) % n),
            )
        })
        .collect();
    let mods: String = (0..n).map(|i| format!("pub mod r{i};\n")).collect();
    files.push(("renderer/ring/mod.rs".into(), mods));
    files.push((
        "renderer/mod.rs".into(),
        "pub mod culling;\npub mod kit;\npub mod ring;\npub mod settings;\npub struct Renderer;\n".into(),
    ));
    let borrowed: Vec<(&str, &str)> = files.iter().map(|(p, t)| (p.as_str(), t.as_str())).collect();
    let v = violations("ring", &borrowed);
    assert_eq!(v.len(), n, "each file of the ring: {v:?}");
    assert!(v.iter().all(|l| l.contains(&format!("cycle of {n} files"))), "{v:?}");
    // Ten files stay within the rule.
    let ten: Vec<(String, String)> = (0..10)
        .map(|i| {
            (
                format!("renderer/ring/r{i}.rs"),
                format!("pub fn f{i}() {{\n    super::r{}::f{}();\n}}\n", (i + 1) % 10, (i + 1) % 10),
            )
        })
        .chain([("renderer/ring/mod.rs".to_string(), (0..10).map(|i| format!("pub mod r{i};\n")).collect())])
        .chain([(
            "renderer/mod.rs".to_string(),
            "pub mod culling;\npub mod kit;\npub mod ring;\npub mod settings;\npub struct Renderer;\n".to_string(),
        )])
        .collect();
    let borrowed: Vec<(&str, &str)> = ten.iter().map(|(p, t)| (p.as_str(), t.as_str())).collect();
    assert_eq!(violations("ten", &borrowed), Vec::<String>::new());
    // Two files, two entries: the scene reaching up into the renderer.
    let v = violations(
        "entries",
        &[
            ("scene/mod.rs", "pub struct Scene;\npub fn up() {\n    crate::renderer::kit::helper();\n}\n"),
            ("renderer/kit/mod.rs", "pub fn helper() {\n    let _ = crate::scene::Scene;\n}\n"),
        ],
    );
    assert!(v.iter().any(|l| l.starts_with("src/scene/mod.rs:3:") && l.contains("across renderer, scene")), "{v:?}");
}

// Sizes: no function past `MAX_FN_LINES` lines, no renderer file past `MAX_FILE_LINES`.

/// The longest function allowed, in lines from its signature's first line to its closing brace.
pub const MAX_FN_LINES: usize = 120;
/// Functions over [`MAX_FN_LINES`] allowed in the whole of `src/`, each a table that says why.
pub const MAX_TABLES: usize = 4;
/// What a function over the limit carries as the first line of its body, followed by the reason.
const TABLE_MARK: &str = "// table:";
/// The longest `.rs` file allowed under `src/renderer/`, its `#[cfg(test)]` items left out.
pub const MAX_FILE_LINES: usize = 900;
/// Renderer files over [`MAX_FILE_LINES`] allowed, each naming its reason.
pub const MAX_LONG_FILES: usize = 3;
/// What a file over the limit carries among its first lines (the comments and blank lines
/// before its first item), followed by the reason, as rustc's tidy reads
/// `// ignore-tidy-filelength`.
const FILE_LENGTH_MARK: &str = "// tidy-filelength:";

/// Every `.rs` file under `dir`, relative to it, in order.
fn rust_files(dir: &Path, rel: &Path, out: &mut Vec<PathBuf>) -> Result<(), String> {
    let entries = std::fs::read_dir(dir.join(rel)).map_err(|e| format!("{}: {e}", dir.join(rel).display()))?;
    let mut paths: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
    paths.sort();
    for path in paths {
        let name = rel.join(path.file_name().expect("an entry's name"));
        if path.is_dir() {
            rust_files(dir, &name, out)?;
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(name);
        }
    }
    Ok(())
}

/// One function's extent: its name (`Type::method` inside an `impl` or a trait), the lines of
/// its signature's start and its closing brace, and whether its body opens with [`TABLE_MARK`]
/// and a reason.
struct FnSpan {
    name: String,
    first: usize,
    last: usize,
    table: bool,
}

/// Collects every function with a body in a file: free, in an `impl`, in a trait, in a nested
/// module or inside another function. `#[cfg(test)]` items (the test modules) are left out.
struct Functions<'a> {
    lines: &'a [&'a str],
    owner: Vec<String>,
    out: Vec<FnSpan>,
}

impl Functions<'_> {
    fn add(&mut self, ident: &syn::Ident, sig: &syn::Signature, block: &syn::Block) {
        use syn::spanned::Spanned;
        let first = sig.span().start().line;
        let open = block.brace_token.span.open().start().line;
        // `lines` is 0-based: the line after the opening brace's is `lines[open]`.
        let table = self
            .lines
            .get(open)
            .and_then(|l| l.trim_start().strip_prefix(TABLE_MARK))
            .is_some_and(|reason| !reason.trim().is_empty());
        let name = match self.owner.last() {
            Some(owner) => format!("{owner}::{ident}"),
            None => ident.to_string(),
        };
        self.out.push(FnSpan { name, first, last: block.brace_token.span.close().start().line, table });
    }
}

impl<'ast> Visit<'ast> for Functions<'_> {
    fn visit_item(&mut self, item: &'ast syn::Item) {
        let attrs: &[syn::Attribute] = match item {
            syn::Item::Mod(i) => &i.attrs,
            syn::Item::Fn(i) => &i.attrs,
            syn::Item::Impl(i) => &i.attrs,
            syn::Item::Trait(i) => &i.attrs,
            _ => &[],
        };
        if !is_cfg_test(attrs) {
            syn::visit::visit_item(self, item);
        }
    }
    fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
        self.add(&f.sig.ident, &f.sig, &f.block);
        syn::visit::visit_item_fn(self, f);
    }
    fn visit_item_impl(&mut self, i: &'ast syn::ItemImpl) {
        let owner = match &*i.self_ty {
            syn::Type::Path(p) => p.path.segments.last().map(|s| s.ident.to_string()),
            _ => None,
        };
        self.owner.push(owner.unwrap_or_else(|| "impl".into()));
        syn::visit::visit_item_impl(self, i);
        self.owner.pop();
    }
    fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
        if !is_cfg_test(&f.attrs) {
            self.add(&f.sig.ident, &f.sig, &f.block);
            syn::visit::visit_impl_item_fn(self, f);
        }
    }
    fn visit_item_trait(&mut self, t: &'ast syn::ItemTrait) {
        self.owner.push(t.ident.to_string());
        syn::visit::visit_item_trait(self, t);
        self.owner.pop();
    }
    fn visit_trait_item_fn(&mut self, f: &'ast syn::TraitItemFn) {
        if let Some(block) = &f.default {
            self.add(&f.sig.ident, &f.sig, block);
        }
        syn::visit::visit_trait_item_fn(self, f);
    }
}

/// Every function of `src/` over [`MAX_FN_LINES`] without a table's reason, every table that
/// is within the limit (its mark unneeded), and more than [`MAX_TABLES`] tables: one line each,
/// `file:line: what`, naming the function and its length. `#[cfg(test)]` items are not
/// counted: a test may be as long as what it sets up.
pub fn long_functions(src: &Path) -> Result<Vec<String>, String> {
    let mut files = Vec::new();
    rust_files(src, Path::new(""), &mut files)?;
    let mut bad = Vec::new();
    let mut tables = Vec::new();
    for rel in files {
        let text = std::fs::read_to_string(src.join(&rel)).map_err(|e| format!("{}: {e}", rel.display()))?;
        let file = parse(&src.join(&rel))?;
        let lines: Vec<&str> = text.lines().collect();
        let mut found = Functions { lines: &lines, owner: Vec::new(), out: Vec::new() };
        found.visit_file(&file);
        let rel = rel.to_string_lossy().replace('\\', "/");
        for f in found.out {
            let length = f.last + 1 - f.first;
            let at = format!("src/{rel}:{}: `{}` is {length} lines", f.first, f.name);
            match (length > MAX_FN_LINES, f.table) {
                (true, false) => bad.push(format!(
                    "{at}; at most {MAX_FN_LINES}, or a table with `{TABLE_MARK} <why>` as its body's first line"
                )),
                (false, true) => bad.push(format!("{at}: within {MAX_FN_LINES}, so its `{TABLE_MARK}` is not needed")),
                (true, true) => tables.push(at),
                (false, false) => {}
            }
        }
    }
    if tables.len() > MAX_TABLES {
        for t in &tables {
            bad.push(format!("{t}: one of {} tables over {MAX_FN_LINES} lines; at most {MAX_TABLES}", tables.len()));
        }
    }
    Ok(bad)
}

/// A file's lines that count against [`MAX_FILE_LINES`]: all but its `#[cfg(test)]` items'
/// (from the attribute to the closing brace).
fn counted_lines(text: &str, file: &syn::File) -> usize {
    use syn::spanned::Spanned;
    let tests: usize = file
        .items
        .iter()
        .filter_map(|item| {
            let attrs: &[syn::Attribute] = match item {
                syn::Item::Mod(i) => &i.attrs,
                syn::Item::Fn(i) => &i.attrs,
                syn::Item::Impl(i) => &i.attrs,
                syn::Item::Use(i) => &i.attrs,
                _ => return None,
            };
            let first = attrs.iter().find(|a| is_cfg_test(std::slice::from_ref(a)))?;
            Some(item.span().end().line + 1 - first.span().start().line)
        })
        .sum();
    text.lines().count() - tests
}

/// Whether a file's first lines (the comments and blank lines before its first item) carry
/// [`FILE_LENGTH_MARK`] and a reason.
fn names_its_length(text: &str) -> bool {
    text.lines()
        .map(str::trim_start)
        .take_while(|l| l.is_empty() || l.starts_with("//"))
        .any(|l| l.strip_prefix(FILE_LENGTH_MARK).is_some_and(|reason| !reason.trim().is_empty()))
}

/// Every `.rs` file under `src/renderer/` over [`MAX_FILE_LINES`] (its `#[cfg(test)]` items
/// left out) that does not name its reason, every reason not needed, and more than
/// [`MAX_LONG_FILES`] reasons: one line each, naming the file and its length.
pub fn long_files(src: &Path) -> Result<Vec<String>, String> {
    let mut files = Vec::new();
    rust_files(src, Path::new("renderer"), &mut files)?;
    let mut bad = Vec::new();
    let mut named = Vec::new();
    for rel in files {
        let text = std::fs::read_to_string(src.join(&rel)).map_err(|e| format!("{}: {e}", rel.display()))?;
        let length = counted_lines(&text, &parse(&src.join(&rel))?);
        let at = format!("src/{}:1: {length} lines besides its tests", rel.to_string_lossy().replace('\\', "/"));
        match (length > MAX_FILE_LINES, names_its_length(&text)) {
            (true, false) => bad.push(format!(
                "{at}; at most {MAX_FILE_LINES} under src/renderer/, or `{FILE_LENGTH_MARK} <why>` in its first lines"
            )),
            (false, true) => {
                bad.push(format!("{at}: within {MAX_FILE_LINES}, so its `{FILE_LENGTH_MARK}` is not needed"))
            }
            (true, true) => named.push(at),
            (false, false) => {}
        }
    }
    if named.len() > MAX_LONG_FILES {
        for f in &named {
            bad.push(format!("{f}: one of {} long files; at most {MAX_LONG_FILES}", named.len()));
        }
    }
    Ok(bad)
}

#[test]
fn no_function_is_longer_than_its_limit_but_a_few_tables() {
    let bad = long_functions(&src_dir()).unwrap_or_else(|e| panic!("reading src/: {e}"));
    assert!(bad.is_empty(), "{} functions:\n{}", bad.len(), bad.join("\n"));
}

#[test]
fn no_renderer_file_is_longer_than_its_limit_but_a_few_named() {
    let bad = long_files(&src_dir()).unwrap_or_else(|e| panic!("reading src/: {e}"));
    assert!(bad.is_empty(), "{} files:\n{}", bad.len(), bad.join("\n"));
}

/// What `check` finds in the planted tree with `files` added.
fn planted_with(name: &str, files: &[(&str, &str)], check: fn(&Path) -> Result<Vec<String>, String>) -> Vec<String> {
    let dir = planted(name, files);
    let out = check(&dir).unwrap_or_else(|e| panic!("{name}: {e}"));
    let _ = std::fs::remove_dir_all(&dir);
    out
}

/// A function of `lines` lines from `fn` to its closing brace, its body opening with `first`.
fn function_of(name: &str, lines: usize, first: &str) -> String {
    let mut body = format!("/// A doc line, not counted.\npub fn {name}() {{\n{first}");
    let filler = lines - 2 - first.lines().count();
    body += &"    let _ = 0;\n".repeat(filler);
    body + "}\n"
}

#[test]
fn a_function_of_121_lines_is_named_with_its_length() {
    assert_eq!(planted_with("sizes-clean", &[], long_functions), Vec::<String>::new());
    let long = format!("pub fn helper() {{}}\n{}", function_of("sweep", 121, ""));
    let v = planted_with("fn-121", &[("renderer/kit/mod.rs", &long)], long_functions);
    assert_eq!(v.len(), 1, "{v:?}");
    assert!(v[0].starts_with("src/renderer/kit/mod.rs:3: `sweep` is 121 lines"), "{v:?}");
    let method = format!("pub struct T;\nimpl T {{\n{}}}\n", function_of("read", 121, "").replace('\n', "\n    "));
    let v = planted_with("method-121", &[("scene/mod.rs", &method)], long_functions);
    assert!(v.len() == 1 && v[0].contains("`T::read` is 121 lines"), "{v:?}");
    let exact = format!("pub fn helper() {{}}\n{}", function_of("sweep", 120, ""));
    assert_eq!(planted_with("fn-120", &[("renderer/kit/mod.rs", &exact)], long_functions), Vec::<String>::new());
    // A test module's functions are not counted.
    let tests = format!("pub fn helper() {{}}\n#[cfg(test)]\nmod tests {{\n{}}}\n", function_of("t", 200, ""));
    assert_eq!(planted_with("fn-test", &[("renderer/kit/mod.rs", &tests)], long_functions), Vec::<String>::new());
}

#[test]
fn a_long_function_passes_as_one_of_four_tables_with_a_reason() {
    let table = |name: &str| function_of(name, 130, "    // table: the sweep's rows, one a line\n");
    let one = format!("pub fn helper() {{}}\n{}", table("sweep"));
    assert_eq!(planted_with("table", &[("renderer/kit/mod.rs", &one)], long_functions), Vec::<String>::new());
    // The mark without a reason, or not on the body's first line, does not count.
    let bare = function_of("sweep", 130, "    // table:\n");
    let v = planted_with("table-bare", &[("scene/mod.rs", &format!("pub struct Scene;\n{bare}"))], long_functions);
    assert!(v.len() == 1 && v[0].contains("`sweep` is 130 lines"), "{v:?}");
    let late = function_of("sweep", 130, "    let _ = 1;\n    // table: the rows\n");
    let v = planted_with("table-late", &[("scene/mod.rs", &format!("pub struct Scene;\n{late}"))], long_functions);
    assert!(v.len() == 1 && v[0].contains("`sweep` is 130 lines"), "{v:?}");
    // A mark on a function within the limit is not needed.
    let short = function_of("sweep", 20, "    // table: the rows\n");
    let v = planted_with("table-short", &[("scene/mod.rs", &format!("pub struct Scene;\n{short}"))], long_functions);
    assert!(v.len() == 1 && v[0].contains("`sweep` is 20 lines") && v[0].contains("not needed"), "{v:?}");
    // Five tables are one too many: each is named.
    let five: String = (0..5).map(|i| table(&format!("t{i}"))).collect();
    let v = planted_with("tables-5", &[("scene/mod.rs", &format!("pub struct Scene;\n{five}"))], long_functions);
    assert!(v.len() == 5 && v.iter().all(|l| l.contains("one of 5 tables")), "{v:?}");
}

/// A renderer file of `lines` lines: `head`, then constants.
fn file_of(lines: usize, head: &str) -> String {
    let mut text = head.to_string();
    for i in 0..lines - head.lines().count() {
        text += &format!("pub const C{i}: u32 = {i};\n");
    }
    text
}

#[test]
fn a_renderer_file_of_901_lines_is_named_with_its_length() {
    assert_eq!(planted_with("files-clean", &[], long_files), Vec::<String>::new());
    let v = planted_with("file-901", &[("renderer/culling/long.rs", &file_of(901, ""))], long_files);
    assert_eq!(v.len(), 1, "{v:?}");
    assert!(v[0].starts_with("src/renderer/culling/long.rs:1: 901 lines"), "{v:?}");
    let tests = file_of(890, "") + "#[cfg(test)]\nmod tests {\n" + &"    // a test's line\n".repeat(60) + "}\n";
    for (name, text) in [
        ("file-900", file_of(900, "")),
        ("file-named", file_of(1000, "//! A table.\n// tidy-filelength: one table, row by row\n")),
        ("file-tests", tests),
    ] {
        assert_eq!(
            planted_with(name, &[("renderer/culling/long.rs", &text)], long_files),
            Vec::<String>::new(),
            "{name}"
        );
    }
    // Outside the renderer no file length is held.
    let scene = file_of(1000, "pub struct Scene;\n");
    assert_eq!(planted_with("file-scene", &[("scene/mod.rs", &scene)], long_files), Vec::<String>::new());
    // A reason on a file within the limit is not needed; more than three reasons are too many.
    let short = file_of(100, "// tidy-filelength: a table\n");
    let v = planted_with("file-short", &[("renderer/culling/long.rs", &short)], long_files);
    assert!(v.len() == 1 && v[0].contains("not needed"), "{v:?}");
    let named = file_of(950, "// tidy-filelength: a table\n");
    let four: Vec<(String, &str)> = (0..4).map(|i| (format!("renderer/culling/long{i}.rs"), named.as_str())).collect();
    let borrowed: Vec<(&str, &str)> = four.iter().map(|(p, t)| (p.as_str(), *t)).collect();
    let v = planted_with("files-4", &borrowed, long_files);
    assert!(v.len() == 4 && v.iter().all(|l| l.contains("one of 4 long files")), "{v:?}");
}

/// Every name a Rust path in `docs/architecture.md` ends in (a backticked `a::b::name` or
/// `name()`), defined somewhere under `src/` or `tests/`: a function, method, field, type,
/// constant or module of that name (a method or field of the type the path names, where it
/// names one).
#[derive(Default)]
struct Names {
    /// Free items and modules by name.
    items: BTreeSet<String>,
    /// Methods, associated items and fields by their type's name.
    members: BTreeMap<String, BTreeSet<String>>,
}

impl<'ast> Visit<'ast> for Names {
    fn visit_item(&mut self, item: &'ast syn::Item) {
        let name = match item {
            syn::Item::Const(i) => Some(i.ident.to_string()),
            syn::Item::Enum(i) => Some(i.ident.to_string()),
            syn::Item::Fn(i) => Some(i.sig.ident.to_string()),
            syn::Item::Static(i) => Some(i.ident.to_string()),
            syn::Item::Trait(i) => Some(i.ident.to_string()),
            syn::Item::Type(i) => Some(i.ident.to_string()),
            syn::Item::Mod(i) => Some(i.ident.to_string()),
            syn::Item::Macro(i) => i.ident.as_ref().map(|i| i.to_string()),
            syn::Item::Struct(s) => {
                let fields = s.fields.iter().filter_map(|f| f.ident.as_ref().map(|i| i.to_string()));
                self.members.entry(s.ident.to_string()).or_default().extend(fields);
                Some(s.ident.to_string())
            }
            syn::Item::Impl(i) => {
                if let syn::Type::Path(p) = &*i.self_ty {
                    if let Some(ty) = p.path.segments.last() {
                        let names = i.items.iter().filter_map(|it| match it {
                            syn::ImplItem::Fn(f) => Some(f.sig.ident.to_string()),
                            syn::ImplItem::Const(c) => Some(c.ident.to_string()),
                            _ => None,
                        });
                        self.members.entry(ty.ident.to_string()).or_default().extend(names);
                    }
                }
                None
            }
            _ => None,
        };
        self.items.extend(name);
        syn::visit::visit_item(self, item);
    }
}

fn read_names(dir: &Path, names: &mut Names) -> Result<(), String> {
    let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            read_names(&path, names)?;
        } else if path.extension().is_some_and(|e| e == "rs") {
            names.visit_file(&parse(&path)?);
            if let Some(stem) = path.file_stem() {
                names.items.insert(stem.to_string_lossy().into_owned());
            }
        }
    }
    Ok(())
}

/// The Rust paths a markdown text names in backticks: `a::b::c` or `name()` (generic
/// arguments and call parentheses dropped).
fn named_paths(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (i, span) in text.split('`').enumerate() {
        if i % 2 == 0 {
            continue;
        }
        let called = span.ends_with("()");
        let path = span.trim_end_matches("()");
        let is_path = !path.is_empty()
            && path.split("::").all(|s| !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'));
        if is_path && (called || path.contains("::")) {
            out.push(path.to_string());
        }
    }
    out
}

#[test]
fn every_function_the_architecture_names_still_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("docs/architecture.md")).expect("docs/architecture.md");
    let mut names = Names::default();
    for dir in ["src", "tests"] {
        if let Err(e) = read_names(&root.join(dir), &mut names) {
            panic!("{e}");
        }
    }
    assert!(named_paths(&doc).len() > 20, "the architecture names its functions");
    let missing = missing_names(&doc, &names);
    assert!(missing.is_empty(), "docs/architecture.md names what no longer exists: {missing:?}");
}

/// The paths `doc` names that `names` lacks.
fn missing_names(doc: &str, names: &Names) -> Vec<String> {
    named_paths(doc)
        .into_iter()
        .filter(|p| {
            let segs: Vec<&str> = p.split("::").collect();
            let last = segs[segs.len() - 1];
            // `Type::member`: a method, associated constant or field of that type.
            let ty = segs.len().checked_sub(2).map(|k| segs[k]).filter(|s| s.starts_with(char::is_uppercase));
            match ty {
                Some(ty) => !names.members.get(ty).is_some_and(|m| m.contains(last)),
                None => !names.items.contains(last),
            }
        })
        .collect()
}

#[test]
fn a_renamed_function_fails_the_architecture_check() {
    let doc = "`Renderer::render` draws, `Renderer::draw` too; `frame::prepare()` and `paths::record`.";
    assert_eq!(named_paths(doc), ["Renderer::render", "Renderer::draw", "frame::prepare", "paths::record"]);
    let mut names = Names::default();
    let code = "struct Renderer; impl Renderer { fn draw(&self) {} } mod frame {} fn record() {}";
    names.visit_file(&syn::parse_file(code).expect("parses"));
    assert_eq!(missing_names(doc, &names), ["Renderer::render", "frame::prepare"]);
}
