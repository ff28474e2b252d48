//! The documentation's links hold: every relative link and image in README.md, ARCHITECTURE.md,
//! docs/book/README.md and the book's chapters (docs/book/src/*.md) names a file that exists,
//! and a `#anchor` a heading of its target (GitHub's and mdBook's slugs: lowercase, spaces to
//! `-`, punctuation other than `-` and `_` dropped). Links to this repository's files on GitHub
//! (`https://github.com/tress-hair/tress/blob/main/PATH`, how the book links files outside it)
//! must name existing paths too. And the book's SUMMARY.md lists every chapter, and every file
//! it lists exists. No GPU, no mdBook: CI checks the book's structure and links without building
//! it (see docs/book/README.md).

use std::collections::{BTreeSet, HashMap};
use std::path::{Component, Path, PathBuf};

/// The repository's address on GitHub, as the book links files outside it.
const GITHUB_BLOB: &str = "https://github.com/tress-hair/tress/blob/main/";
const GITHUB_TREE: &str = "https://github.com/tress-hair/tress/tree/main/";

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn book_src() -> PathBuf {
    root().join("docs/book/src")
}

/// The chapters of the book: docs/book/src/*.md, SUMMARY.md left out.
fn chapters() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(book_src())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .filter(|p| !p.ends_with("SUMMARY.md"))
        .collect();
    files.sort();
    files
}

/// `text` with fenced code blocks and inline code spans blanked out (links in them are examples).
fn prose(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            out.push('\n');
            continue;
        }
        if fenced {
            out.push('\n');
            continue;
        }
        let mut in_code = false;
        for c in line.chars() {
            if c == '`' {
                in_code = !in_code;
                out.push(' ');
            } else {
                out.push(if in_code { ' ' } else { c });
            }
        }
        out.push('\n');
    }
    out
}

/// The targets of a Markdown text's links and images: inline `[text](target "title")`,
/// reference definitions `[name]: target`, and HTML `src="…"` / `href="…"`, with their lines.
fn links(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (n, line) in prose(text).lines().enumerate() {
        let mut rest = line;
        while let Some(i) = rest.find("](") {
            let after = &rest[i + 2..];
            // Up to the matching parenthesis (targets may hold balanced parentheses).
            let mut depth = 0;
            let mut end = after.len();
            for (j, c) in after.char_indices() {
                match c {
                    '(' => depth += 1,
                    ')' if depth == 0 => {
                        end = j;
                        break;
                    }
                    ')' => depth -= 1,
                    _ => {}
                }
            }
            let target = after[..end].split_whitespace().next().unwrap_or("");
            let target = target.trim_start_matches('<').trim_end_matches('>');
            out.push((n + 1, target.to_string()));
            rest = &after[end.min(after.len())..];
        }
        let trimmed = line.trim_start();
        if trimmed.starts_with('[')
            && let Some(i) = trimmed.find("]: ")
        {
            let target = trimmed[i + 3..].split_whitespace().next().unwrap_or("");
            out.push((n + 1, target.to_string()));
        }
        for attr in ["src=\"", "href=\""] {
            let mut rest = line;
            while let Some(i) = rest.find(attr) {
                let after = &rest[i + attr.len()..];
                let end = after.find('"').unwrap_or(after.len());
                out.push((n + 1, after[..end].to_string()));
                rest = &after[end..];
            }
        }
    }
    out
}

/// A heading's anchor as GitHub and mdBook make it.
fn slug(heading: &str) -> String {
    let mut s = String::new();
    for c in heading.trim().chars() {
        if c.is_alphanumeric() || c == '-' || c == '_' {
            s.extend(c.to_lowercase());
        } else if c == ' ' {
            s.push('-');
        }
    }
    s
}

/// The anchors of a Markdown file's headings (a repeated heading's later anchors get `-1`, `-2`).
fn anchors(text: &str) -> BTreeSet<String> {
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut out = BTreeSet::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        }
        if fenced || !line.starts_with('#') {
            continue;
        }
        let heading = line.trim_start_matches('#');
        if !heading.starts_with(' ') {
            continue;
        }
        // Link syntax in a heading keeps only its text.
        let mut text = String::new();
        let mut skip = 0;
        for c in heading.chars() {
            match (c, skip) {
                ('[', 0) => {}
                (']', 0) => skip = 1,
                ('(', 1) => skip = 2,
                (')', 2) => skip = 0,
                (_, 1) => {
                    skip = 0;
                    text.push(c);
                }
                (_, 2) => {}
                _ => text.push(c),
            }
        }
        let base = slug(&text);
        let count = seen.entry(base.clone()).or_insert(0);
        out.insert(match *count {
            0 => base.clone(),
            k => format!("{base}-{k}"),
        });
        *count += 1;
    }
    out
}

/// `path` with `.` and `..` resolved lexically (the files need not exist).
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// What is wrong with `target`, a link in `file`; `None` when it holds.
fn check(file: &Path, target: &str) -> Option<String> {
    let root = normalize(&root());
    let (path_part, anchor) = match target.split_once('#') {
        Some((p, a)) => (p, Some(a)),
        None => (target, None),
    };
    let resolved = if let Some(p) = target
        .strip_prefix(GITHUB_BLOB)
        .or_else(|| target.strip_prefix(GITHUB_TREE))
    {
        let p = p.split('#').next().unwrap_or(p);
        root.join(p)
    } else if target.contains("://") || target.starts_with("mailto:") {
        return None;
    } else if path_part.is_empty() {
        file.to_path_buf()
    } else {
        normalize(&file.parent().unwrap().join(path_part))
    };
    if !resolved.starts_with(&root) {
        return Some(format!("{target}: outside the repository"));
    }
    let shown = resolved
        .strip_prefix(&root)
        .unwrap_or(&resolved)
        .to_path_buf();
    if !resolved.exists() {
        return Some(format!("{target}: no file {}", shown.display()));
    }
    let anchor = anchor?;
    if resolved.extension().is_none_or(|e| e != "md") {
        return None;
    }
    let text = std::fs::read_to_string(&resolved).unwrap();
    if anchors(&text).contains(anchor) {
        None
    } else {
        Some(format!(
            "{target}: no heading with anchor #{anchor} in {}",
            shown.display()
        ))
    }
}

#[test]
fn every_relative_link_and_image_resolves() {
    let mut files = vec![
        root().join("README.md"),
        root().join("ARCHITECTURE.md"),
        root().join("docs/book/README.md"),
    ];
    files.extend(chapters());
    files.push(book_src().join("SUMMARY.md"));
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in &files {
        let text =
            std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        for (line, target) in links(&text) {
            checked += 1;
            if let Some(problem) = check(file, &target) {
                let name = file.strip_prefix(root()).unwrap_or(file);
                broken.push(format!("{}:{line}: {problem}", name.display()));
            }
        }
    }
    assert!(
        checked > 50,
        "only {checked} links found: is the parser right?"
    );
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn the_summary_lists_every_chapter_and_only_chapters_that_exist() {
    let summary = std::fs::read_to_string(book_src().join("SUMMARY.md")).unwrap();
    let listed: BTreeSet<PathBuf> = links(&summary)
        .into_iter()
        .map(|(_, t)| book_src().join(t.split('#').next().unwrap()))
        .collect();
    for path in &listed {
        assert!(
            path.exists(),
            "SUMMARY.md lists {} which does not exist",
            path.display()
        );
    }
    for chapter in chapters() {
        assert!(
            listed.contains(&chapter),
            "SUMMARY.md does not list {}: add it, or mdBook leaves it out of the book",
            chapter.display()
        );
    }
}

#[test]
fn slugs_follow_github_and_mdbook() {
    assert_eq!(
        slug(
            "`tress render [INPUT...] -o OUT.(png|exr)`"
                .replace('`', "")
                .as_str()
        ),
        "tress-render-input--o-outpngexr"
    );
    assert_eq!(
        slug(
            "Physically based strands (`shading = \"marschner\"`)"
                .replace('`', "")
                .as_str()
        ),
        "physically-based-strands-shading--marschner"
    );
    let text = "# A\n## A\n```\n# not a heading\n```\n## [Link](x.md) here\n";
    let a = anchors(text);
    assert!(
        a.contains("a") && a.contains("a-1") && a.contains("link-here"),
        "{a:?}"
    );
    assert!(!a.contains("not-a-heading"));
    let l = links("see [x](a.md#b \"t\") and `[c](d.md)`\n![i](img/p.png)\n[r]: ref.md\n");
    let targets: Vec<&str> = l.iter().map(|(_, t)| t.as_str()).collect();
    assert_eq!(targets, ["a.md#b", "img/p.png", "ref.md"]);
}
