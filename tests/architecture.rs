//! The one-way house: no import runs back between the render core's folders (`src/<family>/`),
//! nor between the files of one folder, nor between the master's files (`server/src/`).
//! Imports are read from the source (`crate::x` paths and `super::x` siblings), leaving out
//! comments, tests and benchmarks; a cycle fails with the path it takes.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

type Graph = BTreeMap<String, BTreeSet<String>>;

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if p.is_dir() {
            if name != "tests" {
                rust_files(&p, out);
            }
        } else if name.ends_with(".rs") && name != "tests.rs" && name != "test_util.rs" {
            out.push(p);
        }
    }
}

/// The source without comments and without its inline `#[cfg(test)]` module.
fn code(text: &str) -> String {
    let text = match text.find("#[cfg(test)]\nmod tests {") {
        Some(i) => &text[..i],
        None => text,
    };
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .map(|l| l.split(" // ").next().unwrap_or(l))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Identifiers following `prefix` in `text` (`crate::film::x` gives "film").
fn idents_after<'a>(text: &'a str, prefix: &str) -> Vec<&'a str> {
    text.match_indices(prefix)
        .filter(|(i, _)| {
            // not part of a longer path such as `luxfarm_crate::`
            text[..*i]
                .chars()
                .last()
                .is_none_or(|c| !(c.is_alphanumeric() || c == '_'))
        })
        .filter_map(|(i, _)| {
            let rest = &text[i + prefix.len()..];
            let end = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                .unwrap_or(rest.len());
            (end > 0).then(|| &rest[..end])
        })
        .collect()
}

/// Folder-level graph of a crate's `src/`: an edge a -> b when a file under `src/a` names
/// `crate::b`.
fn folder_graph(src: &Path) -> Graph {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut g = Graph::new();
    for f in files {
        let rel = f.strip_prefix(src).unwrap();
        let top = rel.iter().next().unwrap().to_string_lossy();
        let module = top.trim_end_matches(".rs").to_string();
        let text = code(&std::fs::read_to_string(&f).unwrap());
        for t in idents_after(&text, "crate::") {
            if t != module {
                g.entry(module.clone()).or_default().insert(t.to_string());
            }
        }
    }
    g
}

/// File-level graph inside one folder: an edge a -> b when `a.rs` names its sibling `b` through
/// `super::b` (or `crate::<folder>::b`).
fn file_graph(dir: &Path, folder_path: &str) -> Graph {
    let mut g = Graph::new();
    let Ok(rd) = std::fs::read_dir(dir) else {
        return g;
    };
    let siblings: BTreeSet<String> = rd
        .flatten()
        .filter_map(|e| {
            let p = e.path();
            let n = p.file_stem()?.to_str()?.to_string();
            (p.is_dir() || p.extension().is_some_and(|x| x == "rs")).then_some(n)
        })
        .filter(|n| n != "mod" && n != "tests" && n != "lib" && n != "main")
        .collect();
    for s in &siblings {
        let file = dir.join(format!("{s}.rs"));
        let file = if file.exists() {
            file
        } else {
            dir.join(s).join("mod.rs")
        };
        let Ok(text) = std::fs::read_to_string(&file) else {
            continue;
        };
        let text = code(&text);
        let mut names = idents_after(&text, "super::");
        if !folder_path.is_empty() {
            names.extend(idents_after(&text, &format!("crate::{folder_path}::")));
        } else {
            names.extend(idents_after(&text, "crate::"));
        }
        for t in names {
            if t != s && siblings.contains(t) {
                g.entry(s.clone()).or_default().insert(t.to_string());
            }
        }
    }
    g
}

/// A cycle of the graph, if it has one.
fn find_cycle(g: &Graph) -> Option<Vec<String>> {
    fn visit(
        g: &Graph,
        v: &str,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(v.to_string(), 1);
        stack.push(v.to_string());
        for w in g.get(v).into_iter().flatten() {
            match state.get(w.as_str()).copied().unwrap_or(0) {
                1 => {
                    let start = stack.iter().position(|x| x == w).unwrap();
                    let mut c = stack[start..].to_vec();
                    c.push(w.clone());
                    return Some(c);
                }
                0 => {
                    if let Some(c) = visit(g, w, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(v.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for v in g.keys() {
        if state.get(v.as_str()).copied().unwrap_or(0) == 0 {
            let mut stack = Vec::new();
            if let Some(c) = visit(g, v, &mut state, &mut stack) {
                return Some(c);
            }
        }
    }
    None
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn core_folders_import_one_way() {
    let g = folder_graph(&root().join("src"));
    assert!(g.contains_key("render"), "the graph was read: {g:?}");
    if let Some(c) = find_cycle(&g) {
        panic!("import cycle between core folders: {}", c.join(" -> "));
    }
}

#[test]
fn files_inside_each_core_folder_import_one_way() {
    let src = root().join("src");
    let mut dirs = vec![(src.clone(), String::new())];
    let mut checked = 0;
    while let Some((dir, path)) = dirs.pop() {
        for e in std::fs::read_dir(&dir).unwrap().flatten() {
            let p = e.path();
            let name = p.file_name().unwrap().to_string_lossy().to_string();
            if p.is_dir() && name != "tests" {
                let sub = if path.is_empty() {
                    name.clone()
                } else {
                    format!("{path}::{name}")
                };
                dirs.push((p, sub));
            }
        }
        if path.is_empty() {
            continue;
        }
        let g = file_graph(&dir, &path);
        checked += 1;
        if let Some(c) = find_cycle(&g) {
            panic!(
                "import cycle between files of src/{path}: {}",
                c.join(" -> ")
            );
        }
    }
    assert!(checked > 10, "folders checked: {checked}");
}

#[test]
fn master_files_import_one_way() {
    let src = root().join("server").join("src");
    let g = file_graph(&src, "");
    assert!(!g.is_empty(), "the master's graph was read");
    if let Some(c) = find_cycle(&g) {
        panic!(
            "import cycle between the master's files: {}",
            c.join(" -> ")
        );
    }
}

#[test]
fn the_checker_sees_a_cycle() {
    let mut g = Graph::new();
    g.entry("a".into()).or_default().insert("b".into());
    g.entry("b".into()).or_default().insert("c".into());
    g.entry("c".into()).or_default().insert("a".into());
    assert_eq!(find_cycle(&g).unwrap().len(), 4);
    g.get_mut("c").unwrap().clear();
    assert!(find_cycle(&g).is_none());
}
