//! Where the race's assets come from ([`Assets`]: a folder, or the tree built into the program) and the
//! courses they hold: each is a folder `track/NAME/` with its scene `NAME.gltf` and its
//! centre line `centerline.json`, whose optional `title` and `about` say what the menus and
//! `scanline-racer courses` show.
//!
//! A course is named by its folder, so a name is a plain folder name ([`is_course_name`]): no separator, no
//! `..`, nothing hidden. The list is in name order, from the folder or from the tree built into the
//! program, so two runs list the same courses in the same order.

use std::path::{Path, PathBuf};

pub use crate::input::trace::{FIRST_COURSE as DEFAULT_COURSE, is_course_name};

/// Where the race's assets come from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Assets {
    /// A folder holding `track/` and `cars/` (a checkout's `assets/`, or one being edited).
    Folder(PathBuf),
    /// The ones built into the program ([`super::built_in`]).
    BuiltIn,
}

impl Assets {
    /// The assets a command uses: the folder `given` (`--assets DIR`), else `$SCANLINE_RACER_ASSETS`, else
    /// an `assets` folder in the current folder or beside the executable's build tree (a checkout, whose
    /// edits then show), else the ones built into the program.
    #[must_use]
    pub fn find(given: Option<&Path>) -> Self {
        match given {
            Some(dir) => Assets::Folder(dir.to_path_buf()),
            None => find_assets().map_or(Assets::BuiltIn, Assets::Folder),
        }
    }
}

/// Where an assets folder is: `$SCANLINE_RACER_ASSETS` (whatever it holds, so a wrong one is named in the
/// error), `./assets`, or beside the executable's build tree; `None` when there is none.
#[must_use]
pub fn find_assets() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os("SCANLINE_RACER_ASSETS").filter(|d| !d.is_empty()) {
        return Some(PathBuf::from(dir));
    }
    let mut candidates: Vec<PathBuf> = vec![PathBuf::from("assets")];
    if let Ok(exe) = std::env::current_exe() {
        // target/release/scanline-racer -> ../../assets
        if let Some(root) = exe.parent().and_then(Path::parent).and_then(Path::parent) {
            candidates.push(root.join("assets"));
        }
    }
    candidates.into_iter().find(|p| p.join(scene_path(DEFAULT_COURSE)).is_file())
}

/// Largest centre line read (the shipped ones are under 200 KB).
pub const MAX_CENTRE_LINE_BYTES: u64 = 16 * 1024 * 1024;

/// Most courses listed from one folder: a folder of thousands of sub-folders is not a list anyone reads.
const MAX_COURSES: usize = 64;
/// Most entries of `track/` looked at (a budget on the folder's reading, far above any real tree).
const MAX_ENTRIES: usize = 4096;

/// One course as the menus and the `courses` command show it.
#[derive(Clone, Debug, PartialEq)]
pub struct CourseInfo {
    /// Its name: the folder under `track/`.
    pub name: String,
    /// Its title (the name when the centre line has none).
    pub title: String,
    /// One sentence about it (empty when the centre line has none).
    pub about: String,
    /// Lap length in metres (0 when the centre line does not say).
    pub length_m: f32,
}

impl CourseInfo {
    /// The course's details from its centre line's text: `title`, `about`, `length_m`.
    #[must_use]
    pub fn from_centre_line(name: &str, text: &str) -> Self {
        let v: serde_json::Value = serde_json::from_str(text).unwrap_or_default();
        let field = |k: &str| v.get(k).and_then(serde_json::Value::as_str).map(|s| s.chars().take(200).collect());
        CourseInfo {
            name: name.to_string(),
            title: field("title").unwrap_or_else(|| name.to_string()),
            about: field("about").unwrap_or_default(),
            length_m: v.get("length_m").and_then(serde_json::Value::as_f64).unwrap_or(0.0) as f32,
        }
    }
}

/// The path of a course's scene (`track/NAME/NAME.gltf`) under an assets tree.
#[must_use]
pub fn scene_path(name: &str) -> String {
    format!("track/{name}/{name}.gltf")
}

/// The path of a course's centre line (`track/NAME/centerline.json`) under an assets tree.
#[must_use]
pub fn centre_line_path(name: &str) -> String {
    format!("track/{name}/centerline.json")
}

impl Assets {
    /// The names of the courses these assets hold, in name order: each folder of `track/` with a plain
    /// name holding its scene and centre line (at most 64).
    #[must_use]
    pub fn course_names(&self) -> Vec<String> {
        let mut names: Vec<String> = match self {
            Assets::Folder(dir) => folder_courses(dir),
            Assets::BuiltIn => super::built_in::FILES
                .iter()
                .filter_map(|(path, _)| {
                    let name = path.strip_prefix("track/")?.split_once('/')?.0;
                    (*path == scene_path(name)).then(|| name.to_string())
                })
                .filter(|name| super::built_in::FILES.iter().any(|(path, _)| *path == centre_line_path(name)))
                .collect(),
        };
        names.retain(|n| is_course_name(n));
        names.sort();
        names.dedup();
        names.truncate(MAX_COURSES);
        names
    }

    /// The courses these assets hold with their titles and lengths, in name order; a centre line that
    /// cannot be read gives the name alone (loading the course says what is wrong with it).
    #[must_use]
    pub fn courses(&self) -> Vec<CourseInfo> {
        self.course_names()
            .iter()
            .map(|name| {
                let text = match self {
                    Assets::Folder(dir) => crate::userfile::read_regular_text(
                        &dir.join(centre_line_path(name)),
                        MAX_CENTRE_LINE_BYTES,
                        "a centre line",
                    )
                    .unwrap_or_default(),
                    Assets::BuiltIn => built_in_text(&centre_line_path(name)).unwrap_or_default().to_string(),
                };
                CourseInfo::from_centre_line(name, &text)
            })
            .collect()
    }
}

/// A text file of the built-in tree, by its path there.
#[must_use]
pub fn built_in_text(path: &str) -> Option<&'static str> {
    super::built_in::FILES.iter().find(|(n, _)| *n == path).and_then(|(_, b)| std::str::from_utf8(b).ok())
}

/// The courses of an assets folder: folders of `dir/track` with a plain name holding the file `NAME.gltf`
/// and something named `centerline.json` (of the first [`MAX_ENTRIES`] entries of `track/`, so that the
/// list, sorted after, is the same on every run for any folder of a sane size).
fn folder_courses(dir: &Path) -> Vec<String> {
    let Ok(entries) = std::fs::read_dir(dir.join("track")) else { return vec![] };
    entries
        .flatten()
        .take(MAX_ENTRIES)
        .filter_map(|e| e.file_name().to_str().map(str::to_string))
        .filter(|name| {
            is_course_name(name) && {
                let p = |rel: String| -> PathBuf { dir.join(rel) };
                // The centre line need only be there: loading it says what is wrong with one that is not a
                // regular file.
                p(scene_path(name)).is_file() && std::fs::symlink_metadata(p(centre_line_path(name))).is_ok()
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn course_names_are_plain_folder_names() {
        for good in ["circuit", "city", "coast-2", "a_b", "x"] {
            assert!(is_course_name(good), "{good}");
        }
        for bad in ["", "..", ".", "a/b", "a\\b", "City", "-x", ".hidden", "a b", "é", &"x".repeat(33)] {
            assert!(!is_course_name(bad), "{bad:?}");
        }
    }

    #[test]
    fn the_built_in_tree_holds_every_shipped_course() {
        let names = Assets::BuiltIn.course_names();
        assert_eq!(names, ["circuit", "city", "mountain"]);
        let folder = Assets::Folder(PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/assets")));
        assert_eq!(folder.course_names(), names);
        let info = folder.courses();
        assert!(info.iter().all(|c| c.length_m >= 3000.0 && !c.title.is_empty()), "{info:?}");
    }

    #[test]
    fn a_centre_line_without_a_title_is_named_by_its_folder() {
        let c = CourseInfo::from_centre_line("mine", "{\"length_m\": 1234.5, \"samples\": []}");
        assert_eq!((c.title.as_str(), c.about.as_str(), c.length_m), ("mine", "", 1234.5));
        let c = CourseInfo::from_centre_line("broken", "not json");
        assert_eq!((c.title.as_str(), c.length_m), ("broken", 0.0));
    }
}
