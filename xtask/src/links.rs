//! The documentation's links, checked: every relative link of the README, ARCHITECTURE.md,
//! docs/ and validation/README.md names a file of the repository, and a `#anchor` a heading of
//! it (GitHub's anchors: the heading in lower case, punctuation dropped, spaces as hyphens).

use crate::schema::root;
use std::path::Path;

/// The documents whose links are checked, from the repository's root.
fn documents(root: &Path) -> Vec<std::path::PathBuf> {
    let mut out: Vec<_> = ["README.md", "ARCHITECTURE.md", "validation/README.md"]
        .iter()
        .map(|p| root.join(p))
        .collect();
    if let Ok(entries) = std::fs::read_dir(root.join("docs")) {
        let mut docs: Vec<_> = entries
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|e| e == "md"))
            .collect();
        docs.sort();
        out.extend(docs);
    }
    out
}

/// The targets of `[text](target)` links in `markdown`, outside code blocks.
fn links(markdown: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut fenced = false;
    for line in markdown.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        let mut rest = line;
        while let Some(i) = rest.find("](") {
            let after = &rest[i + 2..];
            let Some(end) = after.find(')') else { break };
            out.push(after[..end].to_string());
            rest = &after[end..];
        }
    }
    out
}

/// GitHub's anchor of a heading's text.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-' || *c == '_')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of a markdown file's headings.
fn anchors(markdown: &str) -> Vec<String> {
    let mut fenced = false;
    markdown
        .lines()
        .filter(|l| {
            if l.trim_start().starts_with("```") {
                fenced = !fenced;
            }
            !fenced && l.starts_with('#')
        })
        .map(|l| anchor(l.trim_start_matches('#')))
        .collect()
}

/// Every broken link of the documents: (document, link, why).
fn broken(root: &Path) -> Vec<(String, String, &'static str)> {
    let mut out = Vec::new();
    for doc in documents(root) {
        let Ok(text) = std::fs::read_to_string(&doc) else {
            out.push((doc.display().to_string(), String::new(), "document missing"));
            continue;
        };
        let dir = doc.parent().unwrap_or(root);
        for link in links(&text) {
            if link.contains("://") || link.starts_with("mailto:") {
                continue;
            }
            let (path, fragment) = link.split_once('#').unwrap_or((&link, ""));
            let target = if path.is_empty() { doc.clone() } else { dir.join(path) };
            let name = doc.strip_prefix(root).unwrap_or(&doc).display().to_string();
            if !target.exists() {
                out.push((name, link.clone(), "no such file"));
            } else if !fragment.is_empty() {
                let headings = std::fs::read_to_string(&target).map(|t| anchors(&t));
                if !headings.is_ok_and(|h| h.iter().any(|a| a == fragment)) {
                    out.push((name, link.clone(), "no such heading"));
                }
            }
        }
    }
    out
}

#[test]
fn every_documentation_link_names_a_file_and_heading_of_the_repository() {
    let root = root();
    let found = broken(&root);
    assert!(found.is_empty(), "broken links: {found:#?}");
    // The check itself: it sees the README's links and would see a broken one.
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap_or_default();
    assert!(links(&readme).iter().any(|l| l == "docs/commands.md"));
    assert_eq!(
        anchor("## Beam scene (`cargo xtask beam`)".trim_start_matches('#')),
        "beam-scene-cargo-xtask-beam"
    );
    assert_eq!(
        anchors("# a\n```\n# not a heading\n```\n## check-figures\n"),
        ["a", "check-figures"]
    );
}
