//! The running viewer's playback of an animated cache ([`crate::playback`]): each frame the
//! playback's frame shown in the session when it, the session's hair or the technique changed,
//! and nothing while the simulation drives the hair.

use std::time::Instant;

use anyhow::Result;
use tress_render::session::TechniqueKind;

use crate::panel::FrameLoad;
use crate::playback::{self, Animation, PlayAction};

use super::*;

/// What the session's frames show of the cache: a frame is shown again only when one of these
/// changes (a setting that reloads the hair, R, a new technique, the simulation turned off put
/// the hair back as loaded).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct OnScreen {
    frame: u32,
    hair: Vec<usize>,
    technique: TechniqueKind,
}

impl Running {
    /// The scene's animation and its playback (paused at the scene's frame), after the session
    /// opened or reloaded its hair files; what to add to the status line. A file that cannot be
    /// read again is still, and the note says why.
    pub(super) fn probe_animation(&mut self) -> String {
        let (animation, error) = animation_of(&self.session);
        self.playback = animation.playback();
        self.animation = animation;
        self.on_screen = None;
        self.frame_load = None;
        match (error, self.animation.frames) {
            (Some(e), _) => format!(" (no playback: {e})"),
            (None, 1) => String::new(),
            (None, n) => format!(" ({n} frames: Space plays, `,` / `.` step)"),
        }
    }

    /// A playback action; its status line.
    pub(super) fn apply_play(&mut self, action: PlayAction) -> Option<String> {
        if !self.playback.is_animated() {
            return Some("no animated hair to play (the hair files are still)".into());
        }
        self.playback.apply(action);
        let p = &self.playback;
        let at = format!("frame {} of {}", p.frame(), p.frames());
        Some(match action {
            PlayAction::Play(_) | PlayAction::Toggle if p.playing() => {
                format!("playing from {at} at {} fps", p.fps())
            }
            PlayAction::Play(_) | PlayAction::Toggle | PlayAction::Step(_) => {
                format!("paused at {at}")
            }
            PlayAction::Seek(_) => at,
            PlayAction::Fps(_) => format!("{} fps", p.fps()),
            PlayAction::Loop(on) => if on { "looping" } else { "playing once" }.into(),
        })
    }

    /// The playback `dt` wall-clock seconds on, its frame shown in the session (see
    /// [`playback::show_frame`]). While the simulation runs it drives the hair and the cache
    /// waits (its clock stopped). A frame that cannot be shown pauses the playback; its error is
    /// the panel's (the run's, with `strict`).
    pub(super) fn play(&mut self, dt: f64, strict: bool) -> Result<()> {
        if !self.playback.is_animated() {
            return Ok(());
        }
        if self.sim.enabled {
            self.on_screen = None;
            return Ok(());
        }
        let k = self.playback.advance(dt);
        let want = OnScreen {
            frame: k,
            hair: hair_key(&self.session),
            technique: self.session.technique_kind(),
        };
        if self.on_screen.as_ref() == Some(&want) {
            return Ok(());
        }
        let start = Instant::now();
        let ctx = &self.display.ctx;
        match playback::show_frame(&mut self.session, ctx, &self.animation, k) {
            Ok(shown) => {
                self.frame_load = Some(FrameLoad {
                    frame: k,
                    ms: start.elapsed().as_secs_f64() * 1e3,
                    shown,
                });
                // A reload gives new hair: the key after it.
                self.on_screen = Some(OnScreen {
                    hair: hair_key(&self.session),
                    ..want
                });
            }
            Err(e) if strict => return Err(e.context(format!("playback, frame {k}"))),
            Err(e) => {
                self.playback.apply(PlayAction::Play(false));
                self.error = Some(format!("playback, frame {k}: {}", one_line(&e)));
                // Not tried again until something changes.
                self.on_screen = Some(want);
            }
        }
        Ok(())
    }
}

/// The session's animation ([`playback::probe`]); a file that cannot be read again: none, with
/// the error as one line.
pub(super) fn animation_of(session: &Session) -> (Animation, Option<String>) {
    match playback::probe(session.scene()) {
        Ok(a) => (a, None),
        Err(e) => (Animation::default(), Some(one_line(&e))),
    }
}
