//! `sppm-gpu view SCENE`: a window that shows the estimate refining pass by pass, with the
//! camera, method and exposure under the user's hands.
//!
//! It is an application of the library like any other: this module belongs to the binary, so
//! it reaches only the library's public API. It makes its device with
//! [`GpuContext::for_surface`], records each frame's work into its own encoder through
//! [`Integrator`] (`record_pass_part` sized to a time budget, `record_resolve_to_texture`,
//! `set_camera`, `reset`) and draws the texture with its own shader (`blit.wgsl`).
//!
//! Responsiveness: a frame records at most one part of a pass, sized from the measured
//! throughput of earlier parts to take about [`PART_SECONDS`], and never waits for the GPU:
//! while the part before is still running the frame only redraws.

mod blit;
mod orbit;
mod save;

use blit::{Blit, DisplayParams};
use sppm_gpu::gpu::GpuContext;
use sppm_gpu::image_io::Rgb32Image;
use sppm_gpu::integrators::{self, Integrator, PartSize, Work};
use sppm_gpu::scene::{Camera, Method, Named, Scene};
use sppm_gpu::{metrics, say, Error};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::dpi::{PhysicalPosition, PhysicalSize};
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, ModifiersState, NamedKey};
use winit::window::{Window, WindowId};

/// GPU time a frame's part of a pass aims at: 40 ms leaves room for the draw within the
/// 100 ms of 10 frames per second on a slow device.
const PART_SECONDS: f64 = 0.04;

/// Degrees an arrow key turns the camera; fractions of the distance a shifted arrow pans.
const ORBIT_STEP: f32 = 5.0;
const PAN_STEP: f32 = 0.05;
/// Distance factor of a page key or a wheel notch.
const DOLLY_STEP: f32 = 0.9;
/// Exposure change of a key press, stops.
const EXPOSURE_STEP: f32 = 0.5;
/// Seconds between read-backs for the title's radius and relMSE (and the error map).
const READOUT_SECONDS: f64 = 1.0;

/// The keys, as `H` prints them.
pub const KEYS: &str = "\
keys: 1 sppm, 2 pt-nee, 3 pt, 4 lt, 5 bpt, 6 vcm | arrows orbit, shift+arrows pan, page up/down zoom (mouse: left drag orbit, \
right or middle drag pan, wheel zoom), r the scene's camera | + and - exposure | e error map (with --reference) | \
space pause | s save (EXR, PNG and the scene as TOML, next to the scene) | h these keys | q or escape quit";

/// What the command line gives the window.
pub struct Options {
    /// The scene file, for its text and where saves go.
    pub scene_path: PathBuf,
    /// The scene as loaded, with the command line's render settings.
    pub scene: Scene,
    /// A reference image of the same size, for relMSE and the error map.
    pub reference: Option<PathBuf>,
    /// Pause after this many passes, and again after each restart.
    pub passes_then_pause: Option<u32>,
    /// Exposure, stops.
    pub exposure: f32,
}

/// The line to print when there is no display.
pub fn no_display() -> Option<String> {
    let set = |name: &str| std::env::var_os(name).is_some_and(|v| !v.is_empty());
    (!set("DISPLAY") && !set("WAYLAND_DISPLAY")).then(|| {
        "sppm-gpu view needs a display, and neither DISPLAY nor WAYLAND_DISPLAY is set; render without a window with \
         `sppm-gpu SCENE -o OUT.png`"
            .to_string()
    })
}

/// Open the window and run until it is closed.
pub fn run(mut options: Options) -> Result<(), Error> {
    let original = std::fs::read_to_string(&options.scene_path)
        .map_err(|e| Error::Setting(format!("{}: {e}", options.scene_path.display())))?;
    let scene = &mut options.scene;
    // The radius an SPPM render starts from depends on the camera when it is automatic; fix it
    // once, so that every view and the scene a save writes start from the same one.
    if scene.render.radius.is_none() {
        scene.render.radius = Some(integrators::sppm::auto_radius(scene));
    }
    let reference = match &options.reference {
        Some(path) => {
            let image = sppm_gpu::image_io::read_image(path)?;
            if (image.width, image.height) != (scene.render.width, scene.render.height) {
                return Err(Error::Setting(format!(
                    "{}: the reference is {}x{}, the render {}x{}",
                    path.display(),
                    image.width,
                    image.height,
                    scene.render.width,
                    scene.render.height
                )));
            }
            Some(image)
        }
        None => None,
    };
    let event_loop = EventLoop::new().map_err(|e| Error::Setting(format!("cannot open the display: {e}")))?;
    let mut app = App { options, original, reference, view: None, error: None, stats: FrameStats::default() };
    event_loop.run_app(&mut app).map_err(|e| Error::Setting(format!("the window's event loop failed: {e}")))?;
    if let Some(e) = app.error {
        return Err(e);
    }
    say!("{}", app.stats.summary());
    Ok(())
}

struct App {
    options: Options,
    /// The scene file's text, for the scene a save writes.
    original: String,
    reference: Option<Rgb32Image>,
    view: Option<View>,
    /// The error that closed the window.
    error: Option<Error>,
    stats: FrameStats,
}

/// The window, its device and the renderers.
struct View {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    gpu: GpuContext,
    blit: Blit,
    display: DisplayParams,
    /// The estimate of the completed passes, and the error map, as the window shows them.
    estimate: wgpu::Texture,
    error_map: wgpu::Texture,
    /// A renderer per method used so far; a switch back resets it instead of rebuilding it.
    renderers: Vec<(Method, Box<dyn Integrator>)>,
    /// The method shown, and the one asked for (the next restart switches to it).
    method: Method,
    next_method: Method,
    camera: Camera,
    /// Part sizes fitted to PART_SECONDS from measured items per second.
    size: PartSize,
    rates: HashMap<Work, f64>,
    /// The part on the GPU: what it was and when it was submitted; `done` is set when the
    /// GPU has finished it.
    running: Option<(integrators::Part, Instant)>,
    done: Arc<Mutex<Option<Instant>>>,
    /// No part of a pass is recorded and not yet completed.
    at_pass_boundary: bool,
    paused: bool,
    show_error_map: bool,
    /// A camera move or method switch to apply at the next frame, with when it came.
    restart: Option<Instant>,
    /// Inputs not yet shown in a frame, and restarts whose first pass has not yet landed.
    inputs_waiting_for_frame: Vec<Instant>,
    restart_waiting_for_pass: Option<Instant>,
    /// Time spent rendering since the last restart, and when it was last resumed.
    rendering: Duration,
    resumed_at: Option<Instant>,
    readout: Readout,
    modifiers: ModifiersState,
    drag: Option<(MouseButton, PhysicalPosition<f64>)>,
    shown_title: String,
    last_title: Instant,
}

/// What the title shows besides counts, read back at most once a READOUT_SECONDS.
#[derive(Default)]
struct Readout {
    mean_radius: Option<f32>,
    rel_mse: Option<f64>,
    /// Passes at the last read-back, and when.
    passes: u32,
    at: Option<Instant>,
}

/// Frame rate and latency figures for the summary printed on quit.
#[derive(Default)]
struct FrameStats {
    frames_rendering: u64,
    seconds_rendering: f64,
    longest_frame: f64,
    last_frame: Option<Instant>,
    input_to_frame: Vec<f64>,
    input_to_pass: Vec<f64>,
    parts: u64,
    part_seconds: f64,
}

impl FrameStats {
    fn summary(&self) -> String {
        let mean = |v: &[f64]| v.iter().fold(0.0, |a, b| a + b) / v.len().max(1) as f64 * 1e3;
        let max = |v: &[f64]| v.iter().fold(0.0f64, |a, &b| a.max(b)) * 1e3;
        let mut text = format!(
            "frames: {} while rendering in {:.1} s, {:.1} frames/s, longest frame {:.0} ms; {} parts of passes, {:.0} ms \
             each on average",
            self.frames_rendering,
            self.seconds_rendering,
            self.frames_rendering as f64 / self.seconds_rendering.max(1e-9),
            self.longest_frame * 1e3,
            self.parts,
            self.part_seconds / self.parts.max(1) as f64 * 1e3,
        );
        if !self.input_to_frame.is_empty() {
            text += &format!(
                "; input to the next frame {:.0} ms on average, {:.0} ms at most ({} inputs)",
                mean(&self.input_to_frame),
                max(&self.input_to_frame),
                self.input_to_frame.len()
            );
        }
        if !self.input_to_pass.is_empty() {
            text += &format!("; a camera move or method switch to its first pass {:.0} ms on average", mean(&self.input_to_pass));
        }
        text
    }
}

/// The renderer of `method` among those made so far.
fn renderer_of(renderers: &mut [(Method, Box<dyn Integrator>)], method: Method) -> &mut Box<dyn Integrator> {
    &mut renderers.iter_mut().find(|(m, _)| *m == method).expect("a renderer is made before it is used").1
}

impl App {
    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<View, Error> {
        let scene = &self.options.scene;
        let (w, h) = (scene.render.width, scene.render.height);
        let scale = (512 / w.max(h)).max(1);
        let attributes = Window::default_attributes()
            .with_title(format!("sppm-gpu view: {}", self.scene_name()))
            .with_inner_size(PhysicalSize::new(w * scale, h * scale));
        let window =
            Arc::new(event_loop.create_window(attributes).map_err(|e| Error::Setting(format!("cannot open a window: {e}")))?);
        let instance = GpuContext::instance();
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| Error::Setting(format!("cannot draw into the window with the GPU: {e}")))?;
        let gpu = GpuContext::for_surface(&instance, &surface)?;
        let caps = surface.get_capabilities(&gpu.adapter);
        // A format the shader encodes sRGB into, where there is one.
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| !f.is_srgb())
            .or(caps.formats.first().copied())
            .ok_or_else(|| Error::Setting(format!("the GPU {} cannot draw into this window", gpu.adapter_info.name)))?;
        let size = window.inner_size();
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            color_space: wgpu::SurfaceColorSpace::Auto,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoNoVsync,
            desired_maximum_frame_latency: 1,
            alpha_mode: caps.alpha_modes.first().copied().unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: vec![],
        };
        surface.configure(&gpu.device, &config);
        let texture = |label, usage| {
            gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba32Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | usage,
                view_formats: &[],
            })
        };
        let estimate = texture("estimate", wgpu::TextureUsages::STORAGE_BINDING);
        let error_map = texture("error map", wgpu::TextureUsages::COPY_DST);
        let mut display = DisplayParams::fit([w, h], [config.width, config.height]);
        display.exposure = 2f32.powf(self.options.exposure);
        display.surface_srgb = format.is_srgb() as u32;
        let mut scene = scene.clone();
        scene.render.fit_pass_work(gpu.pass_work());
        let renderer = integrators::create(&gpu.device, &gpu.queue, &scene)?;
        let blit = Blit::new(&gpu.device, format);
        let now = Instant::now();
        Ok(View {
            window,
            surface,
            config,
            blit,
            display,
            estimate,
            error_map,
            renderers: vec![(scene.render.method, renderer)],
            method: scene.render.method,
            next_method: scene.render.method,
            camera: scene.camera.clone(),
            gpu,
            // Small first parts; the measured rates take over after one of each.
            size: PartSize { points: 4096, photons: 4096 },
            rates: HashMap::new(),
            running: None,
            done: Arc::new(Mutex::new(None)),
            at_pass_boundary: true,
            paused: false,
            show_error_map: false,
            restart: None,
            inputs_waiting_for_frame: Vec::new(),
            restart_waiting_for_pass: None,
            rendering: Duration::ZERO,
            resumed_at: Some(now),
            readout: Readout::default(),
            modifiers: ModifiersState::empty(),
            drag: None,
            shown_title: String::new(),
            last_title: now - Duration::from_secs(1),
        })
    }

    fn scene_name(&self) -> String {
        self.options.scene_path.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned())
    }

    /// One frame: apply what the user asked for, read back what the title shows, record the
    /// next part of the pass if the GPU is free, and draw.
    fn frame(&mut self) -> Result<(), Error> {
        let name = self.scene_name();
        let limit = self.options.passes_then_pause;
        let Some(view) = self.view.as_mut() else { return Ok(()) };
        let _ = view.gpu.device.poll(wgpu::PollType::Poll);
        view.gpu.check()?;
        if let Some(at) = view.restart.take() {
            view.start_over(&self.options.scene)?;
            view.restart_waiting_for_pass = Some(at);
        }
        view.collect_finished_part(&mut self.stats);
        if view.running.is_none() && view.at_pass_boundary {
            view.read_back(self.reference.as_ref())?;
        }
        if !view.paused && view.running.is_none() {
            view.record_part(limit)?;
        }
        view.draw()?;
        let now = Instant::now();
        for at in view.inputs_waiting_for_frame.drain(..) {
            self.stats.input_to_frame.push((now - at).as_secs_f64());
        }
        if !view.paused {
            if let Some(last) = self.stats.last_frame {
                let dt = (now - last).as_secs_f64();
                self.stats.frames_rendering += 1;
                self.stats.seconds_rendering += dt;
                self.stats.longest_frame = self.stats.longest_frame.max(dt);
            }
            self.stats.last_frame = Some(now);
        } else {
            self.stats.last_frame = None;
        }
        // At most five titles a second while the figures run, at once when they stop.
        let title = view.title(&name);
        if title != view.shown_title && (view.paused || now - view.last_title >= Duration::from_millis(200)) {
            view.window.set_title(&title);
            view.shown_title = title;
            view.last_title = now;
        }
        Ok(())
    }

    fn key(&mut self, key: &Key, event_loop: &ActiveEventLoop) -> Result<(), Error> {
        let home = self.options.scene.camera.clone();
        let has_reference = self.reference.is_some();
        let Some(view) = self.view.as_mut() else { return Ok(()) };
        let shift = view.modifiers.shift_key();
        let camera = view.camera.clone();
        let moved = match key {
            Key::Named(NamedKey::ArrowLeft) if shift => Some(orbit::pan(&camera, -PAN_STEP, 0.0)),
            Key::Named(NamedKey::ArrowRight) if shift => Some(orbit::pan(&camera, PAN_STEP, 0.0)),
            Key::Named(NamedKey::ArrowUp) if shift => Some(orbit::pan(&camera, 0.0, PAN_STEP)),
            Key::Named(NamedKey::ArrowDown) if shift => Some(orbit::pan(&camera, 0.0, -PAN_STEP)),
            Key::Named(NamedKey::ArrowLeft) => Some(orbit::orbit(&camera, -ORBIT_STEP, 0.0)),
            Key::Named(NamedKey::ArrowRight) => Some(orbit::orbit(&camera, ORBIT_STEP, 0.0)),
            Key::Named(NamedKey::ArrowUp) => Some(orbit::orbit(&camera, 0.0, ORBIT_STEP)),
            Key::Named(NamedKey::ArrowDown) => Some(orbit::orbit(&camera, 0.0, -ORBIT_STEP)),
            Key::Named(NamedKey::PageUp) => Some(orbit::dolly(&camera, DOLLY_STEP, &home)),
            Key::Named(NamedKey::PageDown) => Some(orbit::dolly(&camera, 1.0 / DOLLY_STEP, &home)),
            Key::Character(c) if c.as_str() == "r" => Some(home),
            _ => None,
        };
        if let Some(camera) = moved {
            view.move_camera(camera);
            return Ok(());
        }
        let now = Instant::now();
        match key {
            Key::Named(NamedKey::Escape) => event_loop.exit(),
            Key::Named(NamedKey::Space) => view.set_paused(!view.paused),
            Key::Character(c) => match c.as_str() {
                "q" => event_loop.exit(),
                "1" | "2" | "3" | "4" | "5" | "6" => {
                    let method = [Method::Sppm, Method::PtNee, Method::Pt, Method::Lt, Method::Bpt, Method::Vcm]
                        [(c.as_bytes()[0] - b'1') as usize];
                    if method != view.next_method {
                        view.next_method = method;
                        view.restart = Some(now);
                        view.set_paused(false);
                    }
                }
                "+" | "=" => view.display.exposure *= 2f32.powf(EXPOSURE_STEP),
                "-" | "_" => view.display.exposure /= 2f32.powf(EXPOSURE_STEP),
                "e" if has_reference => {
                    view.show_error_map = !view.show_error_map;
                    // Made at the next read-back.
                    view.readout.at = None;
                }
                "e" => say!("no error map without --reference REF.exr"),
                "h" => say!("{KEYS}"),
                "s" => self.save()?,
                _ => return Ok(()),
            },
            _ => return Ok(()),
        }
        if let Some(view) = self.view.as_mut() {
            view.inputs_waiting_for_frame.push(now);
        }
        Ok(())
    }

    /// The save key: finish the pass under way, then write the image and the scene that
    /// renders it.
    fn save(&mut self) -> Result<(), Error> {
        let Some(view) = self.view.as_mut() else { return Ok(()) };
        let renderer = renderer_of(&mut view.renderers, view.method);
        if !view.at_pass_boundary || renderer.passes() == 0 {
            let mut encoder = view.gpu.device.create_command_encoder(&Default::default());
            renderer.record_pass(&mut encoder);
            renderer.record_resolve_to_texture(&mut encoder, &view.estimate)?;
            view.gpu.queue.submit([encoder.finish()]);
            view.at_pass_boundary = true;
        }
        let image = renderer.image()?;
        let passes = renderer.passes();
        let mut render = self.options.scene.render.clone();
        render.method = view.method;
        if sppm_gpu::scene::is_foreign(&self.options.scene_path) {
            let saved = save::save(&self.options.scene_path, &image, None)?;
            say!(
                "saved {} and {} ({} passes of {}; the camera of a Mitsuba XML or pbrt-v4 scene is not written back)",
                saved.exr.display(),
                saved.png.display(),
                passes,
                view.method.name()
            );
            return Ok(());
        }
        let text = save::scene_text(&self.original, &view.camera, &render, passes)?;
        let saved = save::save(&self.options.scene_path, &image, Some(&text))?;
        say!(
            "saved {}, {} and {} ({} passes of {})",
            saved.exr.display(),
            saved.png.display(),
            saved.toml.display(),
            passes,
            view.method.name()
        );
        Ok(())
    }

    fn mouse(&mut self, event: &WindowEvent) {
        let home = self.options.scene.camera.clone();
        let Some(view) = self.view.as_mut() else { return };
        match *event {
            WindowEvent::MouseInput { state: ElementState::Pressed, button, .. } => {
                view.drag = view.drag.or(Some((button, PhysicalPosition::new(f64::NAN, f64::NAN))));
            }
            WindowEvent::MouseInput { state: ElementState::Released, .. } => view.drag = None,
            WindowEvent::CursorMoved { position, .. } => {
                let Some((button, last)) = view.drag else { return };
                view.drag = Some((button, position));
                if last.x.is_nan() {
                    return;
                }
                let (dx, dy) = ((position.x - last.x) as f32, (position.y - last.y) as f32);
                let height = view.config.height.max(1) as f32;
                let camera = match button {
                    MouseButton::Left => orbit::orbit(&view.camera, -dx * 0.3, dy * 0.3),
                    _ => orbit::pan(&view.camera, -dx / height, dy / height),
                };
                view.move_camera(camera);
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 50.0,
                };
                view.move_camera(orbit::dolly(&view.camera, DOLLY_STEP.powf(notches), &home));
            }
            _ => {}
        }
    }
}

impl View {
    fn renderer(&mut self) -> &mut Box<dyn Integrator> {
        renderer_of(&mut self.renderers, self.method)
    }

    fn move_camera(&mut self, camera: Camera) {
        self.camera = camera;
        let now = Instant::now();
        self.restart.get_or_insert(now);
        self.inputs_waiting_for_frame.push(now);
        self.set_paused(false);
    }

    fn set_paused(&mut self, paused: bool) {
        if paused && !self.paused {
            self.rendering += self.resumed_at.take().map_or(Duration::ZERO, |t| t.elapsed());
        } else if !paused && self.paused {
            self.resumed_at = Some(Instant::now());
        }
        self.paused = paused;
    }

    /// Apply a camera move or a method switch: the renderer of the method (made on first use)
    /// starts over from the current camera.
    fn start_over(&mut self, scene: &Scene) -> Result<(), Error> {
        self.method = self.next_method;
        if !self.renderers.iter().any(|(m, _)| *m == self.method) {
            let mut scene = scene.clone();
            scene.render.method = self.method;
            scene.render.fit_pass_work(self.gpu.pass_work());
            scene.camera = self.camera.clone();
            let renderer = integrators::create(&self.gpu.device, &self.gpu.queue, &scene)?;
            self.renderers.push((self.method, renderer));
        }
        let camera = self.camera.clone();
        self.renderer().set_camera(&camera)?;
        // A part still running belongs to the old view; its figures are dropped.
        self.running = None;
        *self.done.lock().unwrap_or_else(|p| p.into_inner()) = None;
        self.at_pass_boundary = true;
        self.rendering = Duration::ZERO;
        self.resumed_at = (!self.paused).then(Instant::now);
        self.readout = Readout::default();
        Ok(())
    }

    /// Take in the part the GPU has finished, if it has: its time refines the rate of its work.
    fn collect_finished_part(&mut self, stats: &mut FrameStats) {
        let Some((part, submitted)) = self.running else { return };
        let Some(done) = self.done.lock().unwrap_or_else(|p| p.into_inner()).take() else { return };
        self.running = None;
        let seconds = (done - submitted).as_secs_f64().max(1e-4);
        stats.parts += 1;
        stats.part_seconds += seconds;
        let rate = part.items as f64 / seconds;
        // Smoothed, so that one slow part does not halve the next.
        let smooth = self.rates.get(&part.work).map_or(rate, |r| 0.5 * r + 0.5 * rate);
        self.rates.insert(part.work, smooth);
        let items = (smooth * PART_SECONDS).clamp(256.0, u32::MAX as f64) as u32;
        match part.work {
            Work::CameraPaths => self.size.points = items,
            Work::Photons => self.size.photons = items,
        }
        if part.pass_done {
            if let Some(at) = self.restart_waiting_for_pass.take() {
                stats.input_to_pass.push(at.elapsed().as_secs_f64());
            }
        }
    }

    /// Record and submit the next part of the pass; after its last part, the estimate into
    /// the window's texture.
    fn record_part(&mut self, limit: Option<u32>) -> Result<(), Error> {
        let size = self.size;
        let mut encoder = self.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("view part") });
        let renderer = renderer_of(&mut self.renderers, self.method);
        let part = renderer.record_pass_part(&mut encoder, size);
        if part.pass_done {
            renderer.record_resolve_to_texture(&mut encoder, &self.estimate)?;
        }
        let passes = renderer.passes();
        let submitted = Instant::now();
        self.gpu.queue.submit([encoder.finish()]);
        let done = self.done.clone();
        self.gpu.queue.on_submitted_work_done(move || {
            *done.lock().unwrap_or_else(|p| p.into_inner()) = Some(Instant::now());
        });
        self.running = Some((part, submitted));
        self.at_pass_boundary = part.pass_done;
        if part.pass_done && limit.is_some_and(|n| passes >= n) {
            self.set_paused(true);
        }
        Ok(())
    }

    /// At a pass boundary with the GPU idle, at most once a READOUT_SECONDS: the mean radius,
    /// relMSE against the reference and the error map.
    fn read_back(&mut self, reference: Option<&Rgb32Image>) -> Result<(), Error> {
        let passes = self.renderer().passes();
        // Paused, the figures stop changing: read them at once.
        let due = self.paused || self.readout.at.is_none_or(|t| t.elapsed().as_secs_f64() >= READOUT_SECONDS);
        if passes == 0 || !due || (passes == self.readout.passes && self.readout.at.is_some()) {
            return Ok(());
        }
        self.readout.mean_radius = self.renderer().radius_stats()?.map(|r| r.mean);
        if let Some(reference) = reference {
            let image = self.renderer().image()?;
            self.readout.rel_mse = metrics::compare(&image, reference, 1).ok().map(|c| c.rel_mse);
            if self.show_error_map {
                let map = metrics::false_colour(&image, reference).map_err(Error::Setting)?;
                let texels: Vec<[f32; 4]> = map.pixels.iter().map(|p| [p[0], p[1], p[2], 1.0]).collect();
                self.gpu.queue.write_texture(
                    self.error_map.as_image_copy(),
                    bytemuck::cast_slice(&texels),
                    wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(map.width * 16), rows_per_image: None },
                    self.error_map.size(),
                );
            }
        }
        self.readout.passes = passes;
        self.readout.at = Some(Instant::now());
        Ok(())
    }

    fn draw(&mut self) -> Result<(), Error> {
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(frame) => frame,
            wgpu::CurrentSurfaceTexture::Suboptimal(frame) => {
                drop(frame);
                self.surface.configure(&self.gpu.device, &self.config);
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => return Ok(()),
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(&self.gpu.device, &self.config);
                return Ok(());
            }
            other => return Err(Error::Setting(format!("cannot draw into the window: {other:?}"))),
        };
        let target = frame.texture.create_view(&wgpu::TextureViewDescriptor::default());
        let mut params = self.display;
        let picture = if self.show_error_map && self.readout.rel_mse.is_some() {
            params.display_values = 1;
            &self.error_map
        } else {
            &self.estimate
        };
        let mut encoder = self.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("view draw") });
        self.blit.record(&self.gpu.device, &self.gpu.queue, &mut encoder, picture, &target, &params);
        self.gpu.queue.submit([encoder.finish()]);
        self.window.pre_present_notify();
        self.gpu.queue.present(frame);
        Ok(())
    }

    fn resize(&mut self, size: PhysicalSize<u32>) {
        if size.width == 0 || size.height == 0 {
            return;
        }
        self.config.width = size.width;
        self.config.height = size.height;
        self.surface.configure(&self.gpu.device, &self.config);
        let exposure = self.display.exposure;
        let surface_srgb = self.display.surface_srgb;
        self.display = DisplayParams::fit(self.display.image_size, [size.width, size.height]);
        self.display.exposure = exposure;
        self.display.surface_srgb = surface_srgb;
    }

    /// `sppm-gpu view: NAME | METHOD | N passes | paused | RATE | TIME | r R | relMSE E | H: keys`
    fn title(&mut self, name: &str) -> String {
        let method = self.method;
        let renderer = self.renderer();
        let passes = renderer.passes();
        let (work, unit) = (renderer.work_per_pass(), renderer.work_unit());
        let seconds = (self.rendering + self.resumed_at.map_or(Duration::ZERO, |t| t.elapsed())).as_secs_f64();
        let mut fields = vec![
            format!("sppm-gpu view: {name}"),
            method.name().to_string(),
            format!("{passes} pass{}", if passes == 1 { "" } else { "es" }),
        ];
        if self.paused {
            fields.push("paused".into());
        }
        fields.push(format!("{:.2} M {unit}/s", passes as f64 * work as f64 / seconds.max(1e-9) / 1e6));
        fields.push(format!("{seconds:.1} s"));
        if let Some(r) = self.readout.mean_radius {
            fields.push(format!("r {r:.2e}"));
        }
        if let Some(e) = self.readout.rel_mse {
            fields.push(format!("relMSE {e:.2e}"));
        }
        if self.show_error_map {
            fields.push("error map".into());
        }
        fields.push("H: keys".into());
        fields.join(" | ")
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.view.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(view) => {
                view.window.request_redraw();
                self.view = Some(view);
            }
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let result = match &event {
            WindowEvent::CloseRequested => {
                event_loop.exit();
                Ok(())
            }
            WindowEvent::Resized(size) => {
                if let Some(view) = self.view.as_mut() {
                    view.resize(*size);
                }
                Ok(())
            }
            WindowEvent::ModifiersChanged(m) => {
                if let Some(view) = self.view.as_mut() {
                    view.modifiers = m.state();
                }
                Ok(())
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                self.key(&event.logical_key, event_loop)
            }
            WindowEvent::MouseInput { .. } | WindowEvent::CursorMoved { .. } | WindowEvent::MouseWheel { .. } => {
                self.mouse(&event);
                Ok(())
            }
            WindowEvent::RedrawRequested => self.frame(),
            _ => Ok(()),
        };
        if let Err(e) = result {
            self.error = Some(e);
            event_loop.exit();
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let name = self.scene_name();
        let Some(view) = self.view.as_mut() else { return };
        // Frames back to back while rendering; while paused, until the last part, the
        // read-back and the title are in, then only when something happens.
        let passes = view.renderer().passes();
        let settled = view.running.is_none() && view.readout.passes == passes && view.title(&name) == view.shown_title;
        let busy = !view.paused || !settled || view.restart.is_some();
        if busy || !view.inputs_waiting_for_frame.is_empty() {
            event_loop.set_control_flow(ControlFlow::Poll);
            view.window.request_redraw();
        } else {
            event_loop.set_control_flow(ControlFlow::Wait);
        }
    }
}
