//! ARCHITECTURE.md invariant 11: no import circle between the files of a crate, except
//! api's functions <-> registry (the `declare_functions!` macro lives beside the
//! declarations it reads).
//!
//! A file depends on another when it names one of its items through `crate::` or
//! `super::` (a parent naming its own child modules is how Rust lays out a crate, and is
//! not counted). Test modules (`#[cfg(test)]`)
//! do not count: a test may use what it tests. The circles that are there today are
//! listed in `KNOWN` (issue 37 opens them); a new one fails the test, and so does a listed
//! one that is gone, so the list can only shrink.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The circles of today, each as its files (crate-relative, sorted), to be opened.
const KNOWN: &[&[&str]] = &[
    &["api/src/functions.rs", "api/src/registry.rs"],
    &["script-host/src/bindings/mod.rs", "script-host/src/require.rs", "script-host/src/sandbox.rs"],
    &[
        "script-host/src/bindings/agent.rs",
        "script-host/src/bindings/expect.rs",
        "script-host/src/bindings/library.rs",
        "script-host/src/bindings/locals.rs",
    ],
];

/// One crate's files by module path (`a::b` for src/a/b.rs or src/a/b/mod.rs).
fn modules(src: &Path) -> BTreeMap<Vec<String>, PathBuf> {
    let mut found = BTreeMap::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap().map(Result::unwrap) {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let relative = path.strip_prefix(src).unwrap().with_extension("");
                let mut module: Vec<String> = relative.iter().map(|p| p.to_string_lossy().into_owned()).collect();
                if matches!(module.last().map(String::as_str), Some("mod" | "lib" | "main")) {
                    module.pop();
                }
                if module.first().is_some_and(|m| m == "bin") {
                    continue;
                }
                found.insert(module, path);
            }
        }
    }
    found
}

/// The file's text without what is compiled for tests only: each `#[cfg(test)]` module (to
/// its closing brace) or `use`, wherever it stands in the file.
fn without_tests(text: &str) -> String {
    const MARK: &str = "#[cfg(test)]";
    let mut kept = String::new();
    let mut rest = text;
    while let Some(at) = rest.find(MARK) {
        kept.push_str(&rest[..at]);
        let item = rest[at + MARK.len()..].trim_start();
        let end = if item.starts_with("mod ") || item.starts_with("pub mod ") || item.starts_with("pub(crate) mod ") {
            block_end(item)
        } else if item.starts_with("use ") {
            item.find(';').map_or(item.len(), |i| i + 1)
        } else {
            0
        };
        rest = &item[end..];
    }
    kept.push_str(rest);
    kept
}

/// Where the block opened by the first `{` of `item` closes (or its end).
fn block_end(item: &str) -> usize {
    let mut depth = 0usize;
    for (i, c) in item.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 1 => return i + 1,
            '}' => depth = depth.saturating_sub(1),
            ';' if depth == 0 => return i + 1,
            _ => {}
        }
    }
    item.len()
}

/// Every path the file names: `crate::a::b`, `super::c`, and the groups of `use x::{..}`,
/// each as its segments, with the first segment (`crate`, `super`, `self` or a name).
fn paths(text: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let bytes = text.as_bytes();
    let ident = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let mut i = 0;
    while i < bytes.len() {
        let starts_word = i == 0 || !(ident(bytes[i - 1]) || bytes[i - 1] == b':');
        if starts_word && ident(bytes[i]) {
            let mut segments = Vec::new();
            let mut j = i;
            loop {
                let start = j;
                while j < bytes.len() && ident(bytes[j]) {
                    j += 1;
                }
                segments.push(text[start..j].to_string());
                if text[j..].starts_with("::") && bytes.get(j + 2).is_some_and(|&c| ident(c)) {
                    j += 2;
                } else {
                    break;
                }
            }
            if segments.len() > 1 || text[j..].starts_with("::{") {
                if text[j..].starts_with("::{") {
                    let close = text[j..].find('}').map_or(text.len(), |c| j + c);
                    for item in text[j + 3..close].split(',') {
                        let first = item.trim().split("::").next().unwrap_or("").trim().to_string();
                        if !first.is_empty() && first.bytes().all(ident) {
                            out.push([segments.clone(), vec![first]].concat());
                        }
                    }
                }
                out.push(segments);
            }
            i = j.max(i + 1);
        } else {
            i += 1;
        }
    }
    out
}

/// The module a path names, as the longest known prefix.
fn resolve(path: &[String], here: &[String], known: &BTreeMap<Vec<String>, PathBuf>) -> Option<Vec<String>> {
    let (mut base, rest): (Vec<String>, &[String]) = match path[0].as_str() {
        "crate" => (Vec::new(), &path[1..]),
        "self" => (here.to_vec(), &path[1..]),
        "super" => {
            let mut base = here.to_vec();
            let mut rest = path;
            while rest.first().is_some_and(|s| s == "super") {
                base.pop()?;
                rest = &rest[1..];
            }
            (base, rest)
        }
        _ => return None,
    };
    let mut best = known.contains_key(&base).then(|| base.clone());
    for segment in rest {
        base.push(segment.clone());
        if known.contains_key(&base) {
            best = Some(base.clone());
        } else {
            break;
        }
    }
    best
}

/// The strongly connected components of more than one file (Tarjan's algorithm).
fn circles(edges: &BTreeMap<usize, BTreeSet<usize>>, n: usize) -> Vec<Vec<usize>> {
    struct Walk<'a> {
        edges: &'a BTreeMap<usize, BTreeSet<usize>>,
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        found: Vec<Vec<usize>>,
    }
    impl Walk<'_> {
        fn visit(&mut self, v: usize) {
            self.index[v] = Some(self.next);
            self.low[v] = self.next;
            self.next += 1;
            self.stack.push(v);
            self.on_stack[v] = true;
            for &w in self.edges.get(&v).into_iter().flatten() {
                match self.index[w] {
                    None => {
                        self.visit(w);
                        self.low[v] = self.low[v].min(self.low[w]);
                    }
                    Some(i) if self.on_stack[w] => self.low[v] = self.low[v].min(i),
                    Some(_) => {}
                }
            }
            if Some(self.low[v]) == self.index[v] {
                let mut component = Vec::new();
                while let Some(w) = self.stack.pop() {
                    self.on_stack[w] = false;
                    component.push(w);
                    if w == v {
                        break;
                    }
                }
                if component.len() > 1 {
                    self.found.push(component);
                }
            }
        }
    }
    let mut walk = Walk {
        edges,
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: Vec::new(),
        next: 0,
        found: Vec::new(),
    };
    for v in 0..n {
        if walk.index[v].is_none() {
            walk.visit(v);
        }
    }
    walk.found
}

/// The circles between the files of the crate in `dir`, as sorted repo-relative paths.
fn crate_circles(root: &Path, dir: &Path) -> Vec<Vec<String>> {
    let known = modules(&dir.join("src"));
    let files: Vec<(&Vec<String>, &PathBuf)> = known.iter().collect();
    let number: BTreeMap<&Vec<String>, usize> = files.iter().enumerate().map(|(i, (m, _))| (*m, i)).collect();
    let mut edges: BTreeMap<usize, BTreeSet<usize>> = BTreeMap::new();
    for (i, (module, file)) in files.iter().enumerate() {
        let text = std::fs::read_to_string(file).unwrap();
        for path in paths(&without_tests(&text)) {
            if let Some(target) = resolve(&path, module, &known)
                && let Some(&j) = number.get(&target)
                && j != i
            {
                edges.entry(i).or_default().insert(j);
            }
        }
    }
    let name = |i: usize| files[i].1.strip_prefix(root).unwrap().to_string_lossy().into_owned();
    let mut found: Vec<Vec<String>> = circles(&edges, files.len())
        .into_iter()
        .map(|c| {
            let mut names: Vec<String> = c.into_iter().map(name).collect();
            names.sort();
            names
        })
        .collect();
    found.sort();
    found
}

fn workspace_crates(root: &Path) -> Vec<PathBuf> {
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).unwrap();
    let members = manifest.split("members = [").nth(1).and_then(|s| s.split(']').next()).expect("workspace members");
    let mut crates: Vec<PathBuf> = members.split(',').map(|m| root.join(m.trim().trim_matches('"'))).collect();
    crates.push(root.to_path_buf());
    crates
}

#[test]
fn no_import_circle_between_files_but_the_known_ones() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let found: BTreeSet<Vec<String>> = workspace_crates(root).iter().flat_map(|c| crate_circles(root, c)).collect();
    let known: BTreeSet<Vec<String>> = KNOWN.iter().map(|c| c.iter().map(|s| s.to_string()).collect()).collect();
    let new: Vec<_> = found.difference(&known).collect();
    let gone: Vec<_> = known.difference(&found).collect();
    assert!(new.is_empty(), "import circles between files (ARCHITECTURE.md invariant 11): {new:#?}");
    assert!(gone.is_empty(), "these circles are open now: take them off KNOWN: {gone:#?}");
}

/// The checker finds a circle where there is one, and none where there is none.
#[test]
fn the_checker_sees_a_circle() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    std::fs::create_dir_all(src.join("a")).unwrap();
    std::fs::write(src.join("a/mod.rs"), "mod inner;\nuse self::inner::X;\nuse crate::{b::Y, c, d::D};\n").unwrap();
    std::fs::write(src.join("a/inner.rs"), "pub struct X;\n").unwrap();
    std::fs::write(src.join("b.rs"), "use super::a::Z;\npub struct Y;\n").unwrap();
    // Test-only uses of a: no circle; the item after the test module counts again.
    std::fs::write(
        src.join("c.rs"),
        "#[cfg(test)]\nuse crate::a::W;\n#[cfg(test)]\nmod tests { fn f() { use crate::a::Z; } }\npub struct C;\n",
    )
    .unwrap();
    std::fs::write(src.join("d.rs"), "#[cfg(test)]\nmod tests {}\nuse crate::a::V;\n").unwrap();
    std::fs::write(src.join("lib.rs"), "mod a;\nmod b;\nmod c;\nmod d;\n").unwrap();
    let found = crate_circles(dir.path(), dir.path());
    assert_eq!(found, vec![vec!["src/a/mod.rs".to_string(), "src/b.rs".to_string(), "src/d.rs".to_string()]]);
}
