//! Every kernel's WGSL, with its imports expanded, parses and validates with naga, and has
//! exactly one entry point, named like its file.

use sppm_gpu::gpu::{shader_source, shader_source_for, validate, DeviceCaps, KERNELS};

#[test]
fn every_kernel_validates() {
    let library = KERNELS.iter().map(|name| (*name, shader_source(name).unwrap()));
    let tests = crate::common::TEST_KERNELS.iter().map(|(name, _)| (*name, crate::common::test_kernel_source(name)));
    for (name, source) in library.chain(tests) {
        let (module, _) = validate(name, &source).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(module.entry_points.len(), 1, "{name}");
        assert_eq!(module.entry_points[0].name, name);
    }
}

#[test]
fn imports_are_expanded_once() {
    let source = shader_source("photon_pass").unwrap();
    assert!(!source.contains("#import"));
    assert_eq!(source.matches("struct Frame {").count(), 1);
}

/// Kernels for a device without subgroup operations or 64-bit atomics use neither: naga
/// validates them without the capabilities.
#[test]
fn kernels_without_subgroups_or_atomic64_use_neither() {
    for name in KERNELS {
        let source = shader_source_for(name, DeviceCaps::NONE).unwrap();
        for builtin in ["subgroupAdd", "subgroupExclusiveAdd", "subgroupBallot", "subgroupShuffle", "u64"] {
            assert!(!source.contains(builtin), "{name} uses {builtin}");
        }
        let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{name}: {e}"));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    }
    assert!(shader_source("photon_pass").unwrap().contains("subgroupBallot"));
    assert!(shader_source("photon_pass").unwrap().contains("atomic<u64>"));
}

/// The storage-buffer limit the renderer asks a device for is what its largest kernel binds
/// in one stage: no fewer (pipeline creation would fail) and no more (a device that could run
/// every kernel would be refused).
#[test]
fn storage_buffers_needed_is_the_largest_kernels_count() {
    let counts: Vec<(&str, u32)> = KERNELS
        .iter()
        .map(|name| {
            let (module, info) = validate(name, &shader_source(name).unwrap()).unwrap_or_else(|e| panic!("{e}"));
            let used = info.get_entry_point(0);
            let storage = module
                .global_variables
                .iter()
                .filter(|(handle, var)| matches!(var.space, naga::AddressSpace::Storage { .. }) && !used[*handle].is_empty())
                .count();
            (*name, storage as u32)
        })
        .collect();
    let most = counts.iter().map(|(_, n)| *n).max().unwrap();
    assert_eq!(sppm_gpu::gpu::STORAGE_BUFFERS_NEEDED, most, "storage buffers per kernel: {counts:?}");
}

/// The kernel table (`gpu::KERNELS`) names exactly the kernels in `shaders/` (one file each,
/// shared WGSL in `shaders/shared/`), so that a kernel is added in one place the test checks.
#[test]
fn the_kernel_table_is_the_shader_folder() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.unwrap().file_name().to_str()?.strip_suffix(".wgsl").map(str::to_owned))
        .collect();
    files.sort();
    let mut kernels: Vec<String> = sppm_gpu::gpu::KERNELS.iter().map(|k| k.to_string()).collect();
    kernels.sort();
    assert_eq!(kernels, files);
    // And the test kernels are those of tests/shaders/, none of them in the library's table.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/shaders");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.unwrap().file_name().to_str()?.strip_suffix(".wgsl").map(str::to_owned))
        .collect();
    files.sort();
    let tests: Vec<String> = crate::common::TEST_KERNELS.iter().map(|(k, _)| k.to_string()).collect();
    assert_eq!(tests, files);
    assert!(tests.iter().all(|t| !kernels.contains(t)));
}

/// Constants declared once on the host and once in WGSL hold the same value.
#[test]
fn host_and_kernel_constants_agree() {
    let source = |kernel: &str| {
        std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders").join(format!("{kernel}.wgsl")))
            .unwrap()
    };
    let wgsl_u32 = |text: &str, name: &str| -> u32 {
        let at = text.find(&format!("const {name}: u32 = ")).unwrap_or_else(|| panic!("no const {name}"));
        let rest = &text[at + format!("const {name}: u32 = ").len()..];
        rest[..rest.find('u').unwrap()].trim().parse().unwrap()
    };
    use sppm_gpu::integrators::sppm;
    assert_eq!(wgsl_u32(&source("photon_pass"), "PHOTONS_PER_THREAD"), sppm::PHOTONS_PER_THREAD);
    // photon_resume_setup's words against the host's byte offsets of the same buffer.
    let resume = source("photon_resume_setup");
    for (name, bytes) in [
        ("ARGS_GRID", sppm::ARGS_GRID),
        ("ARGS_RESUME", sppm::ARGS_RESUME),
        ("ARGS_SCAN", sppm::ARGS_SCAN),
        ("ARGS_COUNTS", sppm::ARGS_COUNTS),
    ] {
        assert_eq!(4 * wgsl_u32(&resume, name) as u64, bytes, "{name}");
    }
}
