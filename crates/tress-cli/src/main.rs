//! The `tress` command-line tool: inspect, generate, convert and render hair assets.
//!
//! It is the front end of the other tress crates: it reads hair files and scenes
//! (`tress-hair`, `tress-scene`), renders them with any technique on the GPU (`tress-render`),
//! ray-traces their reference images (`tress-trace`), simulates them (`tress-sim`) and opens the
//! viewer (`tress-viewer`). `tress --help` lists the commands, `tress COMMAND --help` their
//! options. For example, in a scratch folder:
//!
//! ```sh
//! tress generate curly -o curly.hair --strands 2000 --vertices 24
//! tress info curly.hair
//! tress convert --follow 1 curly.hair curly.usda
//! tress reference curly.usda -o reference.png --width 160 --height 120 --spp 4
//! tress render curly.usda -o strands.png --technique strands --width 160 --height 120
//! ```
//!
//! A binary's doc comments are not doc tests: `tests/cli_front_page.rs` runs these commands
//! (the last one needs a GPU adapter).
//!
//! Every error is printed as one line on stderr (`tress: <file>: <problem>`) and the process
//! exits with status 2.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod cmd;
mod progress;

/// tress — a hair rendering toolkit.
#[derive(Parser, Debug)]
#[command(name = "tress", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Print strand, vertex and segment counts, bounds and attributes of hair files (merged).
    Info(cmd::info::Args),
    /// Generate a procedural hair style and write it as `.hair` or `.tfx` (by extension).
    Generate(cmd::generate::Args),
    /// Convert between hair formats, merging inputs and optionally adding follow hairs.
    Convert(cmd::convert::Args),
    /// Ray-trace the reference image of a scene, hair files or the demo (CPU, many samples per
    /// pixel): color, ambient occlusion or shadow visibility, to PNG or EXR.
    Reference(cmd::reference::Args),
    /// Compare two images: mean FLIP, RMSE and SSIM, and a FLIP heat map.
    CompareImages(cmd::compare_images::Args),
    /// Hair cards from strands: neighbouring strands grouped into ribbons, written as OBJ.
    Cards(cmd::cards::Args),
    /// Bake per-vertex ambient occlusion into a patch OBJ (or the generated patch head).
    BakeAo(cmd::bake_ao::Args),
    /// Render a scene (`.toml`), hair files, or the built-in demo to PNG or EXR.
    Render(cmd::render::Args),
    /// Simulate the hair (GPU, the head moving) and write the frames as an animated cache
    /// (`.abc`, `.usda`, `.usdc`) that DCC tools and `tress render --frame K` play.
    Simulate(cmd::simulate::Args),
    /// The split image of the hybrid paper's Figure 1: strands left, volume right, the LOD
    /// transition between; mean FLIP and timings of both, optionally over a distance sweep.
    Compare(cmd::compare::Args),
    /// Bake the SATF technique's HRIR database (Xu et al. 2006), or check one with --check.
    SatfBake(cmd::satf_bake::Args),
    /// Open the interactive viewer on a scene, hair files or the demo: orbit, switch
    /// techniques, change settings, see per-pass timings and GPU memory.
    View(cmd::view::Args),
    /// Benchmark every technique over the hybrid paper's sweeps (CSV, charts, summary.md), or
    /// with --quality measure image quality against the CPU reference.
    Bench(cmd::bench::Args),
    /// Print every key of a scene's technique tables with its default and meaning (commented
    /// TOML, or with --markdown the book's tables).
    Settings(cmd::settings::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Info(a) => cmd::info::run(a),
        Command::Generate(a) => cmd::generate::run(a),
        Command::Convert(a) => cmd::convert::run(a),
        Command::Reference(a) => cmd::reference::run(a),
        Command::CompareImages(a) => cmd::compare_images::run(a),
        Command::Cards(a) => cmd::cards::run(a),
        Command::BakeAo(a) => cmd::bake_ao::run(a),
        Command::Render(a) => cmd::render::run(a),
        Command::Simulate(a) => cmd::simulate::run(a),
        Command::Compare(a) => cmd::compare::run(a),
        Command::SatfBake(a) => cmd::satf_bake::run(a),
        Command::View(a) => cmd::view::run(a),
        Command::Bench(a) => cmd::bench::run(a),
        Command::Settings(a) => cmd::settings::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tress: {}", one_line(&e));
            ExitCode::from(2)
        }
    }
}

/// The error and its causes on one line, without repeating a cause already in the message.
fn one_line(e: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if line.contains(&text) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&text);
    }
    line.replace('\n', " ")
}
