//! The window's GPU side: one adapter that can both run the renderer and present to the window,
//! its device wrapped in a [`GpuContext`], and the window's surface.
//!
//! The adapter is chosen like [`GpuContext::headless`] chooses one (`WGPU_BACKEND`,
//! `TRESS_ADAPTER`, [`ContextOptions::from_env`]), among those that can present to the window,
//! and checked with [`check_capabilities`] before a device is opened with timestamps when
//! available and the adapter's full limits, as the headless context does.

use std::sync::Arc;

use anyhow::{Context as _, Result, anyhow};
use tress_render::gpu::check_capabilities;
use tress_render::{ContextOptions, GpuContext};
use winit::window::Window;

/// The window's surface and the context that renders and presents.
pub(crate) struct Display {
    pub(crate) ctx: GpuContext,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    /// Configure the surface again before the next frame (it was suboptimal).
    reconfigure: bool,
}

impl Display {
    /// Open the adapter and device for `window` (see the module docs) and configure its surface.
    pub(crate) fn new(
        display_handle: winit::event_loop::OwnedDisplayHandle,
        window: Arc<Window>,
    ) -> Result<Self> {
        pollster::block_on(Self::new_async(display_handle, window))
    }

    async fn new_async(
        display_handle: winit::event_loop::OwnedDisplayHandle,
        window: Arc<Window>,
    ) -> Result<Self> {
        let options = ContextOptions::from_env();
        let mut desc =
            wgpu::InstanceDescriptor::new_with_display_handle(Box::new(display_handle)).with_env();
        if let Some(b) = options.backends {
            desc.backends = b;
        }
        let backends = desc.backends;
        let instance = wgpu::Instance::new(desc);
        let size = window.inner_size();
        let surface = instance
            .create_surface(window)
            .context("creating the window's surface")?;
        let adapters = instance.enumerate_adapters(backends).await;
        let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
        let adapter = match &options.adapter_name {
            Some(name) => {
                let wanted = name.to_lowercase();
                adapters.into_iter().find(|a| {
                    a.get_info().name.to_lowercase().contains(&wanted)
                        && a.is_surface_supported(&surface)
                })
            }
            None => instance
                .request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: options.power_preference,
                    compatible_surface: Some(&surface),
                    ..Default::default()
                })
                .await
                .ok(),
        }
        .ok_or_else(|| {
            anyhow!(
                "no GPU adapter{} can present to the window (adapters: {}; set {} to pick one)",
                options
                    .adapter_name
                    .as_ref()
                    .map(|n| format!(" whose name contains `{n}`"))
                    .unwrap_or_default(),
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                },
                tress_render::gpu::ADAPTER_ENV,
            )
        })?;
        let info = adapter.get_info();
        check_capabilities(
            &info.name,
            adapter.features(),
            &adapter.limits(),
            &adapter.get_downlevel_capabilities(),
        )?;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("viewer/device"),
                required_features: adapter.features() & wgpu::Features::TIMESTAMP_QUERY,
                required_limits: adapter.limits(),
                experimental_features: wgpu::ExperimentalFeatures::disabled(),
                memory_hints: wgpu::MemoryHints::Performance,
                trace: wgpu::Trace::Off,
            })
            .await
            .context("opening the GPU device")?;
        device.on_uncaptured_error(Arc::new(|e: wgpu::Error| {
            tracing::error!("uncaptured wgpu error: {e}");
        }));
        let ctx = GpuContext::from_device(&adapter, device, queue)?;

        let caps = surface.get_capabilities(&adapter);
        // egui blends in gamma space, so a plain 8-bit format is preferred; the presenter
        // encodes sRGB itself then.
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| {
                matches!(
                    f,
                    wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Rgba8Unorm
                )
            })
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| anyhow!("the window's surface supports no format on {}", info.name))?;
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            color_space: wgpu::SurfaceColorSpace::Auto,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: vec![],
        };
        surface.configure(&ctx.device, &config);
        Ok(Display {
            ctx,
            surface,
            config,
            reconfigure: false,
        })
    }

    /// The surface's format.
    pub(crate) fn format(&self) -> wgpu::TextureFormat {
        self.config.format
    }

    /// The surface's size in pixels.
    pub(crate) fn size(&self) -> [u32; 2] {
        [self.config.width, self.config.height]
    }

    /// Follow a window resize (zero sizes, a minimized window, are ignored).
    pub(crate) fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 || [width, height] == self.size() {
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&self.ctx.device, &self.config);
    }

    /// The next surface texture, or `None` when this frame cannot be shown (the surface was
    /// reconfigured or is occluded; the caller draws again later).
    pub(crate) fn acquire(&mut self) -> Option<wgpu::SurfaceTexture> {
        if std::mem::take(&mut self.reconfigure) {
            self.surface.configure(&self.ctx.device, &self.config);
        }
        match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) => Some(t),
            wgpu::CurrentSurfaceTexture::Suboptimal(t) => {
                // Shown as it is (configuring while it lives would panic); configured again
                // before the next frame.
                self.reconfigure = true;
                Some(t)
            }
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(&self.ctx.device, &self.config);
                None
            }
            other => {
                tracing::debug!("skipping a frame: {other:?}");
                None
            }
        }
    }
}
