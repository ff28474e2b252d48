//! `tress settings [TABLE] [--markdown]`: the scene reference, from the code.

use anyhow::{Result, bail};
use tress_render::{SETTING_TABLES, settings_markdown, settings_toml};

/// Arguments of `tress settings`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// The table: strands, volume, hybrid, patches or satf (all of them when absent).
    table: Option<String>,
    /// Print Markdown tables (key, default, meaning: the book's) instead of commented TOML.
    #[arg(long)]
    markdown: bool,
}

pub(crate) fn run(args: Args) -> Result<()> {
    let tables: Vec<&str> = match args.table.as_deref() {
        None => SETTING_TABLES.to_vec(),
        Some(t) if SETTING_TABLES.contains(&t) => vec![t],
        Some(t) => bail!(
            "unknown settings table `{t}` (expected {})",
            SETTING_TABLES.join(", ")
        ),
    };
    let blocks: Vec<String> = tables
        .iter()
        .filter_map(|t| {
            if args.markdown {
                settings_markdown(t)
            } else {
                settings_toml(t)
            }
        })
        .collect();
    print!("{}", blocks.join("\n"));
    Ok(())
}
