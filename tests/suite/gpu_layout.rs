//! Every struct that crosses to the GPU has the same member names, offsets and size in Rust
//! (`src/layout/records.rs`) and in WGSL (`shaders/shared/types.wgsl`), as naga lays it out.

use sppm_gpu::gpu::shader_source;
use sppm_gpu::layout::*;
use std::mem::{offset_of, size_of};

fn check_struct(module: &naga::Module, name: &str, size: usize, fields: &[(&str, usize)]) {
    let (_, ty) =
        module.types.iter().find(|(_, t)| t.name.as_deref() == Some(name)).unwrap_or_else(|| panic!("no WGSL struct {name}"));
    let naga::TypeInner::Struct { members, span } = &ty.inner else { panic!("{name} is not a struct") };
    let wgsl: Vec<(&str, usize)> = members.iter().map(|m| (m.name.as_deref().unwrap_or(""), m.offset as usize)).collect();
    assert_eq!(wgsl, fields, "members and offsets of {name}: WGSL left, Rust right");
    assert_eq!(*span as usize, size, "size of {name}");
}

macro_rules! check {
    ($module:expr, $ty:ty, $wgsl:literal, [$($field:ident),* $(,)?]) => {
        check_struct(&$module, $wgsl, size_of::<$ty>(), &[$((stringify!($field), offset_of!($ty, $field))),*])
    };
}

#[test]
fn gpu_structs_match_wgsl() {
    let module = naga::front::wgsl::parse_str(&shader_source("types").unwrap()).unwrap();
    check!(
        module,
        Frame,
        "Frame",
        [
            cam_position,
            lens_radius,
            cam_right,
            focus_distance,
            cam_up,
            width,
            cam_forward,
            height,
            spp,
            pass_index,
            seed,
            max_depth,
            photon_count,
            emitter_count,
            ray_epsilon,
            power_total,
            alpha,
            vp_count,
            time,
            _pad3,
            row_offset,
            image_height,
            direct,
            direct_samples,
            work_first,
            work_end,
            global_radius,
            first_pass,
            hit_capacity,
            resume,
            at_once,
            pixel_filter,
            filter_width,
            env_aim,
            strategies,
            connect_share,
            merge_share,
            count_work,
            filter_reach,
            _pad5,
            filter_cdf,
        ]
    );
    check!(module, GpuBvhNode, "BvhNode", [box_a, child_a, box_b, child_b]);
    check!(module, BvhParams, "BvhParams", [origin, tree_kind, scale, leaf_base]);
    check!(module, GpuTriangle, "Triangle", [p0, material, e1, shape, e2, attributes]);
    check!(module, GpuSphere, "Sphere", [center, radius, material, shape, attributes, _pad]);
    check!(
        module,
        GpuMaterial,
        "Material",
        [
            albedo,
            kind,
            ior,
            roughness,
            texture,
            texture_size,
            one_sided,
            distribution,
            _pad,
            eta,
            fresnel,
            k,
            _pad1,
            specular,
            coat_weight,
            transmittance,
            coat_fdr,
            coat_table,
            nonlinear,
            coat_thickness,
            coat_scatterings
        ]
    );
    check!(module, GpuShape, "Shape", [emission, emits, velocity, media]);
    check!(module, Emitter, "Emitter", [kind, prim_ref, cdf, pmf, position, area, radiance, radius, direction, width]);
    check!(module, VisiblePoint, "VisiblePoint", [p, radius, weight, normal]);
    check!(module, PhotonHit, "PhotonHit", [p, next, d, depth, beta, normal]);
    check!(module, VpStats, "VpStats", [tau, n, ld, radius]);
    check!(module, RadiusTest, "RadiusTest", [offset_sum, tested, spread_sum, shrinking, tests, rejections]);
    check!(module, GridParams, "GridParams", [origin, cell_size, res, table_mask]);
    check!(module, GridScene, "GridScene", [lo, table_size, hi, _pad]);
}

/// The bidirectional methods' light vertex, declared beside the kernels that keep it.
#[test]
fn light_vertex_matches_wgsl() {
    let module = naga::front::wgsl::parse_str(&shader_source("light_trace").unwrap()).unwrap();
    check!(
        module,
        LightVertex,
        "LightVertex",
        [p, material, ng, shape, ns, length, w_prev, d_vcm, beta, d_vc, uv, d_vm, next, d_merge]
    );
}

#[test]
fn wgsl_constants_match_rust() {
    let module = naga::front::wgsl::parse_str(&shader_source("types").unwrap()).unwrap();
    let constant = |name: &str| -> u32 {
        let (_, c) = module.constants.iter().find(|(_, c)| c.name.as_deref() == Some(name)).unwrap();
        match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => v,
            ref e => panic!("{name}: {e:?}"),
        }
    };
    assert_eq!(constant("HAS_NORMALS"), HAS_NORMALS);
    assert_eq!(constant("HAS_UVS"), HAS_UVS);
    assert_eq!(constant("ATTRIBUTE_INDEX_MASK"), ATTRIBUTE_INDEX_MASK);
    assert_eq!(constant("COAT_TABLE_SIZE"), COAT_TABLE_SIZE);
    assert_eq!(constant("NO_TEXTURE"), NO_TEXTURE);
    assert_eq!(constant("TEXTURE_NEAREST"), TEXTURE_NEAREST);
    assert_eq!(constant("TEXTURE_MIRROR"), TEXTURE_MIRROR);
    assert_eq!(constant("TEXTURE_CLAMP"), TEXTURE_CLAMP);
    assert_eq!(constant("TEXTURE_PALETTE"), TEXTURE_PALETTE);
    assert_eq!(constant("PALETTE_ENTRIES"), PALETTE_ENTRIES);
    assert_eq!(constant("SPHERE_BIT"), sppm_gpu::accel::SPHERE_BIT);
    assert_eq!(constant("EMITS_FRONT"), sppm_gpu::layout::EMITS_FRONT);
    assert_eq!(constant("EMITS_BOTH"), sppm_gpu::layout::EMITS_BOTH);
    assert_eq!(constant("MICROFACET_GGX"), MICROFACET_GGX);
    assert_eq!(constant("MICROFACET_BECKMANN"), MICROFACET_BECKMANN);
    assert_eq!(constant("ACCUM_STRIDE"), ACCUM_STRIDE);
    assert_eq!(constant("OFFSET_SCALE"), OFFSET_SCALE);
    assert_eq!(constant("SPREAD_SCALE"), SPREAD_SCALE);
    assert_eq!(constant("RADIUS_TEST_PHOTONS"), RADIUS_TEST_PHOTONS);
    let float = |name: &str| -> f32 {
        let (_, c) = module.constants.iter().find(|(_, c)| c.name.as_deref() == Some(name)).unwrap();
        match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::F32(v)) => v,
            ref e => panic!("{name}: {e:?}"),
        }
    };
    assert_eq!(float("RADIUS_TEST_CHI2"), RADIUS_TEST_CHI2);
    assert_eq!(float("ALPHA_UNIFORM"), ALPHA_UNIFORM);
    assert_eq!(constant("LEAF_BIT"), sppm_gpu::accel::bvh::LEAF_BIT);
    assert_eq!(constant("LEAF_COUNT_SHIFT"), sppm_gpu::accel::bvh::LEAF_COUNT_SHIFT);
    assert_eq!(constant("LEAF_FIRST_MASK"), sppm_gpu::accel::bvh::LEAF_FIRST_MASK);
    assert_eq!(constant("FILTER_BOX"), FILTER_BOX);
    assert_eq!(constant("FILTER_TENT"), FILTER_TENT);
    assert_eq!(constant("FILTER_GAUSSIAN"), FILTER_GAUSSIAN);
    assert_eq!(constant("FILTER_TABLE_SIZE"), FILTER_TABLE_SIZE);
}

/// The bidirectional strategies' bits (`--strategy-images`), in shared/bidir.wgsl and the
/// layout.
#[test]
fn strategy_bits_match_rust() {
    use sppm_gpu::layout::{
        STRATEGIES_ALL, STRATEGY_CONNECT, STRATEGY_EMISSION, STRATEGY_LIGHT_TRACE, STRATEGY_MERGE, STRATEGY_NEE,
    };
    let module = naga::front::wgsl::parse_str(&shader_source("bidir_camera").unwrap()).unwrap();
    let bits = [
        ("STRATEGY_EMISSION", STRATEGY_EMISSION),
        ("STRATEGY_NEE", STRATEGY_NEE),
        ("STRATEGY_CONNECT", STRATEGY_CONNECT),
        ("STRATEGY_MERGE", STRATEGY_MERGE),
        ("STRATEGY_LIGHT_TRACE", STRATEGY_LIGHT_TRACE),
    ];
    for (name, value) in bits {
        let (_, c) = module.constants.iter().find(|(_, c)| c.name.as_deref() == Some(name)).unwrap();
        match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => assert_eq!(v, value, "{name}"),
            ref e => panic!("{name}: {e:?}"),
        }
    }
    assert_eq!(bits.iter().fold(0, |all, (_, bit)| all | bit), STRATEGIES_ALL);
}

/// vcm's counts of work (its pilot's cost model), in shared/bidir.wgsl and the layout.
#[test]
fn work_counts_match_rust() {
    use sppm_gpu::layout::{WORK_CAMERA_VERTICES, WORK_CONNECTIONS, WORK_COUNTS, WORK_LIGHT_VERTICES, WORK_MERGE_CANDIDATES};
    let module = naga::front::wgsl::parse_str(&shader_source("bidir_camera").unwrap()).unwrap();
    for (name, value) in [
        ("WORK_COUNTS", WORK_COUNTS),
        ("WORK_CAMERA_VERTICES", WORK_CAMERA_VERTICES),
        ("WORK_CONNECTIONS", WORK_CONNECTIONS),
        ("WORK_MERGE_CANDIDATES", WORK_MERGE_CANDIDATES),
        ("WORK_LIGHT_VERTICES", WORK_LIGHT_VERTICES),
    ] {
        let (_, c) = module.constants.iter().find(|(_, c)| c.name.as_deref() == Some(name)).unwrap();
        match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => assert_eq!(v, value, "{name}"),
            ref e => panic!("{name}: {e:?}"),
        }
    }
}

/// Each BSDF family's `MATERIAL_*` and each emitter kind's `EMITTER_*`, declared in its host
/// file and in its WGSL file, holds the same value on both sides.
#[test]
fn kind_constants_match_rust() {
    use sppm_gpu::scene::{emitter, material};
    // The photon pass imports every family and every kind.
    let module = naga::front::wgsl::parse_str(&shader_source("photon_pass").unwrap()).unwrap();
    for (file, name, value) in [
        ("bsdf/diffuse", "MATERIAL_DIFFUSE", material::MATERIAL_DIFFUSE),
        ("bsdf/conductor", "MATERIAL_CONDUCTOR", material::MATERIAL_CONDUCTOR),
        ("bsdf/dielectric", "MATERIAL_DIELECTRIC", material::MATERIAL_DIELECTRIC),
        ("bsdf/plastic", "MATERIAL_PLASTIC", material::MATERIAL_PLASTIC),
        ("bsdf/thin_dielectric", "MATERIAL_THIN_DIELECTRIC", material::MATERIAL_THIN_DIELECTRIC),
        ("emitter/area", "EMITTER_AREA", emitter::EMITTER_AREA),
        ("emitter/point", "EMITTER_POINT", emitter::EMITTER_POINT),
        ("emitter/directional", "EMITTER_DIRECTIONAL", emitter::EMITTER_DIRECTIONAL),
        ("emitter/spot", "EMITTER_SPOT", emitter::EMITTER_SPOT),
        ("emitter/environment", "EMITTER_ENVIRONMENT", emitter::EMITTER_ENVIRONMENT),
    ] {
        assert!(shader_source(file).unwrap().contains(&format!("const {name}: u32")), "{file} declares {name}");
        let (_, c) = module.constants.iter().find(|(_, c)| c.name.as_deref() == Some(name)).unwrap();
        match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => assert_eq!(v, value, "{name}"),
            ref e => panic!("{name}: {e:?}"),
        }
    }
}
