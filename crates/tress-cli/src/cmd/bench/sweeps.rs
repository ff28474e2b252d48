//! The sweeps of `tress bench`: the hybrid paper's §4.1 evaluation for every technique.
//!
//! | sweep        | varies                          | techniques                   | paper     |
//! | ------------ | ------------------------------- | ---------------------------- | --------- |
//! | `distance`   | camera distance, near → far     | all five                     | Fig. 7, 8 |
//! | `strands`    | strand ratio 1 → 0              | strands, volume, hybrid      | Fig. 10   |
//! | `steps`      | raymarch steps                  | volume                       | Fig. 9    |
//! | `resolution` | volume resolution               | volume                       | Fig. 9    |
//! | `k`          | PPLL k (sorted fragments)       | strands                      | §3.3      |
//! | `patches`    | 3-pass vs 4-pass                | patches                      | Scheuermann slides |
//! | `oit`        | k, PPLL vs ShortCut             | strands (two OITs)           | beyond: TressFX 4.1 |
//! | `characters` | characters 1 → 16, spread in depth | every character as strands, `auto` | §1's claim |
//! | `simulation` | guides simulated 1k → 50k (followers: every other strand) | strands, simulated | beyond: TressFX, Frostbite |
//!
//! The `distance` sweep scores every technique's frame (its CSV `flip` column) by mean FLIP
//! against the strand rasterizer's frame at the same distance, over the pixels either frame's
//! hair covers (`agreement.rs`): the hybrid paper's Figure 1 claim, volume ≈ strands from medium
//! distance on.
//!
//! The `oit` sweep draws the strands with the paper's PPLL (its pool allowed to hold the whole
//! frame, so it loses nothing where the device allows) and with ShortCut at each k, and scores
//! every frame by mean FLIP against exact sorted compositing: the PPLL's k = 16 frame with its
//! lists read back and every pixel's fragments sorted on the CPU (`Session::sort_exactly`).
//!
//! The `characters` sweep draws the scene's first head of hair and copies of it spread in depth
//! ([`super::crowd`]): every character as strands, and each with `auto` (strands near, volume
//! far). Its summary says how many characters each mode fits in the time the strands need for
//! two: the paper's "twice the number of game characters … for the same time budget".
//!
//! The `simulation` sweep simulates the scene's hair with more and more of its strands as
//! guides (the rest followers rebuilt from them every step), the head turning, and reports the
//! simulation's time per frame, its share of the strands' frame time, and its memory
//! ([`super::simulation`]).

use anyhow::{Result, bail};
use tress_scene::Scene;

/// One point of a sweep: its x value, a label, and what changes for it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Point {
    /// The x value charted.
    pub(crate) x: f64,
    /// Dotted scene overrides of this point.
    pub(crate) sets: Vec<String>,
    /// The camera's distance as a multiple of the scene's.
    pub(crate) distance: f32,
    /// The scene's hair as this many characters spread in depth (`characters` sweep).
    pub(crate) characters: Option<u32>,
}

/// A sweep: what it varies and over which techniques.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Sweep {
    /// Its name (CSV and chart file names).
    pub(crate) name: &'static str,
    /// Chart title.
    pub(crate) title: &'static str,
    /// The x axis.
    pub(crate) x_label: &'static str,
    /// Log-scaled x axis.
    pub(crate) log_x: bool,
    /// What is measured at every point: techniques, or variants of one.
    pub(crate) series: Vec<SeriesSpec>,
    /// The points.
    pub(crate) points: Vec<Point>,
}

/// One series of a sweep: a technique, and the settings that make it a variant of it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SeriesSpec {
    /// Its name (CSV `technique` column, chart legend).
    pub(crate) name: &'static str,
    /// The technique drawn.
    pub(crate) technique: &'static str,
    /// Dotted scene overrides applied after the point's.
    pub(crate) sets: Vec<String>,
}

/// Each technique as a series of its own.
fn techniques(names: &[&'static str]) -> Vec<SeriesSpec> {
    names
        .iter()
        .map(|&name| SeriesSpec {
            name,
            technique: name,
            sets: Vec::new(),
        })
        .collect()
}

/// Every sweep's name, in the order they run.
pub(crate) const SWEEPS: [&str; 9] = [
    "distance",
    "strands",
    "steps",
    "resolution",
    "k",
    "patches",
    "oit",
    "characters",
    "simulation",
];

/// The `oit` sweep's reference: the PPLL frame (at the paper's k) whose lists are sorted
/// exactly.
pub(crate) const OIT_REFERENCE: (&str, f64) = ("ppll", 16.0);

fn point(x: f64, sets: Vec<String>) -> Point {
    Point {
        x,
        sets,
        distance: 1.0,
        characters: None,
    }
}

/// The sweep called `name`, full or quick, for `scene` (whose hair entries give the base strand
/// ratios of the strand sweep).
pub(crate) fn sweep(name: &str, quick: bool, scene: &Scene) -> Result<Sweep> {
    let pick = |full: &[f64], quick_values: &[f64]| -> Vec<f64> {
        if quick {
            quick_values.to_vec()
        } else {
            full.to_vec()
        }
    };
    Ok(match name {
        "distance" => {
            let far: f64 = 12.0;
            let n = if quick { 2 } else { 8 };
            Sweep {
                name: "distance",
                title: "Frame time by camera distance (Figures 7 and 8)",
                x_label: "camera distance (multiple of the scene's)",
                log_x: true,
                series: techniques(&tress_scene::TECHNIQUES),
                points: (0..n)
                    .map(|i| {
                        let f = far.powf(f64::from(i) / f64::from(n - 1));
                        Point {
                            x: f,
                            sets: Vec::new(),
                            distance: f as f32,
                            characters: None,
                        }
                    })
                    .collect(),
            }
        }
        "strands" => {
            if scene.hair.is_empty() {
                bail!("the strand sweep needs hair in the scene");
            }
            let ratios = pick(&[1.0, 0.75, 0.5, 0.25, 0.1, 0.05], &[1.0, 0.25]);
            Sweep {
                name: "strands",
                title: "Frame time by strand count (Figure 10)",
                x_label: "strand ratio (share of the scene's strands)",
                log_x: false,
                series: techniques(&["strands", "volume", "hybrid"]),
                points: ratios
                    .into_iter()
                    .map(|r| {
                        let sets = scene
                            .hair
                            .iter()
                            .enumerate()
                            .map(|(i, h)| {
                                format!("hair.{i}.strand_ratio={}", f64::from(h.strand_ratio) * r)
                            })
                            .collect();
                        point(r, sets)
                    })
                    .collect(),
            }
        }
        "steps" => Sweep {
            name: "steps",
            title: "Raymarcher time by raymarch steps (Figure 9)",
            x_label: "raymarch steps",
            log_x: true,
            series: techniques(&["volume"]),
            points: pick(&[32.0, 64.0, 128.0, 256.0, 512.0, 1024.0], &[64.0, 512.0])
                .into_iter()
                .map(|s| point(s, vec![format!("volume.steps={s}")]))
                .collect(),
        },
        "resolution" => Sweep {
            name: "resolution",
            title: "Raymarcher time by volume resolution (Figure 9)",
            x_label: "volume resolution (voxels per axis)",
            log_x: true,
            series: techniques(&["volume"]),
            points: pick(&[32.0, 64.0, 128.0, 256.0], &[64.0, 128.0])
                .into_iter()
                // The paper's fixed grid: not sized by the hair on screen.
                .map(|r| {
                    point(
                        r,
                        vec![
                            format!("volume.resolution={r}"),
                            "volume.screen_resolution=false".to_string(),
                        ],
                    )
                })
                .collect(),
        },
        "k" => Sweep {
            name: "k",
            title: "Rasterizer time by PPLL k",
            x_label: "k (fragments sorted per pixel)",
            log_x: true,
            series: techniques(&["strands"]),
            points: pick(&[1.0, 2.0, 4.0, 8.0, 16.0, 32.0], &[4.0, 16.0])
                .into_iter()
                .map(|k| point(k, vec![format!("strands.k={k}")]))
                .collect(),
        },
        "patches" => Sweep {
            name: "patches",
            title: "Polygon patches: 3-pass vs 4-pass (early-Z) render",
            x_label: "passes",
            log_x: false,
            series: techniques(&["patches"]),
            points: [3.0, 4.0]
                .into_iter()
                .map(|p| point(p, vec![format!("patches.scheme=\"{p}-pass\"")]))
                .collect(),
        },
        "oit" => Sweep {
            name: "oit",
            title: "Strand OIT by k: the paper's PPLL vs ShortCut",
            x_label: "k (fragments blended in order per pixel)",
            log_x: true,
            series: vec![
                SeriesSpec {
                    name: "ppll",
                    technique: "strands",
                    // A pool that may hold the whole frame (the device's bindings still bound it).
                    sets: vec![
                        "strands.oit=\"ppll\"".into(),
                        "strands.ppll_max_mib=4096".into(),
                    ],
                },
                SeriesSpec {
                    name: "shortcut",
                    technique: "strands",
                    sets: vec!["strands.oit=\"shortcut\"".into()],
                },
            ],
            points: pick(&[1.0, 2.0, 4.0, 8.0, 16.0], &[8.0, 16.0])
                .into_iter()
                .map(|k| {
                    point(
                        k,
                        vec![format!("strands.k={k}"), format!("strands.shortcut_k={k}")],
                    )
                })
                .collect(),
        },
        "characters" => {
            if scene.hair.is_empty() {
                bail!("the characters sweep needs hair in the scene");
            }
            Sweep {
                name: "characters",
                title: "Frame time by characters on screen (the hybrid paper's §1 claim)",
                x_label: "characters (the scene's hair, spread in depth)",
                log_x: true,
                series: techniques(&["strands", "auto"]),
                points: pick(&[1.0, 2.0, 4.0, 8.0, 16.0], &[1.0, 2.0])
                    .into_iter()
                    .map(|n| Point {
                        characters: Some(n as u32),
                        ..point(n, Vec::new())
                    })
                    .collect(),
            }
        }
        "simulation" => {
            if scene.hair.is_empty() {
                bail!("the simulation sweep needs hair in the scene");
            }
            Sweep {
                name: "simulation",
                title: "Simulation time per frame by guides simulated",
                x_label: "guides simulated (every other strand follows them)",
                log_x: true,
                series: techniques(&["strands"]),
                points: pick(&[1000.0, 5000.0, 10000.0, 50000.0], &[256.0, 1024.0])
                    .into_iter()
                    .map(|g| point(g, Vec::new()))
                    .collect(),
            }
        }
        other => bail!("unknown sweep `{other}` (available: {})", SWEEPS.join(", ")),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn demo() -> Scene {
        tress_render::session::scene_from_inputs(&[]).unwrap().0
    }

    #[test]
    fn every_named_sweep_exists_and_quick_is_smaller() {
        let scene = demo();
        for name in SWEEPS {
            let full = sweep(name, false, &scene).unwrap();
            let quick = sweep(name, true, &scene).unwrap();
            assert_eq!(full.name, name);
            assert!(quick.points.len() <= full.points.len(), "{name}");
            assert!(quick.points.len() >= 2, "{name}: a sweep needs two points");
        }
        assert!(sweep("nope", false, &scene).is_err());
    }

    #[test]
    fn distance_goes_from_the_scene_to_twelve_times_it() {
        let s = sweep("distance", false, &demo()).unwrap();
        assert_eq!(s.points.first().unwrap().distance, 1.0);
        assert!((s.points.last().unwrap().distance - 12.0).abs() < 1e-4);
        assert!(s.points.windows(2).all(|w| w[1].distance > w[0].distance));
    }

    #[test]
    fn strand_ratios_scale_the_scene_s_own_ratio() {
        let scene = demo();
        let base = scene.hair[0].strand_ratio;
        let s = sweep("strands", false, &scene).unwrap();
        assert_eq!(
            s.points[0].sets,
            vec![format!("hair.0.strand_ratio={}", f64::from(base))]
        );
        // Every override is one the scene accepts.
        for p in &s.points {
            let mut sc = scene.clone();
            sc.apply_overrides(&p.sets).unwrap();
            assert!((f64::from(sc.hair[0].strand_ratio) - f64::from(base) * p.x).abs() < 1e-6);
        }
    }

    #[test]
    fn every_override_parses_against_the_demo_scene() {
        let scene = demo();
        for name in SWEEPS {
            for p in sweep(name, false, &scene).unwrap().points {
                let mut sc = scene.clone();
                sc.apply_overrides(&p.sets)
                    .unwrap_or_else(|e| panic!("{name}: {:?}: {e}", p.sets));
            }
        }
    }
}
