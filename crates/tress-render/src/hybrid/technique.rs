//! [`StrandTechnique`]: the strands, volume, hybrid and auto techniques as the session draws
//! them, every `[[hair]]` entry a character of its own.

use crate::scene_setup::PreparedScene;
use crate::session::technique::{SharedFrame, Technique, TechniqueFrame};
use crate::session::{FrameDetail, Memory};
use crate::{
    FrameInputs, GpuContext, HairObject, RenderError, Renderer, StatsReadback, StrandGeometry,
    TargetFormats, Targets,
};
use tress_scene::TechniqueKind;

/// The strand renderer and each character's strands.
#[derive(Debug)]
pub(crate) struct StrandTechnique {
    pub(crate) renderer: Renderer,
    /// Each `[[hair]]` entry's strands.
    pub(crate) hair: Vec<StrandGeometry>,
}

impl StrandTechnique {
    /// The renderer with `prepared`'s settings and every character uploaded.
    pub(crate) fn new(
        ctx: &GpuContext,
        formats: TargetFormats,
        prepared: &PreparedScene,
        readback: StatsReadback,
    ) -> Result<Self, RenderError> {
        let mut renderer = Renderer::new(ctx, formats, prepared.strands.clone())?;
        renderer.apply_settings(ctx, prepared)?;
        renderer.set_stats_readback(readback);
        let hair = prepared
            .objects
            .iter()
            .map(|o| renderer.upload_hair(ctx, &o.asset))
            .collect::<Result<_, _>>()?;
        Ok(StrandTechnique { renderer, hair })
    }
}

impl Renderer {
    /// Push a prepared scene's strand, volume and hybrid settings into the renderer.
    pub(crate) fn apply_settings(
        &mut self,
        ctx: &GpuContext,
        prepared: &PreparedScene,
    ) -> Result<(), RenderError> {
        self.set_settings(ctx, prepared.strands.clone())?;
        self.set_volume_settings(ctx, prepared.volume.clone())?;
        self.set_hybrid_settings(prepared.hybrid.clone())
    }
}

impl Technique for StrandTechnique {
    fn draw(
        &mut self,
        ctx: &GpuContext,
        targets: &Targets<'_>,
        frame: &SharedFrame<'_>,
    ) -> Result<TechniqueFrame, RenderError> {
        let objects: Vec<HairObject<'_>> = if frame.hair_visible {
            self.hair
                .iter()
                .zip(&frame.prepared.objects)
                .map(|(hair, o)| HairObject {
                    hair,
                    material: o.material,
                    technique: o.technique,
                })
                .collect()
        } else {
            Vec::new()
        };
        let stats = self.renderer.render(
            ctx,
            targets,
            &FrameInputs {
                shared: frame.shared,
                material: frame.prepared.material,
                hair: None,
                objects: &objects,
            },
        )?;
        // What this frame's technique uses: the raymarcher alone needs no OIT and no shadow
        // maps (the renderer keeps those of techniques drawn before).
        let raster = if stats.objects.is_empty() {
            frame.kind != TechniqueKind::Volume
        } else {
            stats
                .objects
                .iter()
                .any(|o| o.technique != TechniqueKind::Volume)
        };
        let memory = Memory {
            geometry: self.hair.iter().map(StrandGeometry::bytes).sum::<u64>() + frame.head_bytes(),
            oit: stats.oit.map_or(0, |(_, bytes)| bytes),
            volumes: stats.volume.map_or(0, |v| v.bytes),
            shadow_maps: if raster {
                self.renderer.shadow_bytes()
            } else {
                0
            },
            ..Memory::default()
        };
        Ok(TechniqueFrame {
            timings: stats.gpu.as_ref().map(|g| g.timings.clone()),
            memory,
            detail: FrameDetail::Strands(stats),
        })
    }

    fn set_stats_readback(&mut self, mode: StatsReadback) {
        self.renderer.set_stats_readback(mode);
    }
}
