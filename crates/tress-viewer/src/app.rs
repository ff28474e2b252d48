//! The window's event loop: input to camera, head drag, keys and panel actions, then each frame
//! an animated cache's frame shown and the hair simulated (when on), rendered by the session
//! into an offscreen target, copied onto the window and the panel drawn over it.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context as _, anyhow};
use tress_render::OffscreenTargets;
use tress_render::scene_setup::SatfScene;
use tress_render::session::{DatabaseLoader, Session};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{Key, ModifiersState, NamedKey};
use winit::window::{Window, WindowId};

use crate::display::Display;
use crate::orbit::OrbitCamera;
use crate::panel::{Action, FrameInfo, FrameLoad, PanelState, SimFrameInfo};
use crate::playback::{Animation, PlayAction, Playback};
use crate::present::Presenter;
use crate::sim_controls::{SimAction, SimControls};
use crate::{ViewerOptions, ViewerReport};

mod playing;
mod running;

/// Light rotation speed about the up axis, radians per second.
pub const LIGHT_RADIANS_PER_SECOND: f32 = 0.6;

/// Wheel pixels that count as one line (touchpads report pixels).
const PIXELS_PER_LINE: f64 = 40.0;

/// The SATF database loader, shared by every session the viewer builds (a new file, R).
type SharedLoader = Rc<RefCell<DatabaseLoader>>;

fn session_loader(shared: Option<&SharedLoader>) -> Option<DatabaseLoader> {
    shared.map(|l| {
        let l = Rc::clone(l);
        Box::new(move |s: &SatfScene| (l.borrow_mut())(s)) as DatabaseLoader
    })
}

/// The event loop's handler: the options until the window exists, then the running viewer.
pub(crate) struct App {
    options: ViewerOptions,
    loader: Option<SharedLoader>,
    running: Option<Running>,
    /// The error that ended the loop.
    pub(crate) fatal: Option<anyhow::Error>,
    /// What the run measured, once it ended.
    pub(crate) report: Option<ViewerReport>,
}

impl App {
    pub(crate) fn new(mut options: ViewerOptions) -> Self {
        let loader = options
            .satf_database
            .take()
            .map(|l| Rc::new(RefCell::new(l)));
        App {
            options,
            loader,
            running: None,
            fatal: None,
            report: None,
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        self.fatal.get_or_insert(e);
        event_loop.exit();
    }

    /// Save the exit screenshot, keep the report and stop.
    fn quit(&mut self, event_loop: &ActiveEventLoop) {
        if let Some(run) = &mut self.running {
            let saved = match &self.options.screenshot {
                Some(path) if run.frames > 0 => run.save(path),
                Some(path) => Err(anyhow!("{}: no frame was rendered", path.display())),
                None => Ok(()),
            };
            self.report = Some(run.report());
            if let Err(e) = saved {
                self.fatal.get_or_insert(e);
            }
        }
        event_loop.exit();
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        match Running::new(event_loop, &self.options, self.loader.clone()) {
            Ok(r) => self.running = Some(r),
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(run) = &mut self.running else {
            return;
        };
        let response = run.egui_state.on_window_event(&run.window, &event);
        // The pointer is over the panel (as of the last frame): clicks and the wheel are egui's.
        let over_panel = run.ui_visible && run.egui_ctx.is_pointer_over_egui();
        match event {
            WindowEvent::CloseRequested => self.quit(event_loop),
            WindowEvent::Resized(size) => run.display.resize(size.width, size.height),
            WindowEvent::RedrawRequested => {
                let limit = self.options.frames;
                match run.redraw(limit.is_some()) {
                    Ok(()) if limit.is_some_and(|n| run.frames >= n) => self.quit(event_loop),
                    Ok(()) => {}
                    Err(e) => self.fail(event_loop, e),
                }
            }
            WindowEvent::DroppedFile(path) => run.dropped.push(path),
            WindowEvent::KeyboardInput {
                event:
                    KeyEvent {
                        logical_key,
                        state: ElementState::Pressed,
                        repeat: false,
                        ..
                    },
                ..
            } if !response.consumed && !run.egui_ctx.egui_wants_keyboard_input() => {
                let action = match logical_key.as_ref() {
                    Key::Named(NamedKey::Escape) => None,
                    Key::Named(NamedKey::Space) => Some(Some(Action::Play(PlayAction::Toggle))),
                    Key::Character(c) => match c.to_lowercase().as_str() {
                        "q" => None,
                        "t" => Some(Some(Action::NextTechnique)),
                        "l" => Some(Some(Action::ToggleLights)),
                        "s" => Some(Some(Action::Screenshot)),
                        "r" => Some(Some(Action::Rebuild)),
                        "p" => Some(Some(Action::Sim(SimAction::Pause(!run.sim.paused)))),
                        "." => Some(Some(Action::Play(PlayAction::Step(1)))),
                        "," => Some(Some(Action::Play(PlayAction::Step(-1)))),
                        "u" => {
                            run.ui_visible = !run.ui_visible;
                            Some(None)
                        }
                        _ => Some(None),
                    },
                    _ => Some(None),
                };
                match action {
                    None => self.quit(event_loop),
                    Some(Some(a)) => run.actions.push(a),
                    Some(None) => {}
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                let pressed = state == ElementState::Pressed && !response.consumed && !over_panel;
                match (button, state) {
                    (MouseButton::Left, ElementState::Pressed) => run.mouse.left = pressed,
                    (MouseButton::Middle, ElementState::Pressed) => run.mouse.middle = pressed,
                    (MouseButton::Left, ElementState::Released) => run.mouse.left = false,
                    (MouseButton::Middle, ElementState::Released) => run.mouse.middle = false,
                    _ => {}
                }
            }
            WindowEvent::ModifiersChanged(m) => run.modifiers = m.state(),
            WindowEvent::CursorMoved { position, .. } => {
                if let Some((x, y)) = run.mouse.position {
                    let (dx, dy) = ((position.x - x) as f32, (position.y - y) as f32);
                    if run.mouse.left {
                        // Shift or Ctrl drags move the simulated head; plain drags orbit.
                        if !run.drag_head(dx, dy) {
                            run.orbit.orbit(dx, dy);
                        }
                    } else if run.mouse.middle {
                        run.orbit.pan(dx, dy, run.display.size()[1]);
                    }
                }
                run.mouse.position = Some((position.x, position.y));
            }
            WindowEvent::CursorLeft { .. } => run.mouse.position = None,
            WindowEvent::MouseWheel { delta, .. } if !response.consumed && !over_panel => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / PIXELS_PER_LINE) as f32,
                };
                run.orbit.zoom(lines);
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(run) = &self.running {
            run.window.request_redraw();
        }
    }
}

#[derive(Debug, Default)]
struct Mouse {
    position: Option<(f64, f64)>,
    left: bool,
    middle: bool,
}

/// The viewer once its window exists.
struct Running {
    window: Arc<Window>,
    display: Display,
    presenter: Presenter,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    session: Session,
    /// What is loaded, for the panel.
    source: String,
    orbit: OrbitCamera,
    targets: OffscreenTargets,
    panel: PanelState,
    frame: Option<FrameInfo>,
    status: String,
    error: Option<String>,
    ui_visible: bool,
    rotating: bool,
    light_angle: f32,
    mouse: Mouse,
    /// Files dropped since the last frame (opened together).
    dropped: Vec<PathBuf>,
    /// Actions from keys since the last frame.
    actions: Vec<Action>,
    /// `--set` overrides, applied to every scene opened.
    overrides: Vec<String>,
    loader: Option<SharedLoader>,
    /// The simulation's controls.
    sim: SimControls,
    /// The simulation's part of the last frame.
    sim_frame: Option<SimFrameInfo>,
    /// The hair and head the simulation was started on ([`hair_key`]).
    sim_hair: Vec<usize>,
    /// Start the simulation again before the next frame (its scene settings changed).
    sim_restart: bool,
    /// Keyboard modifiers held (Shift and Ctrl drags move the head).
    modifiers: ModifiersState,
    /// The hair entries read from animated files, their frames and rate.
    animation: Animation,
    /// The animated cache's playback controls.
    playback: Playback,
    /// The cache's frame the session shows, and what it was shown on.
    on_screen: Option<playing::OnScreen>,
    /// How the last frame of the cache was shown, for the panel.
    frame_load: Option<FrameLoad>,
    started: Instant,
    last_frame: Option<Instant>,
    frames: u32,
    first_wall_ms: f64,
    wall_ms_sum: f64,
    interval_ms_sum: f64,
}

/// An error as one line (its causes joined, control characters and runs of white space
/// turned into one space), for the panel.
fn one_line(e: &anyhow::Error) -> String {
    format!("{e:#}")
        .split(|c: char| c.is_whitespace() || c.is_control())
        .filter(|w| !w.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

/// `inputs` as the panel names them.
fn describe(inputs: &[PathBuf]) -> String {
    if inputs.is_empty() {
        "built-in demo".to_string()
    } else {
        inputs
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// What identifies the hair and head a session loaded: a setting that loads them again (a hair or
/// head key) gives new ones, on which the simulation must start again.
fn hair_key(session: &Session) -> Vec<usize> {
    let p = session.prepared();
    p.objects
        .iter()
        .map(|o| o.asset.positions().as_ptr() as usize)
        .chain(p.head.as_ref().map(|m| m.positions.as_ptr() as usize))
        .collect()
}

/// The simulation's controls for a session's scene (off).
fn sim_controls(session: &Session) -> SimControls {
    let scene = session.scene();
    // A scene's `[simulation]` is checked when it loads: an error here cannot happen.
    SimControls::new(
        scene.simulation_settings().unwrap_or_default(),
        scene.head.motion.clone(),
    )
}

/// `tress-view-NNNN.png` in `dir`, the first that does not exist.
pub(crate) fn next_screenshot_path(dir: &Path) -> PathBuf {
    (1..)
        .map(|i| dir.join(format!("tress-view-{i:04}.png")))
        .find(|p| !p.exists())
        .unwrap_or_else(|| dir.join("tress-view.png"))
}
