//! The interactive viewer: a winit window whose frames are rendered into the float target by
//! the same passes as headless rendering, then run through the post chain (eye adaptation,
//! bloom, tone mapping; `render::post`) into the swapchain, or with O only tone mapped at the
//! scene's exposure (`render::present`).
//! Drag with the left button to orbit, scroll to zoom, Esc to quit. Keys pick the mode: P
//! pixel, D pixel-deferred, V vertex, F fixed:N, M multirate, + and - change N; E moves
//! multirate's estimator between the control stage and the compute pre-pass; [ and ] halve
//! and double ε, < and > halve and double n_max; H toggles the tessellation-level heat map, W
//! the wireframe, S the shadows (in a scene whose lights cast them; the renderer is made
//! again without them, or with them, in a second or so), O the post chain. The title shows the mode (with ε and n_max in multirate), the GPU time of
//! the render from timestamps, its speed against `pixel` mode timed in the same window
//! (`speed`; T times `pixel` again), and the shading evaluations as a share of `pixel`
//! mode's (counted at most every `RECOUNT_EVERY`, and when the mode or ε changes). A
//! zero-sized (minimised) window draws nothing and keeps its swapchain until it is restored.
//!
//! A scene with a camera path (`[[path]]`) plays it from the start, looped; Space pauses and
//! resumes it, and a drag or a scroll takes the camera over from where it is.
//!
//! A [`ViewScript`] drives the same loop without a person: key presses, resizes, minimising
//! and memory samples at given turns of the loop. [`ViewScript::soak`] builds the long one
//! that `multirate soak` runs and tests/window.rs checks.
//!
//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`speed`]: the viewer's speed against `pixel` mode, timed in the same window.
//! 2. [`script`]: scripted key presses, resizes and memory samples; the soak's script.
//! 3. [`path_player`]: the camera path as the viewer plays it.

use crate::error::{Error, Result, VkContext as _};
use crate::geometry::camera::Orbit;
use crate::render::post::{Adapt, Output, PostChain, PostSettings};
use crate::render::present::PresentPass;
use crate::render::{Mode, Placement, Renderer, View, MAX_LEVEL};
use crate::scene::settings::{check_epsilon, EPSILON_KEYS, N_MAX_RANGE};
use crate::scene::Scene;
use crate::vk::budget::MemoryUse;
use crate::vk::swapchain::{Acquired, Swapchain};
use crate::vk::target::{AfterPass, RenderTarget};
use crate::vk::timing::GpuTimer;
use crate::vk::{Context, ContextOptions};
use ash::vk;
use path_player::PathPlayer;
pub use script::{ScriptEvent, ViewScript, SOAK_STEP};
use speed::PixelReference;
use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

/// Memory figures taken during a run.
#[derive(Clone, Copy, Debug)]
pub struct MemorySample {
    /// Frames presented when it was taken.
    pub frame: u32,
    pub memory: MemoryUse,
}

/// What a viewer session did.
#[derive(Clone, Debug, Default)]
pub struct ViewReport {
    pub frames_presented: u32,
    /// Turns of the loop (redraws), presented or not.
    pub turns: u32,
    /// Turns that drew nothing because the window was zero-sized (minimised).
    pub turns_minimised: u32,
    /// The view when the window closed.
    pub final_view: Option<View>,
    pub swapchain_recreations: u32,
    pub final_extent: (u32, u32),
    pub validation_messages: usize,
    /// The window title when it closed.
    pub final_title: String,
    /// Presented frames by mode ("pixel", "fixed:4", "multirate (tcs)", ...), in a scripted run.
    pub frames_by_mode: BTreeMap<String, u32>,
    /// Presented frames with the heat map, and with the wireframe, on.
    pub heat_map_frames: u32,
    pub wireframe_frames: u32,
    /// Presented frames of a scene whose lights cast shadows, drawn without them (S).
    pub frames_without_shadows: u32,
    /// Presented frames only tone mapped, the post chain off (O).
    pub frames_without_post: u32,
    /// Presented frames whose camera the scene's path moved (it played, not paused).
    pub frames_on_path: u32,
    /// The n_max values multirate frames were presented with.
    pub n_max_values: BTreeSet<u32>,
    /// The smallest and largest ε multirate frames were presented with.
    pub epsilon_range: Option<(f32, f32)>,
    /// Scripted events run, by kind ("key p", "resize", "minimise", ...).
    pub events: BTreeMap<String, u32>,
    /// Memory figures, one per [`ScriptEvent::SampleMemory`].
    pub memory: Vec<MemorySample>,
    /// From the window's creation to its close.
    pub duration: Duration,
    /// The Vulkan device's name.
    pub device: String,
}

/// How often the viewer counts shading evaluations while the view only moves.
const RECOUNT_EVERY: Duration = Duration::from_secs(2);

/// Opens a window on `scene`, starting with `view`, and runs until it is closed.
pub fn view(
    scene: Scene,
    view: View,
    options: &ContextOptions,
    script: Option<ViewScript>,
) -> Result<ViewReport> {
    let mode = view.mode;
    let event_loop = new_event_loop()?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App {
        orbit: Orbit::from_camera(&scene.camera),
        path: scene.camera_path.clone().map(|path| PathPlayer::new(path, scene.bounds())),
        view,
        scene,
        options: options.clone(),
        script,
        next_event: 0,
        state: None,
        report: ViewReport::default(),
        error: None,
        drag: None,
        fixed_level: if let Mode::Fixed(level) = mode { level } else { 4 },
        shadows: true,
        post: true,
        last_post: None,
        remake_renderer: false,
        gpu_ms: None,
        pixel_reference: None,
        retime: false,
        share: None,
        started: Instant::now(),
    };
    event_loop.run_app(&mut app).map_err(|e| Error::Window(format!("event loop: {e}")))?;
    if let Some(error) = app.error {
        return Err(error);
    }
    if let Some(state) = app.state.take() {
        app.report.validation_messages = state.context.validation().count();
    }
    Ok(app.report)
}

fn new_event_loop() -> Result<EventLoop<()>> {
    let mut builder = EventLoop::builder();
    #[cfg(all(unix, not(target_os = "macos")))]
    {
        // Tests run the viewer off the main thread.
        use winit::platform::x11::EventLoopBuilderExtX11;
        builder.with_any_thread(true);
    }
    builder.build().map_err(|e| Error::Window(format!("cannot open the display: {e}")))
}

/// Per-window GPU state. Field order is drop order: GPU objects go before the window.
struct WindowState {
    frame: FrameSync,
    /// Timestamps around the render of the frame in flight.
    timer: GpuTimer,
    /// The view the frame in flight was drawn with (as the frame guard chose) on a target of
    /// which extent, where it wrote them.
    timed: Option<(View, vk::Extent2D)>,
    present: PresentPass,
    post: PostChain,
    target: RenderTarget,
    renderer: Renderer,
    swapchain: Swapchain,
    /// The window's size as the last `Resized` event gave it (zero when minimised).
    size: PhysicalSize<u32>,
    needs_recreate: bool,
    context: Arc<Context>,
    window: Arc<Window>,
}

/// One frame in flight: its command buffer, acquire semaphore and fence.
struct FrameSync {
    context: Arc<Context>,
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    image_available: vk::Semaphore,
    in_flight: vk::Fence,
}

impl FrameSync {
    fn new(context: &Arc<Context>) -> Result<FrameSync> {
        let device = &context.device;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(context.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: plain object creation on a live device; destroyed in `Drop`.
        unsafe {
            let pool =
                device.create_command_pool(&pool_info, None).while_("creating the frame command pool")?;
            let alloc = vk::CommandBufferAllocateInfo::default()
                .command_pool(pool)
                .level(vk::CommandBufferLevel::PRIMARY)
                .command_buffer_count(1);
            let cmd =
                device.allocate_command_buffers(&alloc).while_("allocating the frame command buffer")?[0];
            let image_available = device
                .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
                .while_("creating a semaphore")?;
            let in_flight = device
                .create_fence(&vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED), None)
                .while_("creating a fence")?;
            context.name(cmd, "frame commands");
            Ok(FrameSync { context: context.clone(), pool, cmd, image_available, in_flight })
        }
    }
}

impl Drop for FrameSync {
    fn drop(&mut self) {
        let _ = self.context.wait_idle();
        // SAFETY: the device is idle, so none of these is in use.
        unsafe {
            self.context.device.destroy_fence(self.in_flight, None);
            self.context.device.destroy_semaphore(self.image_available, None);
            self.context.device.destroy_command_pool(self.pool, None);
        }
    }
}

struct App {
    scene: Scene,
    view: View,
    orbit: Orbit,
    /// The scene's camera path, where it has one.
    path: Option<PathPlayer>,
    options: ContextOptions,
    script: Option<ViewScript>,
    /// The first event of `script` not run yet.
    next_event: usize,
    state: Option<WindowState>,
    report: ViewReport,
    error: Option<Error>,
    drag: Option<(f64, f64)>,
    /// The level `F` returns to after visiting other modes.
    fixed_level: u32,
    /// Whether the scene's shadow-casting lights cast them (S toggles).
    shadows: bool,
    /// Whether frames go through the post chain (O toggles).
    post: bool,
    /// When the last frame through the post chain was recorded (None: adapt the next at once).
    last_post: Option<Instant>,
    /// The renderer is to be made again (for `shadows`) before the next frame.
    remake_renderer: bool,
    /// GPU milliseconds of the render (pre-pass included, tone mapping not), smoothed over
    /// the frames since the shading settings last changed.
    gpu_ms: Option<f64>,
    /// `pixel` mode's GPU time in this window, for the title's speed.
    pixel_reference: Option<PixelReference>,
    /// The user asked (T) for `pixel` mode to be timed again.
    retime: bool,
    /// The last evaluation count: when, for which view, and its share of `pixel` mode's.
    share: Option<EvaluationShare>,
    /// When the window was created.
    started: Instant,
}

/// Shading evaluations of a view as a share of `pixel` mode's at the same camera.
struct EvaluationShare {
    at: Instant,
    view: View,
    /// None where the device cannot count (no stores from the vertex stages).
    percent: Option<f64>,
}

fn extent_of(size: PhysicalSize<u32>) -> vk::Extent2D {
    vk::Extent2D { width: size.width, height: size.height }
}

impl App {
    fn create_state(&self, event_loop: &ActiveEventLoop) -> Result<WindowState> {
        let settings = &self.scene.settings;
        let attributes = Window::default_attributes()
            .with_title("multirate")
            .with_inner_size(PhysicalSize::new(settings.width, settings.height));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| Error::Window(format!("cannot create a window: {e}")))?,
        );
        let (context, surface) = Context::windowed(&self.options, window.as_ref())?;
        let size = extent_of(window.inner_size());
        let swapchain = Swapchain::new(&context, surface, size)?;
        let renderer = Renderer::new(&context, &shown_scene(&self.scene, self.shadows))?;
        let target = RenderTarget::new(&context, swapchain.extent.max_one())?;
        let present = PresentPass::new(&context, swapchain.format.format, !swapchain.is_srgb())?;
        present.bind_target(&target);
        let encode_srgb = !swapchain.is_srgb();
        let mut post =
            PostChain::new(&context, swapchain.format.format, encode_srgb, PostSettings::default())?;
        post.bind_input(&target.color)?;
        let frame = FrameSync::new(&context)?;
        let timer = GpuTimer::new(&context, 1, 1)?;
        Ok(WindowState {
            frame,
            timer,
            timed: None,
            present,
            post,
            target,
            renderer,
            swapchain,
            size: window.inner_size(),
            needs_recreate: false,
            context,
            window,
        })
    }

    /// Renders and presents one frame; returns whether an image was presented.
    fn draw_frame(&mut self) -> Result<bool> {
        let Some(state) = self.state.as_mut() else { return Ok(false) };
        let size = extent_of(state.size);
        if size.width == 0 || size.height == 0 {
            // Minimised: nothing to draw into, and the swapchain stays as it is until the
            // window is restored.
            self.report.turns_minimised += 1;
            return Ok(false);
        }
        if state.needs_recreate || state.swapchain.images.is_empty() {
            if !state.swapchain.recreate(size)? {
                return Ok(false);
            }
            state.target = RenderTarget::new(&state.context, state.swapchain.extent)?;
            state.present.bind_target(&state.target);
            state.post.bind_input(&state.target.color)?;
            state.needs_recreate = false;
            self.report.swapchain_recreations += 1;
        }
        let device = &state.context.device;
        let frame = &state.frame;
        // SAFETY: the fence belongs to this device; waiting makes the command buffer and the
        // acquire semaphore of the previous frame reusable.
        unsafe { device.wait_for_fences(&[frame.in_flight], true, u64::MAX) }
            .while_("waiting for the last frame")?;
        if let Some((drawn, extent)) = state.timed.take() {
            let ms = state.timer.pass_intervals(0, 1)?[0].milliseconds();
            state.renderer.report_frame_time(&drawn, extent, ms);
            self.gpu_ms = Some(self.gpu_ms.map_or(ms, |smoothed| 0.9 * smoothed + 0.1 * ms));
        }
        if std::mem::take(&mut self.remake_renderer) {
            // The last frame has finished (fence above): the old renderer's resources are free.
            state.renderer = Renderer::new(&state.context, &shown_scene(&self.scene, self.shadows))?;
            if self.view.wireframe {
                state.renderer.enable_wireframe()?;
            }
            // Another scene to time and count: `pixel` mode's reference too.
            (self.gpu_ms, self.pixel_reference, self.share) = (None, None, None);
        }
        let camera = match &self.path {
            Some(path) if path.following => path.camera(&self.scene.camera),
            _ => self.orbit.apply(&self.scene.camera),
        };
        let view = self.view.seen_from(camera);
        let settings_changed = self.share.as_ref().is_none_or(|s| {
            (s.view.mode, s.view.estimator.epsilon, s.view.estimator.n_max, s.view.placement)
                != (view.mode, view.estimator.epsilon, view.estimator.n_max, view.placement)
        });
        if settings_changed {
            // The smoothed time is of the shading shown.
            self.gpu_ms = None;
        }
        // The last frame has finished (fence above), so the target is free to count and time in.
        if settings_changed || self.share.as_ref().is_some_and(|s| s.at.elapsed() >= RECOUNT_EVERY) {
            let percent = evaluation_percent(&state.renderer, &state.target, &view)?;
            self.share = Some(EvaluationShare { at: Instant::now(), view: view.clone(), percent });
        }
        if PixelReference::due(self.pixel_reference.as_ref(), &view, state.target.extent(), self.retime) {
            self.pixel_reference = Some(PixelReference::measure(&state.renderer, &state.target, &view)?);
            self.retime = false;
        }
        let index = match state.swapchain.acquire(frame.image_available)? {
            Acquired::Image { index, suboptimal } => {
                // Drawn and presented all the same: the acquire semaphore is signalled.
                state.needs_recreate |= suboptimal;
                index
            }
            Acquired::OutOfDate => {
                state.needs_recreate = true;
                return Ok(false);
            }
        };
        // SAFETY: the previous submission of this command buffer finished (fence above).
        unsafe {
            device.reset_fences(&[frame.in_flight]).while_("resetting the frame fence")?;
            device
                .reset_command_buffer(frame.cmd, vk::CommandBufferResetFlags::empty())
                .while_("resetting the frame commands")?;
            device
                .begin_command_buffer(frame.cmd, &vk::CommandBufferBeginInfo::default())
                .while_("beginning the frame commands")?;
        }
        state.renderer.prepare(&view, &state.target)?;
        // The frame guard may draw it as `pixel` does, where that measured faster.
        let drawn = state.renderer.guarded(&view, state.target.extent());
        state.timer.reset(frame.cmd, 0);
        state.timer.timestamp(frame.cmd, 0, 0, false);
        let recorded = state.renderer.record(frame.cmd, &state.target, &drawn, AfterPass::Sampled);
        state.timer.timestamp(frame.cmd, 0, 0, true);
        state.timed = Some((drawn, state.target.extent()));
        let (image, view) = (state.swapchain.images[index as usize], state.swapchain.views[index as usize]);
        let exposure = self.scene.settings.exposure;
        if self.post {
            let now = Instant::now();
            let adapt = self.last_post.map_or(Adapt::AtOnce, |last| Adapt::After((now - last).as_secs_f32()));
            self.last_post = Some(now);
            let presentable =
                (vk::ImageLayout::PRESENT_SRC_KHR, vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);
            state.post.record(frame.cmd, Output { image, view, after: presentable }, exposure, adapt);
        } else {
            self.last_post = None;
            state.present.record(frame.cmd, image, view, state.swapchain.extent, exposure);
        }
        // SAFETY: recording began above.
        unsafe { device.end_command_buffer(frame.cmd) }.while_("ending the frame commands")?;
        let wait = [vk::SemaphoreSubmitInfo::default()
            .semaphore(frame.image_available)
            .stage_mask(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)];
        let signal = [vk::SemaphoreSubmitInfo::default()
            .semaphore(state.swapchain.render_finished[index as usize])
            .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        let cmd_info = [vk::CommandBufferSubmitInfo::default().command_buffer(frame.cmd)];
        let submit = [vk::SubmitInfo2::default()
            .wait_semaphore_infos(&wait)
            .command_buffer_infos(&cmd_info)
            .signal_semaphore_infos(&signal)];
        state.context.submit(&submit, frame.in_flight)?;
        state.renderer.submitted(recorded);
        if state.swapchain.present(index)? {
            state.needs_recreate = true;
        }
        Ok(true)
    }

    fn update_title(&mut self) {
        let Some(state) = &self.state else { return };
        let mut title = format!("multirate: {} — {}", self.scene.path.display(), self.view.mode);
        if self.view.mode == Mode::Multirate {
            title += &format!(
                " ε {} n_max {} ({} estimator)",
                self.view.estimator.epsilon, self.view.estimator.n_max, self.view.placement
            );
        }
        if let Some(ms) = self.gpu_ms {
            title += &format!(" — GPU {ms:.2} ms");
            if let Some(reference) = self.pixel_reference.as_ref().filter(|_| self.view.mode != Mode::Pixel) {
                title += &format!(", {}", speed::speed_text(reference.ms, ms));
            }
        }
        if let Some(percent) = self.share.as_ref().and_then(|s| s.percent) {
            title += &format!(" — evaluations {percent:.1} % of pixel");
        }
        if !self.post {
            title += " — post off";
        }
        if !self.shadows {
            title += " — shadows off";
        }
        if let Some(path) = &self.path {
            let state = if path.playing() { "" } else { ", paused (Space)" };
            title += &format!(" — path {:.1} s{state}", path.time());
        }
        if title != self.report.final_title {
            state.window.set_title(&title);
            self.report.final_title = title;
        }
    }

    /// Runs the script's events due by the current turn, and closes the window once enough
    /// frames were presented.
    fn run_script(&mut self, event_loop: &ActiveEventLoop) {
        let Some(script) = &self.script else { return };
        let due: Vec<ScriptEvent> = script.events[self.next_event..]
            .iter()
            .take_while(|(turn, _)| *turn <= self.report.turns)
            .map(|(_, event)| *event)
            .collect();
        if self.report.frames_presented >= script.close_at_frame {
            return event_loop.exit();
        }
        self.next_event += due.len();
        for event in due {
            *self.report.events.entry(event.kind()).or_default() += 1;
            self.run_event(event);
        }
    }

    fn run_event(&mut self, event: ScriptEvent) {
        match event {
            ScriptEvent::Key(key) => self.on_key(key),
            ScriptEvent::Resize(width, height) => {
                if let Some(state) = &self.state {
                    let _ = state.window.request_inner_size(PhysicalSize::new(width, height));
                }
            }
            ScriptEvent::Minimise => {
                if let Some(state) = &self.state {
                    state.window.set_minimized(true);
                }
                self.on_resized(PhysicalSize::new(0, 0));
            }
            ScriptEvent::Restore => {
                let Some(state) = &self.state else { return };
                state.window.set_minimized(false);
                let size = state.window.inner_size();
                self.on_resized(size);
            }
            ScriptEvent::SampleMemory => {
                if let Some(state) = &self.state {
                    let memory = MemoryUse::now(&state.context);
                    self.report.memory.push(MemorySample { frame: self.report.frames_presented, memory });
                }
            }
        }
    }

    fn on_resized(&mut self, size: PhysicalSize<u32>) {
        if let Some(state) = self.state.as_mut() {
            state.size = size;
            state.needs_recreate = true;
        }
    }

    /// Counts a presented frame in the report.
    fn count_frame(&mut self) {
        let report = &mut self.report;
        report.frames_presented += 1;
        if let Some(state) = &self.state {
            let extent = state.swapchain.extent;
            report.final_extent = (extent.width, extent.height);
        }
        // What the frames showed is the report of a scripted run only: a person's session
        // spends nothing on it per frame.
        if self.script.is_none() {
            return;
        }
        let view = &self.view;
        let mode = match view.mode {
            Mode::Multirate => format!("{} ({})", view.mode, view.placement),
            mode => mode.to_string(),
        };
        *report.frames_by_mode.entry(mode).or_default() += 1;
        report.heat_map_frames += u32::from(view.heat_map);
        report.wireframe_frames += u32::from(view.wireframe);
        report.frames_without_shadows += u32::from(!self.shadows);
        report.frames_without_post += u32::from(!self.post);
        report.frames_on_path += u32::from(self.path.as_ref().is_some_and(PathPlayer::playing));
        if view.mode == Mode::Multirate {
            let epsilon = view.estimator.epsilon;
            report.n_max_values.insert(view.estimator.n_max);
            let (low, high) = report.epsilon_range.unwrap_or((epsilon, epsilon));
            report.epsilon_range = Some((low.min(epsilon), high.max(epsilon)));
        }
    }

    /// A drag or a scroll moves the camera from where the path has it (paused there).
    fn take_over_from_path(&mut self) {
        if let Some(path) = self.path.as_mut().filter(|path| path.following) {
            self.orbit = Orbit::from_camera(&path.camera(&self.scene.camera));
            path.pause();
            path.following = false;
        }
    }

    /// Mode keys: P pixel, D pixel-deferred, V vertex, F fixed:N, M multirate, + / - change N
    /// (and switch to fixed:N); [ / ] halve / double multirate's ε (within 10⁻⁴ to 10); < / >
    /// (or , / .) halve / double its n_max (within 1 to `MAX_LEVEL`); E moves multirate's
    /// estimator between the control stage and the compute pre-pass; T times `pixel` mode
    /// again for the title's speed; S turns the shadows off and on; O the post chain; Space
    /// pauses and resumes the camera path.
    fn on_key(&mut self, text: &str) {
        let level = match self.view.mode {
            Mode::Fixed(level) => level,
            _ => self.fixed_level,
        };
        self.view.mode = match text.to_ascii_lowercase().as_str() {
            "p" => Mode::Pixel,
            "d" => Mode::PixelDeferred,
            "v" => Mode::Vertex,
            "f" => Mode::Fixed(level),
            "m" => Mode::Multirate,
            "h" => {
                self.view.heat_map = !self.view.heat_map;
                return;
            }
            "t" => {
                self.retime = true;
                return;
            }
            "o" => {
                self.post = !self.post;
                return;
            }
            " " => {
                if let Some(path) = &mut self.path {
                    path.toggle();
                }
                return;
            }
            "s" => {
                if self.scene.shadow_casters.is_empty() {
                    eprintln!("no light of this scene casts shadows");
                } else {
                    self.shadows = !self.shadows;
                    self.remake_renderer = true;
                }
                return;
            }
            "[" | "]" => {
                let factor = if text == "[" { 0.5 } else { 2.0 };
                let stepped =
                    (self.view.estimator.epsilon * factor).clamp(*EPSILON_KEYS.start(), *EPSILON_KEYS.end());
                self.view.estimator.epsilon = check_epsilon(stepped).unwrap_or(self.view.estimator.epsilon);
                return;
            }
            "<" | "," => {
                self.view.estimator.n_max = (self.view.estimator.n_max / 2).max(*N_MAX_RANGE.start());
                return;
            }
            ">" | "." => {
                self.view.estimator.n_max = (self.view.estimator.n_max * 2).min(*N_MAX_RANGE.end());
                return;
            }
            "e" => {
                self.view.placement = match self.view.placement {
                    Placement::Tcs => Placement::Compute,
                    Placement::Compute => Placement::Tcs,
                };
                return;
            }
            "w" => {
                let supported = self.state.as_mut().map(|s| s.renderer.enable_wireframe());
                match supported {
                    Some(Ok(true)) => self.view.wireframe = !self.view.wireframe,
                    Some(Ok(false)) => eprintln!("wireframe needs the fillModeNonSolid feature"),
                    Some(Err(error)) => eprintln!("cannot build the wireframe pipelines: {error}"),
                    None => {}
                }
                return;
            }
            "+" | "=" => Mode::Fixed((level + 1).min(MAX_LEVEL)),
            "-" => Mode::Fixed(level.saturating_sub(1).max(1)),
            _ => return,
        };
        if let Mode::Fixed(level) = self.view.mode {
            self.fixed_level = level;
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, error: Error) {
        self.error = Some(error);
        event_loop.exit();
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_some() {
            return;
        }
        match self.create_state(event_loop) {
            Ok(state) => {
                state.window.request_redraw();
                self.state = Some(state);
                self.started = Instant::now();
            }
            Err(error) => self.fail(event_loop, error),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                match event.logical_key.as_ref() {
                    Key::Named(NamedKey::Escape) => event_loop.exit(),
                    Key::Named(NamedKey::Space) => self.on_key(" "),
                    Key::Character(text) => self.on_key(text),
                    _ => {}
                }
            }
            WindowEvent::Resized(size) => self.on_resized(size),
            WindowEvent::MouseInput { state: pressed, button: MouseButton::Left, .. } => {
                self.drag = (pressed == ElementState::Pressed).then_some((f64::NAN, f64::NAN));
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let Some((x, y)) = self.drag {
                    if x.is_finite() {
                        self.take_over_from_path();
                        self.orbit.rotate((position.x - x) as f32, (position.y - y) as f32);
                    }
                    self.drag = Some((position.x, position.y));
                }
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                self.take_over_from_path();
                self.orbit.zoom(steps);
            }
            WindowEvent::RedrawRequested => {
                match self.draw_frame() {
                    Ok(true) => {
                        self.count_frame();
                        self.update_title();
                    }
                    Ok(false) => {}
                    Err(error) => return self.fail(event_loop, error),
                }
                self.report.turns += 1;
                self.run_script(event_loop);
                if let Some(state) = &self.state {
                    state.window.request_redraw();
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(state) = &self.state {
            state.window.request_redraw();
        }
    }

    fn exiting(&mut self, _event_loop: &ActiveEventLoop) {
        self.report.final_view = Some(self.view.clone());
        self.report.duration = self.started.elapsed();
        if let Some(state) = &self.state {
            self.report.validation_messages = state.context.validation().count();
            self.report.device = state.context.info.name.clone();
        }
    }
}

trait ExtentExt {
    fn max_one(self) -> Self;
}

impl ExtentExt for vk::Extent2D {
    fn max_one(self) -> Self {
        vk::Extent2D { width: self.width.max(1), height: self.height.max(1) }
    }
}

/// `scene`, or a copy of it whose lights cast no shadows.
fn shown_scene(scene: &Scene, shadows: bool) -> std::borrow::Cow<'_, Scene> {
    if shadows || scene.shadow_casters.is_empty() {
        std::borrow::Cow::Borrowed(scene)
    } else {
        std::borrow::Cow::Owned(scene.without_shadows())
    }
}

/// `view`'s shading evaluations as a percentage of `pixel` mode's at the same camera; None
/// where the device cannot count them.
fn evaluation_percent(renderer: &Renderer, target: &RenderTarget, view: &View) -> Result<Option<f64>> {
    let count = |view: &View| match renderer.count_evaluations(target, view) {
        Ok(counts) => Ok(Some(counts)),
        Err(Error::Unsupported { .. }) => Ok(None),
        Err(error) => Err(error),
    };
    // What the view shades, not what its heat map or wireframe show.
    let shaded = View { heat_map: false, wireframe: false, ..view.clone() };
    let pixel = View { mode: Mode::Pixel, ..shaded.clone() };
    let (Some(counts), Some(reference)) = (count(&shaded)?, count(&pixel)?) else { return Ok(None) };
    Ok(Some(100.0 * counts.total() as f64 / reference.total().max(1) as f64))
}

mod path_player;
mod script;
mod speed;
