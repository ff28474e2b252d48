//! `technique = "auto"` under `hybrid.budget_ms`: each frame's plans fitted to the budget
//! ([`crate::hybrid::budget::fit_budget`]) by the cost model the frames' own GPU timestamps
//! teach ([`crate::hybrid::budget::CostModel::observe`]).

use super::Renderer;
use super::objects::Drawn;
use crate::hybrid::budget::{self, CharacterCost};
use crate::stats::FrameStats;
use crate::strands::StrandGeometry;
use crate::{Material, TechniqueKind};

impl Renderer {
    /// Fit the `auto` characters' plans to `hybrid.budget_ms` (nothing without one): the other
    /// characters keep their technique and their cost counts against the budget.
    pub(super) fn fit_budget(
        &self,
        drawn: &mut [Drawn<'_>],
        hair: &[(Option<&StrandGeometry>, Material, TechniqueKind)],
        size: [u32; 2],
    ) {
        let Some(budget_ms) = self.hybrid.budget_ms else {
            return;
        };
        let free: Vec<bool> = hair
            .iter()
            .zip(drawn.iter())
            .map(|((.., t), d)| *t == TechniqueKind::Auto && d.hair.is_some())
            .collect();
        if !free.iter().any(|&f| f) {
            return;
        }
        let frame_pixels = f64::from(size[0]) * f64::from(size[1]);
        let preferred: Vec<f32> = drawn.iter().map(|d| d.plan.lod).collect();
        let costs: Vec<CharacterCost> = drawn
            .iter()
            .zip(&free)
            .map(|(d, &free)| {
                let segments = d.hair.map_or(0, StrandGeometry::segment_count);
                let pixels = f64::from(d.plan.extent.coverage) * frame_pixels;
                let c = self.costs.estimate(segments, pixels);
                if free {
                    c
                } else {
                    // Fixed: its own technique's cost whichever way it is asked.
                    let own = c.at(d.plan.lod);
                    CharacterCost {
                        strands: own,
                        volume: own,
                    }
                }
            })
            .collect();
        let mut nearest_first: Vec<usize> = (0..drawn.len()).collect();
        nearest_first.sort_by(|&a, &b| {
            drawn[a]
                .plan
                .extent
                .depth
                .total_cmp(&drawn[b].plan.extent.depth)
        });
        let lods = budget::fit_budget(&preferred, &costs, &nearest_first, f64::from(budget_ms));
        let settings = (&self.hybrid, &self.settings, &self.volume_settings);
        for ((d, lod), free) in drawn.iter_mut().zip(lods).zip(free) {
            if free && lod != d.plan.lod {
                d.plan = d.plan.at_factor(lod, settings);
            }
        }
    }

    /// Teach the cost model a frame's measured passes (only a report of this very frame: its
    /// characters are the ones measured).
    pub(super) fn learn_costs(&mut self, stats: &FrameStats) {
        let Some(gpu) = stats.gpu.as_ref().filter(|g| g.frame == stats.frame) else {
            return;
        };
        let crate::Timings::Passes(passes) = &gpu.timings else {
            return;
        };
        let raster_ms: f64 = passes
            .iter()
            .filter(|p| p.name.starts_with("strands/"))
            .map(|p| p.ms)
            .sum();
        let frame_pixels = f64::from(stats.size[0]) * f64::from(stats.size[1]);
        let (mut raster_segments, mut vox, mut march) = (0.0, (0.0, 0.0), (0.0, 0.0));
        for (i, o) in stats.objects.iter().enumerate() {
            let segments = f64::from(o.segments);
            if o.technique != TechniqueKind::Volume {
                raster_segments += segments;
            }
            let Some(t) = gpu.object_timings.get(i) else {
                continue;
            };
            if let Some(ms) = t.get("volume/voxelize") {
                vox = (vox.0 + ms, vox.1 + segments);
            }
            if let Some(ms) = t.get("volume/raymarch") {
                march = (march.0 + ms, march.1 + f64::from(o.coverage) * frame_pixels);
            }
        }
        self.costs.observe((raster_ms, raster_segments), vox, march);
    }

    /// What the renderers cost on this device, as learned so far.
    pub fn cost_model(&self) -> &budget::CostModel {
        &self.costs
    }
}
