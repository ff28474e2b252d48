//! [`Form`]: the panel's sliders, checkboxes and combos, each turning a change into a
//! `key=value` [`Action`] for the session.

use std::collections::HashMap;
use std::ops::RangeInclusive;

use egui::Ui;

use super::Action;

/// When a slider's value reaches the session.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Apply {
    /// On every change (settings that only change uniforms).
    Live,
    /// When the slider is released (settings that rebuild GPU resources).
    Released,
}

/// Sliders, checkboxes and combos that turn into `key=value` actions.
pub(super) struct Form<'a> {
    pub(super) pending: &'a mut HashMap<String, f64>,
    pub(super) actions: &'a mut Vec<Action>,
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

    pub(super) fn float(
        &mut self,
        ui: &mut Ui,
        key: &str,
        value: f32,
        range: RangeInclusive<f64>,
        apply: Apply,
    ) {
        self.slider(ui, key, value.into(), range, false, false, apply);
    }

    pub(super) fn log_float(
        &mut self,
        ui: &mut Ui,
        key: &str,
        value: f32,
        range: RangeInclusive<f64>,
        apply: Apply,
    ) {
        self.slider(ui, key, value.into(), range, true, false, apply);
    }

    pub(super) fn int(
        &mut self,
        ui: &mut Ui,
        key: &str,
        value: u32,
        range: RangeInclusive<u32>,
        log: bool,
    ) {
        let range = f64::from(*range.start())..=f64::from(*range.end());
        self.slider(ui, key, value.into(), range, log, true, Apply::Released);
    }

    pub(super) fn check(&mut self, ui: &mut Ui, key: &str, value: bool) {
        let mut v = value;
        if ui.checkbox(&mut v, short(key)).on_hover_text(key).changed() {
            self.actions.push(Action::Set(format!("{key}={v}")));
        }
    }

    pub(super) fn choice(&mut self, ui: &mut Ui, key: &str, value: &str, options: &[&str]) {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_are_the_last_key_part() {
        assert_eq!(short("strands.k"), "k");
        assert_eq!(short("light.0.intensity"), "intensity");
        assert_eq!(short("technique"), "technique");
    }
}
