//! The compiler's layout (ARCHITECTURE.md, "Code map"): the stages are
//! declared in `lib.rs` from the top of the pipeline down, and each imports
//! only from those declared below it; inside a folder no two modules import
//! each other, directly or around a circle. A module may use its own
//! folder's `mod.rs` (its stage's vocabulary) and its own children.
//!
//! The source is read as text: `use` trees and `a::b` paths outside
//! comments, strings and `#[cfg(test)]` code, resolved against the module
//! files. A re-export at the crate root (`crate::Diagnostic`) counts as the
//! module that defines it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

type Module = Vec<String>;

/// Every module of `src` by its path (`[]` for `lib.rs`), with its file.
fn modules(src: &Path) -> BTreeMap<Module, PathBuf> {
    let mut out = BTreeMap::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let rel = path.strip_prefix(src).unwrap().with_extension("");
                let mut m: Module = rel.iter().map(|c| c.to_string_lossy().into_owned()).collect();
                if matches!(m.last().map(String::as_str), Some("mod" | "lib")) {
                    m.pop();
                }
                out.insert(m, path);
            }
        }
    }
    out
}

/// `text` without comments, string and char literals, and from the first
/// `#[cfg(test)]` on (test code may reach anywhere).
fn code_of(text: &str) -> String {
    let text = &text[..text.find("#[cfg(test)]").unwrap_or(text.len())];
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                i += 2;
                while i + 1 < b.len() && !(b[i] == b'*' && b[i + 1] == b'/') {
                    i += 1;
                }
                i += 2;
            }
            b'r' if matches!(b.get(i + 1), Some(b'#' | b'"')) && (i == 0 || !is_ident(b[i - 1])) => {
                let hashes = b[i + 1..].iter().take_while(|&&c| c == b'#').count();
                if b.get(i + 1 + hashes) != Some(&b'"') {
                    out.push('r');
                    i += 1;
                    continue;
                }
                let close: Vec<u8> = std::iter::once(b'"').chain(std::iter::repeat_n(b'#', hashes)).collect();
                i += 2 + hashes;
                while i < b.len() && !b[i..].starts_with(&close) {
                    i += 1;
                }
                i += close.len();
                out.push_str("\"\"");
            }
            b'"' => {
                i += 1;
                while i < b.len() && b[i] != b'"' {
                    i += if b[i] == b'\\' { 2 } else { 1 };
                }
                i += 1;
                out.push_str("\"\"");
            }
            // A char literal ('a', '\n', '\u{..}'), not a lifetime ('a).
            b'\'' if b.get(i + 2) == Some(&b'\'') || b.get(i + 1) == Some(&b'\\') => {
                i += 1;
                while i < b.len() && b[i] != b'\'' {
                    i += if b[i] == b'\\' { 2 } else { 1 };
                }
                i += 1;
                out.push_str("' '");
            }
            c => {
                out.push(c as char);
                i += 1;
            }
        }
    }
    out
}

fn is_ident(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// The paths a `use` tree names: `a::{b, c::{d as e}}` is `a::b` and `a::c::d`.
fn expand(prefix: &[String], tree: &str, out: &mut Vec<Module>) {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        let head = tree.split(" as ").next().unwrap_or("");
        let mut p = prefix.to_vec();
        p.extend(head.split("::").map(str::trim).filter(|s| !s.is_empty()).map(String::from));
        out.push(p);
        return;
    };
    let Some(close) = tree.rfind('}') else { return };
    let mut p = prefix.to_vec();
    p.extend(tree[..open].split("::").map(str::trim).filter(|s| !s.is_empty()).map(String::from));
    let (mut depth, mut start) = (0, open + 1);
    for (k, c) in tree[..close].char_indices().skip(open + 1) {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                expand(&p, &tree[start..k], out);
                start = k + 1;
            }
            _ => {}
        }
    }
    expand(&p, &tree[start..close], out);
}

/// Every path `code` names: its `use` trees expanded, and `a::b` paths.
fn paths(code: &str) -> Vec<Module> {
    let mut out = Vec::new();
    let mut rest = String::with_capacity(code.len());
    let mut i = 0;
    while let Some(k) = code[i..].find("use ").map(|k| k + i) {
        let word_start = k == 0 || !is_ident(code.as_bytes()[k - 1]);
        rest.push_str(&code[i..k]);
        match code[k..].find(';') {
            Some(end) if word_start => {
                expand(&[], &code[k + 4..k + end], &mut out);
                i = k + end + 1;
            }
            _ => {
                rest.push_str("use ");
                i = k + 4;
            }
        }
    }
    rest.push_str(&code[i..]);
    let b = rest.as_bytes();
    let mut k = 0;
    while k < b.len() {
        if is_ident(b[k]) && (k == 0 || (!is_ident(b[k - 1]) && b[k - 1] != b':')) {
            let mut end = k;
            let mut path = Vec::new();
            loop {
                let s = end;
                while end < b.len() && is_ident(b[end]) {
                    end += 1;
                }
                path.push(rest[s..end].to_string());
                if b[end..].starts_with(b"::") && b.get(end + 2).is_some_and(|&c| is_ident(c)) {
                    end += 2;
                } else {
                    break;
                }
            }
            if path.len() > 1 {
                out.push(path);
            }
            k = end.max(k + 1);
        } else {
            k += 1;
        }
    }
    out
}

/// The module `path`, named in module `m`, belongs to: the longest module
/// that prefixes it; `None` for other crates and for items of `m` itself.
fn owner(
    mods: &BTreeMap<Module, PathBuf>,
    root_items: &BTreeMap<String, Module>,
    m: &Module,
    path: &Module,
) -> Option<Module> {
    let (head, tail) = path.split_first()?;
    let mut t: Module = match head.as_str() {
        "crate" => match tail.first().and_then(|f| root_items.get(f.as_str())) {
            Some(defined) => defined.iter().cloned().chain(tail.iter().cloned()).collect(),
            None => tail.to_vec(),
        },
        "super" => m[..m.len().saturating_sub(1)].iter().chain(tail).cloned().collect(),
        "self" => m.iter().chain(tail).cloned().collect(),
        _ => {
            let child: Module = m.iter().cloned().chain([head.clone()]).collect();
            if !mods.contains_key(&child) {
                return None;
            }
            m.iter().chain(path).cloned().collect()
        }
    };
    while let Some(k) = t.iter().position(|s| s == "super") {
        t.drain(k.saturating_sub(1)..=k);
    }
    t.retain(|s| s != "self");
    (0..=t.len()).rev().map(|k| t[..k].to_vec()).find(|p| mods.contains_key(p))
}

/// Module `a` is `b` or contains it.
fn within(a: &Module, b: &Module) -> bool {
    a.len() <= b.len() && b[..a.len()] == a[..]
}

struct Graph {
    /// The top-level modules in the order `lib.rs` declares them.
    order: Vec<String>,
    /// For each module, the modules it imports and one path that does.
    edges: BTreeMap<Module, BTreeMap<Module, String>>,
}

fn graph() -> Graph {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mods = modules(&src);
    let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap();
    let lib_code = code_of(&lib);
    let order: Vec<String> = lib_code
        .lines()
        .filter_map(|l| l.trim().trim_start_matches("pub ").strip_prefix("mod ")?.strip_suffix(';').map(String::from))
        .collect();
    // The crate root's re-exports (`pub use diagnostic::{Diagnostic, ..}`): the module that defines each name.
    let mut root_items = BTreeMap::new();
    for p in paths(&lib_code) {
        if let (Some(first), Some(name)) = (p.first(), p.last())
            && mods.contains_key(&vec![first.clone()])
        {
            let defining: Module = p[..p.len() - 1].to_vec();
            root_items.insert(name.clone(), defining);
        }
    }
    let mut edges: BTreeMap<Module, BTreeMap<Module, String>> = BTreeMap::new();
    for (m, file) in &mods {
        if m.is_empty() || m.last().is_some_and(|s| s == "tests") {
            continue;
        }
        let code = code_of(&std::fs::read_to_string(file).unwrap());
        for p in paths(&code) {
            let Some(o) = owner(&mods, &root_items, m, &p) else { continue };
            // A module and its own folder (parent or child) share a vocabulary.
            if o.is_empty() || within(&o, m) || within(m, &o) {
                continue;
            }
            edges.entry(m.clone()).or_default().entry(o).or_insert_with(|| p.join("::"));
        }
    }
    Graph { order, edges }
}

#[test]
fn each_stage_imports_only_from_the_stages_below_it() {
    let g = graph();
    assert!(g.order.len() > 10 && g.order[0] == "pipeline", "lib.rs declares the stages top down: {:?}", g.order);
    let rank = |m: &Module| g.order.iter().position(|s| Some(s) == m.first());
    let mut up = Vec::new();
    for (a, to) in &g.edges {
        for (b, via) in to {
            if a[0] != b[0] && rank(b) <= rank(a) {
                up.push(format!("{} imports {} ({via})", a.join("::"), b.join("::")));
            }
        }
    }
    assert!(up.is_empty(), "imports that run back up the order of lib.rs:\n{}", up.join("\n"));
}

#[test]
fn no_circle_of_imports() {
    let g = graph();
    // A circle is a path from a module back to itself: look for one from each.
    let mut circles = BTreeSet::new();
    for start in g.edges.keys() {
        let mut stack = vec![(start.clone(), vec![start.join("::")])];
        let mut seen = BTreeSet::new();
        while let Some((m, trail)) = stack.pop() {
            for next in g.edges.get(&m).into_iter().flat_map(|e| e.keys()) {
                if next == start {
                    let mut c = trail.clone();
                    c.sort();
                    circles.insert(c.join(" -> "));
                } else if seen.insert(next.clone()) {
                    let mut t = trail.clone();
                    t.push(next.join("::"));
                    stack.push((next.clone(), t));
                }
            }
        }
    }
    assert!(circles.is_empty(), "circles of imports:\n{}", circles.into_iter().collect::<Vec<_>>().join("\n"));
}

#[test]
fn the_reader_finds_what_it_resolves() {
    // The checks above see what they must: the parts of the reader, on a known text.
    let code = code_of(
        "use a::{b, c::{d as e, f}};\n// use x::y;\nlet s = \"crate::q::r\"; crate::g::h(); super::i::j;\n#[cfg(test)]\nuse z::w;",
    );
    let p = paths(&code);
    let s: Vec<String> = p.iter().map(|p| p.join("::")).collect();
    assert_eq!(s, ["a::b", "a::c::d", "a::c::f", "crate::g::h", "super::i::j"]);
    // And on the compiler: the pipeline reaches the back ends.
    let g = graph();
    let pipeline = &g.edges[&vec!["pipeline".to_string()]];
    assert!(pipeline.keys().any(|m| m[0] == "latero") && pipeline.keys().any(|m| m[0] == "pins"), "{pipeline:?}");
}
