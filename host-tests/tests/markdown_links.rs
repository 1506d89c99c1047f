//! The repository's Markdown holds together and the project stands alone:
//! - every relative link in a Markdown file names a file or folder that exists, and every
//!   `#anchor` (in the page, or `page.md#anchor`) names a heading of its target (GitHub's
//!   and mdBook's slugs: lower case, spaces to `-`, punctuation but `-` and `_` dropped, a
//!   repeated heading `-1`, `-2`, ...); `http(s)://` and `mailto:` links are not checked;
//! - README.md is at most 300 lines (the rest is the book, `docs/src/`);
//! - no tracked text file points at the notes outside the repository or names a vendor
//!   document by its file name: the book holds those facts, and code cites the book page
//!   or the vendor document's title and section.
//!
//! The files are those git lists (tracked, and new ones not ignored), so `target/`,
//! `fuzz/corpus/` and other build output are never read.

use std::collections::{BTreeMap, HashMap};
use std::path::{Component, Path, PathBuf};
use std::process::Command;

use pulldown_cmark::{Event, Options, Parser, Tag, TagEnd};

/// The repository's root (this crate is `host-tests/`).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("host-tests is inside the repository")
        .to_path_buf()
}

/// Files git knows matching `pathspec`: tracked ones (still present), and with `new`
/// also untracked ones that are not ignored. Paths relative to the root, sorted.
fn git_files(pathspec: &str, new: bool) -> Vec<PathBuf> {
    let mut args = vec!["ls-files", "-z", "--cached"];
    if new {
        args.extend(["--others", "--exclude-standard"]);
    }
    args.extend(["--", pathspec]);
    let out = Command::new("git")
        .args(&args)
        .current_dir(root())
        .output()
        .expect("git runs");
    assert!(out.status.success(), "git ls-files: {out:?}");
    let mut files: Vec<PathBuf> = out
        .stdout
        .split(|&b| b == 0)
        .filter(|p| !p.is_empty())
        .map(|p| PathBuf::from(String::from_utf8_lossy(p).into_owned()))
        .filter(|p| root().join(p).is_file())
        .collect();
    files.sort();
    files.dedup();
    files
}

fn markdown_files() -> Vec<PathBuf> {
    git_files("*.md", true)
}

fn options() -> Options {
    Options::ENABLE_TABLES
        | Options::ENABLE_FOOTNOTES
        | Options::ENABLE_STRIKETHROUGH
        | Options::ENABLE_HEADING_ATTRIBUTES
}

/// A heading's anchor as GitHub and mdBook make it: lower case; letters, digits, `-` and
/// `_` kept; each space (or other white space) a `-`; everything else dropped.
fn slug(text: &str) -> String {
    text.trim()
        .chars()
        .flat_map(char::to_lowercase)
        .filter_map(|c| {
            if c.is_alphanumeric() || c == '-' || c == '_' {
                Some(c)
            } else if c.is_whitespace() {
                Some('-')
            } else {
                None
            }
        })
        .collect()
}

/// What one Markdown file offers and asks: its headings' anchors and its links (the
/// destination as written, and the 1-based line it is on).
struct Page {
    anchors: Vec<String>,
    links: Vec<(String, usize)>,
}

fn read_page(text: &str) -> Page {
    let mut anchors = Vec::new();
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut links = Vec::new();
    // The heading being read: its explicit id, if any, and its text so far.
    let mut heading: Option<(Option<String>, String)> = None;
    let line_of = |offset: usize| text[..offset].matches('\n').count() + 1;
    for (event, range) in Parser::new_ext(text, options()).into_offset_iter() {
        match event {
            Event::Start(Tag::Heading { id, .. }) => {
                heading = Some((id.map(|id| id.to_string()), String::new()));
            }
            Event::Text(t) | Event::Code(t) => {
                if let Some((_, buf)) = heading.as_mut() {
                    buf.push_str(&t);
                }
            }
            Event::End(TagEnd::Heading(_)) => {
                let (id, text) = heading.take().expect("a heading ends after it starts");
                let base = id.unwrap_or_else(|| slug(&text));
                let n = seen.entry(base.clone()).or_insert(0);
                anchors.push(if *n == 0 { base } else { format!("{base}-{n}") });
                *n += 1;
            }
            Event::Start(Tag::Link { dest_url, .. } | Tag::Image { dest_url, .. }) => {
                links.push((dest_url.to_string(), line_of(range.start)));
            }
            _ => {}
        }
    }
    Page { anchors, links }
}

/// `base/rel` with `.` and `..` resolved lexically; `None` when it leaves the root.
fn resolve(base: &Path, rel: &str) -> Option<PathBuf> {
    let mut out = PathBuf::new();
    for part in base.join(rel).components() {
        match part {
            Component::Normal(p) => out.push(p),
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    return None;
                }
            }
            Component::RootDir | Component::Prefix(_) => return None,
        }
    }
    Some(out)
}

fn is_external(dest: &str) -> bool {
    let lower = dest.to_ascii_lowercase();
    ["http://", "https://", "mailto:"]
        .iter()
        .any(|scheme| lower.starts_with(scheme))
}

/// `%20` and the like in a link's path.
fn percent_decoded(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%'
            && let Some(hex) = s.get(i + 1..i + 3)
            && let Ok(b) = u8::from_str_radix(hex, 16)
        {
            out.push(b);
            i += 3;
            continue;
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[test]
fn every_relative_link_and_anchor_in_the_markdown_resolves() {
    let root = root();
    let files = markdown_files();
    assert!(
        files.iter().any(|f| f == Path::new("README.md")),
        "git lists README.md"
    );
    let pages: BTreeMap<PathBuf, Page> = files
        .iter()
        .map(|f| {
            let text = std::fs::read_to_string(root.join(f))
                .unwrap_or_else(|e| panic!("{}: {e}", f.display()));
            (f.clone(), read_page(&text))
        })
        .collect();
    let mut dead = Vec::new();
    for (file, page) in &pages {
        let dir = file.parent().unwrap_or(Path::new(""));
        for (dest, line) in &page.links {
            if is_external(dest) || dest.is_empty() {
                continue;
            }
            let where_ = format!("{}:{line}: ({dest})", file.display());
            let (path, anchor) = match dest.split_once('#') {
                Some((p, a)) => (p, Some(a)),
                None => (dest.as_str(), None),
            };
            let target = if path.is_empty() {
                file.clone()
            } else {
                match resolve(dir, &percent_decoded(path)) {
                    Some(t) => t,
                    None => {
                        dead.push(format!("{where_} leaves the repository"));
                        continue;
                    }
                }
            };
            if !root.join(&target).exists() {
                dead.push(format!("{where_} names no file: {}", target.display()));
                continue;
            }
            let Some(anchor) = anchor else { continue };
            let Some(target_page) = pages.get(&target) else {
                if target.extension().is_some_and(|e| e == "md") {
                    dead.push(format!(
                        "{where_}: {} is not a listed Markdown file",
                        target.display()
                    ));
                }
                // An anchor into a file that is not Markdown (a line of source) is not ours
                // to check.
                continue;
            };
            let anchor = percent_decoded(anchor);
            if !target_page.anchors.contains(&anchor) {
                dead.push(format!(
                    "{where_}: no heading #{anchor} in {}",
                    target.display()
                ));
            }
        }
    }
    assert!(
        dead.is_empty(),
        "{} dead links:\n{}",
        dead.len(),
        dead.join("\n")
    );
}

#[test]
fn the_readme_is_at_most_300_lines() {
    let text = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = text.lines().count();
    assert!(
        lines <= 300,
        "README.md has {lines} lines: the detail belongs in the book (docs/src/)"
    );
}

/// Text no tracked file may contain, written here in pieces so that this file passes too:
/// the notes kept outside the repository and the vendor documents' file names.
const FORBIDDEN: [&str; 10] = [
    concat!("../", "shared"),
    concat!("SPEC", "-NOTES"),
    concat!("FC", "-TRAFFIC"),
    concat!("MAVLINK", "-TRAFFIC"),
    concat!("MAVLINK", "-CAMERA"),
    concat!("DESIGN", ".md"),
    concat!("000_", "cac8f"),
    concat!("001_", "8e19e"),
    concat!("003_", "d4f39"),
    concat!("004_", "97d9a"),
];

#[test]
fn no_tracked_file_points_outside_the_repository() {
    let root = root();
    let mut hits = Vec::new();
    for file in git_files(".", false) {
        let Ok(bytes) = std::fs::read(root.join(&file)) else {
            continue;
        };
        if bytes.contains(&0) {
            continue; // not text
        }
        let text = String::from_utf8_lossy(&bytes);
        for (n, line) in text.lines().enumerate() {
            for word in FORBIDDEN.iter().filter(|w| line.contains(*w)) {
                hits.push(format!("{}:{}: {word}", file.display(), n + 1));
            }
        }
    }
    assert!(
        hits.is_empty(),
        "{} references outside the repository (cite a book page under docs/src/, or the \
         vendor document by title and section):\n{}",
        hits.len(),
        hits.join("\n")
    );
}

#[test]
fn slugs_follow_github_and_mdbook() {
    assert_eq!(
        slug("Time sync (RTC_IO + 0x00030E)"),
        "time-sync-rtc_io--0x00030e"
    );
    assert_eq!(
        slug("The demo (scripts/main): the bridge working"),
        "the-demo-scriptsmain-the-bridge-working"
    );
    assert_eq!(
        slug("What ArduPilot's driver does"),
        "what-ardupilots-driver-does"
    );
    let page = read_page("# A\n\n## B\n\n## B\n\n### `code` here {#own-id}\n\n[x](#b-1)\n");
    assert_eq!(page.anchors, ["a", "b", "b-1", "own-id"]);
    assert_eq!(page.links, [("#b-1".to_string(), 9)]);
    assert_eq!(
        resolve(Path::new("docs/src/bridge"), "../figures.md"),
        Some(PathBuf::from("docs/src/figures.md"))
    );
    assert_eq!(resolve(Path::new("docs"), "../../x"), None);
}
