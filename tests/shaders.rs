//! Every kernel's WGSL, with its imports expanded, parses and validates with naga, and has
//! exactly one entry point, named like its file.

use sppm_gpu::gpu::{shader_source, validate, KERNELS};

#[test]
fn every_kernel_validates() {
    for name in KERNELS {
        let source = shader_source(name).unwrap();
        let (module, _) = validate(name, &source).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(module.entry_points.len(), 1, "{name}");
        assert_eq!(module.entry_points[0].name, *name);
    }
}

#[test]
fn imports_are_expanded_once() {
    let source = shader_source("photon_pass").unwrap();
    assert!(!source.contains("#import"));
    assert_eq!(source.matches("struct Frame {").count(), 1);
}
