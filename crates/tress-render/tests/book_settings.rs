//! The book's settings tables are the code's: between `<!-- settings:TABLE -->` and
//! `<!-- /settings -->` a chapter of docs/book/src holds exactly
//! `tress_render::settings_markdown(TABLE)` (what `tress settings TABLE --markdown` prints), and
//! every table of `tress_render::SETTING_TABLES` is in the book. No GPU needed.
//!
//! After changing a setting, its default or its meaning, rewrite the tables with
//! `TRESS_BLESS=1 cargo test -p tress-render --test book_settings`.

use std::path::{Path, PathBuf};

use tress_render::{SETTING_TABLES, settings_markdown};

const OPEN: &str = "<!-- settings:";
const CLOSE: &str = "<!-- /settings -->";

/// `docs/book/src/NAME.md`, for messages.
fn chapter(path: &Path) -> String {
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    format!("docs/book/src/{name}")
}

fn book_src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/book/src")
}

/// One marked table of a chapter: its name and the byte range of the text between the markers.
struct Marked {
    table: String,
    body: std::ops::Range<usize>,
}

fn marked_tables(text: &str, file: &Path) -> Vec<Marked> {
    let mut out = Vec::new();
    let mut at = 0;
    while let Some(i) = text[at..].find(OPEN).map(|i| i + at) {
        let name_end = text[i..]
            .find("-->")
            .map(|j| i + j)
            .unwrap_or_else(|| panic!("{}: unclosed settings marker", chapter(file)));
        let table = text[i + OPEN.len()..name_end].trim().to_string();
        let body_start = name_end + "-->".len();
        let close = text[body_start..]
            .find(CLOSE)
            .map(|j| body_start + j)
            .unwrap_or_else(|| panic!("{}: settings:{table} has no {CLOSE}", chapter(file)));
        out.push(Marked {
            table,
            body: body_start..close,
        });
        at = close + CLOSE.len();
    }
    out
}

#[test]
fn the_books_settings_tables_are_the_codes() {
    let bless = std::env::var_os("TRESS_BLESS").is_some();
    let mut found = Vec::new();
    let mut stale = Vec::new();
    let mut chapters: Vec<PathBuf> = std::fs::read_dir(book_src())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    chapters.sort();
    for path in chapters {
        let text = std::fs::read_to_string(&path).unwrap();
        let mut fixed = text.clone();
        // Back to front, so the earlier ranges stay valid while rewriting.
        for m in marked_tables(&text, &path).into_iter().rev() {
            let Some(md) = settings_markdown(&m.table) else {
                panic!("{}: unknown settings table `{}`", chapter(&path), m.table);
            };
            let want = format!("\n\n{md}\n");
            if text[m.body.clone()] != want {
                stale.push(format!("{} [{}]", chapter(&path), m.table));
                fixed.replace_range(m.body.clone(), &want);
            }
            found.push(m.table);
        }
        if bless && fixed != text {
            std::fs::write(&path, fixed).unwrap();
        }
    }
    for table in SETTING_TABLES {
        assert!(
            found.iter().any(|f| f == table),
            "no chapter of docs/book/src has the [{table}] table: add \
             `<!-- settings:{table} -->` and `<!-- /settings -->` where it belongs and bless"
        );
    }
    assert!(
        bless || stale.is_empty(),
        "the book's settings tables differ from the code's in {}; rewrite them with \
         `TRESS_BLESS=1 cargo test -p tress-render --test book_settings` (or paste \
         `tress settings TABLE --markdown`)",
        stale.join(", ")
    );
}
