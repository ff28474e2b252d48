//! The headless GPU context: adapter choice, capability checks, device.

use std::sync::Arc;

use crate::RenderError;

/// Environment variable: pick the first adapter whose name contains this text (case-insensitive).
pub const ADAPTER_ENV: &str = "TRESS_ADAPTER";

/// The smallest storage-buffer binding the renderer works with (the PPLL head buffer of a
/// 1280x720 frame is 3.5 MiB; the node pool shrinks to what the device allows).
pub const MIN_STORAGE_BINDING_BYTES: u64 = 16 << 20;

/// Storage buffers the strand passes bind in one shader stage (vertex: vertices, segments;
/// fragment: PPLL heads, counters and the node pool's `strands::NODE_CHUNKS` = 4 bindings).
pub const MIN_STORAGE_BUFFERS_PER_STAGE: u32 = 6;

/// How to choose the adapter. [`ContextOptions::from_env`] reads `WGPU_BACKEND` (wgpu's own
/// variable: `vulkan`, `metal`, `dx12`, `gl`) and [`ADAPTER_ENV`].
#[derive(Clone, Debug, Default)]
pub struct ContextOptions {
    /// Backends to consider; all compiled-in backends when `None`.
    pub backends: Option<wgpu::Backends>,
    /// Case-insensitive substring of the adapter name; the default adapter when `None`.
    pub adapter_name: Option<String>,
    /// Power preference when no name is given.
    pub power_preference: wgpu::PowerPreference,
}

impl ContextOptions {
    /// Options from `WGPU_BACKEND` and `TRESS_ADAPTER` (both optional).
    pub fn from_env() -> Self {
        ContextOptions {
            backends: wgpu::Backends::from_env(),
            adapter_name: std::env::var(ADAPTER_ENV)
                .ok()
                .filter(|s| !s.trim().is_empty()),
            power_preference: wgpu::PowerPreference::from_env()
                .unwrap_or(wgpu::PowerPreference::HighPerformance),
        }
    }
}

/// What the device can do beyond the renderer's requirements, found once at start-up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Capabilities {
    /// GPU timestamp queries in passes (`Features::TIMESTAMP_QUERY`).
    pub timestamps: bool,
    /// Largest storage-buffer binding in bytes (128 MiB on lavapipe).
    pub max_storage_binding: u64,
    /// Largest buffer in bytes.
    pub max_buffer_size: u64,
    /// Largest 2D texture edge.
    pub max_texture_2d: u32,
}

/// Check an adapter or device against the renderer's needs: vertex- and fragment-stage storage
/// buffers (with atomics, which WGSL allows on every storage buffer) and the limits the strand
/// passes need. Timestamps are optional. The error names everything that is missing.
pub fn check_capabilities(
    adapter_name: &str,
    features: wgpu::Features,
    limits: &wgpu::Limits,
    downlevel: &wgpu::DownlevelCapabilities,
) -> Result<Capabilities, RenderError> {
    let mut missing = Vec::new();
    if !downlevel
        .flags
        .contains(wgpu::DownlevelFlags::VERTEX_STORAGE)
    {
        missing.push("storage buffers in vertex shaders (strand vertex pulling)".to_string());
    }
    if !downlevel
        .flags
        .contains(wgpu::DownlevelFlags::FRAGMENT_WRITABLE_STORAGE)
    {
        missing.push(
            "writable storage buffers and atomics in fragment shaders (per-pixel linked lists)"
                .to_string(),
        );
    }
    if limits.max_storage_buffers_per_shader_stage < MIN_STORAGE_BUFFERS_PER_STAGE {
        missing.push(format!(
            "{MIN_STORAGE_BUFFERS_PER_STAGE} storage buffers per shader stage (has {})",
            limits.max_storage_buffers_per_shader_stage
        ));
    }
    if limits.max_storage_buffer_binding_size < MIN_STORAGE_BINDING_BYTES {
        missing.push(format!(
            "storage buffer bindings of {MIN_STORAGE_BINDING_BYTES} bytes (has {})",
            limits.max_storage_buffer_binding_size
        ));
    }
    if limits.max_texture_array_layers < crate::MAX_LIGHTS as u32 {
        missing.push(format!("{} texture array layers", crate::MAX_LIGHTS));
    }
    if !missing.is_empty() {
        return Err(RenderError::MissingCapability {
            adapter: adapter_name.to_string(),
            missing: missing.join("; "),
        });
    }
    Ok(Capabilities {
        timestamps: features.contains(wgpu::Features::TIMESTAMP_QUERY),
        max_storage_binding: limits.max_storage_buffer_binding_size,
        max_buffer_size: limits.max_buffer_size,
        max_texture_2d: limits.max_texture_dimension_2d,
    })
}

/// A wgpu device and queue checked for the renderer's needs. Cheap to clone.
#[derive(Clone, Debug)]
pub struct GpuContext {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter it came from.
    pub adapter_info: wgpu::AdapterInfo,
    /// What the device supports.
    pub caps: Capabilities,
}

impl GpuContext {
    /// A headless context with options from the environment ([`ContextOptions::from_env`]).
    pub fn headless() -> Result<Self, RenderError> {
        Self::with_options(&ContextOptions::from_env())
    }

    /// A headless context: chooses an adapter, checks it, and opens a device with timestamp
    /// queries when available and the adapter's full limits. Blocks until the device is ready.
    /// Validation errors outside the renderer's error scopes are logged, never panicked on.
    pub fn with_options(options: &ContextOptions) -> Result<Self, RenderError> {
        pollster::block_on(Self::with_options_async(options))
    }

    /// Async form of [`GpuContext::with_options`].
    pub async fn with_options_async(options: &ContextOptions) -> Result<Self, RenderError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle().with_env();
        if let Some(b) = options.backends {
            desc.backends = b;
        }
        let backends = desc.backends;
        let instance = wgpu::Instance::new(desc);
        let adapter = match &options.adapter_name {
            Some(name) => {
                let wanted = name.to_lowercase();
                let adapters = instance.enumerate_adapters(backends).await;
                let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
                adapters
                    .into_iter()
                    .find(|a| a.get_info().name.to_lowercase().contains(&wanted))
                    .ok_or_else(|| RenderError::NoAdapter {
                        filter: format!(
                            " whose name contains `{name}` (available: {})",
                            if names.is_empty() {
                                "none".to_string()
                            } else {
                                names.join(", ")
                            }
                        ),
                    })?
            }
            None => instance
                .request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: options.power_preference,
                    ..Default::default()
                })
                .await
                .map_err(|_| RenderError::NoAdapter {
                    filter: String::new(),
                })?,
        };
        let info = adapter.get_info();
        check_capabilities(
            &info.name,
            adapter.features(),
            &adapter.limits(),
            &adapter.get_downlevel_capabilities(),
        )?;
        let required_features = adapter.features() & wgpu::Features::TIMESTAMP_QUERY;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("tress/device"),
                required_features,
                required_limits: adapter.limits(),
                experimental_features: wgpu::ExperimentalFeatures::disabled(),
                memory_hints: wgpu::MemoryHints::Performance,
                trace: wgpu::Trace::Off,
            })
            .await?;
        device.on_uncaptured_error(Arc::new(|e: wgpu::Error| {
            tracing::error!("uncaptured wgpu error: {e}");
        }));
        Self::from_device(&adapter, device, queue)
    }

    /// A context around a device the application owns (e.g. a viewer that also presents to a
    /// window). Checks the device's features and limits once; leaves its error handler alone.
    pub fn from_device(
        adapter: &wgpu::Adapter,
        device: wgpu::Device,
        queue: wgpu::Queue,
    ) -> Result<Self, RenderError> {
        let adapter_info = adapter.get_info();
        let caps = check_capabilities(
            &adapter_info.name,
            device.features(),
            &device.limits(),
            &adapter.get_downlevel_capabilities(),
        )?;
        tracing::info!(
            adapter = %adapter_info.name,
            backend = ?adapter_info.backend,
            timestamps = caps.timestamps,
            "tress GPU context"
        );
        Ok(GpuContext {
            device,
            queue,
            adapter_info,
            caps,
        })
    }

    /// Run `f`, capturing wgpu validation and out-of-memory errors it causes as a
    /// [`RenderError::Gpu`] naming `during`.
    pub fn scoped<T>(&self, during: &str, f: impl FnOnce() -> T) -> Result<T, RenderError> {
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out = f();
        let v = pollster::block_on(validation.pop());
        let o = pollster::block_on(oom.pop());
        match v.or(o) {
            Some(e) => Err(RenderError::Gpu {
                during: during.to_string(),
                message: e.to_string(),
            }),
            None => Ok(out),
        }
    }

    /// Block until all submitted work is done.
    pub fn wait_idle(&self) -> Result<(), RenderError> {
        self.device.poll(wgpu::PollType::wait_indefinitely())?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn downlevel(flags: wgpu::DownlevelFlags) -> wgpu::DownlevelCapabilities {
        wgpu::DownlevelCapabilities {
            flags,
            ..Default::default()
        }
    }

    #[test]
    fn full_device_passes_and_reports_timestamps() {
        let caps = check_capabilities(
            "test",
            wgpu::Features::TIMESTAMP_QUERY,
            &wgpu::Limits::default(),
            &downlevel(wgpu::DownlevelFlags::all()),
        )
        .expect("a WebGPU-default device is enough");
        assert!(caps.timestamps);
        assert_eq!(
            caps.max_storage_binding,
            wgpu::Limits::default().max_storage_buffer_binding_size
        );
    }

    #[test]
    fn missing_fragment_storage_is_named() {
        let err = check_capabilities(
            "old-gpu",
            wgpu::Features::empty(),
            &wgpu::Limits::downlevel_webgl2_defaults(),
            &downlevel(wgpu::DownlevelFlags::empty()),
        )
        .expect_err("webgl2 cannot run the PPLL");
        let msg = err.to_string();
        assert!(msg.contains("old-gpu"), "{msg}");
        assert!(msg.contains("fragment shaders"), "{msg}");
        assert!(msg.contains("vertex shaders"), "{msg}");
        assert!(msg.contains("storage buffers per shader stage"), "{msg}");
    }

    #[test]
    fn timestamps_are_optional() {
        let caps = check_capabilities(
            "no-ts",
            wgpu::Features::empty(),
            &wgpu::Limits::default(),
            &downlevel(wgpu::DownlevelFlags::all()),
        )
        .expect("timestamps are optional");
        assert!(!caps.timestamps);
    }
}
