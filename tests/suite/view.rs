//! `sppm-gpu view`, the live preview window, in a real X server: Xvfb, keys sent with xdotool,
//! the window title read back for the view's state. Each save must be the image the command
//! line renders from the saved scene, bit for bit. Without a display the subcommand refuses at
//! once, which needs neither an X server nor a GPU.
//!
//! The X test needs Xvfb and xdotool (`scripts/install-deps.sh` installs them). Without them it
//! is skipped with a message, except under CI (`CI=true`), where it fails.

use crate::common;

use sppm_gpu::image_io::{self, Rgb32Image};
use sppm_gpu::scene::{self, Method, Scene};
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// The scene the view shows, copied into a fresh directory so that its saves land there.
const SCENE: &str = "cornell-box.toml";
/// The view's settings: a small image, quick passes, and a pause after two of them.
const VIEW_ARGS: &[&str] = &["--width", "64", "--height", "64", "--photons", "20000", "--passes-then-pause", "2"];
/// The image size [`VIEW_ARGS`] asks for.
const SIZE: u32 = 64;
/// How long the window and its first paused frame may take: every kernel compiles on first
/// use, which takes minutes on a cold shader cache.
const FIRST_FRAME: Duration = Duration::from_secs(180);
/// How long any later step may take (a method's first passes compile its kernels).
const STEP: Duration = Duration::from_secs(120);
/// How long the view may take to exit after `q`.
const QUIT: Duration = Duration::from_secs(20);
/// Time between two looks at the title.
const POLL: Duration = Duration::from_millis(25);

fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// The binary, with the runtime directory the other tests give it.
fn binary() -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_sppm-gpu"));
    command.env("XDG_RUNTIME_DIR", std::env::temp_dir());
    command
}

/// Sends SIGTERM to `child`, then SIGKILL if it has not exited within `grace`; reaps it.
fn stop(child: &mut Child, grace: Duration) {
    if child.try_wait().ok().flatten().is_some() {
        return;
    }
    let _ = Command::new("kill").arg("-TERM").arg(child.id().to_string()).status();
    let deadline = Instant::now() + grace;
    while Instant::now() < deadline {
        if child.try_wait().ok().flatten().is_some() {
            return;
        }
        std::thread::sleep(POLL);
    }
    let _ = child.kill();
    let _ = child.wait();
}

/// An Xvfb server on a free display, stopped when dropped (even when the test panics).
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    /// Starts Xvfb on the first free display from :91, its log in `log`.
    fn start(log: &Path) -> Self {
        for n in 91..200 {
            let socket = PathBuf::from(format!("/tmp/.X11-unix/X{n}"));
            if socket.exists() || Path::new(&format!("/tmp/.X{n}-lock")).exists() {
                continue;
            }
            // -displayfd: Xvfb writes the display's number to its stdout once it accepts
            // connections (its socket appears earlier, before it is ready to serve them); an
            // early end of that stream means another server took :n. -noreset: by default the
            // server resets when its last client leaves, and refuses connections meanwhile; an
            // `xdotool search` that came and went before the view connected then made the
            // view's XOpenDisplay fail (CI, under load).
            let mut child = Command::new("Xvfb")
                .arg(format!(":{n}"))
                .args(["-screen", "0", "800x600x24", "-nolisten", "tcp", "-noreset", "-displayfd", "1"])
                .stdout(Stdio::piped())
                .stderr(std::fs::File::create(log).unwrap())
                .spawn()
                .expect("Xvfb runs");
            let stdout = child.stdout.take().unwrap();
            let (tx, rx) = std::sync::mpsc::channel();
            std::thread::spawn(move || {
                let mut line = String::new();
                let _ = std::io::BufRead::read_line(&mut std::io::BufReader::new(stdout), &mut line);
                let _ = tx.send(line);
            });
            match rx.recv_timeout(Duration::from_secs(10)) {
                Ok(line) if line.trim() == n.to_string() => return Self { child, display: format!(":{n}") },
                Ok(_) => {
                    stop(&mut child, Duration::from_secs(2));
                    continue;
                }
                Err(_) => {
                    stop(&mut child, Duration::from_secs(2));
                    panic!("Xvfb :{n} was not ready within 10 s; its log: {}", std::fs::read_to_string(log).unwrap_or_default());
                }
            }
        }
        panic!("no free X display from :91 to :199; last Xvfb log: {}", std::fs::read_to_string(log).unwrap_or_default())
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        // SIGTERM, so that Xvfb removes its lock file and socket.
        stop(&mut self.child, Duration::from_secs(5));
    }
}

/// Runs xdotool on `display`, for at most 10 s (`windowfocus --sync` waits for the focus
/// forever): whether it succeeded, and its stdout trimmed.
fn xdotool(display: &str, args: &[&str]) -> (bool, String) {
    let output =
        Command::new("timeout").arg("10").arg("xdotool").args(args).env("DISPLAY", display).output().expect("xdotool runs");
    (output.status.success(), String::from_utf8_lossy(&output.stdout).trim().to_string())
}

/// Reads `pipe` line by line into a shared buffer, on a thread of its own.
fn collect(pipe: impl Read + Send + 'static) -> (Arc<Mutex<String>>, JoinHandle<()>) {
    let text = Arc::new(Mutex::new(String::new()));
    let sink = Arc::clone(&text);
    let reader = std::thread::spawn(move || {
        let mut pipe = BufReader::new(pipe);
        let mut line = Vec::new();
        while pipe.read_until(b'\n', &mut line).is_ok_and(|n| n > 0) {
            sink.lock().unwrap().push_str(&String::from_utf8_lossy(&line));
            line.clear();
        }
    });
    (text, reader)
}

/// The three files of one save.
struct Saved {
    exr: PathBuf,
    png: PathBuf,
    toml: PathBuf,
}

/// The paths in `saved A.exr, B.png and C.toml (...)`.
fn parse_saved(line: &str) -> Saved {
    let parse = || {
        let rest = line.strip_prefix("saved ")?;
        let (exr, rest) = rest.split_once(", ")?;
        let (png, rest) = rest.split_once(" and ")?;
        let toml = rest.split_once(" (").map_or(rest, |(toml, _)| toml);
        Some(Saved { exr: exr.into(), png: png.into(), toml: toml.trim_end().into() })
    };
    parse().unwrap_or_else(|| panic!("not a `saved A.exr, B.png and C.toml (...)` line: {line:?}"))
}

/// A running `sppm-gpu view` and its window; killed when dropped.
struct View {
    child: Child,
    display: String,
    window: String,
    stdout: Arc<Mutex<String>>,
    stderr: Arc<Mutex<String>>,
    readers: Vec<JoinHandle<()>>,
}

impl View {
    /// Starts the view of `scene` on `display` and waits for its window.
    fn start(scene: &Path, display: &str) -> Self {
        let mut child = binary()
            .arg("view")
            .arg(scene)
            .args(VIEW_ARGS)
            .env("DISPLAY", display)
            .env_remove("WAYLAND_DISPLAY")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the binary runs");
        let (stdout, out_reader) = collect(child.stdout.take().unwrap());
        let (stderr, err_reader) = collect(child.stderr.take().unwrap());
        let mut view = Self {
            child,
            display: display.to_string(),
            window: String::new(),
            stdout,
            stderr,
            readers: vec![out_reader, err_reader],
        };
        view.window = view.wait("its window", FIRST_FRAME, |view| {
            let (found, ids) = xdotool(&view.display, &["search", "--onlyvisible", "--name", "^sppm-gpu view: "]);
            ids.lines().next().filter(|_| found).map(str::to_string)
        });
        view
    }

    /// Fails the test with `message` and what the view has said.
    #[track_caller]
    fn fail(&self, message: &str) -> ! {
        let title = if self.window.is_empty() { "(no window)".to_string() } else { self.title() };
        panic!(
            "{message}\nwindow title: {title}\nstdout:\n{}\nstderr:\n{}",
            self.stdout.lock().unwrap(),
            self.stderr.lock().unwrap()
        )
    }

    /// Polls `check` until it gives a value; fails after `timeout`, or at once when the view
    /// has exited.
    #[track_caller]
    fn wait<T>(&mut self, what: &str, timeout: Duration, mut check: impl FnMut(&Self) -> Option<T>) -> T {
        let start = Instant::now();
        loop {
            if let Some(value) = check(self) {
                return value;
            }
            if let Some(status) = self.child.try_wait().unwrap() {
                self.fail(&format!("the view exited ({status}) while the test waited for {what}"));
            }
            if start.elapsed() > timeout {
                self.fail(&format!("no {what} within {} s", timeout.as_secs()));
            }
            std::thread::sleep(POLL);
        }
    }

    fn title(&self) -> String {
        xdotool(&self.display, &["getwindowname", &self.window]).1
    }

    /// Waits for a title holding `part`; returns it.
    #[track_caller]
    fn wait_for_title(&mut self, part: &str, timeout: Duration) -> String {
        self.wait(&format!("title with {part:?}"), timeout, |view| Some(view.title()).filter(|title| title.contains(part)))
    }

    /// Presses `key` in the window. Without a window manager nothing gives the window the
    /// focus, and winit drops keys while it has none: focus it first, then type (XTEST).
    #[track_caller]
    fn press(&self, key: &str) {
        let (focused, _) = xdotool(&self.display, &["windowfocus", "--sync", &self.window]);
        let (typed, _) = xdotool(&self.display, &["key", key]);
        if !(focused && typed) {
            self.fail(&format!("xdotool could not press {key} (focus {focused}, key {typed})"));
        }
    }

    /// The stdout lines that start with `prefix`.
    fn lines_starting(&self, prefix: &str) -> Vec<String> {
        self.stdout.lock().unwrap().lines().filter(|line| line.starts_with(prefix)).map(str::to_string).collect()
    }

    /// Presses `s` and waits for the save's line, the `n`th; its files.
    #[track_caller]
    fn save(&mut self, n: usize) -> Saved {
        self.press("s");
        let line =
            self.wait(&format!("save number {n} on stdout"), STEP, |view| view.lines_starting("saved ").get(n - 1).cloned());
        parse_saved(&line)
    }

    /// Presses `q` and waits for the exit; its status.
    #[track_caller]
    fn quit(&mut self) -> ExitStatus {
        self.press("q");
        let start = Instant::now();
        while start.elapsed() < QUIT {
            if let Some(status) = self.child.try_wait().unwrap() {
                // The pipes are closed: read to their end.
                for reader in self.readers.drain(..) {
                    reader.join().unwrap();
                }
                return status;
            }
            std::thread::sleep(POLL);
        }
        self.fail(&format!("the view did not exit within {} s of `q`", QUIT.as_secs()))
    }
}

impl Drop for View {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Panics unless `a` and `b` have the same size and the same bits in every channel.
#[track_caller]
fn assert_same_bits(a: &Rgb32Image, b: &Rgb32Image, what: &str) {
    assert_eq!((a.width, a.height), (b.width, b.height), "{what}: sizes differ");
    let differ = |(p, q): &(&[f32; 3], &[f32; 3])| p.iter().zip(q.iter()).any(|(x, y)| x.to_bits() != y.to_bits());
    let pairs: Vec<_> = a.pixels.iter().zip(&b.pixels).collect();
    let count = pairs.iter().filter(|pair| differ(pair)).count();
    if let Some(i) = pairs.iter().position(differ) {
        let (x, y) = (i as u32 % a.width, i as u32 / a.width);
        panic!("{what}: {count} of {} pixels differ; the first, ({x}, {y}): {:?} and {:?}", pairs.len(), pairs[i].0, pairs[i].1);
    }
}

/// Checks the files of the `n`th save in `dir`: named after the scene, never over an earlier
/// save, holding a 64x64 image and a scene with `method` and two passes, which the command line
/// renders to the same bits. The image and the saved scene.
#[track_caller]
fn check_save(saved: &Saved, dir: &Path, n: usize, method: Method) -> (Rgb32Image, Scene) {
    let stem = Path::new(SCENE).file_stem().unwrap().to_str().unwrap();
    for (path, ext) in [(&saved.exr, "exr"), (&saved.png, "png"), (&saved.toml, "toml")] {
        assert_eq!(path.file_name().unwrap().to_str().unwrap(), format!("{stem}-view-{n}.{ext}"), "{}", path.display());
        let parent = path.parent().unwrap().canonicalize().unwrap();
        assert_eq!(parent, dir.canonicalize().unwrap(), "saved next to the scene: {}", path.display());
    }
    let image = image_io::read_exr(&saved.exr).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((image.width, image.height), (SIZE, SIZE));
    assert!(
        image.pixels.iter().flatten().all(|v| v.is_finite() && *v >= 0.0),
        "{}: finite and not negative",
        saved.exr.display()
    );
    assert!(image.mean().iter().all(|&m| m > 0.01), "{}: not black: mean {:?}", saved.exr.display(), image.mean());
    let png = image_io::read_png(&saved.png).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((png.width, png.height), (SIZE, SIZE));

    let scene = scene::load(&saved.toml).unwrap_or_else(|e| panic!("{e}"));
    let render = &scene.render;
    assert_eq!(render.method, method, "{}", saved.toml.display());
    assert_eq!(
        (render.width, render.height, render.iterations, render.photons),
        (SIZE, SIZE, 2, 20000),
        "{}",
        saved.toml.display()
    );

    let out = dir.join(format!("cli-{n}.exr"));
    let start = Instant::now();
    let output = binary().arg(&saved.toml).arg("-o").arg(&out).output().expect("the binary runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "sppm-gpu {} -o {}: {stderr}", saved.toml.display(), out.display());
    eprintln!("view: save {n} rendered by the command line in {:.1} s", start.elapsed().as_secs_f64());
    let cli = image_io::read_exr(&out).unwrap_or_else(|e| panic!("{e}"));
    assert_same_bits(&image, &cli, &format!("the view's save {n} and the command line's render of it"));
    (image, scene)
}

/// Without a display the view refuses at once, in one line that names the headless command.
#[test]
fn view_without_display_exits_1() {
    let start = Instant::now();
    let output = binary()
        .arg("view")
        .arg(common::scene_path(SCENE))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "one line: {stderr:?}");
    assert!(stderr.starts_with("error:"), "{stderr:?}");
    assert!(stderr.to_lowercase().contains("display"), "names the display: {stderr:?}");
    assert!(stderr.contains("sppm-gpu ") && stderr.contains(" -o"), "names the headless command: {stderr:?}");
    assert!(output.stdout.is_empty(), "{:?}", String::from_utf8_lossy(&output.stdout));
    eprintln!("view without a display: refused in {:.2} s", start.elapsed().as_secs_f64());
}

/// The view in Xvfb: two passes of SPPM and a pause; `2` switches to pt-nee, `s` saves; `Left`
/// orbits the camera, which starts over, and `s` saves again; `q` quits. Each save renders the
/// same bits from the command line, and the second (moved) differs from the first.
#[test]
fn view_in_xvfb() {
    let missing: Vec<_> = ["Xvfb", "xdotool"]
        .into_iter()
        .filter(|tool| !Command::new("which").arg(tool).output().is_ok_and(|o| o.status.success()))
        .collect();
    if !missing.is_empty() {
        let message = format!("the view test needs {}: run scripts/install-deps.sh", missing.join(" and "));
        if in_ci() {
            panic!("CI=true and {message}");
        }
        eprintln!("skipping: {message}");
        return;
    }
    if common::gpu().is_none() {
        return;
    }
    let dir = common::scratch("view-xvfb");
    let scene = dir.join(SCENE);
    std::fs::copy(common::scene_path(SCENE), &scene).unwrap();
    let xvfb = Xvfb::start(&dir.join("xvfb.log"));
    let start = Instant::now();
    let seconds = |from: Instant| from.elapsed().as_secs_f64();

    // (a) Two SPPM passes, then pt-nee's two, saved.
    let mut view = View::start(&scene, &xvfb.display);
    eprintln!("view: window {} on {} after {:.1} s", view.window, xvfb.display, seconds(start));
    let title = view.wait_for_title("| sppm | 2 passes | paused", FIRST_FRAME);
    assert!(title.starts_with(&format!("sppm-gpu view: {SCENE} | sppm | ")), "{title}");
    eprintln!("view: {title:?} after {:.1} s", seconds(start));
    let step = Instant::now();
    view.press("2");
    let title = view.wait_for_title("| pt-nee | 2 passes | paused", STEP);
    eprintln!("view: {title:?} {:.1} s after `2`", seconds(step));
    let step = Instant::now();
    let saved = view.save(1);
    eprintln!("view: saved {:.1} s after `s`", seconds(step));
    let (first, first_scene) = check_save(&saved, &dir, 1, Method::PtNee);

    // (b) Orbit 5 degrees: the view starts over, pauses after two passes again, and saves the
    // moved image as the second save.
    let before = view.title();
    let step = Instant::now();
    view.press("Left");
    // Wait to see the title leave the paused state and come back. Both passes may end between
    // two looks; then the key has surely been handled after a few seconds, and the saved
    // camera and image below tell whether it moved.
    let mut changed = false;
    let title = view.wait("the title to come back to pt-nee, 2 passes, paused after `Left`", STEP, |view| {
        let title = view.title();
        changed |= title != before;
        let back = title.contains("| pt-nee | 2 passes | paused") && (changed || step.elapsed() > Duration::from_secs(3));
        back.then_some(title)
    });
    eprintln!("view: {title:?} {:.1} s after `Left` (change seen: {changed})", seconds(step));
    let saved = view.save(2);
    let (second, second_scene) = check_save(&saved, &dir, 2, Method::PtNee);
    let (a, b) = (&first_scene.camera, &second_scene.camera);
    assert_eq!(a.look_at, b.look_at, "the orbit keeps the look-at point");
    let (from, to) = (a.position - a.look_at, b.position - b.look_at);
    assert!((from.length() - to.length()).abs() < 1e-4 * from.length(), "the orbit keeps the distance: {from} and {to}");
    let degrees = from.angle_between(to).to_degrees();
    assert!((degrees - 5.0).abs() < 0.1, "`Left` orbits 5 degrees, not {degrees}: {} to {}", a.position, b.position);
    let moved = first.pixels.iter().zip(&second.pixels).filter(|(p, q)| p != q).count();
    assert!(moved > first.pixels.len() / 4, "the moved camera's image differs from the first in {moved} pixels only");

    // (c) Quit.
    let step = Instant::now();
    let status = view.quit();
    assert!(status.success(), "`q` exits with status 0, not {status}");
    let frames = view.lines_starting("frames:");
    assert_eq!(frames.len(), 1, "one `frames:` line:\n{}", view.stdout.lock().unwrap());
    let stderr = view.stderr.lock().unwrap().clone();
    assert!(!stderr.contains("panicked"), "{stderr}");
    eprintln!("view: exited {:.1} s after `q`; {}", seconds(step), frames[0]);
    eprintln!("view: the whole test took {:.1} s", seconds(start));
}
