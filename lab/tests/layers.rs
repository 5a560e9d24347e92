//! The lab's layering, read from its sources: every `crate::` and `super::`
//! path names a module; the graph of those imports has no cycle, and
//! nothing below `commands/` (experiments, runner, io, figures, scene, …)
//! imports `cli` or `commands`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Module path of a source file (`experiments/scene.rs` → `experiments::scene`,
/// `experiments/mod.rs` → `experiments`, `lib.rs` → ``).
fn module_of(rel: &Path) -> String {
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        parts.pop();
    }
    parts.join("::")
}

fn sources(dir: &Path, root: &Path, out: &mut Vec<(String, String)>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            sources(&p, root, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            let rel = p.strip_prefix(root).unwrap();
            if rel == Path::new("main.rs") {
                continue; // the binary: it may use everything
            }
            out.push((module_of(rel), std::fs::read_to_string(&p).unwrap()));
        }
    }
}

/// The code of `text` without comments (line comments and doc comments),
/// so that a path named in prose is not an import.
fn code(text: &str) -> String {
    text.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The modules `text` (the source of module `me`) names: every
/// `crate::a::b…` and `super::…` path, resolved to the longest known
/// module prefix (items inside `use crate::x::{a, b}` groups count too).
fn imports(me: &str, text: &str, known: &BTreeSet<String>) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let text = code(text);
    let resolve = |segs: Vec<String>, out: &mut BTreeSet<String>| {
        for k in (1..=segs.len()).rev() {
            let m = segs[..k].join("::");
            if known.contains(&m) {
                if m != me {
                    out.insert(m);
                }
                return;
            }
        }
    };
    let s = text.as_str();
    for (start, relative) in [("crate::", false), ("super::", true)] {
        let mut from = 0;
        while let Some(i) = s[from..].find(start) {
            let at = from + i;
            from = at + start.len();
            let ok_before = at == 0
                || !s[..at]
                    .chars()
                    .next_back()
                    .is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':');
            if !ok_before {
                continue;
            }
            let mut base: Vec<String> = if !relative {
                Vec::new()
            } else {
                let mut b: Vec<String> = me.split("::").map(String::from).collect();
                b.retain(|x| !x.is_empty());
                b.pop();
                b
            };
            let mut rest = &s[from..];
            while let Some(r) = rest.strip_prefix("super::") {
                base.pop();
                rest = r;
            }
            let path: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':' || *c == '{')
                .collect();
            if let Some(brace) = path.find('{') {
                // `crate::a::{b, c::d}`: each member.
                let head: Vec<String> = path[..brace]
                    .split("::")
                    .filter(|x| !x.is_empty())
                    .map(String::from)
                    .collect();
                let body_start = from + brace + 1;
                let body_end = s[body_start..]
                    .find('}')
                    .map_or(s.len(), |e| body_start + e);
                for member in s[body_start..body_end].split(',') {
                    let mut segs = base.clone();
                    segs.extend(head.iter().cloned());
                    segs.extend(
                        member
                            .trim()
                            .split("::")
                            .map(|x| x.split_whitespace().next().unwrap_or("").to_string())
                            .filter(|x| !x.is_empty() && x != "self"),
                    );
                    resolve(segs, &mut out);
                }
            } else {
                let mut segs = base.clone();
                segs.extend(path.split("::").filter(|x| !x.is_empty()).map(String::from));
                resolve(segs, &mut out);
            }
        }
    }
    out
}

/// Tarjan's strongly connected components; returns those of size > 1.
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct T<'a> {
        g: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on: BTreeSet<&'a str>,
        next: usize,
        out: Vec<Vec<String>>,
    }
    fn visit<'a>(t: &mut T<'a>, v: &'a str) {
        t.index.insert(v, t.next);
        t.low.insert(v, t.next);
        t.next += 1;
        t.stack.push(v);
        t.on.insert(v);
        let g = t.g;
        for w in g.get(v).into_iter().flatten() {
            let w = w.as_str();
            if !t.index.contains_key(w) {
                visit(t, w);
                let lw = t.low[w];
                let lv = t.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if t.on.contains(w) {
                let iw = t.index[w];
                let lv = t.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if t.low[v] == t.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = t.stack.pop().unwrap();
                t.on.remove(w);
                comp.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                t.out.push(comp);
            }
        }
    }
    let mut t = T {
        g: graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in graph.keys() {
        if !t.index.contains_key(v.as_str()) {
            visit(&mut t, v);
        }
    }
    t.out
}

fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&root, &root, &mut files);
    let known: BTreeSet<String> = files.iter().map(|(m, _)| m.clone()).collect();
    files
        .iter()
        .map(|(m, text)| (m.clone(), imports(m, text, &known)))
        .collect()
}

#[test]
fn the_lab_has_no_import_cycle_and_no_upward_import() {
    let g = graph();
    let edges: usize = g.values().map(BTreeSet::len).sum();
    eprintln!("lab import graph: {} modules, {edges} edges", g.len());
    assert!(
        g.len() > 40 && edges > 100,
        "the walk found too little: {g:?}"
    );
    let c = cycles(&g);
    assert!(c.is_empty(), "import cycles: {c:?}");
    for (m, deps) in &g {
        if m == "cli" || m == "commands" || m.starts_with("commands::") || m.is_empty() {
            continue;
        }
        for d in deps {
            assert!(
                d != "cli" && d != "commands" && !d.starts_with("commands::"),
                "{m} imports {d}: only the binary, lib.rs and commands/ may"
            );
        }
    }
}

/// The walk sees an import and a cycle when there is one (so the test
/// above cannot pass by reading nothing).
#[test]
fn the_walk_finds_imports_and_cycles() {
    let known: BTreeSet<String> = ["a", "a::b", "c", "c::d"].map(String::from).into();
    let i = imports(
        "a::b",
        "use crate::c::d::Thing;\nuse super::{x, y};\n// crate::c is prose\nfn f() { crate::c::go() }",
        &known,
    );
    assert_eq!(i, ["a", "c", "c::d"].map(String::from).into());
    let mut g = BTreeMap::new();
    g.insert("a".to_string(), BTreeSet::from(["c".to_string()]));
    g.insert("c".to_string(), BTreeSet::from(["a".to_string()]));
    g.insert("e".to_string(), BTreeSet::from(["a".to_string()]));
    assert_eq!(cycles(&g).len(), 1);
}
