//! Every relative link and image in the documentation resolves (issue 36): README.md,
//! BENCHMARKS.md and every Markdown file under docs/. A link `[text](path)` or image
//! `![alt](path)` names a file relative to the page that holds it; `path#anchor` into a
//! Markdown file must also name one of its headings, slugged as GitHub does (lower case,
//! punctuation but `-` and `_` dropped, spaces as `-`, `-1`, `-2`, ... on repeats). Links with
//! a scheme (`https:`, `mailto:`) are not followed; code spans and fenced blocks are not read.
//! No GPU needed.

use std::collections::HashSet;
use std::fs;
use std::path::{Component, Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The pages checked: README.md, BENCHMARKS.md, docs/**/*.md.
fn pages() -> Vec<PathBuf> {
    let mut out = vec![root().join("README.md"), root().join("BENCHMARKS.md")];
    let mut dirs = vec![root().join("docs")];
    while let Some(dir) = dirs.pop() {
        for entry in fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// The text outside fenced code blocks and code spans, one line at a time.
fn prose_lines(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut fence: Option<&str> = None;
    for line in text.lines() {
        let trimmed = line.trim_start();
        if let Some(f) = fence {
            if trimmed.starts_with(f) {
                fence = None;
            }
            out.push(String::new());
            continue;
        }
        if trimmed.starts_with("```") {
            fence = Some("```");
            out.push(String::new());
            continue;
        }
        if trimmed.starts_with("~~~") {
            fence = Some("~~~");
            out.push(String::new());
            continue;
        }
        // Drop code spans: text between matching runs of backticks.
        let mut kept = String::new();
        let mut rest = line;
        while let Some(start) = rest.find('`') {
            kept.push_str(&rest[..start]);
            let ticks = rest[start..].chars().take_while(|&c| c == '`').count();
            let after = &rest[start + ticks..];
            let closer = "`".repeat(ticks);
            match after.find(&closer) {
                Some(end) => rest = &after[end + ticks..],
                None => {
                    rest = after;
                    break;
                }
            }
        }
        kept.push_str(rest);
        out.push(kept);
    }
    out
}

/// GitHub's anchor for a heading's text.
fn slug(heading: &str) -> String {
    let mut text = String::new();
    let mut in_tag = false;
    for c in heading.trim().chars() {
        match c {
            '<' => in_tag = true,
            '>' if in_tag => in_tag = false,
            _ if in_tag => {}
            _ => text.push(c),
        }
    }
    text.to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == '-' || *c == '_' || *c == ' ')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of a Markdown file's headings (ATX `#` headings outside code blocks).
fn anchors(text: &str) -> HashSet<String> {
    let mut seen = std::collections::HashMap::<String, usize>::new();
    let mut out = HashSet::new();
    let mut fence = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fence = !fence;
            continue;
        }
        if fence {
            continue;
        }
        let hashes = line.chars().take_while(|&c| c == '#').count();
        if hashes == 0 || hashes > 6 || !line[hashes..].starts_with(' ') {
            continue;
        }
        let title = line[hashes..].trim().trim_end_matches('#').trim();
        let base = slug(title);
        let n = seen.entry(base.clone()).or_insert(0);
        out.insert(if *n == 0 { base.clone() } else { format!("{base}-{n}") });
        *n += 1;
    }
    out
}

/// The targets of inline links and images on a line: `[text](target)`, `![alt](target "t")`.
fn targets(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let bytes = line.as_bytes();
    let mut i = 0;
    while let Some(pos) = line[i..].find("](") {
        let start = i + pos + 2;
        // Balanced parentheses inside the target, as in `a_(b).md`.
        let mut depth = 1;
        let mut end = start;
        while end < bytes.len() {
            match bytes[end] {
                b'(' => depth += 1,
                b')' => {
                    depth -= 1;
                    if depth == 0 {
                        break;
                    }
                }
                _ => {}
            }
            end += 1;
        }
        if end >= bytes.len() {
            break;
        }
        let inner = line[start..end].trim();
        let target = inner.split_whitespace().next().unwrap_or("");
        let target = target.trim_start_matches('<').trim_end_matches('>');
        if !target.is_empty() {
            out.push(target.to_string());
        }
        i = end + 1;
    }
    out
}

fn has_scheme(target: &str) -> bool {
    match target.find(':') {
        Some(i) => {
            let scheme = &target[..i];
            !scheme.is_empty() && scheme.chars().all(|c| c.is_ascii_alphanumeric() || c == '+' || c == '-' || c == '.')
        }
        None => false,
    }
}

/// `base/../x` without touching the file system (a link may not leave the repository).
fn normalise(path: &Path) -> Option<PathBuf> {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::ParentDir => {
                if !out.pop() {
                    return None;
                }
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    Some(out)
}

fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            if let Ok(v) = u8::from_str_radix(&s[i + 1..i + 3], 16) {
                out.push(v);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Every failure, as "page:line: target: why".
fn broken_links() -> Vec<String> {
    let root = root();
    let mut failures = Vec::new();
    for page in pages() {
        let text = fs::read_to_string(&page).unwrap();
        let rel_page = page.strip_prefix(&root).unwrap().to_path_buf();
        for (n, line) in prose_lines(&text).iter().enumerate() {
            for target in targets(line) {
                if has_scheme(&target) {
                    continue;
                }
                let (path, anchor) = match target.split_once('#') {
                    Some((p, a)) => (p, Some(a)),
                    None => (target.as_str(), None),
                };
                let where_ = format!("{}:{}: {target}", rel_page.display(), n + 1);
                let file = if path.is_empty() {
                    Some(rel_page.clone())
                } else if path.starts_with('/') {
                    normalise(Path::new(path.trim_start_matches('/')))
                } else {
                    normalise(&rel_page.parent().unwrap().join(percent_decode(path)))
                };
                let Some(file) = file else {
                    failures.push(format!("{where_}: leaves the repository"));
                    continue;
                };
                let full = root.join(&file);
                if !full.exists() {
                    failures.push(format!("{where_}: no file {}", file.display()));
                    continue;
                }
                if let Some(anchor) = anchor {
                    if full.extension().is_some_and(|e| e == "md") {
                        let heads = anchors(&fs::read_to_string(&full).unwrap());
                        if !heads.contains(anchor) {
                            failures.push(format!("{where_}: no heading #{anchor} in {}", file.display()));
                        }
                    }
                }
            }
        }
    }
    failures
}

#[test]
fn every_relative_link_and_image_resolves() {
    let failures = broken_links();
    assert!(failures.is_empty(), "{} broken links in the documentation:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn the_checker_sees_links_anchors_and_code() {
    assert_eq!(
        targets(r#"see [a](x.md#b) and ![img](docs/g.png "t"), [c](https://e.org)"#),
        vec!["x.md#b", "docs/g.png", "https://e.org"]
    );
    assert_eq!(slug("Pacing: time limit, Ctrl-C and throughput"), "pacing-time-limit-ctrl-c-and-throughput");
    assert_eq!(slug("The `envmap` environment (issue 25)"), "the-envmap-environment-issue-25");
    assert_eq!(slug("Mitsuba 0.5/0.6 scenes of the field"), "mitsuba-0506-scenes-of-the-field");
    assert_eq!(slug("CI's time on two cores"), "cis-time-on-two-cores");
    let heads = anchors("# A\n## A\n```\n# not a heading\n```\n### B_c d\n");
    assert!(heads.contains("a") && heads.contains("a-1") && heads.contains("b_c-d"));
    assert!(!heads.contains("not-a-heading"));
    let lines = prose_lines("x `[a](gone.md)` y\n```\n[b](gone.md)\n```\n[c](here.md)\n");
    let found: Vec<String> = lines.iter().flat_map(|l| targets(l)).collect();
    assert_eq!(found, vec!["here.md"]);
    assert!(has_scheme("mailto:a@b") && !has_scheme("docs/a.md"));
    assert_eq!(normalise(Path::new("docs/../README.md")), Some(PathBuf::from("README.md")));
    assert_eq!(normalise(Path::new("../x")), None);
}
