//! The integration tests, one binary (as cargo's own `tests/testsuite/`): each file a module,
//! the shared helpers in `common`. One binary links wgpu, naga and the crate once, where one a
//! file linked them 34 times. Run one module's tests with `cargo test --release --test suite
//! <module>::`.
//!
//! Like every GPU test, those that need an adapter are skipped without one, except under
//! `CI=true`, where they fail; `SPPM_GPU_ADAPTER` picks the adapter (an index or a part of a
//! name, as `--adapter`).

mod accel;
mod adaptive_radius;
mod bad_input;
mod bands;
mod batch;
mod bidir;
mod bright_lights;
mod builder;
mod checkpoint;
mod chi_square;
mod common;
mod compare;
mod convert;
mod cwbvh;
mod device_errors;
mod direct_light;
mod dispatch;
mod docs_links;
mod embed;
mod environment;
mod features;
mod first_hour;
mod fuzz;
mod gpu_layout;
mod gpu_trace;
mod guide_options;
mod hostile_scenes;
mod house;
mod image_metrics;
mod light;
mod limits;
mod media;
mod media_scene;
mod memory;
mod mesh_formats;
mod mitsuba_xml;
mod one_sided;
mod oracles;
mod outputs;
mod path;
mod pbrt;
mod pixel_filter;
mod scene_load;
mod shaders;
mod sobol;
mod sppm;
mod stability;
mod stored_data;
mod tutorial;
mod vcm;
mod view;
