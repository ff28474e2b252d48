//! The egui side panel: technique, the current technique's settings by their scene keys, lights,
//! opening files, the last frame's per-pass timings and memory, and the status line.
//!
//! The panel never changes the session itself: it returns [`Action`]s (`key=value` settings,
//! technique switches, files to open) that the viewer applies after the UI pass, and shows the
//! values the session holds, so a setting the session refuses snaps back and its error shows.
//! Sliders of settings that only change uniforms apply while dragging; those that rebuild GPU
//! resources (volume resolution, patches, SATF) apply when released.

use std::collections::HashMap;
use std::ops::RangeInclusive;
use std::path::PathBuf;

use egui::{Color32, RichText, Ui};
use tress_render::satf::{Reflectance, ShadowApprox};
use tress_render::scene_setup::{patch_settings, satf_settings};
use tress_render::session::{Memory, Session, TECHNIQUES};
use tress_render::{StrandSettings, Timings, VolumeSettings};

/// What the user asked for in the panel, applied by the viewer after the UI pass.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Action {
    /// A dotted `key=value` setting ([`Session::set`]).
    Set(String),
    /// Switch technique.
    Technique(&'static str),
    /// Switch to the next technique in [`TECHNIQUES`] order that can draw (the T key).
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
}

/// When a slider's value reaches the session.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Apply {
    /// On every change (settings that only change uniforms).
    Live,
    /// When the slider is released (settings that rebuild GPU resources).
    Released,
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
            for t in TECHNIQUES {
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
             T: next technique   L: rotate lights   S: screenshot\n\
             R: reload the WGSL from the checkout, rebuild the session\n\
             U: hide this panel   Q / Esc: quit   drop files to open them",
        );
    });
}

/// Sliders, checkboxes and combos that turn into `key=value` actions.
struct Form<'a> {
    pending: &'a mut HashMap<String, f64>,
    actions: &'a mut Vec<Action>,
}

/// The last part of a dotted key, as the widget's label.
fn short(key: &str) -> &str {
    key.rsplit('.').next().unwrap_or(key)
}

impl Form<'_> {
    #[allow(clippy::too_many_arguments)]
    fn slider(
        &mut self,
        ui: &mut Ui,
        key: &str,
        value: f64,
        range: RangeInclusive<f64>,
        log: bool,
        integer: bool,
        apply: Apply,
    ) {
        let mut v = self.pending.get(key).copied().unwrap_or(value);
        let mut slider = egui::Slider::new(&mut v, range)
            .logarithmic(log)
            .text(short(key));
        if integer {
            slider = slider.integer();
        }
        let response = ui.add(slider).on_hover_text(key);
        if response.changed() {
            self.pending.insert(key.to_string(), v);
        }
        // Not dragged: released, or changed by keyboard or typing.
        let done = !response.dragged();
        if let Some(&p) = self.pending.get(key)
            && (done || (apply == Apply::Live && response.changed()))
        {
            let text = if integer {
                format!("{key}={}", p.round() as i64)
            } else {
                // Debug always writes a TOML float (`2.0`, `1e-5`).
                format!("{key}={:?}", p as f32)
            };
            self.actions.push(Action::Set(text));
            if done {
                self.pending.remove(key);
            }
        }
    }

    fn float(
        &mut self,
        ui: &mut Ui,
        key: &str,
        value: f32,
        range: RangeInclusive<f64>,
        apply: Apply,
    ) {
        self.slider(ui, key, value.into(), range, false, false, apply);
    }

    fn log_float(
        &mut self,
        ui: &mut Ui,
        key: &str,
        value: f32,
        range: RangeInclusive<f64>,
        apply: Apply,
    ) {
        self.slider(ui, key, value.into(), range, true, false, apply);
    }

    fn int(&mut self, ui: &mut Ui, key: &str, value: u32, range: RangeInclusive<u32>, log: bool) {
        let range = f64::from(*range.start())..=f64::from(*range.end());
        self.slider(ui, key, value.into(), range, log, true, Apply::Released);
    }

    fn check(&mut self, ui: &mut Ui, key: &str, value: bool) {
        let mut v = value;
        if ui.checkbox(&mut v, short(key)).on_hover_text(key).changed() {
            self.actions.push(Action::Set(format!("{key}={v}")));
        }
    }

    fn choice(&mut self, ui: &mut Ui, key: &str, value: &str, options: &[&str]) {
        let mut chosen = None;
        egui::ComboBox::new(key, short(key))
            .selected_text(value)
            .show_ui(ui, |ui| {
                for o in options {
                    if ui.selectable_label(*o == value, *o).clicked() && *o != value {
                        chosen = Some(*o);
                    }
                }
            });
        if let Some(o) = chosen {
            self.actions.push(Action::Set(format!("{key}=\"{o}\"")));
        }
    }
}

fn settings(
    ui: &mut Ui,
    session: &Session,
    frame: Option<&FrameInfo>,
    switched: bool,
    form: &mut Form<'_>,
) {
    let technique = session.technique();
    let prepared = session.prepared();
    let section = |name: &str, used_by: &[&str]| {
        let open = used_by.contains(&technique);
        egui::CollapsingHeader::new(name)
            .default_open(open)
            .open(switched.then_some(open))
    };
    section("strands", &["strands", "hybrid"])
        .show(ui, |ui| strand_settings(ui, &prepared.strands, form));
    section("volume", &["volume", "hybrid"])
        .show(ui, |ui| volume_settings(ui, &prepared.volume, form));
    section("hybrid", &["hybrid"]).show(ui, |ui| {
        let h = &prepared.hybrid;
        let mut fixed = h.lod.is_some();
        if ui
            .checkbox(&mut fixed, "fixed lod (else from distance)")
            .on_hover_text("hybrid.lod")
            .changed()
        {
            form.actions.push(if fixed {
                Action::Set("hybrid.lod=0.5".into())
            } else {
                Action::AutoLod
            });
        }
        if let Some(lod) = h.lod {
            form.float(ui, "hybrid.lod", lod, 0.0..=1.0, Apply::Live);
        }
        form.float(ui, "hybrid.near", h.near, 0.0..=1000.0, Apply::Live);
        form.float(ui, "hybrid.far", h.far, 0.0..=2000.0, Apply::Live);
        form.choice(
            ui,
            "hybrid.transition",
            h.transition.name(),
            &["alpha", "dither"],
        );
        if let Some(f) = frame.filter(|f| f.technique == "hybrid") {
            ui.label(&f.detail);
        }
    });
    section("patches", &["patches"]).show(ui, |ui| patch_section(ui, session, form));
    section("satf", &["satf"]).show(ui, |ui| satf_section(ui, session, form));
    egui::CollapsingHeader::new("hair fibre (marschner)")
        .show(ui, |ui| fiber_section(ui, session, form));
    egui::CollapsingHeader::new("lights").show(ui, |ui| {
        for (i, light) in session.scene().lights.iter().enumerate() {
            form.float(
                ui,
                &format!("light.{i}.intensity"),
                light.intensity,
                0.0..=4.0,
                Apply::Live,
            );
        }
    });
}

fn strand_settings(ui: &mut Ui, s: &StrandSettings, form: &mut Form<'_>) {
    form.choice(
        ui,
        "strands.oit",
        s.oit.name(),
        &["auto", "ppll", "shortcut"],
    );
    form.int(
        ui,
        "strands.k",
        s.k,
        1..=tress_render::strands::MAX_K,
        false,
    );
    form.int(
        ui,
        "strands.shortcut_k",
        s.shortcut_k,
        1..=tress_render::strands::MAX_SHORTCUT_K,
        false,
    );
    form.log_float(ui, "strands.width_px", s.width_px, 0.25..=16.0, Apply::Live);
    form.float(ui, "strands.alpha", s.alpha, 0.0..=1.0, Apply::Live);
    form.choice(
        ui,
        "strands.shading",
        s.shading.name(),
        &["kajiya-kay", "scheuermann", "marschner"],
    );
    form.check(ui, "strands.coverage", s.coverage);
    form.choice(
        ui,
        "strands.thickness_fade",
        s.thickness_fade.name(),
        &["off", "tip", "projected"],
    );
    form.check(ui, "strands.shadows", s.shadows);
    form.choice(
        ui,
        "strands.shadow_mode",
        s.shadow_mode.name(),
        &["adsm", "volume"],
    );
    form.int(
        ui,
        "strands.shadow_map_size",
        s.shadow_map_size,
        64..=4096,
        true,
    );
    form.float(ui, "strands.shadow_r", s.shadow_r, 0.0..=20.0, Apply::Live);
    form.float(
        ui,
        "strands.shadow_alpha",
        s.shadow_alpha,
        0.0..=1.0,
        Apply::Live,
    );
    form.int(
        ui,
        "strands.pcf_radius",
        s.pcf_radius,
        0..=tress_render::strands::MAX_PCF_RADIUS,
        false,
    );
    form.float(
        ui,
        "strands.shadow_bias",
        s.shadow_bias,
        0.0..=2.0,
        Apply::Live,
    );
    form.check(ui, "strands.ao", s.ao);
}

fn volume_settings(ui: &mut Ui, v: &VolumeSettings, form: &mut Form<'_>) {
    form.int(ui, "volume.resolution", v.resolution, 16..=512, true);
    form.choice(
        ui,
        "volume.voxelize",
        match v.voxelize {
            tress_render::VoxelizeMode::Segments => "segments",
            tress_render::VoxelizeMode::Vertices => "vertices",
        },
        &["segments", "vertices"],
    );
    form.int(ui, "volume.steps", v.steps, 8..=2048, true);
    form.log_float(ui, "volume.iso", v.iso, 0.05..=64.0, Apply::Live);
    form.check(ui, "volume.skip_empty", v.skip_empty);
    form.check(ui, "volume.shadows", v.shadows);
    form.choice(
        ui,
        "volume.occlusion",
        v.occlusion.name(),
        &["adsm", "strands"],
    );
    form.float(
        ui,
        "volume.shadow_alpha",
        v.shadow_alpha,
        0.0..=1.0,
        Apply::Live,
    );
    form.log_float(
        ui,
        "volume.strand_width",
        v.strand_width,
        1e-4..=0.1,
        Apply::Live,
    );
    form.check(ui, "volume.ao", v.ao);
    form.log_float(
        ui,
        "volume.ao_radius",
        v.ao_radius,
        0.05..=20.0,
        Apply::Live,
    );
    form.int(ui, "volume.ao_samples", v.ao_samples, 1..=64, false);
    form.float(
        ui,
        "volume.ao_intensity",
        v.ao_intensity,
        0.0..=4.0,
        Apply::Live,
    );
}

/// The keys of [`fiber_section`].
const FIBER_KEYS: [&str; 6] = [
    "hair.0.material.eumelanin",
    "hair.0.material.pheomelanin",
    "hair.0.material.beta_m",
    "hair.0.material.beta_n",
    "hair.0.material.alpha_deg",
    "hair.0.material.eta",
];

/// The physically based fibre of the first hair entry (`[hair.material]`), which
/// `strands.shading` and `patches.shading = "marschner"` shade: melanin (when the material gives
/// its colour that way; `sigma_a` and `target_color` are left to the text field), roughness,
/// tilt and index.
fn fiber_section(ui: &mut Ui, session: &Session, form: &mut Form<'_>) {
    let Some(m) = session.scene().hair.first().map(|h| &h.material) else {
        ui.label("no hair");
        return;
    };
    if m.sigma_a.is_none() && m.target_color.is_none() {
        let eumelanin = m.eumelanin.unwrap_or(tress_scene::DEFAULT_EUMELANIN);
        let pheomelanin = m.pheomelanin.unwrap_or(tress_scene::DEFAULT_PHEOMELANIN);
        form.float(ui, FIBER_KEYS[0], eumelanin, 0.0..=8.0, Apply::Released);
        form.float(ui, FIBER_KEYS[1], pheomelanin, 0.0..=4.0, Apply::Released);
    }
    form.float(ui, FIBER_KEYS[2], m.beta_m, 0.01..=1.0, Apply::Released);
    form.float(ui, FIBER_KEYS[3], m.beta_n, 0.01..=1.0, Apply::Released);
    form.float(
        ui,
        FIBER_KEYS[4],
        m.alpha_deg,
        -10.0..=10.0,
        Apply::Released,
    );
    form.float(ui, FIBER_KEYS[5], m.eta, 1.01..=2.5, Apply::Released);
}

fn patch_section(ui: &mut Ui, session: &Session, form: &mut Form<'_>) {
    let p = match patch_settings(session.scene()) {
        Ok(p) => p,
        Err(e) => {
            ui.colored_label(Color32::LIGHT_RED, e.to_string());
            return;
        }
    };
    ui.label(RichText::new("changes rebuild the patches (and their AO bake)").small());
    form.choice(ui, "patches.scheme", p.scheme.name(), &["4-pass", "3-pass"]);
    form.choice(
        ui,
        "patches.shading",
        p.shading.name(),
        &["scheuermann", "marschner"],
    );
    form.float(
        ui,
        "patches.alpha_ref",
        p.alpha_ref,
        0.01..=1.0,
        Apply::Released,
    );
    form.float(
        ui,
        "patches.min_alpha",
        p.min_alpha,
        0.0..=0.99,
        Apply::Released,
    );
    form.check(ui, "patches.ambient_occlusion", p.ambient_occlusion);
    form.check(ui, "patches.mipmaps", p.mipmaps);
    let l = &p.lighting;
    form.float(
        ui,
        "patches.primary_shift",
        l.primary_shift,
        -1.0..=1.0,
        Apply::Released,
    );
    form.log_float(
        ui,
        "patches.primary_exponent",
        l.primary_exponent,
        1.0..=1024.0,
        Apply::Released,
    );
    form.float(
        ui,
        "patches.secondary_shift",
        l.secondary_shift,
        -1.0..=1.0,
        Apply::Released,
    );
    form.log_float(
        ui,
        "patches.secondary_exponent",
        l.secondary_exponent,
        1.0..=1024.0,
        Apply::Released,
    );
}

fn satf_section(ui: &mut Ui, session: &Session, form: &mut Form<'_>) {
    let s = match satf_settings(session.scene()) {
        Ok(s) => s.settings,
        Err(e) => {
            ui.colored_label(Color32::LIGHT_RED, e.to_string());
            return;
        }
    };
    ui.label(RichText::new("changes rebuild the clusters and maps").small());
    let r = Apply::Released;
    form.float(ui, "satf.k_threshold", s.lookup.k_threshold, 0.0..=2.0, r);
    form.float(ui, "satf.k_shadow", s.k_shadow, 0.0..=4.0, r);
    form.choice(
        ui,
        "satf.shadow_approx",
        match s.shadow_approx {
            ShadowApprox::Exponential => "exponential",
            ShadowApprox::Linear => "linear",
        },
        &["exponential", "linear"],
    );
    form.check(ui, "satf.local_shadows", s.local_shadows);
    form.check(ui, "satf.cluster_shadows", s.cluster_shadows);
    form.float(ui, "satf.shadow_opacity", s.shadow_opacity, 0.0..=1.0, r);
    let l = &s.lighting;
    form.float(ui, "satf.k_dif", l.k_dif, 0.0..=2.0, r);
    form.float(ui, "satf.k_spe1", l.k_spe1, 0.0..=2.0, r);
    form.float(ui, "satf.k_spe2", l.k_spe2, 0.0..=2.0, r);
    form.log_float(ui, "satf.k_h", l.k_h, 1.0..=1024.0, r);
    form.float(ui, "satf.primary_shift", l.primary_shift, 0.0..=0.5, r);
    form.float(ui, "satf.secondary_shift", l.secondary_shift, 0.0..=0.5, r);
    form.choice(
        ui,
        "satf.reflectance",
        match s.reflectance {
            Reflectance::Straight => "straight",
            Reflectance::Premultiplied => "premultiplied",
        },
        &["straight", "premultiplied"],
    );
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
    ui.label("GPU memory");
    egui::Grid::new("memory").striped(true).show(ui, |ui| {
        for (name, bytes) in f.memory.rows() {
            ui.label(name);
            ui.label(mib(bytes));
            ui.end_row();
        }
        ui.strong("total");
        ui.strong(mib(f.memory.total()));
        ui.end_row();
    });
    if !f.detail.is_empty() {
        ui.label(&f.detail);
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The fibre section's keys are material keys a scene accepts, and each changes the fibre.
    #[test]
    fn fiber_keys_change_the_fibre() {
        let text = "[[hair]]\ngenerator = { style = \"straight\", strands = 4 }\n";
        let base = tress_scene::Scene::from_str(text, ".").unwrap();
        let fibre = |s: &tress_scene::Scene| s.hair[0].material.fiber().unwrap();
        for key in FIBER_KEYS {
            let mut scene = base.clone();
            let value = if key.ends_with("eta") { 1.3 } else { 0.5 };
            scene.apply_override(&format!("{key}={value}")).unwrap();
            assert_ne!(fibre(&scene), fibre(&base), "{key}");
        }
    }

    #[test]
    fn labels_are_the_last_key_part() {
        assert_eq!(short("strands.k"), "k");
        assert_eq!(short("light.0.intensity"), "intensity");
        assert_eq!(short("technique"), "technique");
    }
}
