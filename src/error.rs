//! The library's error type: every failure keeps what was being done and, for Vulkan, the
//! `vk::Result`. Only the binary converts these into `anyhow` reports.

use ash::vk;
use std::path::PathBuf;

/// Any failure of the renderer.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("Vulkan call failed while {what}: {result}")]
    Vulkan { what: &'static str, result: vk::Result },
    #[error("cannot load the Vulkan loader (libvulkan.so.1; Debian package libvulkan1): {0}")]
    Loader(#[from] ash::LoadingError),
    #[error("no usable Vulkan device: {0}")]
    NoDevice(String),
    #[error(
        "the Khronos validation layer VK_LAYER_KHRONOS_validation is not installed \
         (Debian package vulkan-validationlayers)"
    )]
    ValidationLayerMissing,
    #[error("GPU memory allocation for {what} failed: {source}")]
    Allocation { what: String, source: gpu_allocator::AllocationError },
    /// A buffer or image whose memory could not be had: the resource, the bytes it needs and
    /// the heap it would come from.
    #[error(
        "GPU memory for {what} ({} MiB) cannot be allocated: {reason}; the device's {heap} heap \
         holds {} MiB",
        mib(*.size),
        mib(*.heap_size)
    )]
    ResourceMemory { what: String, size: u64, heap: &'static str, heap_size: u64, reason: String },
    /// An image larger than the device allows along a side.
    #[error(
        "{what} is {width}×{height} texels, more than the device's maxImageDimension2D ({max}) \
         along a side"
    )]
    ImageTooLarge { what: String, width: u32, height: u32, max: u32 },
    /// A scene that does not fit the device or the shaders, found before anything was created
    /// on the GPU (`render::limits`).
    #[error("{}: {what}: more than {limit} allows", scene.display())]
    SceneLimit { scene: PathBuf, what: String, limit: String },
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),
    #[error("{}: {message}", path.display())]
    Output { path: PathBuf, message: String },
    #[error("window system: {0}")]
    Window(String),
    #[error("{}: the scene has no camera path ([[path]]); give --path orbit:SECONDS", scene.display())]
    NoCameraPath { scene: PathBuf },
    #[error("the device {device} cannot {what}: it lacks {missing}")]
    Unsupported { device: String, what: &'static str, missing: &'static str },
    #[error(
        "the device {device} tessellates inner level {inner}, outer levels {outer:?} otherwise than the \
         tessellator model that multirate's effective-level table comes from (src/analysis/tessellator.rs), \
         so multirate cannot bound its error on it; the pixel, vertex and fixed:N modes still work"
    )]
    Patterns { device: String, inner: f32, outer: [f32; 3] },
}

/// `bytes` in MiB with one decimal, for messages.
pub fn mib(bytes: u64) -> String {
    format!("{:.1}", bytes as f64 / (1024.0 * 1024.0))
}

/// Shorthand for results of this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Attaches what was being done to a raw `vk::Result`.
pub trait VkContext<T> {
    fn while_(self, what: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for Result<T, vk::Result> {
    fn while_(self, what: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vulkan { what, result })
    }
}
