//! The `sppm_gpu` Python package's native module, `sppm_gpu._native`: scenes loaded with the
//! library's readers, rendered on the library's integrators through its pacer, images handed
//! to numpy without a copy. The package's Python side (`python/sppm_gpu/`) re-exports it with
//! its type stubs; `docs/guide/python.md` shows it in use.
//!
//! Every render runs off the calling thread with the GIL released (`render()` and `compare()`
//! on the device's render thread, where renders share the kernels they have in common; a
//! progressive render on a thread of its own); the calling thread waits for it in short steps
//! and checks Python's signals between them, so that Ctrl-C raises `KeyboardInterrupt` within
//! a pass, without waiting for the pass (the renderer then stops after the passes already on
//! the device).

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::exceptions::{PyException, PyRuntimeError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use sppm_gpu::gpu::GpuContext;
use sppm_gpu::image_io::{self, Rgb32Image};
use sppm_gpu::integrators::{self, Integrator};
use sppm_gpu::pacing::{DeviceQueue, Goal, Pacer};
use sppm_gpu::scene::{self, Named, Overrides, SettingNames};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::Duration;

pyo3::create_exception!(
    sppm_gpu,
    Error,
    PyException,
    "Anything sppm_gpu refuses or fails at: the base of SceneError, GpuError, ImageError and SettingError."
);
pyo3::create_exception!(
    sppm_gpu,
    SceneError,
    Error,
    "A scene file, or a mesh or texture it names, is malformed or missing. Attributes: file (str), line (int or None), key (str or None), message (str)."
);
pyo3::create_exception!(sppm_gpu, GpuError, Error, "No adapter, a device the renderer cannot use, or a failed device.");
pyo3::create_exception!(sppm_gpu, ImageError, Error, "An image could not be read or written. Attribute: file (str).");
pyo3::create_exception!(sppm_gpu, SettingError, Error, "A setting out of range or unknown.");

/// The library's error as the Python exception of its kind, with the scene error's place as
/// attributes.
fn to_py(py: Python<'_>, error: sppm_gpu::Error) -> PyErr {
    let message = error.to_string();
    match error {
        sppm_gpu::Error::Scene(e) => {
            let err = SceneError::new_err(message);
            let value = err.value(py);
            let _ = value.setattr("file", e.file.display().to_string());
            let _ = value.setattr("line", e.line);
            let _ = value.setattr("key", e.key);
            let _ = value.setattr("message", e.message);
            err
        }
        sppm_gpu::Error::Gpu(_) => GpuError::new_err(message),
        sppm_gpu::Error::Image(e) => {
            let err = ImageError::new_err(message);
            let _ = err.value(py).setattr("file", e.path().display().to_string());
            err
        }
        sppm_gpu::Error::Setting(_) => SettingError::new_err(message),
    }
}

/// A library result as a Python one.
fn py_result<T>(py: Python<'_>, result: Result<T, sppm_gpu::Error>) -> PyResult<T> {
    result.map_err(|e| to_py(py, e))
}

/// An image as a float32 numpy array (height, width, 3), C-contiguous, handed over without a
/// copy.
fn to_array<'py>(py: Python<'py>, image: Rgb32Image) -> Bound<'py, PyArray3<f32>> {
    let (w, h) = (image.width as usize, image.height as usize);
    let flat: Vec<f32> = image.pixels.into_iter().flatten().collect();
    Array3::from_shape_vec((h, w, 3), flat).expect("width * height * 3 values").into_pyarray(py)
}

/// A numpy array (height, width, 3) as an image.
fn from_array(array: &PyReadonlyArray3<'_, f32>) -> PyResult<Rgb32Image> {
    let shape = array.shape();
    if shape[2] != 3 || shape[0] == 0 || shape[1] == 0 {
        return Err(PyTypeError::new_err(format!(
            "an image is an array of shape (height, width, 3), got ({}, {}, {})",
            shape[0], shape[1], shape[2]
        )));
    }
    let (h, w) = (u32::try_from(shape[0]), u32::try_from(shape[1]));
    let (Ok(h), Ok(w)) = (h, w) else {
        return Err(PyTypeError::new_err("the image is too large"));
    };
    let view = array.as_array();
    Ok(Rgb32Image::from_fn(w, h, |x, y| {
        let (x, y) = (x as usize, y as usize);
        [view[[y, x, 0]], view[[y, x, 1]], view[[y, x, 2]]]
    }))
}

/// Work for a device's render thread.
type Work = Box<dyn FnOnce() + Send>;

/// A device, kept for the process, and its render thread: every render on the device runs on
/// that thread, one after another, inside `share_kernels`, so that a render whose kernels
/// (name, source, constants) an earlier one made takes them as they are, without naga or the
/// driver compiling them again (seconds on lavapipe): a sweep over settings pays once.
struct Device {
    gpu: Arc<GpuContext>,
    jobs: Mutex<mpsc::Sender<Work>>,
}

/// Renders that share one `share_kernels` scope, after which its kernels are let go (the
/// next render makes its own again): the memory they hold stays bounded.
const RENDERS_SHARING_KERNELS: usize = 32;

impl Device {
    fn new(gpu: GpuContext) -> Result<Arc<Self>, sppm_gpu::Error> {
        let (tx, rx) = mpsc::channel::<Work>();
        std::thread::Builder::new()
            .name("sppm_gpu renderer".into())
            .spawn(move || loop {
                let open = sppm_gpu::gpu::share_kernels(|| {
                    for _ in 0..RENDERS_SHARING_KERNELS {
                        match rx.recv() {
                            Ok(work) => work(),
                            Err(_) => return false,
                        }
                    }
                    true
                });
                if !open {
                    return;
                }
            })
            .map_err(|e| sppm_gpu::Error::Setting(format!("cannot start a render thread: {e}")))?;
        Ok(Arc::new(Device { gpu: Arc::new(gpu), jobs: Mutex::new(tx) }))
    }

    /// Runs `work` on the device's render thread, after the renders before it.
    fn run(
        &self,
        work: impl FnOnce(&mpsc::SyncSender<Message>) -> Result<(), sppm_gpu::Error> + Send + 'static,
    ) -> mpsc::Receiver<Message> {
        let (job, rx) = job(work);
        if let Err(mpsc::SendError(_)) = self.jobs.lock().unwrap_or_else(|p| p.into_inner()).send(job) {
            return ended(sppm_gpu::Error::Setting("the device's render thread has ended".into()));
        }
        rx
    }
}

/// The devices made so far, one per adapter.
static DEVICES: Mutex<Vec<Arc<Device>>> = Mutex::new(Vec::new());

/// Whether two adapters are one.
fn same_adapter(a: &wgpu::AdapterInfo, b: &wgpu::AdapterInfo) -> bool {
    (a.name.as_str(), a.vendor, a.device, a.backend, a.driver.as_str())
        == (b.name.as_str(), b.vendor, b.device, b.backend, b.driver.as_str())
}

/// The adapter `selector` names, by the rule of `GpuContext::with_adapter`: its index in
/// `adapters()`, or a part of its name that no other adapter's name has. `None` where it
/// names none (`with_adapter` then says why).
fn named_adapter(selector: &str) -> Option<wgpu::AdapterInfo> {
    let all = sppm_gpu::gpu::adapters();
    if let Ok(index) = selector.trim().parse::<usize>() {
        return all.into_iter().nth(index);
    }
    let part = selector.trim().to_lowercase();
    let mut matches = all.into_iter().filter(|a| a.name.to_lowercase().contains(&part));
    match (matches.next(), matches.next()) {
        (Some(one), None) => Some(one),
        _ => None,
    }
}

/// The device for `adapter` (an index into `adapters()` or a part of a name; `None`: the
/// default adapter, or the one `SPPM_GPU_ADAPTER` names).
fn device(adapter: Option<String>) -> Result<Arc<Device>, sppm_gpu::Error> {
    let mut devices = DEVICES.lock().unwrap_or_else(|p| p.into_inner());
    devices.retain(|d| d.gpu.check().is_ok());
    let wanted = adapter.as_deref().and_then(named_adapter);
    let found = match (&adapter, &wanted) {
        (None, _) => devices.first(),
        (Some(_), Some(info)) => devices.iter().find(|d| same_adapter(&d.gpu.adapter_info, info)),
        (Some(_), None) => None,
    };
    if let Some(d) = found {
        return Ok(d.clone());
    }
    let d = Device::new(match &adapter {
        Some(selector) => GpuContext::with_adapter(selector)?,
        None => GpuContext::new()?,
    })?;
    // The default device first, as `adapter=None` takes the first.
    match adapter {
        None => devices.insert(0, d.clone()),
        Some(_) => devices.push(d.clone()),
    }
    Ok(d)
}

/// `adapter=`: an int (index) or a str (part of a name).
fn adapter_selector(adapter: Option<&Bound<'_, PyAny>>) -> PyResult<Option<String>> {
    match adapter {
        None => Ok(None),
        Some(a) if a.is_none() => Ok(None),
        Some(a) => {
            if let Ok(i) = a.extract::<u32>() {
                Ok(Some(i.to_string()))
            } else if let Ok(s) = a.extract::<String>() {
                Ok(Some(s))
            } else {
                Err(PyTypeError::new_err("adapter is an index (int) or a part of an adapter's name (str)"))
            }
        }
    }
}

/// What a worker thread sends: an image after so many passes (and seconds of passes), or the
/// end of the run.
enum Message {
    Image { passes: u32, seconds: f64, image: Rgb32Image },
    Done(Result<(), sppm_gpu::Error>),
}

/// `work` as a job that sends its messages, then its end, on the channel returned; a panic
/// in it comes back as an error.
fn job(
    work: impl FnOnce(&mpsc::SyncSender<Message>) -> Result<(), sppm_gpu::Error> + Send + 'static,
) -> (Work, mpsc::Receiver<Message>) {
    let (tx, rx) = mpsc::sync_channel(1);
    let job = Box::new(move || {
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| work(&tx))).unwrap_or_else(|panic| {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic".into());
            Err(sppm_gpu::Error::Setting(format!("internal error in the renderer: {what}")))
        });
        let _ = tx.send(Message::Done(result));
    });
    (job, rx)
}

/// A channel that says only that the work ended with `error`.
fn ended(error: sppm_gpu::Error) -> mpsc::Receiver<Message> {
    let (tx, rx) = mpsc::sync_channel(1);
    let _ = tx.send(Message::Done(Err(error)));
    rx
}

/// Runs `work` on a thread of its own.
fn spawn_worker(
    name: &str,
    work: impl FnOnce(&mpsc::SyncSender<Message>) -> Result<(), sppm_gpu::Error> + Send + 'static,
) -> mpsc::Receiver<Message> {
    let (job, rx) = job(work);
    match std::thread::Builder::new().name(name.to_string()).spawn(job) {
        Ok(_) => rx,
        Err(e) => ended(sppm_gpu::Error::Setting(format!("cannot start a render thread: {e}"))),
    }
}

/// Waits for the worker's next message with the GIL released, checking Python's signals every
/// 50 ms: on Ctrl-C, `stop` is set (the worker ends after the passes on the device) and the
/// `KeyboardInterrupt` is raised at once.
fn wait(py: Python<'_>, rx: &mut mpsc::Receiver<Message>, stop: &AtomicBool) -> PyResult<Message> {
    loop {
        let receiver = &mut *rx;
        match py.detach(move || receiver.recv_timeout(Duration::from_millis(50))) {
            Ok(message) => return Ok(message),
            Err(mpsc::RecvTimeoutError::Timeout) => {
                if let Err(e) = py.check_signals() {
                    stop.store(true, Ordering::SeqCst);
                    return Err(e);
                }
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err("the render thread ended without a result"));
            }
        }
    }
}

/// The settings of one render: the scene with the overrides applied, and the device.
struct Job {
    scene: scene::Scene,
    gpu: Arc<GpuContext>,
    device: Arc<Device>,
}

impl Job {
    /// `scene` with `overrides` applied as the command line applies its options; a time
    /// limit without a pass count runs as many passes as fit. The device's pass work is
    /// filled in, its memory checked.
    fn new(
        py: Python<'_>,
        scene: &scene::Scene,
        overrides: &Overrides,
        adapter: Option<String>,
    ) -> Result<Self, sppm_gpu::Error> {
        let mut scene = scene.clone();
        overrides.apply_to_scene(&mut scene, SettingNames::Keywords)?;
        if overrides.time_limit.is_some() && overrides.iterations.is_none() {
            scene.render.iterations = u32::MAX;
        }
        let device = py.detach(|| device(adapter))?;
        let gpu = device.gpu.clone();
        scene.render.fit_pass_work(gpu.pass_work());
        integrators::check_memory(&gpu.device, &gpu.adapter_info, &scene, None)?;
        Ok(Job { scene, gpu, device })
    }

    /// The integrator, its kernels compiled first under a time limit (so that the limit is
    /// spent on passes, as the command line does).
    fn integrator(&self) -> Result<Box<dyn Integrator>, sppm_gpu::Error> {
        let gpu = &self.gpu;
        match self.scene.render.time_limit {
            Some(_) => {
                Ok(integrators::create_compiled(&gpu.device, &gpu.queue, &self.scene, integrators::FirstPasses::Checked)?.0)
            }
            None => integrators::create(&gpu.device, &gpu.queue, &self.scene),
        }
    }

    /// Runs passes until `end_pass` or until `budget` seconds of passes, through the
    /// library's pacer; returns the seconds the passes took, and `setup`, what the
    /// integrator spent on the render before this run's first pass (vcm's pilot and the check
    /// of its first passes: [`Integrator::setup_seconds`] on the first run, else 0), which the
    /// budget counts. Stops early when `stop` is set.
    fn run(
        &self,
        integrator: &mut dyn Integrator,
        end_pass: u32,
        budget: Option<f64>,
        setup: f64,
        stop: &AtomicBool,
    ) -> Result<f64, sppm_gpu::Error> {
        let gpu = &self.gpu;
        let passes = integrator.passes();
        let budget = budget.map(|b| (b - setup).max(0.0));
        let mut pacer =
            Pacer::new(DeviceQueue::new(integrator, &gpu.device, &gpu.queue), passes, Goal { end_pass, time_limit: budget });
        let mut seconds = 0.0;
        loop {
            if stop.load(Ordering::SeqCst) {
                pacer.stop();
            }
            let Some(done) = pacer.next_completion()? else { break };
            gpu.check()?;
            seconds = done.seconds;
        }
        Ok(setup + seconds)
    }
}

/// Where a progressive render gives an image: after every `every` passes, or at 1, 2, 4, 8,
/// ... passes; and at the end.
fn next_stop(passes: u32, every: Option<u32>, end: u32) -> u32 {
    let next = match every {
        Some(n) => (passes / n + 1).saturating_mul(n),
        None if passes == 0 => 1,
        None => passes.saturating_mul(2),
    };
    next.min(end)
}

/// The render settings that keywords override, one row each: the keyword, how its value is
/// read (`number`: an int, or for a float setting an int or float; `named`: a str, one of the
/// setting's names), the field of [`Overrides`] it sets, and what it means. The one list of
/// them: `$then` makes what it needs of it, the parser ([`KEYWORDS`]) or the lines of
/// `Scene.render`'s docstring (`settings_doc!`). The stubs (`__init__.pyi`) type the same
/// keys, and a test checks that the two agree.
macro_rules! render_settings {
    ($then:ident) => {
        $then! {
            method: named => method, "sppm, pt, pt-nee, lt, bpt or vcm";
            passes: number => iterations, "SPPM's passes, or a path tracer's samples a pixel (--iterations)";
            time_limit: number => time_limit, "seconds of passes; without passes, as many passes as fit";
            seed: number => seed, "the random seed";
            width: number => width, "image width in pixels";
            height: number => height, "image height in pixels";
            photons: number => photons, "photons per SPPM pass";
            radius: number => radius, "SPPM's initial gather radius in scene units";
            alpha: number => alpha, "SPPM's radius reduction, 0 < alpha < 1";
            spp: number => spp, "SPPM's camera samples a pixel in each pass; a path tracer's in all, its passes";
            max_depth: number => max_depth, "most scattering events on a path";
            direct: named => direct, "SPPM's direct light: sampled or photons";
            direct_samples: number => direct_samples, "SPPM's camera paths per visible point that gather direct light";
            light_paths: number => light_paths, "bpt's and vcm's light subpaths a pass (0: vcm without light subpaths)";
            connect_share: number => connect_share, "bpt's and vcm's share of camera vertices that connect, in [0, 1] (vcm with neither share given: its pilot's)";
            merge_share: number => merge_share, "vcm's share of camera vertices that merge, in [0, 1]";
            radius_schedule: named => radius_schedule, "SPPM's radius schedule: per-point or global";
            radius_rule: named => radius_rule, "SPPM's radius rule: shrink or adaptive";
            sampler: named => sampler, "where the random numbers come from: independent or sobol";
        }
    };
}

/// A render setting's keyword and how it sets its field of [`Overrides`] from a value (not
/// None).
struct Keyword {
    name: &'static str,
    set: fn(&mut Overrides, &Bound<'_, PyAny>) -> PyResult<()>,
}

/// [`KEYWORDS`] from [`render_settings`]'s rows.
macro_rules! keyword_table {
    ($($key:ident: $read:ident => $field:ident, $doc:literal;)*) => {
        /// Every render setting's keyword, in the order of [`render_settings`].
        const KEYWORDS: &[Keyword] = &[$(Keyword {
            name: stringify!($key),
            set: |o, value| {
                o.$field = Some($read(stringify!($key), value)?);
                Ok(())
            },
        }),*];
    };
}
render_settings!(keyword_table);

/// The settings as a docstring's list (`- method: the method: ...`), one line each, from
/// [`render_settings`]'s rows.
macro_rules! settings_doc {
    ($($key:ident: $read:ident => $field:ident, $doc:literal;)*) => {
        concat!($("- ", stringify!($key), ": ", $doc, "\n"),*)
    };
}

/// `error`, raised reading keyword `key`'s value, as the same exception naming the keyword
/// (`argument 'passes': 'str' object cannot be interpreted as an integer`).
fn naming(py: Python<'_>, key: &str, error: PyErr) -> PyErr {
    let named = PyErr::from_type(error.get_type(py), format!("argument '{key}': {}", error.value(py)));
    named.set_cause(py, Some(error));
    named
}

/// A number setting's value: an int, or for a float setting an int or a float.
fn number<'py, T>(key: &str, value: &Bound<'py, PyAny>) -> PyResult<T>
where
    T: for<'a> FromPyObject<'a, 'py, Error = PyErr>,
{
    value.extract().map_err(|e| naming(value.py(), key, e))
}

/// A named setting's value (`method`, `direct`, ...): a str, one of its names.
fn named<T: Named>(key: &str, value: &Bound<'_, PyAny>) -> PyResult<T> {
    let py = value.py();
    let name: String = value.extract().map_err(|e| naming(py, key, e))?;
    T::from_name(&name).map_err(|e| to_py(py, sppm_gpu::Error::Setting(e)))
}

/// The render's overrides from `function`'s keyword arguments `params` (a value of None keeps
/// the scene's setting). A keyword that is not a setting, or one of the settings `refused`
/// (each with the reason), is a TypeError, as Python raises for a bad keyword, naming it
/// and listing the settings `function` takes.
fn overrides(function: &str, params: Option<&Bound<'_, PyDict>>, refused: &[(&str, &str)]) -> PyResult<Overrides> {
    let mut o = Overrides::default();
    for (key, value) in params.into_iter().flat_map(|p| p.iter()) {
        let key: String = key.extract()?;
        let reason = refused.iter().find(|(name, _)| *name == key).map(|(_, why)| *why);
        let Some(keyword) = KEYWORDS.iter().find(|k| k.name == key && reason.is_none()) else {
            let taken: Vec<&str> = KEYWORDS.iter().map(|k| k.name).filter(|n| refused.iter().all(|(r, _)| r != n)).collect();
            let why = reason.map_or_else(String::new, |why| format!(" ({why})"));
            return Err(PyTypeError::new_err(format!(
                "{function}() got an unexpected keyword argument '{key}'{why}; its settings are: {}",
                taken.join(", ")
            )));
        };
        if !value.is_none() {
            (keyword.set)(&mut o, &value)?;
        }
    }
    Ok(o)
}

/// A loaded scene: its geometry, materials, lights and camera, and its `[render]` settings.
/// `render()` renders it with settings overridden by keyword; the scene itself is never
/// changed, so one scene serves any number of renders.
#[pyclass(module = "sppm_gpu", frozen)]
struct Scene {
    scene: scene::Scene,
}

#[pymethods]
impl Scene {
    /// The scene file.
    #[getter]
    fn path(&self) -> String {
        self.scene.path.display().to_string()
    }

    /// Image width in pixels (the scene's `render.width`).
    #[getter]
    fn width(&self) -> u32 {
        self.scene.render.width
    }

    /// Image height in pixels (the scene's `render.height`).
    #[getter]
    fn height(&self) -> u32 {
        self.scene.render.height
    }

    /// The scene's method: sppm, pt, pt-nee, lt, bpt or vcm.
    #[getter]
    fn method(&self) -> &'static str {
        self.scene.render.method.name()
    }

    /// The scene's passes (`render.iterations`).
    #[getter]
    fn passes(&self) -> u32 {
        self.scene.render.iterations
    }

    /// The scene's seed (`render.seed`).
    #[getter]
    fn seed(&self) -> u32 {
        self.scene.render.seed
    }

    /// The scene's time limit in seconds (`render.time_limit`), or None.
    #[getter]
    fn time_limit(&self) -> Option<f64> {
        self.scene.render.time_limit
    }

    fn __repr__(&self) -> String {
        let r = &self.scene.render;
        format!(
            "<sppm_gpu.Scene {} {}x{} method={} passes={}>",
            self.scene.path.display(),
            r.width,
            r.height,
            r.method.name(),
            r.iterations
        )
    }

    /// Render the scene; returns linear RGB radiance as a float32 array (height, width, 3).
    /// Each setting, a keyword, overrides the scene's as the command line's option of the same
    /// name does; None keeps the scene's. adapter: the device, an index into adapters() or a
    /// part of an adapter's name (None: the default). The settings:
    #[doc = render_settings!(settings_doc)]
    #[pyo3(signature = (*, adapter=None, **params))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        adapter: Option<&Bound<'py, PyAny>>,
        params: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyArray3<f32>>> {
        let o = overrides("Scene.render", params, &[])?;
        let job = py_result(py, Job::new(py, &self.scene, &o, adapter_selector(adapter)?))?;
        warn_limitations(py, &job.scene)?;
        let stop = Arc::new(AtomicBool::new(false));
        let worker_stop = stop.clone();
        let device = job.device.clone();
        let mut rx = device.run(move |tx| {
            let mut integrator = job.integrator()?;
            let r = &job.scene.render;
            let setup = integrator.setup_seconds();
            let seconds = job.run(integrator.as_mut(), r.iterations, r.time_limit, setup, &worker_stop)?;
            let image = integrator.image()?;
            job.gpu.check()?;
            let _ = tx.send(Message::Image { passes: integrator.passes(), seconds, image });
            Ok(())
        });
        let mut image = None;
        loop {
            match wait(py, &mut rx, &stop)? {
                Message::Image { image: i, .. } => image = Some(i),
                Message::Done(result) => {
                    py_result(py, result)?;
                    break;
                }
            }
        }
        let image = image.ok_or_else(|| PyRuntimeError::new_err("the render ended without an image"))?;
        Ok(to_array(py, image))
    }

    /// Render progressively: an iterator of (passes, image), an image after every `every`
    /// passes (or at 1, 2, 4, 8, ... passes when every is None) and one at the end. The other
    /// keywords are render()'s. Time spent by the caller between images is not counted
    /// against time_limit.
    #[pyo3(signature = (*, every=None, adapter=None, **params))]
    fn progressive<'py>(
        &self,
        py: Python<'py>,
        every: Option<u32>,
        adapter: Option<&Bound<'py, PyAny>>,
        params: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Progressive> {
        if every == Some(0) {
            return Err(to_py(py, sppm_gpu::Error::Setting("every must be at least 1 pass".into())));
        }
        let o = overrides("Scene.progressive", params, &[])?;
        let job = py_result(py, Job::new(py, &self.scene, &o, adapter_selector(adapter)?))?;
        warn_limitations(py, &job.scene)?;
        let stop = Arc::new(AtomicBool::new(false));
        let worker_stop = stop.clone();
        // On a thread of its own rather than the device's render thread: the caller may hold
        // the iterator unfinished, its next image waiting, while it renders something else.
        let rx = spawn_worker("sppm_gpu progressive", move |tx| {
            let mut integrator = job.integrator()?;
            let r = &job.scene.render;
            let mut seconds = 0.0;
            while integrator.passes() < r.iterations && !worker_stop.load(Ordering::SeqCst) {
                let end = next_stop(integrator.passes(), every, r.iterations);
                let budget = r.time_limit.map(|t| t - seconds);
                if budget.is_some_and(|b| b <= 0.0) {
                    break;
                }
                let before = integrator.passes();
                let setup = if seconds == 0.0 { integrator.setup_seconds() } else { 0.0 };
                seconds += job.run(integrator.as_mut(), end, budget, setup, &worker_stop)?;
                if integrator.passes() == before {
                    break;
                }
                let image = integrator.image()?;
                job.gpu.check()?;
                // The iterator was dropped: nothing more to do.
                if tx.send(Message::Image { passes: integrator.passes(), seconds, image }).is_err() {
                    break;
                }
                // Short of the segment's end: the time limit, or a stop.
                if integrator.passes() < end {
                    break;
                }
            }
            Ok(())
        });
        Ok(Progressive { rx: Mutex::new(Some(rx)), stop, seconds: Mutex::new(0.0) })
    }
}

/// The scene's limitations under its method, as Python warnings (the command line prints them).
fn warn_limitations(py: Python<'_>, scene: &scene::Scene) -> PyResult<()> {
    for warning in integrators::limitations(scene) {
        let message = std::ffi::CString::new(format!("{}: {warning}", scene.path.display())).unwrap_or_default();
        PyErr::warn(py, &py.get_type::<pyo3::exceptions::PyUserWarning>(), &message, 1)?;
    }
    Ok(())
}

/// The iterator of `Scene.progressive()`: (passes, image) pairs.
#[pyclass(module = "sppm_gpu")]
struct Progressive {
    /// The worker's messages; `None` once it has ended.
    rx: Mutex<Option<mpsc::Receiver<Message>>>,
    /// Tells the worker to stop (the iterator dropped, or Ctrl-C).
    stop: Arc<AtomicBool>,
    /// Seconds of passes at the last image given.
    seconds: Mutex<f64>,
}

#[pymethods]
impl Progressive {
    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__<'py>(&self, py: Python<'py>) -> PyResult<Option<(u32, Bound<'py, PyArray3<f32>>)>> {
        let mut guard = self.rx.lock().unwrap_or_else(|p| p.into_inner());
        let Some(rx) = guard.as_mut() else { return Ok(None) };
        match wait(py, rx, &self.stop) {
            Ok(Message::Image { passes, seconds, image }) => {
                *self.seconds.lock().unwrap_or_else(|p| p.into_inner()) = seconds;
                Ok(Some((passes, to_array(py, image))))
            }
            Ok(Message::Done(result)) => {
                *guard = None;
                py_result(py, result)?;
                Ok(None)
            }
            Err(e) => {
                *guard = None;
                Err(e)
            }
        }
    }

    /// Seconds of passes (the device's time, from the first pass's submission, kernels
    /// compiled before) when the last image was taken.
    #[getter]
    fn seconds(&self) -> f64 {
        *self.seconds.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Stop the render after the passes on the device; the iterator then ends.
    fn close(&self) {
        self.stop.store(true, Ordering::SeqCst);
        *self.rx.lock().unwrap_or_else(|p| p.into_inner()) = None;
    }
}

impl Drop for Progressive {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
    }
}

/// Load a scene file: TOML (.toml), Mitsuba scene XML (.xml) or pbrt-v4 (.pbrt). Keyword
/// arguments set a Mitsuba scene's parameters ($name), as the command line's -D name=value.
#[pyfunction]
#[pyo3(signature = (path, **params))]
fn load(py: Python<'_>, path: PathBuf, params: Option<&Bound<'_, PyDict>>) -> PyResult<Scene> {
    let mut defines = Vec::new();
    if let Some(params) = params {
        for (name, value) in params.iter() {
            let name: String = name.extract()?;
            let value = if let Ok(b) = value.extract::<bool>() { b.to_string() } else { value.str()?.to_string() };
            defines.push((name, value));
        }
    }
    let scene = py.detach(|| scene::load_with(&path, &defines)).map_err(|e| to_py(py, e.into()))?;
    Ok(Scene { scene })
}

/// Write an image, float array (height, width, 3) of linear RGB: OpenEXR (.exr, 32-bit float)
/// or sRGB PNG (.png), as the command line writes them.
#[pyfunction]
fn write(py: Python<'_>, path: PathBuf, image: PyReadonlyArray3<'_, f32>) -> PyResult<()> {
    let image = from_array(&image)?;
    py.detach(|| image_io::write_image(&path, &image)).map_err(|e| to_py(py, e.into()))
}

/// Read an image (.exr or .png) as linear RGB, a float32 array (height, width, 3).
#[pyfunction]
fn read<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let image = py.detach(|| image_io::read_image(&path)).map_err(|e| to_py(py, e.into()))?;
    Ok(to_array(py, image))
}

/// The Vulkan, Metal and DX12 adapters of this machine, as dicts (index, name, backend,
/// device_type, driver), in the order adapter= numbers them.
#[pyfunction]
fn adapters(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let infos = py.detach(sppm_gpu::gpu::adapters);
    let list = PyList::empty(py);
    for (index, info) in infos.into_iter().enumerate() {
        let d = PyDict::new(py);
        d.set_item("index", index)?;
        d.set_item("name", info.name)?;
        d.set_item("backend", format!("{:?}", info.backend).to_lowercase())?;
        d.set_item("device_type", format!("{:?}", info.device_type))?;
        d.set_item("driver", format!("{} {}", info.driver, info.driver_info).trim().to_string())?;
        list.append(d)?;
    }
    Ok(list)
}

/// The render settings `compare` sets itself, with the reason, refused as its keywords.
const COMPARE_REFUSES: &[(&str, &str)] = &[
    ("method", "it runs each of methods"),
    ("passes", "max_passes caps each method's passes"),
    ("direct", "sppm and sppm-photons of methods set it"),
];

/// Equal-time comparison of methods against a reference image, as the command line's
/// `compare`: each method runs for time_limit seconds of passes, its relMSE and RMSE measured
/// at doubling times from first_snapshot. Returns the rows of compare.csv as dicts (method,
/// seconds, passes, relMSE, RMSE); compare.csv, relmse-vs-time.png and equal-time.png are
/// written into out when it is given. The other keywords are render()'s settings but method,
/// passes and direct, and its adapter. The comparison cannot stop part way: Ctrl-C raises at
/// once, and it ends on its thread.
#[pyfunction]
#[pyo3(signature = (scene, reference, methods, time_limit, first_snapshot=0.5, downsample=1, max_passes=None,
    out=None, *, adapter=None, **params))]
#[allow(clippy::too_many_arguments)]
fn compare<'py>(
    py: Python<'py>,
    scene: &Scene,
    reference: PathBuf,
    methods: Vec<String>,
    time_limit: f64,
    first_snapshot: f64,
    downsample: u32,
    max_passes: Option<u32>,
    out: Option<PathBuf>,
    adapter: Option<&Bound<'py, PyAny>>,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyList>> {
    use sppm_gpu::experiments;
    let methods: Vec<experiments::Variant> =
        py_result(py, methods.iter().map(|m| experiments::Variant::parse(m)).collect::<Result<_, _>>())?;
    let selector = adapter_selector(adapter)?;
    let mut o = overrides("compare", params, COMPARE_REFUSES)?;
    o.time_limit = Some(time_limit);
    let mut s = scene.scene.clone();
    py_result(py, o.apply_to_scene(&mut s, SettingNames::Keywords))?;
    let name = s.path.file_stem().map_or_else(|| "scene".to_string(), |n| n.to_string_lossy().into_owned());
    // Without `out`, the files go to a temporary folder, removed afterwards.
    let (folder, temporary) = match out {
        Some(out) => (out, false),
        None => {
            let dir = std::env::temp_dir().join(format!("sppm_gpu-compare-{}-{}", std::process::id(), unique()));
            (dir, true)
        }
    };
    let opts = experiments::CompareOptions {
        reference,
        methods,
        time_limit,
        first_snapshot,
        downsample,
        max_passes,
        out: folder.clone(),
    };
    let device = py_result(py, py.detach(|| device(selector)))?;
    let gpu = device.gpu.clone();
    let stop = Arc::new(AtomicBool::new(false));
    let (tx, rx) = mpsc::sync_channel(1);
    // On the device's render thread: the methods' kernels are those of earlier renders.
    let mut done = device.run(move |_| {
        let result = experiments::compare_on(&gpu, &s, &name, &opts);
        if temporary {
            let _ = std::fs::remove_dir_all(&opts.out);
        }
        let _ = tx.send(result?);
        Ok(())
    });
    loop {
        if let Message::Done(result) = wait(py, &mut done, &stop)? {
            py_result(py, result)?;
            break;
        }
    }
    let snapshots = rx.try_recv().map_err(|_| PyRuntimeError::new_err("the comparison ended without a result"))?;
    let list = PyList::empty(py);
    for s in snapshots {
        let d = PyDict::new(py);
        d.set_item("method", s.label)?;
        d.set_item("seconds", s.seconds)?;
        d.set_item("passes", s.passes)?;
        d.set_item("relMSE", s.rel_mse)?;
        d.set_item("RMSE", s.rmse)?;
        list.append(d)?;
    }
    Ok(list)
}

/// A number no other call of this process has had, for temporary names.
fn unique() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    NEXT.fetch_add(1, Ordering::SeqCst)
}

/// The native module, `sppm_gpu._native`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<Scene>()?;
    m.add_class::<Progressive>()?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(write, m)?)?;
    m.add_function(wrap_pyfunction!(read, m)?)?;
    m.add_function(wrap_pyfunction!(adapters, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add("Error", py.get_type::<Error>())?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("GpuError", py.get_type::<GpuError>())?;
    m.add("ImageError", py.get_type::<ImageError>())?;
    m.add("SettingError", py.get_type::<SettingError>())?;
    Ok(())
}
