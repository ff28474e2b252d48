//! Merging several assets into one (a TressFX character is often several `.tfx` files).

use glam::{Vec2, Vec3};

use crate::{HairAsset, HairError};

impl HairAsset {
    /// Concatenate assets, strand order preserved. An optional array is kept if any input has it;
    /// inputs without it get the default (thickness: the mean thickness of those that have it,
    /// transparency 0, color the mean color of those that have it, UV 0).
    pub fn merge(assets: &[HairAsset]) -> Result<HairAsset, HairError> {
        let (first, rest) = assets
            .split_first()
            .ok_or_else(|| HairError::Invalid("nothing to merge".into()))?;
        if rest.is_empty() {
            return Ok(first.clone());
        }
        let vertices: usize = assets.iter().map(HairAsset::vertex_count).sum();
        let mut positions = Vec::with_capacity(vertices);
        let mut counts = Vec::with_capacity(assets.iter().map(HairAsset::strand_count).sum());
        for a in assets {
            positions.extend_from_slice(a.positions());
            counts.extend(a.vertex_counts());
        }
        let mut out = HairAsset::from_counts(positions, &counts)?;
        if assets.iter().any(|a| a.thickness().is_some()) {
            let fill = mean(assets.iter().filter_map(|a| a.thickness()), 0.0);
            out = out.with_thickness(gather(
                assets,
                |a| a.thickness(),
                fill,
                HairAsset::vertex_count,
            ))?;
        }
        if assets.iter().any(|a| a.transparency().is_some()) {
            out = out.with_transparency(gather(
                assets,
                |a| a.transparency(),
                0.0,
                HairAsset::vertex_count,
            ))?;
        }
        if assets.iter().any(|a| a.color().is_some()) {
            let fill = mean(assets.iter().filter_map(|a| a.color()), Vec3::ZERO);
            out = out.with_color(gather(assets, |a| a.color(), fill, HairAsset::vertex_count))?;
        }
        if assets.iter().any(|a| a.strand_uv().is_some()) {
            out = out.with_strand_uv(gather(
                assets,
                |a| a.strand_uv(),
                Vec2::ZERO,
                HairAsset::strand_count,
            ))?;
        }
        Ok(out)
    }

    /// [`merge`](Self::merge) taking the assets: a single asset comes back as it is, not copied
    /// (a reader that found one curves prim or object need not duplicate its arrays).
    pub fn merge_owned(mut assets: Vec<HairAsset>) -> Result<HairAsset, HairError> {
        if assets.len() == 1
            && let Some(only) = assets.pop()
        {
            return Ok(only);
        }
        Self::merge(&assets)
    }
}

fn gather<T: Copy>(
    assets: &[HairAsset],
    get: impl Fn(&HairAsset) -> Option<&[T]>,
    fill: T,
    len: impl Fn(&HairAsset) -> usize,
) -> Vec<T> {
    let mut out = Vec::new();
    for a in assets {
        match get(a) {
            Some(v) => out.extend_from_slice(v),
            None => out.extend(std::iter::repeat_n(fill, len(a))),
        }
    }
    out
}

fn mean<'a, T>(arrays: impl Iterator<Item = &'a [T]>, zero: T) -> T
where
    T: Copy + std::ops::Add<Output = T> + std::ops::Div<f32, Output = T> + 'a,
{
    let (sum, n) = arrays
        .flatten()
        .fold((zero, 0usize), |(s, n), &x| (s + x, n + 1));
    if n == 0 { zero } else { sum / n as f32 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merge_concatenates_and_fills() {
        let a = HairAsset::from_counts(vec![Vec3::ZERO, Vec3::Y], &[2])
            .unwrap()
            .with_thickness(vec![2.0, 4.0])
            .unwrap();
        let b = HairAsset::from_counts(vec![Vec3::X, Vec3::ONE, Vec3::Z], &[3]).unwrap();
        let m = HairAsset::merge(&[a, b]).unwrap();
        assert_eq!(m.strand_count(), 2);
        assert_eq!(m.strand(1), &[Vec3::X, Vec3::ONE, Vec3::Z]);
        assert_eq!(m.thickness().unwrap(), &[2.0, 4.0, 3.0, 3.0, 3.0]);
        assert!(m.color().is_none());
        assert!(HairAsset::merge(&[]).is_err());
        assert!(HairAsset::merge_owned(Vec::new()).is_err());
        let only = m.clone();
        assert_eq!(HairAsset::merge_owned(vec![only]).unwrap(), m);
        assert_eq!(
            HairAsset::merge_owned(vec![m.clone(), m.clone()]).unwrap(),
            HairAsset::merge(&[m.clone(), m]).unwrap()
        );
    }
}
