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
    /// wgpu could not map a buffer for reading.
    #[error("reading back from the GPU failed: {0}")]
    Map(#[from] wgpu::BufferAsyncError),
    /// A mapped buffer's range could not be read.
    #[error("reading back from the GPU failed: {0}")]
    MapRange(#[from] wgpu::MapRangeError),
    /// A caller-provided render target does not fit.
    #[error("render target: {0}")]
    Target(String),
    /// Input data (asset, mesh, camera, settings) is invalid.
    #[error("invalid input: {0}")]
    Invalid(String),
    /// A scene file, an override or a technique table is invalid (the error names the file or
    /// key).
    #[error("invalid input: {0}")]
    Scene(#[from] tress_scene::SceneError),
    /// Hair or mesh data could not be read or built.
    #[error("invalid input: {0}")]
    Hair(#[from] tress_hair::HairError),
    /// A setting's value was refused where it is used (`context` names the setting or step:
    /// `satf.bake`, `patches.textures`, a head mesh's file, ...).
    #[error("invalid input: {context}: {source}")]
    Setting {
        /// The setting or step.
        context: String,
        /// What was wrong with it.
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// The caller's SATF database loader ([`crate::session::DatabaseLoader`]) failed.
    #[error("invalid input: {}", chain(.0.as_ref()))]
    Database(#[source] Box<dyn std::error::Error + Send + Sync>),
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

impl RenderError {
    /// A [`RenderError::Setting`]: `source` refused the value of `context`.
    pub fn setting(
        context: impl Into<String>,
        source: impl Into<Box<dyn std::error::Error + Send + Sync>>,
    ) -> Self {
        RenderError::Setting {
            context: context.into(),
            source: source.into(),
        }
    }
}

/// An error and its sources as one line, `a: b: c`, without repeating a source the message
/// already holds.
fn chain(e: &(dyn std::error::Error + 'static)) -> String {
    let mut line = e.to_string();
    let mut at = e.source();
    while let Some(s) = at {
        let text = s.to_string();
        if !line.contains(&text) {
            line.push_str(": ");
            line.push_str(&text);
        }
        at = s.source();
    }
    line
}

#[cfg(test)]
mod tests {
    use std::error::Error;

    use super::*;

    #[test]
    fn errors_from_other_crates_keep_their_source_and_message() {
        // A scene table with an unknown key: the scene's own error, as the source.
        let scene = tress_scene::Scene::from_str("[strands]\nwidth_pixels = 2.0\n", ".")
            .expect("the scene parses");
        let e = crate::PreparedScene::load_settings(&scene).expect_err("unknown key");
        let RenderError::Scene(inner) = &e else {
            panic!("not a scene error: {e:?}");
        };
        assert_eq!(e.to_string(), format!("invalid input: {inner}"));
        assert!(e.source().is_some());
        // A setting refused by the crate that uses it names the setting and keeps the error.
        let hair = tress_hair::HairError::Parameter("rays must be positive".into());
        let e = RenderError::setting("patches.ao", hair);
        assert_eq!(
            e.to_string(),
            "invalid input: patches.ao: invalid parameter: rays must be positive"
        );
        assert!(
            e.source()
                .and_then(|s| s.downcast_ref::<tress_hair::HairError>())
                .is_some()
        );
        // A loader's error chain reads as one line.
        let io = std::io::Error::other("disk on fire");
        let file = tress_hair::HairError::from(io).in_file("db.satfdb");
        let e = RenderError::Database(Box::new(file));
        assert_eq!(e.to_string(), "invalid input: db.satfdb: disk on fire");
    }
}
