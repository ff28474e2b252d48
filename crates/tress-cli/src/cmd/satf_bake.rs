//! `tress satf-bake -o DB [--samples N] [--angles M] [--pixels P] [--seed S] [--json]` and
//! `tress satf-bake --check DB`: bake (or check) the HRIR database of the SATF technique (Xu et
//! al. 2006, §4–5) with `tress_satf::bake` on every core (rayon), with a progress bar on a
//! terminal.
//!
//! The file is written to `DB.partial` and renamed when complete, so an interrupted bake never
//! leaves a truncated database behind. `tress render --technique satf` uses the same functions
//! to bake its database on first use ([`database_for_render`]): into the file `satf.database`
//! names, or, when the scene names none, into the cache folder ([`cache_dir`]) under a name that
//! hashes every bake setting.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use tress_satf::database::{BakeSettings, Database, bake};

/// Arguments of `tress satf-bake`. Unset parameters take `BakeSettings::default()`.
#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// Output database file (`.satfdb`).
    #[arg(
        short,
        long,
        required_unless_present = "check",
        conflicts_with = "check"
    )]
    output: Option<PathBuf>,
    /// Check an existing database instead of baking: reads and validates it (magic, version,
    /// settings, size, checksum) and prints what it holds.
    #[arg(long, value_name = "DB")]
    check: Option<PathBuf>,
    /// Random generalized sectors (default 2048).
    #[arg(long)]
    samples: Option<u32>,
    /// View and light azimuth bins over the full circle (default 16 each).
    #[arg(long)]
    angles: Option<u32>,
    /// View azimuth bins (overrides --angles).
    #[arg(long)]
    view_angles: Option<u32>,
    /// Light azimuth bins (overrides --angles).
    #[arg(long)]
    light_angles: Option<u32>,
    /// Samples (pixels) of each HRIR across a sector (default 16).
    #[arg(long)]
    pixels: Option<u32>,
    /// Most strands in a random sector (default 48).
    #[arg(long)]
    max_strands: Option<u32>,
    /// Random seed (same seed and settings, same database).
    #[arg(long)]
    seed: Option<u64>,
    /// Print exactly one JSON object describing the database.
    #[arg(long)]
    json: bool,
}

/// What a bake or a check reports.
#[derive(Serialize, Debug)]
pub(crate) struct BakeReport {
    /// The database file.
    pub(crate) path: String,
    /// Samples (generalized sectors).
    pub(crate) samples: usize,
    /// View azimuth bins.
    pub(crate) view_angles: u32,
    /// Light azimuth bins.
    pub(crate) light_angles: u32,
    /// Pixels per HRIR.
    pub(crate) pixels: u32,
    /// File size in bytes.
    pub(crate) bytes: u64,
    /// Bake time in seconds (`None` for a check).
    pub(crate) seconds: Option<f64>,
    /// Rayon worker threads of the bake.
    pub(crate) threads: usize,
}

impl BakeReport {
    fn new(path: &Path, db: &Database, bytes: u64, seconds: Option<f64>) -> Self {
        let h = &db.settings().hrir;
        BakeReport {
            path: path.display().to_string(),
            samples: db.sample_count(),
            view_angles: h.view_angles,
            light_angles: h.light_angles,
            pixels: h.pixels,
            bytes,
            seconds,
            threads: rayon_threads(),
        }
    }

    fn line(&self) -> String {
        let mib = self.bytes as f64 / f64::from(1u32 << 20);
        let what = format!(
            "{} samples, {}x{} view/light angles, {} pixels, {} bytes ({mib:.2} MiB)",
            self.samples, self.view_angles, self.light_angles, self.pixels, self.bytes
        );
        match self.seconds {
            Some(s) => format!(
                "wrote {}: {what}, baked in {s:.2} s on {} threads",
                self.path, self.threads
            ),
            None => format!("{}: valid HRIR database, {what}", self.path),
        }
    }
}

fn rayon_threads() -> usize {
    rayon::current_num_threads()
}

/// The bake settings the arguments describe, validated.
fn settings_from(args: &Args) -> Result<BakeSettings> {
    let mut s = BakeSettings::default();
    if let Some(n) = args.samples {
        s.samples = n;
    }
    if let Some(m) = args.angles {
        s.hrir.view_angles = m;
        s.hrir.light_angles = m;
    }
    if let Some(m) = args.view_angles {
        s.hrir.view_angles = m;
    }
    if let Some(m) = args.light_angles {
        s.hrir.light_angles = m;
    }
    if let Some(p) = args.pixels {
        s.hrir.pixels = p;
    }
    if let Some(n) = args.max_strands {
        s.max_strands = n;
    }
    if let Some(seed) = args.seed {
        s.seed = seed;
    }
    s.validate()?;
    Ok(s)
}

pub(crate) fn run(args: Args) -> Result<()> {
    let report = match (&args.check, &args.output) {
        (Some(path), _) => check(path)?,
        (None, Some(path)) => {
            let settings = settings_from(&args)?;
            bake_to(path, &settings)?
        }
        (None, None) => bail!("give -o DB to bake or --check DB to check a database"),
    };
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
    } else {
        println!("{}", report.line());
    }
    Ok(())
}

/// Read and validate a database file.
fn check(path: &Path) -> Result<BakeReport> {
    let db = Database::load(path)?;
    let bytes = std::fs::metadata(path)
        .with_context(|| path.display().to_string())?
        .len();
    Ok(BakeReport::new(path, &db, bytes, None))
}

/// Bake a database with `settings` and write it to `path` (through `path.partial`), with a
/// progress bar on a terminal.
pub(crate) fn bake_to(path: &Path, settings: &BakeSettings) -> Result<BakeReport> {
    settings.validate()?;
    let total = u64::from(settings.samples);
    let pb = ProgressBar::new(total);
    pb.set_style(
        ProgressStyle::with_template(
            "baking HRIR database {bar:32} {pos}/{len} sectors ({elapsed}, {eta} left)",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let start = Instant::now();
    let db = bake(settings, |_, _| pb.inc(1));
    pb.finish_and_clear();
    let db = db?;
    let seconds = start.elapsed().as_secs_f64();
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| dir.display().to_string())?;
    }
    let mut partial = path.as_os_str().to_owned();
    partial.push(".partial");
    let partial = PathBuf::from(partial);
    db.save(&partial)?;
    std::fs::rename(&partial, path)
        .with_context(|| format!("{}: moving the finished database here", path.display()))?;
    let bytes = std::fs::metadata(path)
        .with_context(|| path.display().to_string())?
        .len();
    Ok(BakeReport::new(path, &db, bytes, Some(seconds)))
}

/// Where `tress render --technique satf` caches databases baked on first use:
/// `$TRESS_CACHE_DIR`, else `$XDG_CACHE_HOME/tress`, else `$HOME/.cache/tress`, else the system
/// temporary folder's `tress-cache`.
pub(crate) fn cache_dir() -> PathBuf {
    let env = |k: &str| {
        std::env::var_os(k)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    env("TRESS_CACHE_DIR")
        .or_else(|| env("XDG_CACHE_HOME").map(|d| d.join("tress")))
        .or_else(|| env("HOME").map(|d| d.join(".cache").join("tress")))
        .unwrap_or_else(|| std::env::temp_dir().join("tress-cache"))
}

/// The cache file of a database baked with `settings`: named by a hash of the file format's
/// version and every setting, so databases of different settings or formats never collide.
pub(crate) fn cache_path(settings: &BakeSettings) -> PathBuf {
    let mut text = format!("version={};", tress_satf::format::FORMAT_VERSION);
    for (k, v) in settings.fields() {
        text.push_str(&format!("{k}={v};"));
    }
    let hash = tress_satf::format::fnv1a64(text.as_bytes());
    cache_dir().join(format!("satf-{hash:016x}.satfdb"))
}

/// The database of a render: the file at `path` (or the cache file of `settings` when `None`),
/// baked there first with `settings` when it does not exist, saying so on stderr. With
/// `require_match` an existing file must have been baked with `settings`; a corrupt or
/// mismatched file is an error naming it. Returns the database and its path.
pub(crate) fn database_for_render(
    path: Option<&Path>,
    settings: &BakeSettings,
    require_match: bool,
) -> Result<(Database, PathBuf)> {
    let path = path.map_or_else(|| cache_path(settings), Path::to_path_buf);
    if !path.exists() {
        eprintln!(
            "tress: SATF database {} not found: baking it ({} samples, takes a while once)",
            path.display(),
            settings.samples
        );
        let report = bake_to(&path, settings)?;
        eprintln!("tress: {}", report.line());
    }
    let db = if require_match {
        Database::load_expecting(&path, settings)?
    } else {
        Database::load(&path)?
    };
    Ok((db, path))
}
