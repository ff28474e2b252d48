//! The [`Technique`] trait: what [`super::Session`] asks of each technique to draw a frame, and
//! what every technique is given ([`SharedFrame`]: the camera, lights, ambient, the head, the
//! clear colour and the prepared scene, decided once by the session).
//!
//! Each technique's own state and passes live in its folder: the strands, volume, hybrid and
//! auto ([`crate::hybrid::StrandTechnique`]), patches ([`crate::patches::PatchTechnique`]) and
//! SATF ([`crate::satf::SatfTechnique`]).

use super::{FrameDetail, Memory};
use crate::scene_setup::PreparedScene;
use crate::{GpuContext, HeadGeometry, RenderError, SharedInputs, StatsReadback, Targets, Timings};
use tress_scene::TechniqueKind;

/// What the session gives every technique for a frame.
pub(crate) struct SharedFrame<'a> {
    /// The camera (its viewport is the targets' size), the frame's lights, the ambient light,
    /// the opaque head (every character's heads and bodies in one mesh) and the scene's
    /// background, opaque.
    pub(crate) shared: SharedInputs<'a>,
    /// The scene's hair, materials and settings.
    pub(crate) prepared: &'a PreparedScene,
    /// Draw the hair (else only the head and background).
    pub(crate) hair_visible: bool,
    /// The session's technique (the strand renderer draws four of them).
    pub(crate) kind: TechniqueKind,
}

impl SharedFrame<'_> {
    /// Bytes of the head's buffers (every technique's memory counts them).
    pub(crate) fn head_bytes(&self) -> u64 {
        self.shared.head.map_or(0, HeadGeometry::bytes)
    }
}

/// What a technique reports about a frame it drew.
pub(crate) struct TechniqueFrame {
    /// Per-pass GPU times (`None` until results arrive with deferred readback).
    pub(crate) timings: Option<Timings>,
    /// The GPU memory the frame's technique uses.
    pub(crate) memory: Memory,
    /// The technique's own statistics.
    pub(crate) detail: FrameDetail,
}

/// A technique the session draws frames with.
pub(crate) trait Technique {
    /// Draw one frame into `targets` and report it.
    fn draw(
        &mut self,
        ctx: &GpuContext,
        targets: &Targets<'_>,
        frame: &SharedFrame<'_>,
    ) -> Result<TechniqueFrame, RenderError>;

    /// How GPU statistics are read back from now on.
    fn set_stats_readback(&mut self, mode: StatsReadback);
}
