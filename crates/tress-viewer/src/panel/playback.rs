//! The panel's playback section, shown for an animated cache: play and pause, previous and next
//! frame, loop, the frame slider and the frame rate, as [`PlayAction`]s for
//! [`crate::playback::Playback`]; and how the last frame was shown.

use egui::{RichText, Ui};

use super::{Action, FrameLoad};
use crate::playback::{FPS_RANGE, PlayAction, Playback, Shown};

/// How playback works, under the section.
const HELP: &str = "Space plays or pauses, `,` and `.` step a frame back and on. Playing \
follows the clock at the frame rate (frames are skipped when the display is slower). The \
strands, volume, hybrid and auto techniques replace only the hair's positions; patches and SATF \
reload the hair at the frame (hair.N.frame), as slow as opening the file.";

/// The section. `simulating`: the simulation drives the hair and the controls wait.
pub(super) fn playback_section(
    ui: &mut Ui,
    p: &Playback,
    load: Option<&FrameLoad>,
    simulating: bool,
    actions: &mut Vec<Action>,
) {
    let mut push = |a: PlayAction| actions.push(Action::Play(a));
    if simulating {
        ui.label("the simulation drives the hair: turn it off to play the cache");
    }
    ui.add_enabled_ui(!simulating, |ui| {
        ui.horizontal(|ui| {
            let play = if p.playing() { "pause" } else { "play" };
            if ui.button(play).on_hover_text("Space").clicked() {
                push(PlayAction::Play(!p.playing()));
            }
            if ui.button("previous").on_hover_text(",").clicked() {
                push(PlayAction::Step(-1));
            }
            if ui.button("next").on_hover_text(".").clicked() {
                push(PlayAction::Step(1));
            }
            let mut looping = p.looping();
            if ui
                .checkbox(&mut looping, "loop")
                .on_hover_text("wrap round at the last frame, or stop there")
                .changed()
            {
                push(PlayAction::Loop(looping));
            }
        });
        let mut frame = p.frame();
        if ui
            .add(egui::Slider::new(&mut frame, 0..=p.frames() - 1).text("frame"))
            .on_hover_text("hair.N.frame: the sample of Alembic P / USD points")
            .changed()
        {
            push(PlayAction::Seek(frame));
        }
        let mut fps = p.fps();
        if ui
            .add(egui::Slider::new(&mut fps, FPS_RANGE).text("fps"))
            .changed()
        {
            push(PlayAction::Fps(fps));
        }
    });
    let rate = match p.file_fps() {
        Some(f) => format!("the file's rate {f:.3} fps"),
        None => "the file gives no rate (24 fps by default)".into(),
    };
    ui.label(format!(
        "frame {} of 0..{}, {}; {rate}",
        p.frame(),
        p.frames() - 1,
        if p.playing() { "playing" } else { "paused" }
    ));
    if let Some(l) = load {
        let how = match l.shown {
            Shown::Positions => "positions replaced",
            Shown::Reloaded => "the session's hair reloaded",
        };
        ui.label(format!("frame {} shown in {:.1} ms ({how})", l.frame, l.ms));
    }
    ui.label(RichText::new(HELP).small());
}
