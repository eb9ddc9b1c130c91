//! The error type of rendering: everything a user can get wrong or the device can refuse.

use std::fmt;

/// Any error the library returns: a scene it cannot load, a device it cannot use, an image it
/// cannot read or write, or a setting out of range. `Display` gives the one-line message the
/// command line prints.
#[derive(Debug)]
pub enum Error {
    /// The scene file, or a mesh or texture it names, is malformed or missing; names the file,
    /// line and key.
    Scene(crate::scene::SceneError),
    /// No adapter, a device without the limits the renderer needs, or a failed readback.
    Gpu(crate::gpu::GpuError),
    /// An image could not be read, written or compared.
    Image(crate::image_io::ImageError),
    /// A setting out of range, given on the command line or through the API.
    Setting(String),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Scene(e) => write!(f, "{e}"),
            Error::Gpu(e) => write!(f, "GPU: {e}"),
            Error::Image(e) => write!(f, "{e}"),
            Error::Setting(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for Error {}

impl From<crate::scene::SceneError> for Error {
    fn from(e: crate::scene::SceneError) -> Self {
        Error::Scene(e)
    }
}

impl From<crate::gpu::GpuError> for Error {
    fn from(e: crate::gpu::GpuError) -> Self {
        Error::Gpu(e)
    }
}

impl From<crate::image_io::ImageError> for Error {
    fn from(e: crate::image_io::ImageError) -> Self {
        Error::Image(e)
    }
}
