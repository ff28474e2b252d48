//! Step 7 of the fit (see the parent module's docs): fitting the groups, then splitting the
//! groups whose shell strays from their strands, worst first, within a budget of clusters.

use glam::Vec3;
use rayon::prelude::*;

use super::{FitSettings, MIN_SPLIT_STRANDS, fit_cluster, group_strands, stray};
use crate::error::SatfError;
use crate::hierarchy::MacroCluster;

/// Each round cuts the groups whose stray score is at least this share of the worst's.
const WORST_SHARE: f32 = 0.9;

/// A fitted group: its strands (indices into the resampled strands), its cluster and how far
/// its shell strays over the threshold ([`stray::stray_score`]; 0 when it is not to be split).
struct Fitted {
    strands: Vec<u32>,
    cluster: MacroCluster,
    stray: f32,
}

/// The clusters of `groups` (indices into `kept`) and the number of strands that could not be
/// fitted. In rounds, the groups whose shell strays by more than [`FitSettings::stray_split`]
/// of its half-axis or than 2% of the hair's diagonal are cut in two, as long as the clusters
/// stay within [`FitSettings::max_clusters`] (the groups of step 2 are all kept, even above it;
/// a half without a trajectory, fitted strand by strand, may also go past it). Each round cuts
/// only the groups that stray within a tenth as far as the worst, worst first, so the budget
/// goes where the shell strays most (a fan of strands from a ponytail's tie, cut down to a few
/// strands) rather than to every group straying a little in the first rounds.
pub(super) fn fit_groups(
    kept: &[Vec<Vec3>],
    groups: Vec<Vec<u32>>,
    settings: &FitSettings,
) -> Result<(Vec<MacroCluster>, usize), SatfError> {
    let (mut fitted, mut lost) = fit_all(kept, groups, settings)?;
    loop {
        let mut room = (settings.max_clusters as usize).saturating_sub(fitted.len());
        let top = fitted.iter().map(|f| f.stray).fold(0.0f32, f32::max);
        let mut worst: Vec<usize> = (0..fitted.len())
            .filter(|&i| fitted[i].stray > 1.0 && fitted[i].stray >= WORST_SHARE * top)
            .collect();
        if worst.is_empty() || room == 0 {
            break;
        }
        worst.sort_by(|&a, &b| fitted[b].stray.total_cmp(&fitted[a].stray));
        let mut halves = Vec::new();
        let mut cut = vec![false; fitted.len()];
        for &i in &worst {
            if room == 0 {
                break;
            }
            // Usually two halves; more where a half is still too large for the cut.
            let h = halve(kept, &fitted[i].strands, settings);
            if h.len() >= 2 && h.len() - 1 <= room {
                room -= h.len() - 1;
                halves.extend(h);
                cut[i] = true;
            } else {
                // No cut separates these strands, or its halves do not fit in the budget
                // (which only shrinks): keep the group as it is.
                fitted[i].stray = 0.0;
            }
        }
        let mut index = 0;
        fitted.retain(|_| {
            index += 1;
            !cut[index - 1]
        });
        let (more, l) = fit_all(kept, halves, settings)?;
        fitted.extend(more);
        lost += l;
    }
    Ok((fitted.into_iter().map(|f| f.cluster).collect(), lost))
}

/// Fit each group as one cluster, or strand by strand when the group has no trajectory.
fn fit_all(
    kept: &[Vec<Vec3>],
    groups: Vec<Vec<u32>>,
    settings: &FitSettings,
) -> Result<(Vec<Fitted>, usize), SatfError> {
    let floor = settings.min_radius.unwrap_or(0.0);
    let parts = groups
        .into_par_iter()
        .map(|g| -> Result<(Vec<Fitted>, usize), SatfError> {
            let strands: Vec<&[Vec3]> = g.iter().map(|&i| kept[i as usize].as_slice()).collect();
            match fit_cluster(&strands, settings) {
                Ok(cluster) => {
                    // Groups too small for the relative test may still be split where their
                    // shell lies far from every strand.
                    let relative = strands.len() >= 2 * MIN_SPLIT_STRANDS;
                    let stray = if settings.stray_split > 0.0 {
                        stray::stray_score(
                            &cluster,
                            &strands,
                            floor,
                            settings.stray_split,
                            relative,
                        )
                    } else {
                        0.0
                    };
                    Ok((
                        vec![Fitted {
                            strands: g,
                            cluster,
                            stray,
                        }],
                        0,
                    ))
                }
                Err(SatfError::Degenerate(_)) => {
                    let mut out = Vec::new();
                    let mut lost = 0;
                    for (&i, s) in g.iter().zip(&strands) {
                        match fit_cluster(std::slice::from_ref(s), settings) {
                            Ok(cluster) => out.push(Fitted {
                                strands: vec![i],
                                cluster,
                                stray: 0.0,
                            }),
                            Err(SatfError::Degenerate(_)) => lost += 1,
                            Err(e) => return Err(e),
                        }
                    }
                    Ok((out, lost))
                }
                Err(e) => Err(e),
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut out = Vec::new();
    let mut lost = 0;
    for (f, l) in parts {
        out.extend(f);
        lost += l;
    }
    Ok((out, lost))
}

/// `strands` (indices into `kept`) cut in two at their widest gap, as in step 2.
fn halve(kept: &[Vec<Vec3>], strands: &[u32], settings: &FitSettings) -> Vec<Vec<u32>> {
    let owned: Vec<Vec<Vec3>> = strands.iter().map(|&i| kept[i as usize].clone()).collect();
    let half = FitSettings {
        strands_per_cluster: strands.len().div_ceil(2) as u32,
        ..*settings
    };
    group_strands(&owned, &half)
        .into_iter()
        .map(|h| h.into_iter().map(|j| strands[j as usize]).collect())
        .collect()
}
