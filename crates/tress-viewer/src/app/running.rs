//! The running viewer's work ([`Running`]): an animated cache's frame shown (`playing.rs`), the
//! hair simulated to the frame's time (when on) and the frame rendered by the session into the
//! offscreen target, copied onto the window with the panel drawn over it; panel and key actions
//! applied to the session; the report at the end. The event handling that drives it is in
//! `app.rs`.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Result, anyhow};
use glam::Quat;
use tress_render::session::{Session, SessionOptions, TechniqueKind};

/// The techniques the viewer switches between, in order: the five, then `auto`.
const TECHNIQUES: [&str; 6] = TechniqueKind::NAMES;
use tress_render::{
    COLOR_FORMAT, DirectionalLight, OffscreenTargets, StatsReadback, TargetFormats, read_texture,
};
use winit::event_loop::ActiveEventLoop;
use winit::window::Window;

use crate::display::Display;
use crate::orbit::OrbitCamera;
use crate::panel::{self, Action, FrameInfo, PanelState, SimFrameInfo};
use crate::present::Presenter;
use crate::sim_controls::{Command, SimAction};
use crate::{ViewerOptions, ViewerReport, reload};

use super::*;

impl Running {
    pub(super) fn new(
        event_loop: &ActiveEventLoop,
        options: &ViewerOptions,
        loader: Option<SharedLoader>,
    ) -> Result<Self> {
        let [w, h] = options.size;
        let window = Arc::new(
            event_loop
                .create_window(
                    Window::default_attributes()
                        .with_title("tress view")
                        .with_inner_size(winit::dpi::PhysicalSize::new(w, h)),
                )
                .context("creating the window")?,
        );
        let display = Display::new(event_loop.owned_display_handle(), Arc::clone(&window))?;
        let ctx = &display.ctx;
        let size = display.size();

        let mut overrides = options.overrides.clone();
        if let Some(t) = &options.technique {
            overrides.push(format!("technique=\"{t}\""));
        }
        let session = new_session(
            ctx,
            &options.inputs,
            size,
            &overrides,
            loader.as_ref(),
            None,
        )?;
        let orbit = OrbitCamera::from_scene(&session.scene().camera);
        let targets = OffscreenTargets::new(ctx, size, COLOR_FORMAT)?;
        let sim = sim_controls(&session);
        let (animation, probe_error) = playing::animation_of(&session);
        let mut actions = Vec::new();
        if session
            .scene()
            .simulation_settings()
            .is_ok_and(|s| s.enabled)
        {
            // `[simulation] enabled = true`: the scene is meant to be seen moving.
            actions.push(Action::Sim(SimAction::Enable(true)));
        }

        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            window.theme(),
            Some(ctx.caps.max_texture_2d as usize),
        );
        let egui_renderer = egui_wgpu::Renderer::new(
            &ctx.device,
            display.format(),
            egui_wgpu::RendererOptions::default(),
        );
        let presenter = Presenter::new(&ctx.device, display.format());
        let format = display.format();
        tracing::info!(adapter = %ctx.adapter_info.name, surface = ?format, "tress view");
        Ok(Running {
            presenter,
            egui_ctx,
            egui_state,
            egui_renderer,
            session,
            source: describe(&options.inputs),
            orbit,
            targets,
            panel: PanelState::default(),
            frame: None,
            status: if animation.frames > 1 {
                format!("{} frames: Space plays, `,` / `.` step", animation.frames)
            } else {
                String::new()
            },
            error: probe_error,
            ui_visible: true,
            rotating: false,
            light_angle: 0.0,
            mouse: Mouse::default(),
            dropped: Vec::new(),
            actions,
            overrides: options.overrides.clone(),
            loader,
            sim,
            sim_frame: None,
            sim_hair: Vec::new(),
            sim_restart: false,
            modifiers: ModifiersState::empty(),
            playback: animation.playback(),
            animation,
            on_screen: None,
            frame_load: None,
            started: Instant::now(),
            last_frame: None,
            frames: 0,
            first_wall_ms: 0.0,
            wall_ms_sum: 0.0,
            interval_ms_sum: 0.0,
            window,
            display,
        })
    }

    /// Switch to the first technique after the current one in [`TECHNIQUES`] order that can
    /// draw this scene; those that cannot (SATF without a database, say) are skipped and named.
    pub(super) fn next_technique(&mut self) -> Result<String> {
        let ctx = &self.display.ctx;
        let i = TECHNIQUES
            .iter()
            .position(|t| *t == self.session.technique())
            .unwrap_or(0);
        let mut skipped = Vec::new();
        for step in 1..TECHNIQUES.len() {
            let t = TECHNIQUES[(i + step) % TECHNIQUES.len()];
            match self.session.set_technique(ctx, t) {
                Ok(()) if skipped.is_empty() => return Ok(format!("technique {t}")),
                Ok(()) => {
                    return Ok(format!("technique {t} (skipped {})", skipped.join("; ")));
                }
                Err(e) => skipped.push(format!("{t}: {e}")),
            }
        }
        Err(anyhow!(
            "no other technique can draw this scene ({})",
            skipped.join("; ")
        ))
    }

    /// The scene's lights, turned about the up axis by the rotation so far.
    pub(super) fn lights(&self) -> Vec<DirectionalLight> {
        let turn = Quat::from_axis_angle(self.orbit.up(), self.light_angle);
        self.session
            .lights()
            .iter()
            .map(|l| DirectionalLight {
                direction: turn * l.direction,
                ..*l
            })
            .collect()
    }

    /// Apply one action; failures become the panel's error line.
    pub(super) fn apply(&mut self, action: Action) {
        let result = self.try_apply(action);
        match result {
            Ok(Some(status)) => {
                self.status = status;
                self.error = None;
            }
            Ok(None) => self.error = None,
            Err(e) => self.error = Some(one_line(&e)),
        }
    }

    pub(super) fn try_apply(&mut self, action: Action) -> Result<Option<String>> {
        let ctx = &self.display.ctx;
        match action {
            Action::Set(kv) => {
                let hair = hair_key(&self.session);
                self.session.set(ctx, &kv).with_context(|| kv.clone())?;
                if kv.trim_start().starts_with("camera.") {
                    self.orbit = OrbitCamera::from_scene(&self.session.scene().camera);
                }
                // The hair files or their frame set: the playback starts from what loaded.
                let mut note = String::new();
                if hair != hair_key(&self.session) && kv.trim_start().starts_with("hair.") {
                    note = self.probe_animation();
                }
                // `simulation.*` or `head.motion.*`: the panel's edits start from the new
                // values, and a running simulation starts again with them.
                let scene = self.session.scene();
                let base = scene.simulation_settings()?;
                if !self.sim.same_scene(&base, scene.head.motion.as_ref()) {
                    self.sim.rebase(base, scene.head.motion.clone());
                    self.sim_restart = self.sim.enabled;
                }
                Ok(Some(format!("set {kv}{note}")))
            }
            Action::Sim(a) => {
                let command = self.sim.apply(a.clone());
                let started = self.apply_sim(command)?;
                Ok(started.or_else(|| self.sim_status(&a)))
            }
            Action::Play(a) => Ok(self.apply_play(a)),
            Action::NextTechnique => self.next_technique().map(Some),
            Action::Technique(t) => {
                self.session
                    .set_technique(ctx, t)
                    .with_context(|| format!("technique {t}"))?;
                Ok(Some(format!("technique {t}")))
            }
            Action::Open(paths) => {
                let size = self.display.size();
                let session = new_session(
                    ctx,
                    &paths,
                    size,
                    &self.overrides,
                    self.loader.as_ref(),
                    Some(self.session.technique()),
                )?;
                self.session = session;
                self.orbit = OrbitCamera::from_scene(&self.session.scene().camera);
                self.source = describe(&paths);
                self.frame = None;
                // A new scene: its own simulation settings, off unless it asks to simulate.
                self.sim = sim_controls(&self.session);
                self.sim_frame = None;
                if self.sim.settings().is_ok_and(|s| s.enabled) {
                    self.actions.push(Action::Sim(SimAction::Enable(true)));
                }
                let note = self.probe_animation();
                Ok(Some(format!("opened {}{note}", self.source)))
            }
            Action::Rebuild => {
                let checkout = reload::find_checkout();
                tress_render::shaders::set_source_dir(checkout.clone());
                self.rebuild(self.session.scene().clone())
                    .context("R: the session keeps its pipelines")?;
                Ok(Some(reload::report(checkout.as_deref())))
            }
            Action::AutoLod => {
                let mut scene = self.session.scene().clone();
                scene.hybrid.remove("lod");
                self.rebuild(scene)?;
                Ok(Some(
                    "hybrid.lod from the eye distance (session rebuilt)".into(),
                ))
            }
            Action::Screenshot => {
                let path = next_screenshot_path(Path::new("."));
                self.save(&path)?;
                Ok(Some(format!("saved {}", path.display())))
            }
            Action::ToggleLights => {
                self.rotating = !self.rotating;
                Ok(Some(
                    if self.rotating {
                        "lights rotating"
                    } else {
                        "lights still"
                    }
                    .into(),
                ))
            }
        }
    }

    /// Run a simulation command on the session; a start reports what is simulated. A start that
    /// fails turns the simulation off (the hair back at rest) and is the error.
    pub(super) fn apply_sim(&mut self, command: Command) -> Result<Option<String>> {
        let ctx = &self.display.ctx;
        let started = match command {
            Command::None => return Ok(None),
            Command::Stop => {
                self.session.stop_simulation(ctx)?;
                self.sim_frame = None;
                return Ok(Some("simulation off: the hair at rest".into()));
            }
            Command::Start { settings, motion } => self
                .session
                .start_simulation(ctx, settings, motion)
                .map(|()| true),
            Command::Restart { settings, motion } => self
                .session
                .start_simulation(ctx, settings, motion)
                .map(|()| false),
        };
        let fresh = match started {
            Ok(fresh) => fresh,
            Err(e) => {
                self.sim.stopped();
                self.sim_frame = None;
                if let Err(stop) = self.session.stop_simulation(ctx) {
                    tracing::warn!("stopping the simulation: {stop}");
                }
                return Err(anyhow::Error::from(e).context("simulation"));
            }
        };
        let sim = self
            .session
            .simulation()
            .context("the simulation did not start")?;
        if fresh {
            self.sim.started(sim.pivots().collect());
        }
        let (guides, strands) = sim.counts();
        self.sim_hair = hair_key(&self.session);
        self.sim_restart = false;
        Ok(Some(if fresh {
            format!("simulating {guides} guides of {strands} strands from 0 s")
        } else {
            format!(
                "simulation restarted with the new settings at {:.2} s ({guides} guides)",
                self.sim.time()
            )
        }))
    }

    /// The status line of a simulation action that did not start or stop anything.
    fn sim_status(&self, action: &SimAction) -> Option<String> {
        let off = !self.sim.enabled;
        Some(match action {
            SimAction::Pause(_) | SimAction::Step if off => "the simulation is off".into(),
            SimAction::Pause(true) => format!("simulation paused at {:.3} s", self.sim.time()),
            SimAction::Pause(false) => "simulation running".into(),
            SimAction::Step => format!(
                "one step: {:.4} s ({} Hz)",
                self.sim.time(),
                self.sim.rate_hz()
            ),
            SimAction::Motion(_) | SimAction::Edit(_) if off => {
                "kept for when the simulation starts".into()
            }
            _ => return None,
        })
    }

    /// A left drag of `(dx, dy)` pixels with Shift (the head moves in the view plane) or Ctrl
    /// (the head turns) while simulating; false when it is not the head's (an orbit).
    pub(super) fn drag_head(&mut self, dx: f32, dy: f32) -> bool {
        if self.modifiers.shift_key() {
            let (right, up, units_per_pixel) = self.orbit.view_plane(self.display.size()[1]);
            self.sim.drag_move(dx, dy, right, up, units_per_pixel)
        } else if self.modifiers.control_key() {
            self.sim.drag_turn(dx)
        } else {
            false
        }
    }

    /// The hair simulated to the frame's time, `dt` seconds of wall clock after the last frame
    /// (see [`crate::sim_controls`]); a session rebuilt or reloaded since the simulation started
    /// starts it again. A step that fails turns the simulation off: its error is the panel's
    /// (the run's, with `strict`).
    pub(super) fn simulate(&mut self, dt: f64, strict: bool) -> Result<()> {
        self.sim_frame = None;
        if self.sim.enabled
            && (self.sim_restart
                || self.session.simulation().is_none()
                || hair_key(&self.session) != self.sim_hair)
        {
            let command = self.sim.apply(SimAction::Reset);
            match self.apply_sim(command) {
                Ok(status) => self.status = status.unwrap_or_default(),
                Err(e) if strict => return Err(e),
                Err(e) => self.error = Some(one_line(&e)),
            }
        }
        let Some(t) = self.sim.advance(dt) else {
            return Ok(());
        };
        let ctx = &self.display.ctx;
        let sim = &self.sim;
        match self
            .session
            .simulate_to_with(ctx, t, true, |k, time| sim.head(k, time))
        {
            Ok(f) => {
                self.sim_frame = self.session.simulation().map(|s| {
                    let (guides, strands) = s.counts();
                    SimFrameInfo {
                        steps: f.steps,
                        wall_ms: f.wall_ms,
                        gpu: f.gpu.clone(),
                        guides,
                        strands,
                        bytes: s.bytes(),
                    }
                });
            }
            Err(e) => {
                self.sim.stopped();
                if let Err(stop) = self.session.stop_simulation(ctx) {
                    tracing::warn!("stopping the simulation: {stop}");
                }
                if strict {
                    return Err(anyhow::Error::from(e).context("simulation"));
                }
                self.error = Some(format!("simulation stopped: {e}"));
            }
        }
        Ok(())
    }

    /// A new session on `scene` as it is now (technique and settings kept).
    pub(super) fn rebuild(&mut self, scene: tress_scene::Scene) -> Result<()> {
        let options = SessionOptions {
            auto_frame: false,
            overrides: Vec::new(),
            satf_database: session_loader(self.loader.as_ref()),
            readback: StatsReadback::Deferred,
        };
        self.session = Session::new(&self.display.ctx, TargetFormats::default(), scene, options)?;
        self.frame = None;
        Ok(())
    }

    /// Write the last rendered frame as a PNG.
    /// Save what the window shows without the panel: the frame drawn by the presentation
    /// shader into a texture of the surface's format, read back (an 8-bit surface that is not
    /// sRGB holds the shader's encoded values, read as such).
    pub(super) fn save(&self, path: &Path) -> Result<()> {
        let ctx = &self.display.ctx;
        let format = self.display.format();
        let shot = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("viewer/screenshot"),
            size: self.targets.color.size(),
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = shot.create_view(&Default::default());
        let mut encoder = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("viewer/screenshot/encoder"),
            });
        self.presenter
            .draw(&ctx.device, &mut encoder, &self.targets.color_view, &view);
        ctx.queue.submit([encoder.finish()]);
        let mut image = read_texture(ctx, &shot)?;
        if !format.is_srgb() {
            for p in &mut image.pixels {
                for c in &mut p[..3] {
                    *c = tress_render::gpu::srgb_to_linear(*c);
                }
            }
        }
        image.save_png(path)?;
        Ok(())
    }

    /// One frame: UI, actions, render, present. With `strict` (a `--frames` run) a frame the
    /// session cannot render ends the run; otherwise its error shows in the panel.
    pub(super) fn redraw(&mut self, strict: bool) -> Result<()> {
        let now = Instant::now();
        let interval_ms = self
            .last_frame
            .map_or(0.0, |t| (now - t).as_secs_f64() * 1e3);
        if self.rotating {
            self.light_angle += LIGHT_RADIANS_PER_SECOND * (interval_ms * 1e-3) as f32;
        }

        // The panel (drawn from the previous frame's statistics).
        let mut actions = std::mem::take(&mut self.actions);
        let raw = self.egui_state.take_egui_input(&self.window);
        let adapter = format!(
            "{} ({:?})",
            self.display.ctx.adapter_info.name, self.display.ctx.adapter_info.backend
        );
        let view = panel::View {
            session: &self.session,
            frame: self.frame.as_ref(),
            source: &self.source,
            adapter: &adapter,
            status: &self.status,
            error: self.error.as_deref(),
            rotating: self.rotating,
            sim: &self.sim,
            playback: &self.playback,
            frame_load: self.frame_load.as_ref(),
        };
        let visible = self.ui_visible;
        let panel = &mut self.panel;
        let mut asked = Vec::new();
        let mut output = self.egui_ctx.run_ui(raw, |ui| {
            if visible {
                asked = panel::show(ui, &view, panel);
            }
        });
        // egui's texture changes, taken at once so that no early return drops them unapplied:
        // new texels now, frees after this frame's submission.
        {
            let ctx = &self.display.ctx;
            for (id, deltas) in output.textures_delta.set.drain() {
                for delta in deltas {
                    self.egui_renderer
                        .update_texture(&ctx.device, &ctx.queue, id, &delta);
                }
            }
        }
        let freed = std::mem::take(&mut output.textures_delta.free);
        self.egui_state
            .handle_platform_output(&self.window, output.platform_output);
        actions.extend(asked);
        if !self.dropped.is_empty() {
            actions.push(Action::Open(std::mem::take(&mut self.dropped)));
        }
        for a in actions {
            self.apply(a);
        }
        self.play(interval_ms * 1e-3, strict)?;
        self.simulate(interval_ms * 1e-3, strict)?;

        // The frame.
        let ctx = &self.display.ctx.clone();
        let size = self.display.size();
        if self.targets.size() != size {
            self.targets = OffscreenTargets::new(ctx, size, COLOR_FORMAT)?;
        }
        let camera = self.orbit.camera(size);
        let lights = self.lights();
        match self
            .session
            .render(ctx, &self.targets.targets(), &camera, Some(&lights))
        {
            Ok(f) => {
                let previous = self
                    .frame
                    .take()
                    .filter(|p| p.technique == f.technique)
                    .and_then(|p| p.timings);
                if self.frames == 0 {
                    self.first_wall_ms = f.wall_ms;
                } else {
                    self.wall_ms_sum += f.wall_ms;
                    self.interval_ms_sum += interval_ms;
                }
                self.frames += 1;
                self.frame = Some(FrameInfo {
                    technique: f.technique,
                    size: f.size,
                    timings: f.timings.clone().or(previous),
                    wall_ms: f.wall_ms,
                    interval_ms,
                    memory: f.memory,
                    detail: panel::detail(&f.detail),
                    simulation: self.sim_frame.clone(),
                });
            }
            Err(e) if strict => return Err(e.into()),
            Err(e) => self.error = Some(format!("render: {e}")),
        }
        self.last_frame = Some(now);

        // Onto the window, the panel over it.
        let device = &ctx.device;
        let queue = &ctx.queue;
        if let Some(surface) = self.display.acquire() {
            let view = surface.texture.create_view(&Default::default());
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("viewer/present/encoder"),
            });
            self.presenter
                .draw(device, &mut encoder, &self.targets.color_view, &view);
            let screen = egui_wgpu::ScreenDescriptor {
                size_in_pixels: size,
                pixels_per_point: output.pixels_per_point,
            };
            let jobs = self
                .egui_ctx
                .tessellate(output.shapes, output.pixels_per_point);
            let mut buffers =
                self.egui_renderer
                    .update_buffers(device, queue, &mut encoder, &jobs, &screen);
            {
                let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("viewer/egui/pass"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Load,
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                self.egui_renderer
                    .render(&mut pass.forget_lifetime(), &jobs, &screen);
            }
            buffers.push(encoder.finish());
            queue.submit(buffers);
            self.window.pre_present_notify();
            queue.present(surface);
        }
        for id in &freed {
            self.egui_renderer.free_texture(id);
        }
        Ok(())
    }

    pub(super) fn report(&self) -> ViewerReport {
        let later = f64::from(self.frames.saturating_sub(1).max(1));
        ViewerReport {
            frames: self.frames,
            technique: self.session.technique(),
            size: self.display.size(),
            adapter: self.display.ctx.adapter_info.name.clone(),
            first_frame_ms: self.first_wall_ms,
            mean_render_ms: self.wall_ms_sum / later,
            mean_interval_ms: self.interval_ms_sum / later,
            timings: self.frame.as_ref().and_then(|f| f.timings.clone()),
            seconds: self.started.elapsed().as_secs_f64(),
        }
    }
}

/// A session on `inputs` for a target of `size` pixels (the framing fits its aspect), with the
/// `--set` overrides. `keep` is the technique to stay with when the inputs are hair files, which
/// name none.
pub(super) fn new_session(
    ctx: &tress_render::GpuContext,
    inputs: &[PathBuf],
    size: [u32; 2],
    overrides: &[String],
    loader: Option<&SharedLoader>,
    keep: Option<&'static str>,
) -> Result<Session> {
    let (scene, auto_frame) = tress_render::session::scene_from_inputs(inputs)?;
    let hair_files = auto_frame && scene.technique == "strands";
    let mut all = vec![
        format!("output.width={}", size[0]),
        format!("output.height={}", size[1]),
    ];
    if let (true, Some(t)) = (hair_files, keep) {
        all.push(format!("technique=\"{t}\""));
    }
    all.extend(overrides.iter().cloned());
    let options = SessionOptions {
        auto_frame,
        overrides: all,
        satf_database: session_loader(loader),
        readback: StatsReadback::Deferred,
    };
    // Loading errors name the file; only the demo needs naming.
    let session = Session::new(ctx, TargetFormats::default(), scene, options);
    if inputs.is_empty() {
        Ok(session.context("the built-in demo")?)
    } else {
        Ok(session?)
    }
}
