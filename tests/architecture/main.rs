//! The house's rules, checked on the source (issue 44): every `use
//! crate::…`, `super::…` and inline `crate::…` path of `src/` is
//! resolved to the module file it names, and
//! - a module imports only modules of a lower layer (the order written in
//!   docs/design.md, "Layers, lowest first"), never a sibling of its own
//!   layer nor a higher one;
//! - no file imports itself through any chain of imports (no circle,
//!   of two files or more).
//!
//! Test code (`#[cfg(test)]` to the end of a file, `tests.rs`,
//! `*_tests.rs`) and comments are not read. Each violation names the file
//! and the line.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A module path inside the crate: `["actors", "navigate"]`.
type Module = Vec<String>;

/// One source file: its module and its text.
struct File {
    path: String,
    module: Module,
    text: String,
}

/// An import: from a file's line, the module it names.
#[derive(Debug, Clone)]
struct Import {
    file: String,
    line: usize,
    from: Module,
    to: Module,
    written: String,
}

/// The module a file under `src/` holds.
fn module_of(rel: &Path) -> Module {
    let mut parts: Vec<String> = rel
        .with_extension("")
        .iter()
        .map(|c| c.to_string_lossy().into_owned())
        .collect();
    if parts.last().is_some_and(|l| l == "mod" || l == "lib") {
        parts.pop();
    }
    parts
}

/// Whether a file is test code only.
fn is_test_file(rel: &str) -> bool {
    rel.ends_with("/tests.rs") || rel.ends_with("_tests.rs")
}

/// The text the rules read: comments blanked and everything from the
/// first `#[cfg(test)]` on dropped, lines kept in place.
fn code(text: &str) -> String {
    let mut out = Vec::new();
    for l in text.lines() {
        if l.trim_start().starts_with("#[cfg(test)]") {
            break;
        }
        out.push(match l.find("//") {
            Some(k) => &l[..k],
            None => l,
        });
    }
    out.join("\n")
}

/// The full paths a `use` tree stands for: `a::{b, c::{d, e}}` →
/// `a::b`, `a::c::d`, `a::c::e`.
fn expand(tree: &str) -> Vec<String> {
    // Renames (`x as y`) name x.
    let mut words = tree.split_whitespace();
    let mut tree = String::new();
    while let Some(w) = words.next() {
        if w == "as" {
            let renamed = words.next().unwrap_or("");
            tree.extend(renamed.chars().filter(|c| matches!(c, ',' | '}')));
        } else {
            tree.push_str(w);
        }
    }
    let Some(open) = tree.find('{') else {
        return vec![tree];
    };
    let prefix = &tree[..open];
    let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0, 0);
    for (i, c) in inner.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&inner[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&inner[start..]);
    parts
        .into_iter()
        .filter(|p| !p.is_empty())
        .flat_map(|p| expand(p).into_iter().map(move |q| format!("{prefix}{q}")))
        .collect()
}

/// Every crate-relative path a file names, with its line: the `use`
/// trees expanded, and inline `crate::…` and `super::…` paths.
fn paths(text: &str) -> Vec<(usize, String)> {
    let line_of = |at: usize| text[..at].matches('\n').count() + 1;
    let mut out = Vec::new();
    let mut rest = 0;
    while let Some(k) = text[rest..].find("use ") {
        let at = rest + k;
        rest = at + 4;
        let before = text[..at].chars().last();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let Some(end) = text[at..].find(';') else {
            break;
        };
        let tree = &text[at + 4..at + end];
        for p in expand(tree) {
            out.push((line_of(at), p));
        }
        rest = at + end;
    }
    // Inline paths outside `use` lines.
    for (i, l) in text.lines().enumerate() {
        if l.trim_start().starts_with("use ") || l.trim_start().starts_with("pub use ") {
            continue;
        }
        for start in ["crate::", "super::"] {
            let mut from = 0;
            while let Some(k) = l[from..].find(start) {
                let at = from + k;
                let end = l[at..]
                    .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                    .map_or(l.len(), |e| at + e);
                let before = l[..at].chars().last();
                if !before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                    out.push((i + 1, l[at..end].trim_end_matches(':').to_string()));
                }
                from = end.max(at + 1);
            }
        }
    }
    out
}

/// The module file a path from `from` names: the longest module prefix
/// of the path that is a file; None for paths outside the crate.
fn resolve(from: &Module, path: &str, modules: &BTreeSet<Module>) -> Option<Module> {
    let mut parts: Vec<&str> = path.split("::").filter(|p| !p.is_empty()).collect();
    let mut base: Module = match parts.first()? {
        &"crate" => {
            parts.remove(0);
            Vec::new()
        }
        &"super" | &"self" => from.clone(),
        // A path from a child module (`use child::X`).
        &child
            if modules.contains(
                &from
                    .iter()
                    .cloned()
                    .chain([child.to_string()])
                    .collect::<Module>(),
            ) =>
        {
            from.clone()
        }
        _ => return None,
    };
    while let Some(&p) = parts.first() {
        match p {
            "super" => {
                base.pop();
            }
            "self" => {}
            _ => break,
        }
        parts.remove(0);
    }
    let full: Module = base
        .into_iter()
        .chain(parts.iter().map(|s| s.to_string()))
        .collect();
    (1..=full.len())
        .rev()
        .map(|k| full[..k].to_vec())
        .find(|m| modules.contains(m))
}

/// Every import between two different module files.
/// The inline modules (`mod name {` … `}`) open at each line of a
/// file's code, outermost first: a path there is relative to them.
fn inline_modules(code: &str) -> Vec<Vec<String>> {
    let mut open: Vec<(String, usize)> = Vec::new();
    let mut at_line = Vec::new();
    for l in code.lines() {
        let indent = l.len() - l.trim_start().len();
        if open
            .last()
            .is_some_and(|(_, i)| *i == indent && l.trim() == "}")
        {
            open.pop();
        }
        at_line.push(open.iter().map(|(n, _)| n.clone()).collect());
        let t = l.trim_start().trim_start_matches("pub ");
        if let Some(name) = t.strip_prefix("mod ").and_then(|r| r.strip_suffix(" {")) {
            open.push((name.trim().to_string(), indent));
        }
    }
    at_line
}

fn imports(files: &[File]) -> Vec<Import> {
    let modules: BTreeSet<Module> = files.iter().map(|f| f.module.clone()).collect();
    let mut out = Vec::new();
    for f in files {
        let code = code(&f.text);
        let inline = inline_modules(&code);
        for (line, p) in paths(&code) {
            let mut here = f.module.clone();
            here.extend(inline.get(line - 1).cloned().unwrap_or_default());
            if let Some(to) = resolve(&here, &p, &modules) {
                if to != f.module && !to.is_empty() {
                    out.push(Import {
                        file: f.path.clone(),
                        line,
                        from: f.module.clone(),
                        to,
                        written: p,
                    });
                }
            }
        }
    }
    out
}

/// The layers, lowest first, as docs/design.md writes them: a line
/// `Layers, lowest first: a | b c | …`.
fn layers(design: &str) -> BTreeMap<String, usize> {
    let line = design
        .lines()
        .find_map(|l| l.split("Layers, lowest first:").nth(1))
        .expect("docs/design.md names the layers: `Layers, lowest first: a | b c | …`");
    line.trim()
        .trim_matches('`')
        .split('|')
        .enumerate()
        .flat_map(|(k, group)| {
            group
                .split_whitespace()
                .map(move |m| (m.trim_matches('`').to_string(), k))
        })
        .collect()
}

/// Every rule broken, one line each.
fn violations(files: &[File], layers: &BTreeMap<String, usize>) -> Vec<String> {
    let all = imports(files);
    let mut out = Vec::new();
    for f in files {
        if let Some(top) = f.module.first() {
            if !layers.contains_key(top) {
                out.push(format!(
                    "{}: module `{top}` is in no layer of docs/design.md",
                    f.path
                ));
            }
        }
    }
    for i in &all {
        let (a, b) = (&i.from[0], &i.to[0]);
        if a == b {
            continue;
        }
        if let (Some(&la), Some(&lb)) = (layers.get(a), layers.get(b)) {
            if lb >= la {
                out.push(format!(
                    "{}:{}: `{}`: {a} (layer {la}) imports {b} (layer {lb}), not a lower layer",
                    i.file, i.line, i.written
                ));
            }
        }
    }
    out.extend(circles(&all));
    out
}

/// Every circle of imports, of any length (issue 55: four files of
/// `actors` imported each other round a circle the pair rule missed):
/// one line each, the files in order with the line of each import.
/// Tarjan's strongly connected components; in each of more than one
/// file, the shortest circle through each of its files.
fn circles(all: &[Import]) -> Vec<String> {
    let mut next: BTreeMap<&Module, Vec<&Import>> = BTreeMap::new();
    for i in all {
        next.entry(&i.from).or_default().push(i);
        next.entry(&i.to).or_default();
    }
    let nodes: Vec<&Module> = next.keys().copied().collect();
    let index_of: BTreeMap<&Module, usize> =
        nodes.iter().enumerate().map(|(k, m)| (*m, k)).collect();
    let edges: Vec<Vec<usize>> = nodes
        .iter()
        .map(|m| next[m].iter().map(|i| index_of[&i.to]).collect())
        .collect();
    let components = strongly_connected(&edges);
    let mut out = Vec::new();
    let mut said = BTreeSet::new();
    for c in components.iter().filter(|c| c.len() > 1) {
        let inside: BTreeSet<usize> = c.iter().copied().collect();
        for &start in &inside {
            let Some(steps) = shortest_circle(start, &inside, &next, &nodes, &index_of) else {
                continue;
            };
            // Each circle once, whichever of its files it was found from.
            let mut key: Vec<usize> = steps.iter().map(|i| index_of[&i.from]).collect();
            let first = (0..key.len()).min_by_key(|&k| key[k]).unwrap_or(0);
            key.rotate_left(first);
            if !said.insert(key) {
                continue;
            }
            let path: Vec<String> = steps
                .iter()
                .map(|i| format!("{}:{} (`{}`)", i.file, i.line, i.written))
                .collect();
            out.push(format!(
                "a circle of {} files: {} → back to the first",
                steps.len(),
                path.join(" → ")
            ));
        }
    }
    out
}

/// The imports of the shortest circle from `start` back to it within
/// `inside`, in order (breadth first).
fn shortest_circle<'a>(
    start: usize,
    inside: &BTreeSet<usize>,
    next: &BTreeMap<&Module, Vec<&'a Import>>,
    nodes: &[&Module],
    index_of: &BTreeMap<&Module, usize>,
) -> Option<Vec<&'a Import>> {
    let mut came: BTreeMap<usize, &Import> = BTreeMap::new();
    let mut queue = std::collections::VecDeque::from([start]);
    while let Some(n) = queue.pop_front() {
        for &i in &next[nodes[n]] {
            let m = index_of[&i.to];
            if m == start {
                let mut steps = vec![i];
                let mut at = n;
                while at != start {
                    let back = came[&at];
                    steps.push(back);
                    at = index_of[&back.from];
                }
                steps.reverse();
                return Some(steps);
            }
            if inside.contains(&m) && !came.contains_key(&m) {
                came.insert(m, i);
                queue.push_back(m);
            }
        }
    }
    None
}

/// Tarjan's strongly connected components of a graph given as each
/// node's successors, each component's nodes.
fn strongly_connected(edges: &[Vec<usize>]) -> Vec<Vec<usize>> {
    struct State<'a> {
        edges: &'a [Vec<usize>],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        out: Vec<Vec<usize>>,
    }
    fn visit(s: &mut State, v: usize) {
        s.index[v] = Some(s.next);
        s.low[v] = s.next;
        s.next += 1;
        s.stack.push(v);
        s.on_stack[v] = true;
        for k in 0..s.edges[v].len() {
            let w = s.edges[v][k];
            match s.index[w] {
                None => {
                    visit(s, w);
                    s.low[v] = s.low[v].min(s.low[w]);
                }
                Some(iw) if s.on_stack[w] => s.low[v] = s.low[v].min(iw),
                _ => {}
            }
        }
        if Some(s.low[v]) == s.index[v] {
            let mut c = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack[w] = false;
                c.push(w);
                if w == v {
                    break;
                }
            }
            s.out.push(c);
        }
    }
    let n = edges.len();
    let mut s = State {
        edges,
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: Vec::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in 0..n {
        if s.index[v].is_none() {
            visit(&mut s, v);
        }
    }
    s.out
}

/// Every `.rs` file under `src/` but the binary's `main.rs` and test
/// files.
fn source_files() -> Vec<File> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut stack = vec![root.clone()];
    let mut out = Vec::new();
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap() {
            let p: PathBuf = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
                continue;
            }
            let rel = p.strip_prefix(&root).unwrap();
            let name = rel.to_string_lossy().replace('\\', "/");
            if p.extension().is_none_or(|x| x != "rs") || name == "main.rs" || is_test_file(&name) {
                continue;
            }
            out.push(File {
                path: format!("src/{name}"),
                module: module_of(rel),
                text: std::fs::read_to_string(&p).unwrap(),
            });
        }
    }
    out.sort_by(|a, b| a.path.cmp(&b.path));
    out
}

fn design() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/design.md")).unwrap()
}

#[test]
fn every_module_imports_only_lower_layers_and_no_file_imports_itself_round_a_circle() {
    let files = source_files();
    assert!(files.len() > 100, "the sources are found");
    let found = violations(&files, &layers(&design()));
    assert!(
        found.is_empty(),
        "{} violations:\n{}",
        found.len(),
        found.join("\n")
    );
}

fn file(path: &str, text: &str) -> File {
    File {
        path: path.into(),
        module: module_of(Path::new(path.trim_start_matches("src/"))),
        text: text.into(),
    }
}

/// A planted back-import and a planted pair of files importing each
/// other are found, named by file and line.
#[test]
fn planted_violations_are_found() {
    let layers = layers("Layers, lowest first: `source | lsys | film`");
    let files = vec![
        file("src/source.rs", "pub struct S;\n"),
        file(
            "src/lsys/mod.rs",
            "pub mod a;\npub mod b;\n\nuse crate::film::Film;\n",
        ),
        file("src/lsys/a.rs", "use super::{b::B, c};\npub struct A;\n"),
        file(
            "src/lsys/b.rs",
            "use super::a::A;\npub struct B;\n#[cfg(test)]\nmod tests { use crate::film::X; }\n",
        ),
        file(
            "src/film/mod.rs",
            "mod view;\nuse crate::{lsys::a::A, source::S};\nuse view::V;\n// use crate::film::nothing;\npub struct Film;\n",
        ),
        file("src/film/view.rs", "use super::Film;\npub struct V;\n"),
    ];
    let found = violations(&files, &layers);
    // The back-import, the two pairs, and the circle the back-import
    // closes (lsys → film → lsys::a → lsys).
    assert_eq!(found.len(), 4, "{found:#?}");
    assert!(
        found[0].starts_with(
            "src/lsys/mod.rs:4: `crate::film::Film`: lsys (layer 1) imports film (layer 2)"
        ),
        "{}",
        found[0]
    );
    assert!(
        found.iter().any(|f| {
            f.starts_with(
            "a circle of 2 files: src/lsys/a.rs:1 (`super::b::B`) → src/lsys/b.rs:1 (`super::a::A`)"
        )
        }),
        "{found:#?}"
    );
    // The same tree without the plants keeps the rules.
    let clean: Vec<File> = files
        .into_iter()
        .map(|mut f| {
            f.text = f
                .text
                .replace("use crate::film::Film;", "")
                .replace("b::B, ", "")
                .replace("use view::V;", "");
            f
        })
        .collect();
    assert!(violations(&clean, &layers).is_empty());
}

/// A planted circle of three files, none of which imports its importer
/// directly, is found, named file by file (issue 55).
#[test]
fn a_planted_circle_of_three_files_is_found() {
    let layers = layers("Layers, lowest first: `actors`");
    let files = vec![
        file(
            "src/actors/mod.rs",
            "pub mod live;\npub mod tennis;\npub mod eyes;\n",
        ),
        file(
            "src/actors/live.rs",
            "use super::tennis::Player;\npub struct Living;\n",
        ),
        file(
            "src/actors/tennis.rs",
            "\nuse crate::actors::eyes::Eyes;\npub struct Player;\n",
        ),
        file(
            "src/actors/eyes.rs",
            "use super::live::Living;\npub struct Eyes;\n",
        ),
    ];
    let found = violations(&files, &layers);
    assert_eq!(found.len(), 1, "{found:#?}");
    assert_eq!(
        found[0],
        "a circle of 3 files: src/actors/eyes.rs:1 (`super::live::Living`) → src/actors/live.rs:1 (`super::tennis::Player`) → src/actors/tennis.rs:2 (`crate::actors::eyes::Eyes`) → back to the first"
    );
    // Broken at any one file, no circle is left.
    let mut broken = files;
    broken[2].text = "pub struct Player;\n".into();
    assert!(violations(&broken, &layers).is_empty());
}

#[test]
fn use_trees_expand() {
    assert_eq!(
        expand("super::{a, b::{c, d as e}}"),
        ["super::a", "super::b::c", "super::b::d"]
    );
}
