//! The `tress` command-line tool.

fn main() {}
