//! The documentation holds together: the README stays a front door (≤ 12 KB, links that resolve),
//! every `models.md#anchor` the code and shaders cite exists, and the user docs describe the tool
//! as it is (no issue numbers).

use std::path::{Path, PathBuf};

use crate::common::repo;

fn files(dir: &Path, ext: &[&str], out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            files(&p, ext, out);
        } else if p.extension().is_some_and(|x| ext.iter().any(|e| x == *e)) {
            out.push(p);
        }
    }
}

fn docs() -> Vec<PathBuf> {
    let mut out = vec![repo().join("README.md")];
    files(&repo().join("docs"), &["md"], &mut out);
    out
}

/// The anchors a Markdown file offers: `<a id>` tags and GitHub's heading slugs.
fn anchors(text: &str) -> Vec<String> {
    let mut out: Vec<String> =
        text.split("<a id=\"").skip(1).filter_map(|s| s.split('"').next()).map(String::from).collect();
    for line in text.lines().filter(|l| l.starts_with('#')) {
        let title = line.trim_start_matches('#').trim();
        let slug: String = title
            .to_lowercase()
            .chars()
            .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-' || *c == '_')
            .map(|c| if c == ' ' { '-' } else { c })
            .collect();
        out.push(slug);
    }
    out
}

#[test]
fn every_cited_model_anchor_exists() {
    let _timer = crate::common::timed!();
    let models = std::fs::read_to_string(repo().join("docs/models.md")).unwrap();
    assert!(!models.contains("{#"), "`{{#id}}` anchors do not render on GitHub: use <a id=\"…\"></a>");
    let offered = anchors(&models);
    let mut sources = Vec::new();
    for dir in ["src", "shaders", "docs", "tests"] {
        files(&repo().join(dir), &["rs", "wgsl", "md"], &mut sources);
    }
    sources.push(repo().join("README.md"));
    let mut cited = 0;
    for f in sources {
        let text = std::fs::read_to_string(&f).unwrap();
        for rest in text.split("models.md#").skip(1) {
            let id: String = rest.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '-' || *c == '_').collect();
            if id.is_empty() || f.ends_with("docs.rs") {
                continue;
            }
            cited += 1;
            assert!(offered.contains(&id), "{} cites models.md#{id}, which docs/models.md lacks", f.display());
        }
    }
    assert!(cited > 50, "only {cited} citations found: the scan is broken");
}

#[test]
fn the_readme_is_a_front_door_and_every_link_resolves() {
    let _timer = crate::common::timed!();
    let readme = std::fs::read_to_string(repo().join("README.md")).unwrap();
    assert!(
        readme.len() <= 12 * 1024,
        "README.md is {} bytes; keep it ≤ 12 KB and move the rest to docs/",
        readme.len()
    );
    for f in docs() {
        let text = std::fs::read_to_string(&f).unwrap();
        for link in text.split("](").skip(1).filter_map(|s| s.split(')').next()) {
            if link.starts_with("http") || link.starts_with('#') {
                continue;
            }
            let (path, anchor) = link.split_once('#').map_or((link, None), |(p, a)| (p, Some(a)));
            let target = f.parent().unwrap().join(path);
            assert!(target.exists(), "{} links to {link}, which does not exist", f.display());
            if let Some(a) = anchor {
                let offered = anchors(&std::fs::read_to_string(&target).unwrap());
                assert!(offered.iter().any(|o| o == a), "{} links to {link}: no such anchor", f.display());
            }
        }
    }
}

#[test]
fn user_docs_describe_the_tool_as_it_is() {
    let _timer = crate::common::timed!();
    for f in docs() {
        let text = std::fs::read_to_string(&f).unwrap();
        for (i, line) in text.lines().enumerate() {
            let lower = line.to_lowercase();
            assert!(
                !lower.contains("issue ") && !lower.contains("issue's"),
                "{}:{}: history belongs in commit bodies: {line}",
                f.display(),
                i + 1
            );
        }
    }
}

/// Every picture under docs/ is rebuilt by tools/docs_pictures.sh from the code as it is, so none
/// can show what the code no longer draws without a line that would redraw it.
#[test]
fn every_docs_picture_has_a_recipe_in_the_rebuild_script() {
    let _timer = crate::common::timed!();
    let script = std::fs::read_to_string(repo().join("tools/docs_pictures.sh")).unwrap();
    let mut pictures = Vec::new();
    files(&repo().join("docs"), &["png"], &mut pictures);
    assert!(!pictures.is_empty());
    for p in pictures {
        let name = p.strip_prefix(repo()).unwrap().to_string_lossy().replace('\\', "/");
        assert!(script.contains(&name), "{name}: tools/docs_pictures.sh does not write it");
    }
}
