//! The settings sections of the panel: one per technique (the scene keys of `[strands]`,
//! `[volume]`, `[hybrid]`, `[patches]`, `[satf]`), the hair fibre and the lights, each widget
//! showing the value the session holds.

use egui::{Color32, RichText, Ui};
use tress_render::satf::{Reflectance, ShadowApprox};
use tress_render::scene_setup::{patch_settings, satf_settings};
use tress_render::session::Session;
use tress_render::{StrandSettings, VolumeSettings};

use super::form::{Apply, Form};
use super::{Action, FrameInfo};

pub(super) fn settings(
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
    section("strands", &["strands", "hybrid", "auto"])
        .show(ui, |ui| strand_settings(ui, &prepared.strands, form));
    section("volume", &["volume", "hybrid", "auto"])
        .show(ui, |ui| volume_settings(ui, &prepared.volume, form));
    section("hybrid", &["hybrid", "auto"]).show(ui, |ui| {
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
        form.float(
            ui,
            "hybrid.auto_near_px",
            h.auto_near_px,
            0.0..=4000.0,
            Apply::Live,
        );
        form.float(
            ui,
            "hybrid.auto_far_px",
            h.auto_far_px,
            0.0..=4000.0,
            Apply::Live,
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
    form.choice(ui, "volume.opacity", v.opacity.name(), &["strands", "iso"]);
    form.choice(
        ui,
        "volume.highlights",
        v.highlights.name(),
        &["strands", "mean_tangent"],
    );
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
    let p = match patch_settings(session.scene(), session.prepared().first_hair()) {
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
    let s = match satf_settings(session.scene(), session.prepared().first_hair()) {
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
}
