//! The GPU core: context and capability checks, render targets, readback to PNG/EXR, timestamp
//! queries and the GPU-visible struct types.

mod context;
mod readback;
mod target;
mod timer;
pub mod types;

pub use context::{
    ADAPTER_ENV, Capabilities, ContextOptions, GpuContext, MIN_STORAGE_BINDING_BYTES,
    MIN_STORAGE_BUFFERS_PER_STAGE, check_capabilities,
};
pub use readback::{
    LinearImage, f16_to_f32, linear_to_srgb, read_buffer, read_texture, srgb_to_linear,
};
pub use target::{COLOR_FORMAT, DEPTH_FORMAT, OffscreenTargets, TargetFormats, Targets};
pub(crate) use timer::GpuTimer;
pub use timer::{PassTiming, Timings};
