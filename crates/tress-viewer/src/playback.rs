//! Playing an animated hair cache (Alembic `P` sampled once a frame, USD `points.timeSamples`,
//! as `tress simulate` writes them): which `[[hair]]` entries are animated and how many frames
//! they have ([`probe`]), the playback controls as plain state ([`Playback`]: play and pause,
//! stepping, seeking, the frame rate, looping, and real time to frames), and showing a frame in
//! a session ([`show_frame`]).
//!
//! A frame shows as `tress render cache.abc --frame K` draws it: every animated entry read again
//! at frame `K` ([`tress_hair::formats::ReadOptions::frame`], the scene's `hair.N.frame`) through
//! the scene's loading (files merged, follow hairs, subset, transform). With the techniques that
//! draw strands (strands, volume, hybrid, auto) only the vertex positions change
//! ([`Session::update_hair_positions`]): the file read again at `K` and the positions uploaded,
//! the renderer, its pipelines and the head kept. Patches and SATF build their cards and clusters
//! from the loaded hair, so for them the frame is the setting `hair.N.frame=K` ([`Session::set`]),
//! which reloads the session's hair and head and rebuilds the technique: correct, and as slow as
//! opening the scene.
//!
//! Time: while playing, the frame advances by the wall-clock time between the viewer's frames at
//! [`Playback::fps`] (the file's rate where it says, else [`DEFAULT_FPS`]), so frames are skipped
//! when the display is slower than the cache; at the last frame playback wraps to the first
//! ([`Playback::looping`]) or stops there.

use std::ops::RangeInclusive;

use anyhow::{Context as _, Result};
use tress_hair::HairAsset;
use tress_hair::formats::{self, Format, ReadOptions};
use tress_render::GpuContext;
use tress_render::scene_setup::PreparedScene;
use tress_render::session::Session;
use tress_scene::Scene;

/// Frames a second when the file does not say.
pub(crate) const DEFAULT_FPS: f64 = 24.0;

/// The frame rates the panel offers (and [`PlayAction::Fps`] clamps to).
pub(crate) const FPS_RANGE: RangeInclusive<f64> = 1.0..=120.0;

/// What the user asked of the playback.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum PlayAction {
    /// Play (`true`) or pause. Playing from the last frame without looping starts at the first.
    Play(bool),
    /// Play if paused, pause if playing (Space).
    Toggle,
    /// Pause and move this many frames (`.` one on, `,` one back); wraps round when looping,
    /// stops at the ends otherwise.
    Step(i32),
    /// Go to a frame (the slider; past the last is the last), playing or not.
    Seek(u32),
    /// Frames a second (clamped to [`FPS_RANGE`]; not a finite number: unchanged).
    Fps(f64),
    /// Wrap round at the last frame (`true`) or stop there.
    Loop(bool),
}

/// The playback controls (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Playback {
    frames: u32,
    frame: u32,
    playing: bool,
    looping: bool,
    fps: f64,
    file_fps: Option<f64>,
    /// Wall-clock seconds the current frame has shown while playing, below `1 / fps`.
    shown_for: f64,
}

impl Default for Playback {
    /// One frame: nothing to play.
    fn default() -> Self {
        Playback::new(1, None, 0)
    }
}

impl Playback {
    /// Paused at `frame` (past the last: the last) of `frames` (at least 1), looping, at the
    /// file's rate `file_fps` (clamped to [`FPS_RANGE`]) or [`DEFAULT_FPS`].
    pub(crate) fn new(frames: u32, file_fps: Option<f64>, frame: u32) -> Self {
        let frames = frames.max(1);
        let file_fps = file_fps.filter(|f| f.is_finite() && *f > 0.0);
        Playback {
            frames,
            frame: frame.min(frames - 1),
            playing: false,
            looping: true,
            fps: file_fps.map_or(DEFAULT_FPS, clamp_fps),
            file_fps,
            shown_for: 0.0,
        }
    }

    /// Whether there is anything to play (more than one frame).
    pub(crate) fn is_animated(&self) -> bool {
        self.frames > 1
    }

    /// Frames in all.
    pub(crate) fn frames(&self) -> u32 {
        self.frames
    }

    /// The frame to show (0 the first).
    pub(crate) fn frame(&self) -> u32 {
        self.frame
    }

    /// Whether the frames advance with time.
    pub(crate) fn playing(&self) -> bool {
        self.playing
    }

    /// Whether playback wraps round at the last frame.
    pub(crate) fn looping(&self) -> bool {
        self.looping
    }

    /// Frames a second.
    pub(crate) fn fps(&self) -> f64 {
        self.fps
    }

    /// The rate the file gives, if it does.
    pub(crate) fn file_fps(&self) -> Option<f64> {
        self.file_fps
    }

    fn last(&self) -> u32 {
        self.frames - 1
    }

    /// Apply what the user asked.
    pub(crate) fn apply(&mut self, action: PlayAction) {
        match action {
            PlayAction::Play(true) => {
                if !self.looping && self.frame == self.last() {
                    self.frame = 0;
                }
                self.playing = self.is_animated();
                self.shown_for = 0.0;
            }
            PlayAction::Play(false) => {
                self.playing = false;
                self.shown_for = 0.0;
            }
            PlayAction::Toggle => self.apply(PlayAction::Play(!self.playing)),
            PlayAction::Step(n) => {
                self.playing = false;
                self.shown_for = 0.0;
                let to = i64::from(self.frame) + i64::from(n);
                let frames = i64::from(self.frames);
                self.frame = if self.looping {
                    to.rem_euclid(frames)
                } else {
                    to.clamp(0, frames - 1)
                } as u32;
            }
            PlayAction::Seek(k) => {
                self.frame = k.min(self.last());
                self.shown_for = 0.0;
            }
            PlayAction::Fps(f) if f.is_finite() => {
                self.fps = clamp_fps(f);
                self.shown_for = 0.0;
            }
            PlayAction::Fps(_) => {}
            PlayAction::Loop(on) => self.looping = on,
        }
    }

    /// `dt` wall-clock seconds later (the interval since the last viewer frame): the frame to
    /// show. Playing, each `1 / fps` seconds is one frame on; at the last frame playback wraps
    /// to the first when looping, else stops there (paused).
    pub(crate) fn advance(&mut self, dt: f64) -> u32 {
        if !self.playing || !dt.is_finite() || dt <= 0.0 {
            return self.frame;
        }
        self.shown_for += dt;
        let period = 1.0 / self.fps;
        let on = (self.shown_for / period).floor();
        if on < 1.0 {
            return self.frame;
        }
        self.shown_for = (self.shown_for - on * period).max(0.0);
        // Whole frames on; a stall of years is still a number of frames.
        let on = on.min(f64::from(u32::MAX)) as u64;
        let to = u64::from(self.frame) + on;
        if self.looping {
            self.frame = (to % u64::from(self.frames)) as u32;
        } else if to >= u64::from(self.last()) {
            self.frame = self.last();
            self.playing = false;
            self.shown_for = 0.0;
        } else {
            self.frame = to as u32;
        }
        self.frame
    }
}

fn clamp_fps(f: f64) -> f64 {
    f.clamp(*FPS_RANGE.start(), *FPS_RANGE.end())
}

/// What a scene animates: the `[[hair]]` entries read from animated files.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Animation {
    /// The animated entries, by index in `[[hair]]`.
    pub(crate) entries: Vec<usize>,
    /// Frames: the most of any of their files (1: nothing is animated).
    pub(crate) frames: u32,
    /// The rate of the file with the most frames, where it says.
    pub(crate) fps: Option<f64>,
    /// The frame the scene loads: the first animated entry's `frame` (unset: 0).
    pub(crate) start: u32,
}

impl Default for Animation {
    /// Nothing animated.
    fn default() -> Self {
        Animation {
            entries: Vec::new(),
            frames: 1,
            fps: None,
            start: 0,
        }
    }
}

impl Animation {
    /// The playback of this animation, paused at the scene's frame.
    pub(crate) fn playback(&self) -> Playback {
        Playback::new(self.frames, self.fps, self.start)
    }
}

/// The formats that hold animation (Alembic and USD).
fn may_be_animated(format: Format) -> bool {
    matches!(
        format,
        Format::Abc | Format::Usda | Format::Usdc | Format::Usdz | Format::Usd
    )
}

/// Which of the scene's hair entries come from animated files, and their frames and rate. Each
/// Alembic or USD file of an entry is read once more for its frame count
/// ([`formats::Details::frames`]); generated hair and the other formats are still.
pub(crate) fn probe(scene: &Scene) -> Result<Animation> {
    let mut animation = Animation::default();
    for (i, spec) in scene.hair.iter().enumerate() {
        let defaults = ReadOptions::default();
        let options = ReadOptions {
            cubic_segments: spec.cubic_segments.unwrap_or(defaults.cubic_segments),
            ..defaults
        };
        let mut animated = false;
        for file in &spec.files {
            let path = scene.resolve(file);
            if !Format::from_path(&path).is_ok_and(may_be_animated) {
                continue;
            }
            let details = formats::load_path(&path, &options)
                .with_context(|| format!("hair.{i}: counting its frames"))?
                .details;
            if details.frames > 1 {
                animated = true;
            }
            if details.frames > animation.frames {
                animation.frames = details.frames;
                animation.fps = details.fps;
            }
        }
        if animated {
            if animation.entries.is_empty() {
                animation.start = spec.frame.unwrap_or(0);
            }
            animation.entries.push(i);
        }
    }
    Ok(animation)
}

/// The session's hair at frame `k`, merged in entry order as the strand renderer takes it
/// ([`Session::update_hair_positions`]): the animated entries of `scene` read again at `k`
/// through the scene's loading, the others as `prepared` holds them.
pub(crate) fn hair_at(
    scene: &Scene,
    prepared: &PreparedScene,
    animation: &Animation,
    k: u32,
) -> Result<HairAsset> {
    let mut at_k = scene.clone();
    at_k.hair = animation
        .entries
        .iter()
        .map(|&i| {
            let mut spec = scene.hair[i].clone();
            spec.frame = Some(k);
            spec
        })
        .collect();
    let mut read = at_k.load_hair()?.into_iter();
    let mut assets = Vec::with_capacity(prepared.objects.len());
    for (i, object) in prepared.objects.iter().enumerate() {
        if animation.entries.contains(&i) {
            assets.push(read.next().context("an animated hair entry was not read")?);
        } else {
            assets.push(object.asset.clone());
        }
    }
    Ok(HairAsset::merge_owned(assets)?)
}

/// How a frame was shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Shown {
    /// The vertex positions replaced (strands, volume, hybrid, auto).
    Positions,
    /// The session's hair reloaded at the frame (`hair.N.frame`; patches, SATF).
    Reloaded,
}

/// Show frame `k` of `animation` in `session` (see the module docs for the two ways).
pub(crate) fn show_frame(
    session: &mut Session,
    ctx: &GpuContext,
    animation: &Animation,
    k: u32,
) -> Result<Shown> {
    if session.technique_kind().draws_strands() {
        let asset = hair_at(session.scene(), session.prepared(), animation, k)?;
        session.update_hair_positions(ctx, &asset)?;
        return Ok(Shown::Positions);
    }
    for &i in &animation.entries {
        if session
            .scene()
            .hair
            .get(i)
            .and_then(|h| h.frame)
            .unwrap_or(0)
            != k
        {
            let kv = format!("hair.{i}.frame={k}");
            session.set(ctx, &kv).with_context(|| kv.clone())?;
        }
    }
    Ok(Shown::Reloaded)
}

#[cfg(test)]
mod gpu_tests;
#[cfg(test)]
mod tests;
