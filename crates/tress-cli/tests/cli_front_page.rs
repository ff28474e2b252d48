//! The example on the `tress` binary's front page (`src/main.rs`) runs: every command of its
//! `sh` block, in order, in one scratch folder. A binary's doc comments are not doc tests, so
//! this test stands in for one. `tress render` needs a GPU adapter (see `common`).

mod common;

use std::process::Command;

/// The lines of the first ```` ```sh ```` block in the `//!` comments at the top of `main.rs`.
fn front_page_commands() -> Vec<&'static str> {
    include_str!("../src/main.rs")
        .lines()
        .map_while(|l| l.strip_prefix("//!"))
        .map(str::trim)
        .skip_while(|l| *l != "```sh")
        .skip(1)
        .take_while(|l| *l != "```")
        .collect()
}

#[test]
fn the_front_page_commands_run() {
    let commands = front_page_commands();
    assert!(
        commands.len() >= 3,
        "no sh block on the front page: {commands:?}"
    );
    let dir = common::tmp("front-page");
    std::fs::create_dir_all(&dir).unwrap();
    for line in commands {
        let words: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(words[0], "tress", "{line}");
        let gpu = words[1] == "render";
        if gpu && common::skip_gpu() {
            continue;
        }
        let out = Command::new(env!("CARGO_BIN_EXE_tress"))
            .args(&words[1..])
            .current_dir(&dir)
            .output()
            .expect("run tress");
        if gpu {
            common::assert_gpu_success(&out);
        } else {
            assert!(
                out.status.success(),
                "{line}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        // Every file the command names as its output (`-o FILE`, or convert's last path) exists.
        let written = match words[1] {
            "convert" => words.last(),
            _ => words.iter().position(|w| *w == "-o").map(|i| &words[i + 1]),
        };
        if let Some(file) = written {
            assert!(dir.join(file).is_file(), "{line}: {file} was not written");
        }
    }
}
