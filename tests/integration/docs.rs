//! The documentation stays a door and a map: README.md fits on a few screens (at most 200 lines; the rest
//! belongs in docs/), and every relative link in README.md and docs/ leads to a file that exists.

use std::path::{Path, PathBuf};

/// Most lines README.md may have.
const README_LINES: usize = 200;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn the_readme_is_a_door_of_at_most_200_lines() {
    let text = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = text.lines().count();
    assert!(lines <= README_LINES, "README.md has {lines} lines, over {README_LINES}: move the detail to docs/");
    for section in ["## The two commands", "## Controls", "## The main commands", "## Documentation"] {
        assert!(text.lines().any(|l| l == section), "README.md has no '{section}' section");
    }
}

/// The relative link targets of markdown `text` (`](target)`, without `#anchor`), web links left out.
fn links(text: &str) -> Vec<String> {
    text.split("](")
        .skip(1)
        .filter_map(|rest| rest.split(')').next())
        .map(|t| t.split('#').next().unwrap_or_default().to_string())
        .filter(|t| !t.is_empty() && !t.contains("://") && !t.starts_with("mailto:"))
        .collect()
}

#[test]
fn every_relative_link_leads_to_a_file() {
    let mut files = vec![root().join("README.md"), root().join("CHANGELOG.md"), root().join("ARCHITECTURE.md")];
    files.extend(
        std::fs::read_dir(root().join("docs"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "md")),
    );
    let mut checked = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let dir = file.parent().unwrap_or(Path::new("."));
        for target in links(&text) {
            assert!(dir.join(&target).exists(), "{}: the link to {target} leads nowhere", file.display());
            checked += 1;
        }
    }
    assert!(checked > 20, "only {checked} links found");
    assert_eq!(links("see [a](b.md#x) and [c](https://e.org) ![d](e.png)"), ["b.md", "e.png"]);
}
