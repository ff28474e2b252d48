//! The error type of the renderer.

/// Everything that can go wrong in `tress-render`. The library never panics on user data or in a
/// frame: it returns one of these.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No GPU adapter matched the request.
    #[error(
        "no GPU adapter found{filter}: install a Vulkan driver (on Debian/Ubuntu the CPU \
         implementation lavapipe: `apt-get install mesa-vulkan-drivers`), or check \
         WGPU_BACKEND / TRESS_ADAPTER"
    )]
    NoAdapter {
        /// A description of the filter that was applied (empty when none).
        filter: String,
    },
    /// The adapter lacks a capability the renderer needs.
    #[error("the GPU adapter `{adapter}` cannot run tress: {missing}")]
    MissingCapability {
        /// Adapter name.
        adapter: String,
        /// What is missing, in words.
        missing: String,
    },
    /// Requesting the device failed.
    #[error("could not open the GPU device: {0}")]
    RequestDevice(#[from] wgpu::RequestDeviceError),
    /// A wgpu validation or out-of-memory error was captured.
    #[error("GPU error during {during}: {message}")]
    Gpu {
        /// What the renderer was doing.
        during: String,
        /// The message wgpu gave.
        message: String,
    },
    /// Waiting for the GPU failed (device lost or timeout).
    #[error("waiting for the GPU failed: {0}")]
    Poll(#[from] wgpu::PollError),
    /// Mapping a buffer for reading failed.
    #[error("reading back from the GPU failed: {0}")]
    Readback(String),
    /// A caller-provided render target does not fit.
    #[error("render target: {0}")]
    Target(String),
    /// Input data (asset, mesh, camera, settings) is invalid.
    #[error("invalid input: {0}")]
    Invalid(String),
    /// A resource would exceed a device limit.
    #[error("{what} needs {needed} bytes but the device allows {limit}")]
    Limit {
        /// The resource.
        what: String,
        /// Bytes requested.
        needed: u64,
        /// The device limit.
        limit: u64,
    },
    /// A shader module could not be composed (unknown include).
    #[error("shader {module}: {message}")]
    Shader {
        /// The module being composed.
        module: String,
        /// What went wrong.
        message: String,
    },
    /// Writing an image file failed.
    #[error("writing image {path}: {source}")]
    Image {
        /// Destination path.
        path: String,
        /// The underlying error.
        source: image::ImageError,
    },
}
