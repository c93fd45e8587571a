//! The Vulkan instance, the chosen physical device, the logical device, its one queue, the
//! memory allocator and the validation messenger. `Context::headless()` needs no window system;
//! `Context::windowed(..)` also enables presentation and returns a surface.

use crate::error::{Error, Result, VkContext};
use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use raw_window_handle::{HasDisplayHandle, HasWindowHandle, RawDisplayHandle};
use std::ffi::{c_void, CStr, CString};
use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// How to create a context.
#[derive(Clone, Debug, Default)]
pub struct ContextOptions {
    /// Enable the Khronos validation layer and count every warning and error it reports.
    pub validate: bool,
    /// Pick the first device whose name contains this text (case-insensitive).
    pub device_name: Option<String>,
}

/// Optional device features the renderer uses when present.
#[derive(Clone, Copy, Debug, Default)]
pub struct OptionalFeatures {
    pub pipeline_statistics: bool,
    pub fill_mode_non_solid: bool,
    pub geometry_shader: bool,
    /// Storage-buffer writes and atomics in vertex, tessellation and geometry stages.
    pub vertex_pipeline_stores: bool,
    /// Storage-buffer writes and atomics in fragment shaders.
    pub fragment_stores: bool,
    /// `VK_EXT_memory_budget`, enabled where present: the driver's memory use per heap
    /// (`vk::budget`).
    pub memory_budget: bool,
    /// `drawIndirectCount` (Vulkan 1.2): an indirect draw whose count the device reads, so that
    /// the patch lists' draws the pre-pass did not fill are not recorded at all.
    pub draw_indirect_count: bool,
}

/// Facts about the chosen device, for reports.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    pub name: String,
    pub driver: String,
    pub api_version: String,
    pub timestamp_period_ns: f32,
    pub timestamp_valid_bits: u32,
    pub max_tessellation_level: u32,
    /// A CPU device (lavapipe): it runs a workgroup's invocations in SIMD batches, each batch
    /// through all the code any of its lanes takes, rather than as independent threads.
    pub cpu: bool,
}

impl DeviceInfo {
    /// Lavapipe (Mesa's llvmpipe), the CPU device CI runs on, whose quirks the renderer and the
    /// tests know.
    pub fn is_lavapipe(&self) -> bool {
        names_lavapipe(&self.name)
    }
}

/// Whether `device` is the name of a lavapipe device ([`DeviceInfo::is_lavapipe`]).
pub fn names_lavapipe(device: &str) -> bool {
    device.contains("llvmpipe")
}

/// The device's limits that a scene and its resources must fit, read once when the context is
/// created: `render::limits` checks each scene against them before creating anything on the
/// GPU, and `vk::memory` each buffer and image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DeviceLimits {
    /// `maxStorageBufferRange`: the most bytes one storage-buffer binding covers.
    pub max_storage_buffer_range: u64,
    /// `maxTexelBufferElements`: the most texels one texel buffer view covers.
    pub max_texel_buffer_elements: u64,
    /// `maxBufferSize` (Vulkan 1.3): the most bytes one buffer may hold.
    pub max_buffer_size: u64,
    /// `maxMemoryAllocationSize` (Vulkan 1.1): the most bytes one memory allocation may hold.
    pub max_memory_allocation_size: u64,
    /// `maxDrawIndexedIndexValue`: the largest vertex index an indexed draw may use.
    pub max_draw_indexed_index_value: u64,
    /// `maxComputeWorkGroupCount[0]`: the most workgroups one dispatch may open along x.
    pub max_compute_work_group_count_x: u64,
    /// `maxDrawIndirectCount`: the most draws one indirect draw may make (1 without
    /// `multiDrawIndirect`).
    pub max_draw_indirect_count: u32,
    /// `maxImageDimension2D`: the most texels along either side of a 2D image.
    pub max_image_dimension_2d: u32,
    /// Bytes of the largest device-local memory heap.
    pub device_local_heap: u64,
    /// Bytes of the largest heap with a host-visible memory type (staging and read-back).
    pub host_visible_heap: u64,
}

impl DeviceLimits {
    /// The limits of `device`.
    fn of(instance: &ash::Instance, device: vk::PhysicalDevice) -> DeviceLimits {
        let mut vulkan11 = vk::PhysicalDeviceVulkan11Properties::default();
        let mut vulkan13 = vk::PhysicalDeviceVulkan13Properties::default();
        let mut properties =
            vk::PhysicalDeviceProperties2::default().push_next(&mut vulkan11).push_next(&mut vulkan13);
        // SAFETY: plain queries on a Vulkan 1.3 physical device.
        let memory = unsafe {
            instance.get_physical_device_properties2(device, &mut properties);
            instance.get_physical_device_memory_properties(device)
        };
        let limits = properties.properties.limits;
        let heaps = &memory.memory_heaps[..memory.memory_heap_count as usize];
        let types = &memory.memory_types[..memory.memory_type_count as usize];
        let largest_heap = |wanted: vk::MemoryPropertyFlags| {
            types
                .iter()
                .filter(|t| t.property_flags.contains(wanted))
                .map(|t| heaps[t.heap_index as usize].size)
                .max()
                .unwrap_or(0)
        };
        DeviceLimits {
            max_storage_buffer_range: u64::from(limits.max_storage_buffer_range),
            max_texel_buffer_elements: u64::from(limits.max_texel_buffer_elements),
            max_buffer_size: vulkan13.max_buffer_size,
            max_memory_allocation_size: vulkan11.max_memory_allocation_size,
            max_draw_indexed_index_value: u64::from(limits.max_draw_indexed_index_value),
            max_compute_work_group_count_x: u64::from(limits.max_compute_work_group_count[0]),
            max_draw_indirect_count: limits.max_draw_indirect_count,
            max_image_dimension_2d: limits.max_image_dimension2_d,
            device_local_heap: largest_heap(vk::MemoryPropertyFlags::DEVICE_LOCAL),
            host_visible_heap: largest_heap(vk::MemoryPropertyFlags::HOST_VISIBLE),
        }
    }

    /// The smaller of each limit of `self` and `other`.
    pub fn min(&self, other: &DeviceLimits) -> DeviceLimits {
        DeviceLimits {
            max_storage_buffer_range: self.max_storage_buffer_range.min(other.max_storage_buffer_range),
            max_texel_buffer_elements: self.max_texel_buffer_elements.min(other.max_texel_buffer_elements),
            max_buffer_size: self.max_buffer_size.min(other.max_buffer_size),
            max_memory_allocation_size: self.max_memory_allocation_size.min(other.max_memory_allocation_size),
            max_draw_indexed_index_value: self
                .max_draw_indexed_index_value
                .min(other.max_draw_indexed_index_value),
            max_compute_work_group_count_x: self
                .max_compute_work_group_count_x
                .min(other.max_compute_work_group_count_x),
            max_draw_indirect_count: self.max_draw_indirect_count.min(other.max_draw_indirect_count),
            max_image_dimension_2d: self.max_image_dimension_2d.min(other.max_image_dimension_2d),
            device_local_heap: self.device_local_heap.min(other.device_local_heap),
            host_visible_heap: self.host_visible_heap.min(other.host_visible_heap),
        }
    }
}

/// Warnings and errors reported by the validation layer (and the loader) since start-up.
#[derive(Debug, Default)]
pub struct ValidationLog {
    count: AtomicUsize,
    messages: Mutex<Vec<String>>,
}

impl ValidationLog {
    pub fn count(&self) -> usize {
        self.count.load(Ordering::SeqCst)
    }

    pub fn messages(&self) -> Vec<String> {
        self.messages.lock().map(|m| m.clone()).unwrap_or_default()
    }
}

/// What the tessellation patterns of the device were found to be (see
/// `render::capture::check_patterns`): the largest `n_max` checked (0: none), and the device's
/// own effective-level table where the built-in one does not hold on it (`None`: it does).
pub(crate) struct PatternCheck {
    pub checked_up_to: u32,
    pub measured: Option<Arc<Vec<u32>>>,
}

/// Everything a pass needs to talk to the GPU. Shared as `Arc<Context>`; resources keep an
/// `Arc` so the device outlives them.
pub struct Context {
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    pub physical_device: vk::PhysicalDevice,
    pub device: ash::Device,
    pub queue_family: u32,
    queue: Mutex<vk::Queue>,
    pub allocator: ManuallyDrop<Mutex<Allocator>>,
    pub features: OptionalFeatures,
    pub info: DeviceInfo,
    /// The device's limits, read once here.
    pub limits: DeviceLimits,
    pub surface_instance: Option<ash::khr::surface::Instance>,
    debug_instance: Option<ash::ext::debug_utils::Instance>,
    debug_device: Option<ash::ext::debug_utils::Device>,
    /// What `render::capture::check_patterns` found about this device's tessellation
    /// patterns, and up to which `n_max`.
    pub(crate) pattern_check: Mutex<PatternCheck>,
    messenger: vk::DebugUtilsMessengerEXT,
    validation: Arc<ValidationLog>,
    one_shot_pool: Mutex<vk::CommandPool>,
}

unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the loader passes valid callback data for the duration of the call, and `user`
    // is the `ValidationLog` that the owning `Context` keeps alive until the messenger is gone.
    let (message, log) = unsafe {
        let text = (*data).message_as_c_str().map(|m| m.to_string_lossy().into_owned());
        (text.unwrap_or_default(), &*(user as *const ValidationLog))
    };
    let line = format!("[{severity:?} {kind:?}] {message}");
    eprintln!("vulkan: {line}");
    log.count.fetch_add(1, Ordering::SeqCst);
    if let Ok(mut messages) = log.messages.lock() {
        messages.push(line);
    }
    vk::FALSE
}

struct Candidate {
    device: vk::PhysicalDevice,
    queue_family: u32,
    score: u32,
}

impl Context {
    /// A context without presentation, for offscreen rendering and tests.
    pub fn headless(options: &ContextOptions) -> Result<Arc<Context>> {
        Self::create(options, None).map(|(context, _)| context)
    }

    /// A context that can present to `window`, and the window's surface.
    pub fn windowed<W>(options: &ContextOptions, window: &W) -> Result<(Arc<Context>, vk::SurfaceKHR)>
    where
        W: HasDisplayHandle + HasWindowHandle,
    {
        let (context, surface) = Self::create(options, Some(window))?;
        Ok((context, surface.expect("a windowed context always has a surface")))
    }

    fn create(
        options: &ContextOptions,
        window: Option<&dyn WindowHandles>,
    ) -> Result<(Arc<Context>, Option<vk::SurfaceKHR>)> {
        // SAFETY: loading libvulkan runs its initialisers; it is the system's Vulkan loader.
        let entry = unsafe { ash::Entry::load()? };
        let display: Option<RawDisplayHandle> = match window {
            Some(w) => Some(w.display()?),
            None => None,
        };
        let created = create_instance(&entry, options, display)?;
        let instance = created.instance;
        let surface_instance = display.map(|_| ash::khr::surface::Instance::new(&entry, &instance));
        let surface = match window {
            Some(w) => Some(w.create_surface(&entry, &instance)?),
            None => None,
        };

        let chosen = match pick_device(
            &instance,
            surface_instance.as_ref().zip(surface),
            options.device_name.as_deref(),
        ) {
            Ok(chosen) => chosen,
            Err(error) => {
                // SAFETY: nothing else was created from the instance yet except these.
                unsafe {
                    if let (Some(s), Some(surface)) = (&surface_instance, surface) {
                        s.destroy_surface(surface, None);
                    }
                    if let Some(debug) = &created.debug_instance {
                        if created.messenger != vk::DebugUtilsMessengerEXT::null() {
                            debug.destroy_debug_utils_messenger(created.messenger, None);
                        }
                    }
                    instance.destroy_instance(None);
                }
                return Err(error);
            }
        };

        let (device, features, properties) = create_device(&instance, &chosen, surface.is_some())?;
        // SAFETY: the family was requested with one queue.
        let queue = unsafe { device.get_device_queue(chosen.queue_family, 0) };

        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device: chosen.device,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })
        .map_err(|source| Error::Allocation { what: "the allocator".into(), source })?;

        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(chosen.queue_family)
            .flags(vk::CommandPoolCreateFlags::TRANSIENT);
        // SAFETY: valid device and create info.
        let one_shot_pool = unsafe { device.create_command_pool(&pool_info, None) }
            .while_("creating the upload command pool")?;

        let debug_device =
            created.debug_instance.as_ref().map(|_| ash::ext::debug_utils::Device::new(&instance, &device));
        let info = device_info_of(&instance, chosen.device, &properties, chosen.queue_family);
        let limits = DeviceLimits::of(&instance, chosen.device);
        let context = Arc::new(Context {
            entry,
            instance,
            physical_device: chosen.device,
            device,
            queue_family: chosen.queue_family,
            queue: Mutex::new(queue),
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            features,
            info,
            limits,
            surface_instance,
            debug_instance: created.debug_instance,
            debug_device,
            pattern_check: Mutex::new(PatternCheck { checked_up_to: 0, measured: None }),
            messenger: created.messenger,
            validation: created.validation,
            one_shot_pool: Mutex::new(one_shot_pool),
        });
        Ok((context, surface))
    }

    /// Warnings and errors the validation layer reported so far.
    pub fn validation(&self) -> &ValidationLog {
        &self.validation
    }

    /// Gives a Vulkan object a name that GPU captures and validation messages show.
    pub fn name<H: vk::Handle>(&self, object: H, name: &str) {
        let Some(debug) = &self.debug_device else { return };
        let Ok(name) = CString::new(name) else { return };
        let info = vk::DebugUtilsObjectNameInfoEXT::default().object_handle(object).object_name(&name);
        // SAFETY: `object` is a live handle of this device; naming is advisory, so a failure
        // is ignored on purpose.
        let _ = unsafe { debug.set_debug_utils_object_name(&info) };
    }

    /// Submits command buffers to the queue (the queue is externally synchronised).
    pub fn submit(&self, submits: &[vk::SubmitInfo2<'_>], fence: vk::Fence) -> Result<()> {
        let queue = self.queue.lock().expect("queue lock is never poisoned");
        // SAFETY: the queue is guarded by the mutex; the caller keeps the buffers alive.
        unsafe { self.device.queue_submit2(*queue, submits, fence) }.while_("submitting work")
    }

    /// Presents on the queue.
    pub fn present(
        &self,
        swapchain: &ash::khr::swapchain::Device,
        info: &vk::PresentInfoKHR<'_>,
    ) -> Result<bool, vk::Result> {
        let queue = self.queue.lock().expect("queue lock is never poisoned");
        // SAFETY: the queue is guarded by the mutex; `info` refers to live objects.
        unsafe { swapchain.queue_present(*queue, info) }
    }

    /// Records commands with `record`, submits them and waits until they finish.
    pub fn run_once(&self, record: impl FnOnce(vk::CommandBuffer)) -> Result<()> {
        let pool = self.one_shot_pool.lock().expect("pool lock is never poisoned");
        let alloc_info = vk::CommandBufferAllocateInfo::default()
            .command_pool(*pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool is guarded by the mutex for the whole recording and wait.
        let cmd = unsafe { self.device.allocate_command_buffers(&alloc_info) }
            .while_("allocating a one-shot command buffer")?[0];
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: freshly allocated command buffer.
        unsafe { self.device.begin_command_buffer(cmd, &begin) }.while_("beginning commands")?;
        record(cmd);
        // SAFETY: recording started above.
        unsafe { self.device.end_command_buffer(cmd) }.while_("ending commands")?;
        // SAFETY: plain fence creation.
        let fence = unsafe { self.device.create_fence(&vk::FenceCreateInfo::default(), None) }
            .while_("creating a fence")?;
        let cmd_info = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmd_info)];
        let result = self.submit(&submit, fence).and_then(|_| {
            // SAFETY: the fence belongs to this device and was just submitted.
            unsafe { self.device.wait_for_fences(&[fence], true, u64::MAX) }
                .while_("waiting for one-shot commands")
        });
        // SAFETY: the work finished (or never started), so the fence and buffer are idle.
        unsafe {
            self.device.destroy_fence(fence, None);
            self.device.free_command_buffers(*pool, &[cmd]);
        }
        result
    }

    /// Waits until the device is idle.
    pub fn wait_idle(&self) -> Result<()> {
        let _queue = self.queue.lock().expect("queue lock is never poisoned");
        // SAFETY: holding the queue lock keeps other submissions out while waiting.
        unsafe { self.device.device_wait_idle() }.while_("waiting for the device")
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: every resource holds an `Arc<Context>`, so none is alive any more; the
        // allocator is dropped before the device it allocates from.
        unsafe {
            let _ = self.device.device_wait_idle();
            let pool = *self.one_shot_pool.get_mut().expect("not poisoned");
            self.device.destroy_command_pool(pool, None);
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some(debug) = &self.debug_instance {
                if self.messenger != vk::DebugUtilsMessengerEXT::null() {
                    debug.destroy_debug_utils_messenger(self.messenger, None);
                }
            }
            self.instance.destroy_instance(None);
        }
    }
}

/// Handles of a window, boxed behind one trait object for `Context::create`.
trait WindowHandles {
    fn display(&self) -> Result<RawDisplayHandle>;
    fn create_surface(&self, entry: &ash::Entry, instance: &ash::Instance) -> Result<vk::SurfaceKHR>;
}

impl<W: HasDisplayHandle + HasWindowHandle> WindowHandles for W {
    fn display(&self) -> Result<RawDisplayHandle> {
        self.display_handle()
            .map(|h| h.as_raw())
            .map_err(|e| Error::Window(format!("no display handle: {e}")))
    }

    fn create_surface(&self, entry: &ash::Entry, instance: &ash::Instance) -> Result<vk::SurfaceKHR> {
        let window =
            self.window_handle().map_err(|e| Error::Window(format!("no window handle: {e}")))?.as_raw();
        // SAFETY: the handles come from a live window that outlives the surface (the viewer
        // destroys the swapchain and surface before the window).
        unsafe { ash_window::create_surface(entry, instance, self.display()?, window, None) }
            .while_("creating the window surface")
    }
}

/// The instance and, where the loader has `VK_EXT_debug_utils`, the validation messenger that
/// reports into `validation`.
struct CreatedInstance {
    instance: ash::Instance,
    validation: Arc<ValidationLog>,
    debug_instance: Option<ash::ext::debug_utils::Instance>,
    messenger: vk::DebugUtilsMessengerEXT,
}

/// Creates the instance with the validation layer (when asked for) and the extensions that
/// presenting to `display` needs.
fn create_instance(
    entry: &ash::Entry,
    options: &ContextOptions,
    display: Option<RawDisplayHandle>,
) -> Result<CreatedInstance> {
    // SAFETY: plain queries on a loaded entry.
    let layers = unsafe { entry.enumerate_instance_layer_properties() }.while_("listing instance layers")?;
    let has_validation_layer =
        layers.iter().any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == VALIDATION_LAYER));
    if options.validate && !has_validation_layer {
        return Err(Error::ValidationLayerMissing);
    }
    // SAFETY: plain query on a loaded entry.
    let available_extensions = unsafe { entry.enumerate_instance_extension_properties(None) }
        .while_("listing instance extensions")?;
    let has_debug_utils = available_extensions
        .iter()
        .any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == ash::ext::debug_utils::NAME));

    let mut extensions: Vec<*const i8> = Vec::new();
    if has_debug_utils {
        extensions.push(ash::ext::debug_utils::NAME.as_ptr());
    }
    if let Some(display) = display {
        let required = ash_window::enumerate_required_extensions(display)
            .while_("listing the surface extensions of this window system")?;
        extensions.extend_from_slice(required);
    }
    let layer_names: Vec<*const i8> =
        if options.validate { vec![VALIDATION_LAYER.as_ptr()] } else { Vec::new() };

    let app_name = CString::new("multirate").expect("no interior NUL");
    let app_info = vk::ApplicationInfo::default()
        .application_name(&app_name)
        .application_version(1)
        .engine_name(&app_name)
        .api_version(vk::API_VERSION_1_3);
    let validation = Arc::new(ValidationLog::default());
    let mut messenger_info = vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(debug_callback))
        .user_data(Arc::as_ptr(&validation) as *mut c_void);
    let mut instance_info = vk::InstanceCreateInfo::default()
        .application_info(&app_info)
        .enabled_extension_names(&extensions)
        .enabled_layer_names(&layer_names);
    if options.validate && has_debug_utils {
        // Also report problems in vkCreateInstance and vkDestroyInstance themselves.
        instance_info = instance_info.push_next(&mut messenger_info);
    }
    // SAFETY: every pointer in `instance_info` refers to locals that outlive the call.
    let instance =
        unsafe { entry.create_instance(&instance_info, None) }.while_("creating the Vulkan instance")?;

    let (debug_instance, messenger) = if has_debug_utils {
        let debug = ash::ext::debug_utils::Instance::new(entry, &instance);
        let messenger = if options.validate {
            // SAFETY: the callback's user data (`validation`) lives as long as the context.
            unsafe { debug.create_debug_utils_messenger(&messenger_info, None) }
                .while_("creating the validation messenger")?
        } else {
            vk::DebugUtilsMessengerEXT::null()
        };
        (Some(debug), messenger)
    } else {
        (None, vk::DebugUtilsMessengerEXT::null())
    };
    Ok(CreatedInstance { instance, validation, debug_instance, messenger })
}

/// Creates the logical device on `chosen` with tessellation, the optional features it has, and
/// the swapchain extension when presenting; returns it with those features and its properties.
fn create_device(
    instance: &ash::Instance,
    chosen: &Candidate,
    presents: bool,
) -> Result<(ash::Device, OptionalFeatures, vk::PhysicalDeviceProperties)> {
    let mut supported12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut queried = vk::PhysicalDeviceFeatures2::default().push_next(&mut supported12);
    // SAFETY: plain queries on a valid physical device of a Vulkan 1.3 instance; the chained
    // struct outlives the call.
    let (properties, supported_extensions) = unsafe {
        instance.get_physical_device_features2(chosen.device, &mut queried);
        (
            instance.get_physical_device_properties(chosen.device),
            instance.enumerate_device_extension_properties(chosen.device),
        )
    };
    let supported = queried.features;
    let has_extension = |wanted: &CStr| {
        supported_extensions.iter().flatten().any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == wanted))
    };
    let features = OptionalFeatures {
        pipeline_statistics: supported.pipeline_statistics_query == vk::TRUE,
        fill_mode_non_solid: supported.fill_mode_non_solid == vk::TRUE,
        geometry_shader: supported.geometry_shader == vk::TRUE,
        vertex_pipeline_stores: supported.vertex_pipeline_stores_and_atomics == vk::TRUE,
        fragment_stores: supported.fragment_stores_and_atomics == vk::TRUE,
        memory_budget: has_extension(ash::ext::memory_budget::NAME),
        draw_indirect_count: supported12.draw_indirect_count == vk::TRUE,
    };
    let enabled = vk::PhysicalDeviceFeatures::default()
        .tessellation_shader(true)
        .pipeline_statistics_query(features.pipeline_statistics)
        .fill_mode_non_solid(features.fill_mode_non_solid)
        .geometry_shader(features.geometry_shader)
        .vertex_pipeline_stores_and_atomics(features.vertex_pipeline_stores)
        .fragment_stores_and_atomics(features.fragment_stores);
    // maintenance4 (required of every Vulkan 1.3 device) allows the LocalSizeId execution mode
    // that shaderc emits for compute shaders compiled to SPIR-V 1.6.
    let mut vulkan13 = vk::PhysicalDeviceVulkan13Features::default()
        .dynamic_rendering(true)
        .synchronization2(true)
        .maintenance4(true);
    let mut vulkan12 =
        vk::PhysicalDeviceVulkan12Features::default().draw_indirect_count(features.draw_indirect_count);
    let priorities = [1.0f32];
    let queue_info = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(chosen.queue_family)
        .queue_priorities(&priorities)];
    let mut device_extensions: Vec<*const i8> =
        if presents { vec![ash::khr::swapchain::NAME.as_ptr()] } else { Vec::new() };
    if features.memory_budget {
        device_extensions.push(ash::ext::memory_budget::NAME.as_ptr());
    }
    let device_info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queue_info)
        .enabled_extension_names(&device_extensions)
        .enabled_features(&enabled)
        .push_next(&mut vulkan13)
        .push_next(&mut vulkan12);
    // SAFETY: the create info only points at locals that outlive the call.
    let device = unsafe { instance.create_device(chosen.device, &device_info, None) }
        .while_("creating the logical device")?;
    Ok((device, features, properties))
}

fn pick_device(
    instance: &ash::Instance,
    surface: Option<(&ash::khr::surface::Instance, vk::SurfaceKHR)>,
    wanted_name: Option<&str>,
) -> Result<Candidate> {
    // SAFETY: plain query on a valid instance.
    let devices = unsafe { instance.enumerate_physical_devices() }.while_("listing physical devices")?;
    let mut rejected = Vec::new();
    let mut best: Option<Candidate> = None;
    for device in devices {
        // SAFETY: plain queries on an enumerated physical device.
        let (properties, features, families) = unsafe {
            (
                instance.get_physical_device_properties(device),
                instance.get_physical_device_features(device),
                instance.get_physical_device_queue_family_properties(device),
            )
        };
        let name =
            properties.device_name_as_c_str().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        if let Some(wanted) = wanted_name {
            if !name.to_lowercase().contains(&wanted.to_lowercase()) {
                rejected.push(format!("{name}: not the requested device \"{wanted}\""));
                continue;
            }
        }
        if let Some(reason) = unsuitability(&properties, &features) {
            rejected.push(format!("{name}: {reason}"));
            continue;
        }
        let family = families.iter().enumerate().position(|(index, family)| {
            let graphics = family.queue_flags.contains(vk::QueueFlags::GRAPHICS);
            let present = surface.is_none_or(|(loader, surface)| {
                // SAFETY: valid device, family index and surface.
                unsafe { loader.get_physical_device_surface_support(device, index as u32, surface) }
                    .unwrap_or(false)
            });
            graphics && present
        });
        let Some(queue_family) = family else {
            rejected.push(format!("{name}: no graphics queue that can present to the window"));
            continue;
        };
        let score = match properties.device_type {
            vk::PhysicalDeviceType::DISCRETE_GPU => 4,
            vk::PhysicalDeviceType::INTEGRATED_GPU => 3,
            vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
            _ => 1,
        };
        if best.as_ref().is_none_or(|b| score > b.score) {
            best = Some(Candidate { device, queue_family: queue_family as u32, score });
        }
    }
    best.ok_or_else(|| {
        if rejected.is_empty() {
            Error::NoDevice(
                "the Vulkan loader found no device (Debian: install mesa-vulkan-drivers for lavapipe)".into(),
            )
        } else {
            Error::NoDevice(rejected.join("; "))
        }
    })
}

/// Why a device cannot run the renderer, or `None` when it can.
pub fn unsuitability(
    properties: &vk::PhysicalDeviceProperties,
    features: &vk::PhysicalDeviceFeatures,
) -> Option<String> {
    if properties.api_version < vk::API_VERSION_1_3 {
        return Some(format!(
            "supports Vulkan {}.{}, 1.3 is needed",
            vk::api_version_major(properties.api_version),
            vk::api_version_minor(properties.api_version)
        ));
    }
    if features.tessellation_shader != vk::TRUE {
        return Some(
            "no tessellationShader feature (multirate shading needs the hardware tessellator)".into(),
        );
    }
    None
}

fn device_info_of(
    instance: &ash::Instance,
    device: vk::PhysicalDevice,
    properties: &vk::PhysicalDeviceProperties,
    queue_family: u32,
) -> DeviceInfo {
    let mut driver = vk::PhysicalDeviceDriverProperties::default();
    let mut properties2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver);
    // SAFETY: plain query on a Vulkan 1.3 physical device.
    let families = unsafe {
        instance.get_physical_device_properties2(device, &mut properties2);
        instance.get_physical_device_queue_family_properties(device)
    };
    let name =
        properties.device_name_as_c_str().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let driver_name = driver.driver_name_as_c_str().map(|n| n.to_string_lossy().into_owned());
    let driver_info = driver.driver_info_as_c_str().map(|n| n.to_string_lossy().into_owned());
    let api = properties.api_version;
    DeviceInfo {
        name,
        driver: format!("{} {}", driver_name.unwrap_or_default(), driver_info.unwrap_or_default())
            .trim()
            .to_string(),
        api_version: format!(
            "{}.{}.{}",
            vk::api_version_major(api),
            vk::api_version_minor(api),
            vk::api_version_patch(api)
        ),
        timestamp_period_ns: properties.limits.timestamp_period,
        timestamp_valid_bits: families.get(queue_family as usize).map_or(0, |f| f.timestamp_valid_bits),
        max_tessellation_level: properties.limits.max_tessellation_generation_level,
        cpu: properties.device_type == vk::PhysicalDeviceType::CPU,
    }
}

#[cfg(test)]
mod tests;
