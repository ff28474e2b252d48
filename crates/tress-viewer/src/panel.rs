//! The egui side panel: technique, the current technique's settings by their scene keys, lights,
//! an animated cache's playback, the simulation, opening files, the last frame's per-pass timings
//! and statistics ([`detail`]), the simulation's time and memory, and the status line.
//!
//! The panel never changes the session itself: it returns [`Action`]s (`key=value` settings,
//! technique switches, files to open) that the viewer applies after the UI pass, and shows the
//! values the session holds, so a setting the session refuses snaps back and its error shows.
//! Sliders of settings that only change uniforms apply while dragging; those that rebuild GPU
//! resources (volume resolution, patches, SATF) apply when released. The simulation section's
//! sliders apply when released too: each change starts the session's simulation again
//! ([`crate::sim_controls`]).

use std::collections::HashMap;
use std::path::PathBuf;

use egui::{Color32, RichText, Ui};
use tress_render::Timings;
use tress_render::session::{FrameDetail, Memory, Session, TechniqueKind};

use crate::playback::{PlayAction, Playback, Shown};
use crate::sim_controls::{SimAction, SimControls, SimEdit};

mod form;
mod playback;
mod settings;
mod simulation;

use form::Form;
use settings::settings;

/// What the user asked for in the panel, applied by the viewer after the UI pass.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Action {
    /// A dotted `key=value` setting ([`Session::set`]).
    Set(String),
    /// Switch technique.
    Technique(&'static str),
    /// Switch to the next technique in [`TechniqueKind::NAMES`] order that can draw (the T key).
    NextTechnique,
    /// Open files (a scene, hair files or a card OBJ) as a new session.
    Open(Vec<PathBuf>),
    /// Rebuild the session (the R key).
    Rebuild,
    /// Return the hybrid to the distance-driven blend factor (removes `hybrid.lod`).
    AutoLod,
    /// Save a screenshot (the S key).
    Screenshot,
    /// Start or stop the light rotation (the L key).
    ToggleLights,
    /// The simulation's controls.
    Sim(SimAction),
    /// The animated cache's playback (Space, `,`, `.`).
    Play(PlayAction),
}

/// How a frame of an animated cache was shown, for the playback section.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FrameLoad {
    /// The frame.
    pub(crate) frame: u32,
    /// CPU wall time of showing it (reading the files, uploading or reloading), milliseconds.
    pub(crate) ms: f64,
    /// Positions replaced, or the session's hair reloaded.
    pub(crate) shown: Shown,
}

/// The simulation's part of a frame, for the timings.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct SimFrameInfo {
    /// Steps run for the frame (every character).
    pub(crate) steps: u64,
    /// CPU wall time from recording the first step to the GPU's end of the last (the session
    /// waits for it), milliseconds.
    pub(crate) wall_ms: Option<f64>,
    /// The simulation passes' GPU times for the frame (timestamps, summed over its substeps),
    /// `NotSupported` on a device without timestamps.
    pub(crate) gpu: Timings,
    /// Guides simulated.
    pub(crate) guides: usize,
    /// Strands drawn from them (guides and followers).
    pub(crate) strands: usize,
    /// GPU memory of the simulation.
    pub(crate) bytes: u64,
}

/// The last frame as the panel shows it.
#[derive(Clone, Debug, Default)]
pub(crate) struct FrameInfo {
    /// Technique that drew it.
    pub(crate) technique: &'static str,
    /// Size in pixels.
    pub(crate) size: [u32; 2],
    /// The newest per-pass GPU times (deferred: a frame or two behind), `None` before any.
    pub(crate) timings: Option<Timings>,
    /// CPU wall time of the render call, milliseconds.
    pub(crate) wall_ms: f64,
    /// Time between the last two frames shown, milliseconds.
    pub(crate) interval_ms: f64,
    /// GPU memory the technique holds.
    pub(crate) memory: Memory,
    /// The technique's own statistics in one line.
    pub(crate) detail: String,
    /// The simulation's steps for the frame, when simulating.
    pub(crate) simulation: Option<SimFrameInfo>,
}

/// What the panel shows besides the session.
pub(crate) struct View<'a> {
    /// The session (settings are read from it).
    pub(crate) session: &'a Session,
    /// The last frame.
    pub(crate) frame: Option<&'a FrameInfo>,
    /// What is loaded (inputs, or "built-in demo").
    pub(crate) source: &'a str,
    /// The adapter's name and backend.
    pub(crate) adapter: &'a str,
    /// Status line (the last action's outcome).
    pub(crate) status: &'a str,
    /// The last error, one line.
    pub(crate) error: Option<&'a str>,
    /// Whether the lights rotate.
    pub(crate) rotating: bool,
    /// The simulation's controls.
    pub(crate) sim: &'a SimControls,
    /// The animated cache's playback (one frame: no section).
    pub(crate) playback: &'a Playback,
    /// How its last frame was shown.
    pub(crate) frame_load: Option<&'a FrameLoad>,
}

/// Text fields and slider values being dragged, kept between frames.
#[derive(Debug, Default)]
pub(crate) struct PanelState {
    /// The Open field.
    pub(crate) open_path: String,
    /// The free `key=value` field.
    set_text: String,
    /// Slider values not yet applied (being dragged), by key.
    pending: HashMap<String, f64>,
    /// The technique whose sections were opened last.
    shown_technique: &'static str,
    /// The simulation's settings while a slider is dragged.
    sim_edit: Option<SimEdit>,
}

/// Draw the panel into the root `ui` and return what was asked for.
pub(crate) fn show(ui: &mut Ui, view: &View<'_>, state: &mut PanelState) -> Vec<Action> {
    let mut actions = Vec::new();
    let frame = egui::Frame::side_top_panel(ui.style()).fill(Color32::from_black_alpha(210));
    egui::Panel::right("tress-viewer-panel")
        .resizable(true)
        .default_size(330.0)
        .frame(frame)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                header(ui, view, state, &mut actions);
                status(ui, view);
                ui.separator();
                // A new technique opens its sections and closes the others.
                let technique = view.session.technique();
                let switched =
                    std::mem::replace(&mut state.shown_technique, technique) != technique;
                let mut form = Form {
                    pending: &mut state.pending,
                    actions: &mut actions,
                };
                settings(ui, view.session, view.frame, switched, &mut form);
                if view.playback.is_animated() {
                    egui::CollapsingHeader::new("playback")
                        .default_open(true)
                        .show(ui, |ui| {
                            playback::playback_section(
                                ui,
                                view.playback,
                                view.frame_load,
                                view.sim.enabled,
                                &mut actions,
                            );
                        });
                }
                egui::CollapsingHeader::new("simulation")
                    .default_open(view.sim.enabled)
                    .show(ui, |ui| {
                        simulation::simulation_section(
                            ui,
                            view.sim,
                            &mut state.sim_edit,
                            &mut actions,
                        );
                    });
                ui.separator();
                free_setting(ui, &mut state.set_text, &mut actions);
                ui.separator();
                frame_stats(ui, view.frame);
            });
        });
    actions
}

fn header(ui: &mut Ui, view: &View<'_>, state: &mut PanelState, actions: &mut Vec<Action>) {
    ui.heading("tress viewer");
    ui.label(RichText::new(view.adapter).small());
    ui.label(format!("loaded: {}", view.source));
    let current = view.session.technique();
    egui::ComboBox::new("technique", "technique (T)")
        .selected_text(current)
        .show_ui(ui, |ui| {
            for t in TechniqueKind::NAMES {
                if ui.selectable_label(t == current, t).clicked() && t != current {
                    actions.push(Action::Technique(t));
                }
            }
        });
    ui.horizontal(|ui| {
        let lights = if view.rotating {
            "stop lights (L)"
        } else {
            "rotate lights (L)"
        };
        if ui.button(lights).clicked() {
            actions.push(Action::ToggleLights);
        }
        if ui.button("screenshot (S)").clicked() {
            actions.push(Action::Screenshot);
        }
        if ui
            .button("reload shaders (R)")
            .on_hover_text(
                "Read the WGSL from the checkout (TRESS_SOURCE_DIR, the working directory's, or \
                 the one this binary was built from) and rebuild the session on it",
            )
            .clicked()
        {
            actions.push(Action::Rebuild);
        }
    });
    ui.horizontal(|ui| {
        let field = ui.add(
            egui::TextEdit::singleline(&mut state.open_path)
                .hint_text("scene.toml, hair files, cards.obj")
                .desired_width(210.0),
        );
        let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if (ui.button("Open").clicked() || enter) && !state.open_path.trim().is_empty() {
            let paths = state
                .open_path
                .split_whitespace()
                .map(PathBuf::from)
                .collect();
            actions.push(Action::Open(paths));
        }
    });
    egui::CollapsingHeader::new("keys").show(ui, |ui| {
        ui.label(
            "left drag: orbit   middle drag: pan   wheel: zoom\n\
             simulating: Shift + left drag moves the head, Ctrl + left drag turns it\n\
             T: next technique   L: rotate lights   S: screenshot\n\
             R: reload the WGSL from the checkout, rebuild the session\n\
             P: pause or run the simulation\n\
             Space: play or pause an animated cache   , / .: previous / next frame\n\
             U: hide this panel   Q / Esc: quit   drop files to open them",
        );
    });
}

fn free_setting(ui: &mut Ui, text: &mut String, actions: &mut Vec<Action>) {
    ui.label("any setting (key=value, as --set):");
    ui.horizontal(|ui| {
        let field = ui.add(
            egui::TextEdit::singleline(text)
                .hint_text("strands.shadow_width_px=2")
                .desired_width(210.0),
        );
        let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if (ui.button("Set").clicked() || enter) && text.contains('=') {
            actions.push(Action::Set(text.trim().to_string()));
        }
    });
}

fn frame_stats(ui: &mut Ui, frame: Option<&FrameInfo>) {
    let Some(f) = frame else {
        ui.label("no frame yet");
        return;
    };
    ui.strong(format!("{} at {}x{}", f.technique, f.size[0], f.size[1]));
    ui.label(format!(
        "frame interval {:.1} ms ({:.1} fps); render call {:.1} ms CPU wall",
        f.interval_ms,
        if f.interval_ms > 0.0 {
            1e3 / f.interval_ms
        } else {
            0.0
        },
        f.wall_ms
    ));
    match &f.timings {
        Some(Timings::Passes(passes)) => {
            egui::Grid::new("timings").striped(true).show(ui, |ui| {
                for p in passes {
                    ui.label(p.name);
                    ui.label(format!("{:.3} ms", p.ms));
                    ui.end_row();
                }
                ui.strong("GPU total");
                ui.strong(format!(
                    "{:.3} ms",
                    passes.iter().map(|p| p.ms).sum::<f64>()
                ));
                ui.end_row();
            });
        }
        Some(Timings::NotSupported) => {
            ui.label(format!(
                "no GPU timestamps on this device: CPU wall time {:.2} ms",
                f.wall_ms
            ));
        }
        None => {
            ui.label(format!(
                "GPU timings not back yet: CPU wall time {:.2} ms",
                f.wall_ms
            ));
        }
    }
    if let Some(s) = &f.simulation {
        simulation_stats(ui, s);
    }
    ui.label("GPU memory");
    let sim_bytes = f.simulation.as_ref().map(|s| s.bytes);
    egui::Grid::new("memory").striped(true).show(ui, |ui| {
        for (name, bytes) in f.memory.rows() {
            ui.label(name);
            ui.label(mib(bytes));
            ui.end_row();
        }
        if let Some(bytes) = sim_bytes {
            ui.label("simulation");
            ui.label(mib(bytes));
            ui.end_row();
        }
        ui.strong("total");
        ui.strong(mib(f.memory.total() + sim_bytes.unwrap_or(0)));
        ui.end_row();
    });
    if !f.detail.is_empty() {
        ui.label(&f.detail);
    }
}

/// The simulation's frame: its passes' GPU times (this frame's, not deferred) or, on a device
/// without timestamps, the wall time of its steps, labelled as such; guides and strands.
fn simulation_stats(ui: &mut Ui, s: &SimFrameInfo) {
    ui.label(simulation_line(s));
    if let Timings::Passes(passes) = &s.gpu {
        egui::Grid::new("simulation-timings")
            .striped(true)
            .show(ui, |ui| {
                for p in passes {
                    ui.label(p.name);
                    ui.label(format!("{:.3} ms", p.ms));
                    ui.end_row();
                }
                ui.strong("simulation GPU");
                ui.strong(format!(
                    "{:.3} ms",
                    passes.iter().map(|p| p.ms).sum::<f64>()
                ));
                ui.end_row();
            });
    }
}

/// The simulation's frame in one line: steps, their wall time (the CPU's clock from recording
/// the first step to the GPU's end of the last; the GPU's own time is in the passes' timestamps,
/// where the device has them), guides and strands.
fn simulation_line(s: &SimFrameInfo) -> String {
    let wall = match s.wall_ms {
        Some(ms) => format!("{ms:.3} ms CPU wall, GPU waited for"),
        None => "not timed".into(),
    };
    let gpu = match &s.gpu {
        Timings::Passes(_) => "",
        Timings::NotSupported => " (no GPU timestamps on this device: wall time only)",
    };
    format!(
        "simulation: {} step{} in {wall}{gpu}; {} guides, {} strands",
        s.steps,
        if s.steps == 1 { "" } else { "s" },
        s.guides,
        s.strands
    )
}

fn mib(bytes: u64) -> String {
    format!("{:.2} MiB", bytes as f64 / f64::from(1 << 20))
}

fn status(ui: &mut Ui, view: &View<'_>) {
    if let Some(e) = view.error {
        ui.colored_label(Color32::LIGHT_RED, e);
    }
    if !view.status.is_empty() {
        ui.label(RichText::new(view.status).small());
    }
}

/// The technique's statistics in one line.
pub(crate) fn detail(d: &FrameDetail) -> String {
    match d {
        FrameDetail::Strands(s) => {
            let mut line = format!("{} segments, PPLL capacity {}", s.segments, s.ppll_capacity);
            if let Some(g) = &s.gpu {
                line += &format!(" ({} used, {} dropped)", g.ppll.used, g.ppll.dropped);
                if let Some(o) = g.oit {
                    line += &format!(
                        ", OIT {}: {} fragments, {} lost",
                        o.kind, o.fragments, o.lost
                    );
                }
            }
            if let Some(v) = &s.volume {
                line += &format!(", volume {}³", v.resolution);
            }
            line + &format!(", lod {:.2}", s.lod)
        }
        FrameDetail::Patches(p) => format!("{} triangles, {}", p.triangles, p.scheme.name()),
        FrameDetail::Satf(s) => {
            let mut line = format!(
                "{} clusters, {} layers, {} HSVs",
                s.clusters, s.layers, s.hsvs
            );
            let skipped = s.skipped_strands;
            if skipped.total() > 0 {
                line += &format!(
                    ", {} strands skipped ({} too short, {} degenerate)",
                    skipped.total(),
                    skipped.too_short,
                    skipped.degenerate
                );
            }
            line
        }
    }
}
