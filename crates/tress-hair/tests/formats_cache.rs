//! Animated caches (`write_cache_path`): every frame written as `.abc`, `.usda` and `.usdc`
//! reads back exactly at its index (`ReadOptions::frame`), a frame past the last reads the last,
//! the strands' counts and widths are kept, and a format that holds no animation is refused.

use glam::Vec3;
use tress_hair::HairAsset;
use tress_hair::formats::{ReadOptions, load_path, write_cache_path};

fn asset() -> HairAsset {
    let positions: Vec<Vec3> = (0..12)
        .map(|i| Vec3::new((i / 4) as f32, -((i % 4) as f32), 0.5))
        .collect();
    HairAsset::from_counts(positions, &[4, 4, 4])
        .unwrap()
        .with_thickness(vec![0.02; 12])
        .unwrap()
}

/// Frame `k`: the rest pose swung in x, by an amount that grows along each strand.
fn frames(a: &HairAsset) -> Vec<Vec<Vec3>> {
    (0..6)
        .map(|k| {
            a.positions()
                .iter()
                .map(|p| *p + Vec3::new(0.1 * k as f32 * -p.y, 0.0, 0.01 * k as f32))
                .collect()
        })
        .collect()
}

#[test]
fn every_frame_of_every_cache_format_reads_back() {
    let dir = std::env::temp_dir().join(format!("tress-cache-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let a = asset();
    let f = frames(&a);
    for ext in ["abc", "usda", "usdc"] {
        let path = dir.join(format!("cache.{ext}"));
        write_cache_path(&path, &a, &f, 30.0).unwrap();
        for (k, want) in f.iter().enumerate().chain([(99, &f[5])]) {
            let options = ReadOptions {
                frame: k as u32,
                ..ReadOptions::default()
            };
            let got = load_path(&path, &options).unwrap().asset;
            assert_eq!(got.positions(), &want[..], "{ext}, frame {k}");
            assert_eq!(got.vertex_counts().collect::<Vec<_>>(), vec![4, 4, 4]);
            assert_eq!(got.thickness(), a.thickness(), "{ext}");
        }
    }
    let e = write_cache_path(&dir.join("cache.hair"), &a, &f, 30.0)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("cache.hair") && e.contains("holds no animation"),
        "{e}"
    );
    let short = vec![f[0][..5].to_vec()];
    let e = write_cache_path(&dir.join("bad.abc"), &a, &short, 30.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("frame 0 has 5 points, the hair 12"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}
