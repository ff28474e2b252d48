//! [`PatchTechnique`]: the patches technique as the session draws it.

use crate::patches::scene::{PatchScene, load_patches, patch_settings};
use crate::scene_setup::PreparedScene;
use crate::session::technique::{SharedFrame, Technique, TechniqueFrame};
use crate::session::{FrameDetail, Memory};
use crate::{
    GpuContext, PatchFrameInputs, PatchGeometry, PatchRenderer, RenderError, StatsReadback,
    TargetFormats, Targets,
};

/// The patch renderer, the uploaded cards and what they were made from.
#[derive(Debug)]
pub(crate) struct PatchTechnique {
    pub(crate) renderer: PatchRenderer,
    pub(crate) geometry: PatchGeometry,
    pub(crate) scene: PatchScene,
}

impl PatchTechnique {
    /// The scene's cards (loaded, generated or made from its strands) uploaded.
    pub(crate) fn new(
        ctx: &GpuContext,
        formats: TargetFormats,
        scene: &tress_scene::Scene,
        prepared: &PreparedScene,
        readback: StatsReadback,
    ) -> Result<Self, RenderError> {
        let cards = load_patches(scene, prepared)?;
        let settings = patch_settings(scene, prepared.first_hair())?;
        let mut renderer = if cards.textures_from_files {
            PatchRenderer::with_textures(ctx, formats, settings, cards.textures.clone())?
        } else {
            PatchRenderer::new(ctx, formats, settings)?
        };
        renderer.set_stats_readback(readback);
        let geometry = renderer.upload_patches(ctx, &cards.mesh, cards.sort_center)?;
        Ok(PatchTechnique {
            renderer,
            geometry,
            scene: cards,
        })
    }
}

impl Technique for PatchTechnique {
    fn draw(
        &mut self,
        ctx: &GpuContext,
        targets: &Targets<'_>,
        frame: &SharedFrame<'_>,
    ) -> Result<TechniqueFrame, RenderError> {
        let stats = self.renderer.render(
            ctx,
            targets,
            &PatchFrameInputs {
                shared: frame.shared,
                head_color: frame.prepared.material.head_color,
                patches: frame.hair_visible.then_some(&self.geometry),
            },
        )?;
        let memory = Memory {
            geometry: self.geometry.bytes() + frame.head_bytes(),
            textures: self.renderer.texture_bytes(),
            ..Memory::default()
        };
        Ok(TechniqueFrame {
            timings: stats.timings.clone(),
            memory,
            detail: FrameDetail::Patches(stats),
        })
    }

    fn set_stats_readback(&mut self, mode: StatsReadback) {
        self.renderer.set_stats_readback(mode);
    }
}
