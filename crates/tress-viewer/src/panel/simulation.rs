//! The panel's simulation section: on and off, pause, step, reset, the head's motion and the
//! live settings, as [`SimAction`]s for [`crate::sim_controls::SimControls`].

use std::ops::RangeInclusive;

use egui::{RichText, Ui};

use super::Action;
use crate::sim_controls::{
    DAMPING_MAX, HeadDrag, MotionChoice, SimAction, SimControls, SimEdit, WIND_MAX,
};

/// How the controls work, under the section.
const HELP: &str = "Shift + left drag moves the head in the view plane, Ctrl + left drag turns \
it (while simulating; plain drag still orbits). Time follows the clock, a frame counting at most \
0.1 s; the hair steps at rate_hz whatever the display does. Step runs one step of 1/rate_hz \
(paused). Reset and a new motion start again at 0 s. A changed setting applies when its slider \
is released: the simulation restarts with it, the hair at rest on the head where it is, the \
clock and the motion going on.";

/// The section; `pending` holds the edits of a slider being dragged.
pub(super) fn simulation_section(
    ui: &mut Ui,
    sim: &SimControls,
    pending: &mut Option<SimEdit>,
    actions: &mut Vec<Action>,
) {
    let mut push = |a: SimAction| actions.push(Action::Sim(a));
    ui.horizontal(|ui| {
        let mut on = sim.enabled;
        if ui
            .checkbox(&mut on, "simulate")
            .on_hover_text("simulate the hair on the GPU (strands, volume, hybrid, auto)")
            .changed()
        {
            push(SimAction::Enable(on));
        }
        ui.add_enabled_ui(sim.enabled, |ui| {
            let mut paused = sim.paused;
            if ui.toggle_value(&mut paused, "pause").changed() {
                push(SimAction::Pause(paused));
            }
            if ui
                .button("step")
                .on_hover_text("pause, then one step of 1/rate_hz seconds")
                .clicked()
            {
                push(SimAction::Step);
            }
            if ui
                .button("reset")
                .on_hover_text("start again at 0 s, the head back where it began")
                .clicked()
            {
                push(SimAction::Reset);
            }
        });
    });
    egui::ComboBox::new("simulation-motion", "head motion")
        .selected_text(sim.motion.name())
        .show_ui(ui, |ui| {
            for m in MotionChoice::ALL {
                if ui.selectable_label(m == sim.motion, m.name()).clicked() && m != sim.motion {
                    push(SimAction::Motion(m));
                }
            }
        });
    if sim.enabled {
        let rate = sim.rate_hz();
        ui.label(format!(
            "{:.2} s simulated at {rate} Hz{}",
            sim.time(),
            if sim.paused { ", paused" } else { "" }
        ));
        let drag = sim.drag();
        if drag != HeadDrag::default() {
            let t = drag.translation;
            ui.label(format!(
                "head dragged by ({:.1}, {:.1}, {:.1}), turned {:.0}°",
                t.x,
                t.y,
                t.z,
                drag.yaw.to_degrees()
            ));
        }
    }

    // The settings: applied on release (each change restarts the session's simulation).
    let mut e = pending.unwrap_or(sim.edit);
    let mut changed = false;
    let mut dragging = false;
    let mut slider =
        |ui: &mut Ui, v: &mut f32, range: RangeInclusive<f32>, label: &str, key: &str| {
            let r = ui
                .add(egui::Slider::new(v, range).text(label))
                .on_hover_text(key);
            changed |= r.changed();
            dragging |= r.dragged();
        };
    slider(
        ui,
        &mut e.local_stiffness,
        0.0..=1.0,
        "local stiffness",
        "simulation.local_stiffness",
    );
    slider(
        ui,
        &mut e.global_stiffness,
        0.0..=1.0,
        "global stiffness",
        "simulation.global_stiffness",
    );
    slider(
        ui,
        &mut e.damping,
        0.0..=DAMPING_MAX,
        "damping",
        "simulation.damping",
    );
    slider(
        ui,
        &mut e.wind_strength,
        0.0..=WIND_MAX,
        "wind",
        "simulation.wind.strength (world units a second)",
    );
    slider(
        ui,
        &mut e.wind_turbulence,
        0.0..=1.0,
        "turbulence",
        "simulation.wind.turbulence",
    );
    slider(
        ui,
        &mut e.wind_angle_deg,
        -180.0..=180.0,
        "wind heading °",
        "simulation.wind.direction turned about the vertical: 0° blows towards +x, 90° towards +z",
    );
    if changed {
        *pending = Some(e);
    }
    if !dragging
        && let Some(p) = pending.take()
        && p != sim.edit
    {
        push(SimAction::Edit(p));
    }
    ui.label(RichText::new(HELP).small());
}
