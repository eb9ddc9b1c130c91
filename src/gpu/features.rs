//! The kernels' specialization for one scene: the [`Features`] its GPU data uses and, for a
//! small scene, its BVH as code.

use super::scene_buffers::SceneData;
use crate::layout::{Features, HAS_NORMALS, HAS_UVS, NO_TEXTURE};

impl Features {
    /// The features `data` uses: its primitives and media, and those each material's family
    /// and each emitter's kind turns on (src/scene/material/, src/scene/emitter/).
    pub fn of(data: &SceneData) -> Self {
        let mut f = Features {
            triangles: !data.triangles.is_empty(),
            spheres: !data.spheres.is_empty(),
            motion: data.motion,
            shading_normals: data.triangles.iter().any(|t| t.attributes & HAS_NORMALS != 0),
            uvs: data.triangles.iter().any(|t| t.attributes & HAS_UVS != 0),
            textures: data.materials.iter().any(|m| m.texture != NO_TEXTURE),
            mirror: false,
            glossy: false,
            smooth_dielectric: false,
            rough_dielectric: false,
            plastic: false,
            rough_plastic: false,
            thin_dielectric: false,
            one_sided: false,
            conductor_fresnel: false,
            beckmann: false,
            triangle_lights: false,
            sphere_lights: false,
            point_lights: false,
            directional_lights: false,
            spot_lights: false,
            environment: false,
            envmap: false,
            media: data.media,
        };
        for m in &data.materials {
            crate::scene::material::turn_on_features(m, &mut f);
        }
        for e in &data.emitters {
            crate::scene::emitter::turn_on_features(e, &mut f);
        }
        f
    }
}

/// Everything the tracing kernels of one scene are specialized on: the constants of its
/// [`Features`] and, for a small scene, its BVH as code (see [`super::baked_bvh`]).
pub struct Specialization {
    /// `USES_*` overrides.
    pub constants: Vec<(&'static str, f64)>,
    /// Source replacements: the baked traversal, or nothing.
    pub replace: Vec<(&'static str, String)>,
}

impl Specialization {
    /// The specialization for `data`'s scene.
    pub fn of(data: &SceneData) -> Self {
        let mut constants = Features::of(data).constants();
        constants.push(super::scene_buffers::layout_constant(data));
        // Where the media are, and the camera's (shared/medium.wgsl).
        constants.push(("MEDIA_FIRST", data.media_first as f64));
        constants.push(("CAMERA_MEDIUM", data.camera_medium as f64));
        Self { constants, replace: super::baked_bvh::replacements(data) }
    }

    /// Kernel `name` compiled for this scene.
    pub fn kernel(&self, device: &wgpu::Device, name: &'static str) -> Result<super::Kernel, super::GpuError> {
        self.kernel_with(device, name, &[])
    }

    /// Kernel `name` compiled for this scene with `constants` besides (overrides a kernel
    /// declares for its own uses, such as shared/grid_build.wgsl's `LISTS_OWN_CELL`).
    pub fn kernel_with(
        &self,
        device: &wgpu::Device,
        name: &'static str,
        constants: &[(&'static str, f64)],
    ) -> Result<super::Kernel, super::GpuError> {
        let replace: Vec<(&str, &str)> = self.replace.iter().map(|(token, code)| (*token, code.as_str())).collect();
        let all: Vec<(&str, f64)> = self.constants.iter().chain(constants).copied().collect();
        super::Kernel::specialized(device, name, &replace, &all)
    }
}
