//! Order-independent transparency of the strand rasterizer: the paper's PPLL k-buffer
//! ([`PpllBuild`] + [`PpllResolve`]), the bounded-memory ShortCut ([`ShortcutDepth`] +
//! [`ShortcutShade`] + [`ShortcutResolve`]), and the per-frame choice
//! between them
//! ([`Oit::Auto`], the default).
//!
//! # Implementation
//!
//! - **PPLL** (Jansson 2019 §3.2): exactly the paper's linked lists and k-buffer resolve. Its
//!   node pool grows after a frame that dropped fragments, up to `ppll_max_bytes` and
//!   [`NODE_CHUNKS`](super::NODE_CHUNKS) storage bindings of the device's largest size.
//!   Fragments beyond the pool are dropped and counted (design rule 8): with [`Oit::Ppll`] they
//!   are lost.
//! - **ShortCut** (after TressFX 4.1's "ShortCut" OIT): a depth-only pass keeps each pixel's `k`
//!   nearest fragment depths (an `atomicMax` chain over `k` sorted key layers; a fragment
//!   farther than a full set of `k` stops after one load), a shade pass
//!   shades the `k - 1` nearest fragments into their layers (the k-th nearest depth is the
//!   tail's threshold, as in TressFX, and its fragment the tail's first) (a layer's word keeps its depth key and
//!   takes the fragment's alpha in its low bits), multiplies every other fragment's
//!   opacity into a transmittance target and, for the tail fragments a roulette on a hash of
//!   their strand picks (likelier near the k-th depth), adds their shaded color weighted by a
//!   depth falloff (from the `k` layers' mean spacing) into a tail color target, and a resolve blends the `k - 1` layers front to back with the tail
//!   under them. Its memory is fixed by the screen and `k` (61.5 MiB at 1280x720 with the default
//!   k = 8, 54.5 MiB at k = 7) and it never drops a fragment. The tail's opacity is exact; its
//!   color is the falloff-weighted mean of the picked fragments, or the threshold's (the k-th
//!   and its ties) where no falloff is known. CPU twin: `tress_shading::resolve_shortcut`.
//! - **Auto**: PPLL while a grown pool holds the frame and its k-buffer sorts most of it;
//!   ShortCut once a frame asks for more nodes than the cap allows, or once more than
//!   [`AUTO_TAIL_SHARE`] of a PPLL frame's fragments fell into the k-buffer's unsorted tail
//!   (the resolve counts them). Back to the PPLL when a ShortCut frame's fragment count (its
//!   depth pass counts them) fits the cap with the growth margin, after a tail switch only once
//!   that count has doubled since (the hair grew on screen, so fewer fragments lie behind each
//!   pixel's k nearest). An offline frame
//!   (statistics waited for, targets cleared) is rendered again at once with the grown pool or
//!   with ShortCut, so it loses nothing; an interactive frame (deferred statistics) may lose
//!   fragments in the one frame before the switch, and its report says how many.

use std::fmt;
use std::str::FromStr;

use crate::bind::Layouts;
use crate::gpu::GpuTimer;
use crate::gpu::types::StrandParams;
use crate::stats::GpuReport;
use crate::strands::ppll;
use crate::strands::ppll_build::PpllBuildInputs;
use crate::strands::shortcut::ShortcutBuffers;
use crate::strands::shortcut_depth::ShortcutDepth;
use crate::strands::shortcut_resolve::ShortcutResolve;
use crate::strands::shortcut_shade::ShortcutShade;
use crate::strands::{PpllBuild, PpllPool, PpllResolve, StrandGeometry, StrandSettings};
use crate::{GpuContext, RenderError};

/// The share of a PPLL frame's fragments merged unsorted behind their pixel's `k` nearest beyond
/// which [`Oit::Auto`] draws with ShortCut: its tail (shaded near the k-th depth, with exact
/// opacity) is then nearer the exact composite than the k-buffer's mean-colour tail. Measured
/// against `tress render --exact-oit` on the generated fur and ponytail at 1×, 2× and 4× their
/// scenes' distance (README, *Strand OIT*): the PPLL was nearer only where 71% of the fragments
/// were in its tail (0.086 against 0.100), ShortCut at 86–99.7% (0.03–0.09 against 0.08–0.34).
pub const AUTO_TAIL_SHARE: f64 = 0.75;

/// Whether more than [`AUTO_TAIL_SHARE`] of `fragments` fell into the k-buffer's tail.
fn tail_dominated(tail: u32, fragments: u32) -> bool {
    f64::from(tail) > AUTO_TAIL_SHARE * f64::from(fragments)
}

/// Which OIT the strand rasterizer uses (`strands.oit`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Oit {
    /// PPLL while a grown pool holds the frame, else ShortCut, `"auto"`.
    #[default]
    Auto,
    /// Always the paper's PPLL k-buffer; fragments beyond the pool's cap are lost, `"ppll"`.
    Ppll,
    /// Always ShortCut, `"shortcut"`.
    Shortcut,
}

impl Oit {
    /// The setting's spelling.
    pub fn name(self) -> &'static str {
        match self {
            Oit::Auto => "auto",
            Oit::Ppll => "ppll",
            Oit::Shortcut => "shortcut",
        }
    }
}

impl fmt::Display for Oit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Oit {
    type Err = RenderError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "auto" => Ok(Oit::Auto),
            "ppll" => Ok(Oit::Ppll),
            "shortcut" => Ok(Oit::Shortcut),
            _ => Err(RenderError::Invalid(format!(
                "unknown oit `{s}` (expected auto, ppll or shortcut)"
            ))),
        }
    }
}

/// The OIT that drew a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OitKind {
    /// The per-pixel linked lists.
    Ppll,
    /// ShortCut.
    Shortcut,
}

impl OitKind {
    /// `"ppll"` or `"shortcut"`.
    pub fn name(self) -> &'static str {
        match self {
            OitKind::Ppll => "ppll",
            OitKind::Shortcut => "shortcut",
        }
    }
}

impl fmt::Display for OitKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What the OIT of a frame did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OitStats {
    /// Which OIT drew the frame.
    pub kind: OitKind,
    /// Strand fragments it was given (in front of the head, not too faint).
    pub fragments: u32,
    /// Fragments that did not reach the image (a full PPLL pool; always 0 for ShortCut).
    pub lost: u32,
    /// PPLL: fragments its k-buffer merged unsorted behind their pixel's `k` nearest (0 for
    /// ShortCut, whose tail is counted by neither pass).
    pub tail: u32,
    /// Bytes of its buffers.
    pub bytes: u64,
}

/// What the OIT passes of a frame read and write.
pub(crate) struct OitInputs<'a> {
    /// The frame's view group (camera and the settings every part shares), read by the
    /// resolves.
    pub(crate) view: &'a wgpu::BindGroup,
    /// The heads of hair drawn into this OIT, each with its own groups: one frame composites
    /// them all, sorted together per pixel.
    pub(crate) parts: &'a [OitPart<'a>],
    /// The head's depth: read-only attachment and texture.
    pub(crate) depth: &'a wgpu::TextureView,
    /// Where the resolve composites (the target, or the hybrid's strand layer).
    pub(crate) color: &'a wgpu::TextureView,
}

/// One head of hair drawn into the OIT: its view group (camera, its settings), its lighting
/// group (its material and volume) and its strands.
pub(crate) struct OitPart<'a> {
    pub(crate) view: &'a wgpu::BindGroup,
    pub(crate) lighting: &'a wgpu::BindGroup,
    pub(crate) geometry: &'a StrandGeometry,
}

/// Both OITs' pipelines, their buffers and the auto choice's state.
#[derive(Debug)]
pub(crate) struct StrandOit {
    build: PpllBuild,
    resolve: PpllResolve,
    depth: ShortcutDepth,
    shade: ShortcutShade,
    shortcut_resolve: ShortcutResolve,
    pool: Option<PpllPool>,
    grown_capacity: Option<u32>,
    shortcut: Option<ShortcutBuffers>,
    /// [`Oit::Auto`] has switched to ShortCut.
    auto_shortcut: bool,
    /// The fragments of the PPLL frame whose tail made [`Oit::Auto`] switch (`None`: it switched
    /// for the pool's cap, or has not switched).
    tail_switch: Option<u32>,
}

impl StrandOit {
    pub(crate) fn new(
        ctx: &GpuContext,
        layouts: &Layouts,
        color_format: wgpu::TextureFormat,
    ) -> Result<Self, RenderError> {
        let depth = ShortcutDepth::new(ctx, layouts)?;
        let shade = ShortcutShade::new(ctx, layouts, &depth.layout)?;
        Ok(StrandOit {
            build: PpllBuild::new(ctx, layouts)?,
            resolve: PpllResolve::new(ctx, layouts, color_format)?,
            shortcut_resolve: ShortcutResolve::new(ctx, &layouts.view, color_format)?,
            depth,
            shade,
            pool: None,
            grown_capacity: None,
            shortcut: None,
            auto_shortcut: false,
            tail_switch: None,
        })
    }

    /// Forget the buffers and the auto choice (the OIT settings changed).
    pub(crate) fn reset(&mut self) {
        self.pool = None;
        self.grown_capacity = None;
        self.shortcut = None;
        self.auto_shortcut = false;
        self.tail_switch = None;
    }

    /// The OIT of the next frame under `settings`.
    pub(crate) fn kind(&self, settings: &StrandSettings) -> OitKind {
        match settings.oit {
            Oit::Ppll => OitKind::Ppll,
            Oit::Shortcut => OitKind::Shortcut,
            Oit::Auto if self.auto_shortcut => OitKind::Shortcut,
            Oit::Auto => OitKind::Ppll,
        }
    }

    /// Allocate (or keep) the buffers `kind` needs for a target of `size`.
    pub(crate) fn prepare(
        &mut self,
        ctx: &GpuContext,
        settings: &StrandSettings,
        size: [u32; 2],
        kind: OitKind,
    ) -> Result<(), RenderError> {
        match kind {
            OitKind::Ppll => {
                let cap_nodes = PpllPool::cap_nodes(ctx, settings.ppll_max_bytes);
                let pixels = u64::from(size[0]) * u64::from(size[1]);
                let capacity = self.grown_capacity.unwrap_or_else(|| {
                    ppll::initial_capacity(pixels, settings.ppll_nodes_per_pixel, cap_nodes)
                });
                if self
                    .pool
                    .as_ref()
                    .is_none_or(|p| p.size != size || p.capacity != capacity)
                {
                    self.pool = None;
                    self.pool = Some(PpllPool::new(ctx, size, capacity)?);
                }
            }
            OitKind::Shortcut => {
                let k = settings.shortcut_k;
                if self
                    .shortcut
                    .as_ref()
                    .is_none_or(|b| b.size != size || b.k != k)
                {
                    self.shortcut = None;
                    self.shortcut = Some(ShortcutBuffers::new(ctx, size, k)?);
                }
            }
        }
        Ok(())
    }

    /// Fill the uniform fields of `kind`'s buffers.
    pub(crate) fn fill_params(&self, kind: OitKind, params: &mut StrandParams) {
        params.node_capacity = 1;
        params.nodes_per_chunk = 1;
        if let (OitKind::Ppll, Some(p)) = (kind, &self.pool) {
            params.node_capacity = p.capacity;
            params.nodes_per_chunk = p.nodes_per_chunk;
        }
        if let (OitKind::Shortcut, Some(b)) = (kind, &self.shortcut) {
            params.shortcut_k = b.k;
        }
    }

    /// PPLL node capacity (0 without a pool).
    pub(crate) fn ppll_capacity(&self) -> u32 {
        self.pool.as_ref().map_or(0, |p| p.capacity)
    }

    /// The PPLL pool's lists as the last frame drawn with it left them (None without a pool).
    pub(crate) fn ppll_fragments(
        &self,
        ctx: &GpuContext,
    ) -> Result<Option<crate::strands::PpllFragments>, RenderError> {
        self.pool
            .as_ref()
            .map(|p| crate::strands::ppll_readback::read_fragments(ctx, p))
            .transpose()
    }

    /// Bytes of the PPLL pool (0 without one).
    pub(crate) fn ppll_bytes(&self) -> u64 {
        self.pool.as_ref().map_or(0, PpllPool::bytes)
    }

    /// Bytes of `kind`'s buffers.
    pub(crate) fn bytes(&self, kind: OitKind) -> u64 {
        match kind {
            OitKind::Ppll => self.ppll_bytes(),
            OitKind::Shortcut => self.shortcut.as_ref().map_or(0, ShortcutBuffers::bytes),
        }
    }

    /// The counters `kind`'s passes write (PPLL layout: requested, dropped).
    pub(crate) fn counters(&self, kind: OitKind) -> Option<&wgpu::Buffer> {
        match kind {
            OitKind::Ppll => self.pool.as_ref().map(|p| &p.counters),
            OitKind::Shortcut => self.shortcut.as_ref().map(|b| &b.counters),
        }
    }

    /// Record `kind`'s passes (after [`StrandOit::prepare`]).
    pub(crate) fn encode(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        kind: OitKind,
        inputs: &OitInputs<'_>,
        timer: &GpuTimer,
    ) {
        match kind {
            OitKind::Ppll => {
                let Some(pool) = &self.pool else { return };
                let build = PpllBuildInputs {
                    parts: inputs.parts,
                    pool,
                    depth: inputs.depth,
                };
                self.build.encode(
                    ctx,
                    encoder,
                    &build,
                    timer.render_writes("strands/ppll_build", true, true),
                );
                self.resolve.encode(
                    ctx,
                    encoder,
                    inputs.view,
                    pool,
                    inputs.color,
                    timer.render_writes("strands/ppll_resolve", true, true),
                );
            }
            OitKind::Shortcut => {
                let Some(buffers) = &self.shortcut else {
                    return;
                };
                let group = buffers.raster_group(ctx, &self.depth.layout, inputs.depth);
                self.depth.encode(
                    encoder,
                    inputs,
                    buffers,
                    &group,
                    timer.render_writes("strands/shortcut_depth", true, true),
                );
                self.shade.encode(
                    encoder,
                    inputs,
                    buffers,
                    &group,
                    timer.render_writes("strands/shortcut_shade", true, true),
                );
                self.shortcut_resolve.encode(
                    ctx,
                    encoder,
                    inputs.view,
                    buffers,
                    inputs.color,
                    timer.render_writes("strands/shortcut_resolve", true, true),
                );
            }
        }
    }

    /// Learn from a frame's report: grow the PPLL pool, or switch between the PPLL and ShortCut
    /// under [`Oit::Auto`]. Returns whether the next frame would lose fewer fragments than the
    /// reported one, or blend far more of them in order (so an offline frame is worth rendering
    /// again).
    pub(crate) fn learn(
        &mut self,
        ctx: &GpuContext,
        settings: &StrandSettings,
        report: &GpuReport,
    ) -> bool {
        let Some(o) = report.oit else { return false };
        let cap = PpllPool::cap_nodes(ctx, settings.ppll_max_bytes);
        match o.kind {
            OitKind::Ppll if o.lost > 0 => {
                if settings.oit == Oit::Auto && o.fragments > cap {
                    tracing::debug!(
                        fragments = o.fragments,
                        cap,
                        "the PPLL cannot hold the frame: switching to ShortCut"
                    );
                    self.auto_shortcut = true;
                    self.pool = None;
                    self.grown_capacity = None;
                    return true;
                }
                let Some(pool) = &self.pool else { return false };
                let grown = ppll::grown_capacity(pool.capacity, o.fragments, cap);
                if grown > pool.capacity {
                    tracing::debug!(
                        from = pool.capacity,
                        to = grown,
                        "growing the PPLL node pool"
                    );
                    self.grown_capacity = Some(grown);
                    return true;
                }
                false
            }
            OitKind::Ppll if settings.oit == Oit::Auto && tail_dominated(o.tail, o.fragments) => {
                tracing::debug!(
                    fragments = o.fragments,
                    tail = o.tail,
                    "most fragments fell into the k-buffer's unsorted tail: switching to ShortCut"
                );
                self.auto_shortcut = true;
                self.tail_switch = Some(o.fragments);
                self.pool = None;
                self.grown_capacity = None;
                true
            }
            OitKind::Shortcut if settings.oit == Oit::Auto && self.auto_shortcut => {
                let want = ppll::grown_capacity(0, o.fragments, u32::MAX - 1);
                let grown = self
                    .tail_switch
                    .is_none_or(|at| u64::from(o.fragments) >= 2 * u64::from(at));
                if want <= cap && grown {
                    tracing::debug!(
                        fragments = o.fragments,
                        "a grown PPLL holds the frame again: switching back"
                    );
                    self.auto_shortcut = false;
                    self.tail_switch = None;
                    self.shortcut = None;
                    self.grown_capacity = Some(want.max(1));
                }
                false
            }
            _ => false,
        }
    }
}
