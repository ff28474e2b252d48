//! [`SatfTechnique`]: the SATF technique as the session draws it.

use std::time::Instant;

use crate::satf::scene::{SatfScene, load_clusters, satf_settings};
use crate::scene_setup::PreparedScene;
use crate::session::technique::{SharedFrame, Technique, TechniqueFrame};
use crate::session::{DatabaseLoader, FrameDetail, Memory};
use crate::{
    GpuContext, RenderError, SatfDatabase, SatfFrameInputs, SatfGeometry, SatfRenderer,
    StatsReadback, TargetFormats, Targets,
};

/// The SATF renderer, its clusters and HRIR database, and what they were made with.
#[derive(Debug)]
pub(crate) struct SatfTechnique {
    pub(crate) renderer: SatfRenderer,
    pub(crate) geometry: SatfGeometry,
    pub(crate) database: SatfDatabase,
    pub(crate) settings: SatfScene,
    /// CPU milliseconds spent fitting or generating the clusters.
    pub(crate) clusters_ms: f64,
}

impl SatfTechnique {
    /// The scene's clusters (fitted to its hair or generated) and the database `loader` finds
    /// for its settings, uploaded.
    pub(crate) fn new(
        ctx: &GpuContext,
        formats: TargetFormats,
        (scene, prepared): (&tress_scene::Scene, &PreparedScene),
        loader: Option<&mut DatabaseLoader>,
        readback: StatsReadback,
    ) -> Result<Self, RenderError> {
        let settings = satf_settings(scene, prepared.first_hair())?;
        let loader = loader.ok_or_else(|| {
            RenderError::Invalid(
                "the satf technique needs an HRIR database (none was given)".into(),
            )
        })?;
        let db = loader(&settings).map_err(RenderError::Database)?;
        let start = Instant::now();
        let volume = load_clusters(scene, &settings, prepared.hair().as_deref())?;
        let clusters_ms = start.elapsed().as_secs_f64() * 1e3;
        let database = SatfDatabase::new(ctx, &db)?;
        let geometry = SatfGeometry::new(ctx, &volume, &database, &settings.settings)?;
        let mut renderer = SatfRenderer::new(ctx, formats, settings.settings)?;
        renderer.set_stats_readback(readback);
        Ok(SatfTechnique {
            renderer,
            geometry,
            database,
            settings,
            clusters_ms,
        })
    }
}

impl Technique for SatfTechnique {
    fn draw(
        &mut self,
        ctx: &GpuContext,
        targets: &Targets<'_>,
        frame: &SharedFrame<'_>,
    ) -> Result<TechniqueFrame, RenderError> {
        let stats = self.renderer.render(
            ctx,
            targets,
            &SatfFrameInputs {
                shared: frame.shared,
                head_color: frame.prepared.material.head_color,
                clusters: frame.hair_visible.then_some(&self.geometry),
                database: &self.database,
            },
        )?;
        let memory = Memory {
            geometry: self.geometry.buffer_bytes() + frame.head_bytes(),
            textures: self.geometry.atlas_bytes(),
            shadow_maps: self.renderer.shadow_bytes(),
            database: self.database.bytes(),
            ..Memory::default()
        };
        Ok(TechniqueFrame {
            timings: stats.gpu_frame.map(|_| stats.timings.clone()),
            memory,
            detail: FrameDetail::Satf(stats),
        })
    }

    fn set_stats_readback(&mut self, mode: StatsReadback) {
        self.renderer.set_stats_readback(mode);
    }
}
