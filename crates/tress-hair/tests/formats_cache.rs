//! Animated caches (`write_cache_path`): every frame written as `.abc`, `.usda` and `.usdc`
//! reads back exactly at its index (`ReadOptions::frame`), a frame past the last reads the last,
//! the strands' counts and widths are kept, the read reports the frame count (`Details::frames`,
//! 1 for a still file) and a format that holds no animation is refused.

use glam::Vec3;
use tress_hair::HairAsset;
use tress_hair::formats::{ReadOptions, load_path, write_cache_path, write_path};

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

#[test]
fn a_cache_reports_its_frame_count_and_a_still_file_one() {
    let dir = std::env::temp_dir().join(format!("tress-cache-frames-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let a = asset();
    let f = frames(&a);
    for ext in ["abc", "usda", "usdc"] {
        let path = dir.join(format!("cache.{ext}"));
        write_cache_path(&path, &a, &f[..3], 30.0).unwrap();
        // Any frame's read reports the count, the frame past the last too.
        for frame in [0, 2, 7] {
            let options = ReadOptions {
                frame,
                ..ReadOptions::default()
            };
            let d = load_path(&path, &options).unwrap().details;
            assert_eq!(d.frames, 3, "{ext}, read at frame {frame}");
        }
        // A one-frame cache and a still file are one frame.
        write_cache_path(&path, &a, &f[..1], 30.0).unwrap();
        let one = load_path(&path, &ReadOptions::default()).unwrap().details;
        assert_eq!(one.frames, 1, "{ext}: a cache of one frame");
        assert_eq!(one.fps, None, "{ext}: one frame has no rate");
        let still = dir.join(format!("still.{ext}"));
        write_path(&still, &a).unwrap();
        let d = load_path(&still, &ReadOptions::default()).unwrap().details;
        assert_eq!((d.frames, d.fps), (1, None), "{ext}: a still file");
    }
    // The file says its rate: Alembic P's time sampling, USD timeCodesPerSecond over the
    // samples' spacing.
    for ext in ["abc", "usda", "usdc"] {
        let path = dir.join(format!("rate.{ext}"));
        write_cache_path(&path, &a, &f, 30.0).unwrap();
        let d = load_path(&path, &ReadOptions::default()).unwrap().details;
        assert_eq!(d.frames, 6, "{ext}");
        let fps = d.fps.unwrap_or_else(|| panic!("{ext}: no rate"));
        assert!((fps - 30.0).abs() < 1e-9, "{ext}: {fps}");
    }
    let hair = dir.join("still.hair");
    write_path(&hair, &a).unwrap();
    assert_eq!(
        load_path(&hair, &ReadOptions::default())
            .unwrap()
            .details
            .frames,
        1
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_large_usdc_cache_of_equal_strands_reads_back() {
    // 20,000 strands of 4 vertices: their vertex counts compress far below the integer coding's
    // worst-case size (openusd refused such a block as larger than LZ4 can expand; every
    // simulation cache of a real groom hit it).
    let (strands, vertices) = (20_000u32, 4u32);
    let positions: Vec<Vec3> = (0..strands * vertices)
        .map(|i| Vec3::new((i / vertices) as f32 * 0.01, -((i % vertices) as f32), 0.0))
        .collect();
    let a = HairAsset::from_counts(positions, &vec![vertices; strands as usize]).unwrap();
    let moved: Vec<Vec3> = a.positions().iter().map(|p| *p + Vec3::X).collect();
    let frames = vec![a.positions().to_vec(), moved.clone()];
    let dir = std::env::temp_dir().join(format!("tress-cache-large-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for ext in ["usdc", "abc"] {
        let path = dir.join(format!("large.{ext}"));
        write_cache_path(&path, &a, &frames, 24.0).unwrap();
        let options = ReadOptions {
            frame: 1,
            ..ReadOptions::default()
        };
        let got = load_path(&path, &options).unwrap().asset;
        assert_eq!(got.strand_count(), strands as usize, "{ext}");
        assert_eq!(got.positions(), &moved[..], "{ext}");
    }
    // A still file of the same hair too.
    let still = dir.join("still.usdc");
    tress_hair::formats::write_path(&still, &a).unwrap();
    assert_eq!(
        tress_hair::formats::read_path(&still).unwrap().positions(),
        a.positions()
    );
    std::fs::remove_dir_all(&dir).ok();
}
