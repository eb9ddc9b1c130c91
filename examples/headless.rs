//! Render a scene file headless through the library API and save a PNG.
//!
//! ```text
//! cargo run --release --example headless -- scenes/cornell-box.toml 16 cornell-box.png
//! ```
//!
//! Arguments: the scene, the number of passes (default: the scene's `iterations`) and the
//! output PNG (default `headless.png`). The device is the library's own [`GpuContext`]; see
//! `examples/embed.rs` for rendering on a device of your own.

use sppm_gpu::gpu::GpuContext;
use sppm_gpu::integrators::Sppm;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let scene_path = PathBuf::from(args.next().ok_or("usage: headless SCENE.toml [PASSES] [OUT.png]")?);
    let scene = sppm_gpu::scene::load(&scene_path)?;
    let passes = match args.next() {
        Some(n) => n.parse::<u32>().ok().filter(|&n| n > 0).ok_or(format!("PASSES must be a positive integer, got {n:?}"))?,
        None => scene.render.iterations,
    };
    let output = PathBuf::from(args.next().unwrap_or_else(|| "headless.png".into()));

    let gpu = GpuContext::new()?;
    let mut sppm = Sppm::new(&gpu.device, &gpu.queue, &scene)?;
    let start = Instant::now();
    for _ in 0..passes {
        sppm.run_pass()?;
    }
    let image = sppm.image()?; // waits for the passes
    let seconds = start.elapsed().as_secs_f64();
    let radius = sppm.radius_stats()?;
    sppm_gpu::image_io::write_png(&output, &image)?;
    println!(
        "{}: {} passes, {} photons in {seconds:.2} s on {}; radius min {:.4} mean {:.4} max {:.4} -> {}",
        scene_path.display(),
        sppm.passes(),
        sppm.photons_traced(),
        gpu.adapter_info.name,
        radius.min,
        radius.mean,
        radius.max,
        output.display()
    );
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
