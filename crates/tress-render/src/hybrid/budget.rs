//! `auto` under a frame budget (`hybrid.budget_ms`): what each character costs drawn each way,
//! measured on this device, and the best quality that fits the budget, nearest characters first.
//!
//! **Cost model.** The rasterizer's cost follows the strand segments it draws, the voxelizer's
//! the segments it voxelizes, the raymarcher's the pixels it covers (the hybrid paper's economic
//! claim, §1). [`CostModel`] keeps one rate for each (milliseconds a segment, a segment, a
//! pixel), measured from the frames' own GPU timestamps ([`CostModel::observe`]: the frame's
//! rasterizer passes over the segments rasterized, each character's voxelization and raymarch
//! over its segments and covered pixels), smoothed over frames (an exponential mean, a quarter
//! weight to each new frame). Until a frame has measured a rate, it is a prior of the right
//! order for a CPU Vulkan (lavapipe), so the first frames are planned too. A hybrid character
//! pays for both renderers.
//!
//! **Choice** ([`fit_budget`]). Each character starts from what `auto` picks by its size on
//! screen (its blend factor); going from the nearest to the farthest, it keeps that if it fits
//! beside the cheapest the farther characters can be drawn, else it takes the best of strands
//! (factor 0) and volume (factor 1) that fits, else the cheapest. A generous budget changes
//! nothing; a tight one lowers the far characters' quality first and exceeds the budget only
//! when even the cheapest choice of every character does.

/// The blend factor of a character drawn as strands alone.
pub const STRANDS: f32 = 0.0;
/// The blend factor of a character drawn as the volume alone.
pub const VOLUME: f32 = 1.0;

/// What a character costs, milliseconds, drawn by each renderer alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CharacterCost {
    /// Drawn as strands (`lod = 0`).
    pub strands: f64,
    /// Drawn as the volume (`lod = 1`): its voxelization and raymarch.
    pub volume: f64,
}

impl CharacterCost {
    /// The cost at blend factor `lod`: strands at 0, the volume at 1, both between.
    pub fn at(&self, lod: f32) -> f64 {
        match lod {
            l if l <= STRANDS => self.strands,
            l if l >= VOLUME => self.volume,
            _ => self.strands + self.volume,
        }
    }

    /// The cheaper renderer's cost.
    pub fn cheapest(&self) -> f64 {
        self.strands.min(self.volume)
    }
}

/// Milliseconds per unit of what each renderer's cost follows, measured and smoothed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CostModel {
    /// Rasterizer (shadow maps, OIT build and resolve) per strand segment drawn.
    pub raster_ms_per_segment: f64,
    /// Voxelization per strand segment voxelized.
    pub voxelize_ms_per_segment: f64,
    /// Raymarch per pixel the character's bounding square covers.
    pub raymarch_ms_per_pixel: f64,
    /// Frames that measured each rate (raster, voxelize, raymarch): 0 while it is the prior.
    pub measured: [u32; 3],
}

impl Default for CostModel {
    /// The prior: lavapipe's order of magnitude on the 136k-strand ponytail at 1280×720 (about
    /// 60 s of rasterizer for 2.2M segments, 8 s of voxelization, 40 s of raymarch over 400k
    /// pixels).
    fn default() -> Self {
        CostModel {
            raster_ms_per_segment: 60_000.0 / 2.2e6,
            voxelize_ms_per_segment: 8_000.0 / 2.2e6,
            raymarch_ms_per_pixel: 40_000.0 / 4.0e5,
            measured: [0; 3],
        }
    }
}

/// The weight of a new frame's measurement in the smoothed rate.
const SMOOTHING: f64 = 0.25;

impl CostModel {
    /// A character of `segments` strand segments covering `pixels` pixels.
    pub fn estimate(&self, segments: u32, pixels: f64) -> CharacterCost {
        let segments = f64::from(segments);
        CharacterCost {
            strands: self.raster_ms_per_segment * segments,
            volume: self.voxelize_ms_per_segment * segments + self.raymarch_ms_per_pixel * pixels,
        }
    }

    /// Fold one frame's measurement into the rates: `(ms, units)` for the rasterizer (its passes
    /// over the segments it drew), the voxelizer (over the segments voxelized) and the
    /// raymarcher (over the pixels the raymarched characters cover). A part with no units or no
    /// time measured is skipped.
    pub fn observe(&mut self, raster: (f64, f64), voxelize: (f64, f64), raymarch: (f64, f64)) {
        let rates = [
            &mut self.raster_ms_per_segment,
            &mut self.voxelize_ms_per_segment,
            &mut self.raymarch_ms_per_pixel,
        ];
        for ((rate, measured), (ms, units)) in rates
            .into_iter()
            .zip(&mut self.measured)
            .zip([raster, voxelize, raymarch])
        {
            if !(units > 0.0 && ms.is_finite() && ms >= 0.0) {
                continue;
            }
            let now = ms / units;
            *rate = if *measured == 0 {
                now
            } else {
                *rate + SMOOTHING * (now - *rate)
            };
            *measured = measured.saturating_add(1);
        }
    }
}

/// The blend factors that fit `budget_ms` (see the module docs): `preferred[i]` is what `auto`
/// picks for character `i` by its size, `costs[i]` what it costs, `nearest_first` the
/// characters' indices from the nearest.
pub fn fit_budget(
    preferred: &[f32],
    costs: &[CharacterCost],
    nearest_first: &[usize],
    budget_ms: f64,
) -> Vec<f32> {
    let mut lods = preferred.to_vec();
    let mut rest: f64 = nearest_first.iter().map(|&i| costs[i].cheapest()).sum();
    let mut used = 0.0;
    for &i in nearest_first {
        let c = costs[i];
        rest -= c.cheapest();
        let fits = |lod: f32| used + c.at(lod) + rest <= budget_ms;
        let choice = [preferred[i], STRANDS, VOLUME]
            .into_iter()
            .find(|&l| fits(l))
            .unwrap_or(if c.strands <= c.volume {
                STRANDS
            } else {
                VOLUME
            });
        lods[i] = choice;
        used += c.at(choice);
    }
    lods
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Five characters from near to far: large on screen (strands), two hybrids, two small
    /// (volume); the strands' cost follows the segments (equal), the volume's the pixels.
    fn crowd() -> (Vec<f32>, Vec<CharacterCost>) {
        let preferred = vec![0.0, 0.3, 0.7, 1.0, 1.0];
        let costs = [40.0, 20.0, 10.0, 4.0, 2.0]
            .into_iter()
            .map(|volume| CharacterCost {
                strands: 30.0,
                volume,
            })
            .collect();
        (preferred, costs)
    }

    fn total(lods: &[f32], costs: &[CharacterCost]) -> f64 {
        lods.iter().zip(costs).map(|(l, c)| c.at(*l)).sum()
    }

    #[test]
    fn a_generous_budget_picks_what_auto_picks_by_size() {
        let (preferred, costs) = crowd();
        let order = [0, 1, 2, 3, 4];
        let all = total(&preferred, &costs); // 30 + 50 + 40 + 4 + 2
        assert_eq!(all, 126.0);
        assert_eq!(fit_budget(&preferred, &costs, &order, all), preferred);
        assert_eq!(fit_budget(&preferred, &costs, &order, 1e9), preferred);
    }

    #[test]
    fn a_tight_budget_drops_the_far_characters_quality_first_and_stays_within_it() {
        let (preferred, costs) = crowd();
        let order = [0, 1, 2, 3, 4];
        // Without the far hybrid's strands (40 -> 10) the frame takes 96.
        let lods = fit_budget(&preferred, &costs, &order, 100.0);
        assert_eq!(lods, vec![0.0, 0.3, 1.0, 1.0, 1.0]);
        assert!(total(&lods, &costs) <= 100.0);
        // Tighter: the nearer hybrid gives way too, to strands (30) before the volume (20).
        let lods = fit_budget(&preferred, &costs, &order, 80.0);
        assert_eq!(lods, vec![0.0, 0.0, 1.0, 1.0, 1.0]);
        assert!(total(&lods, &costs) <= 80.0);
        // Every budget: within it whenever the cheapest choice of all fits.
        let cheapest: f64 = costs.iter().map(CharacterCost::cheapest).sum();
        for budget in (0..140).map(f64::from) {
            let lods = fit_budget(&preferred, &costs, &order, budget);
            if budget >= cheapest {
                assert!(total(&lods, &costs) <= budget, "{budget}: {lods:?}");
            } else {
                // Nothing fits: every character at its cheapest.
                let each: Vec<f64> = lods.iter().zip(&costs).map(|(l, c)| c.at(*l)).collect();
                let least: Vec<f64> = costs.iter().map(CharacterCost::cheapest).collect();
                assert_eq!(each, least, "{budget}");
            }
        }
    }

    #[test]
    fn the_nearest_character_keeps_its_quality_longest() {
        let (preferred, costs) = crowd();
        // The same characters listed far to near: the order given decides who keeps quality.
        let lods = fit_budget(&preferred, &costs, &[4, 3, 2, 1, 0], 100.0);
        assert_eq!(
            lods[2], 0.7,
            "the nearest of the two hybrids now is index 2"
        );
        assert_eq!(lods[1], 1.0, "the farther hybrid gives way, to the volume");
        assert_eq!(lods, vec![0.0, 1.0, 0.7, 1.0, 1.0]);
    }

    #[test]
    fn the_model_measures_and_smooths_its_rates() {
        let mut m = CostModel::default();
        let prior = m;
        let c = m.estimate(1000, 200.0);
        assert!((c.strands - prior.raster_ms_per_segment * 1000.0).abs() < 1e-9);
        // The first measurement replaces the prior, the next moves a quarter of the way.
        m.observe((10.0, 1000.0), (2.0, 1000.0), (4.0, 100.0));
        assert_eq!(m.raster_ms_per_segment, 0.01);
        assert_eq!(m.raymarch_ms_per_pixel, 0.04);
        m.observe((20.0, 1000.0), (0.0, 0.0), (f64::NAN, 100.0));
        assert!((m.raster_ms_per_segment - 0.0125).abs() < 1e-12);
        assert_eq!(m.voxelize_ms_per_segment, 0.002, "no segments: kept");
        assert_eq!(m.raymarch_ms_per_pixel, 0.04, "no time: kept");
        assert_eq!(m.measured, [2, 1, 1]);
        let c = m.estimate(1000, 100.0);
        assert!((c.volume - (2.0 + 4.0)).abs() < 1e-9);
        assert_eq!(c.at(0.5), c.strands + c.volume);
    }
}
