//! The scene in GPU layout: host arrays built from a loaded scene and its BVH (no device
//! needed, so they can be tested alone), then uploaded as storage buffers.

use super::types::*;
use crate::accel::{Bvh, SPHERE_BIT};
use crate::scene::{LightKind, MaterialKind, Scene, SceneError};
use glam::Vec3;
use wgpu::util::DeviceExt;

/// Everything the tracing kernels read about the scene, in GPU layout.
pub struct SceneData {
    pub bvh: Bvh,
    pub triangles: Vec<GpuTriangle>,
    pub spheres: Vec<GpuSphere>,
    pub materials: Vec<GpuMaterial>,
    pub shapes: Vec<GpuShape>,
    /// Three per smooth triangle, xyz used.
    pub normals: Vec<[f32; 4]>,
    pub emitters: Vec<Emitter>,
    /// Sum of the emitters' power (average over RGB of Le * area * pi).
    pub power_total: f32,
    pub bounds_min: Vec3,
    pub bounds_max: Vec3,
}

fn not_supported(scene: &Scene, line: usize, key: &str, what: &str) -> SceneError {
    SceneError {
        file: scene.path.clone(),
        line: Some(line),
        key: Some(key.to_string()),
        message: format!("{what} is not supported yet"),
    }
}

/// Reject what the kernels cannot render yet, naming where it is in the file.
fn check_supported(scene: &Scene) -> Result<(), SceneError> {
    for m in &scene.materials {
        let key = format!("materials.{}", m.name);
        match &m.kind {
            MaterialKind::Glossy { .. } => return Err(not_supported(scene, m.line, &key, "the glossy material")),
            MaterialKind::Dielectric { roughness, .. } if *roughness > 0.0 => {
                return Err(not_supported(scene, m.line, &format!("{key}.roughness"), "a rough dielectric"))
            }
            MaterialKind::Diffuse { texture: Some(_), .. } => {
                return Err(not_supported(scene, m.line, &format!("{key}.texture"), "a texture"))
            }
            _ => {}
        }
    }
    for (i, s) in scene.shapes.iter().enumerate() {
        if s.velocity.is_some() {
            let line = s.velocity_line.unwrap_or(s.line);
            return Err(not_supported(scene, line, &format!("shapes[{i}].velocity"), "motion blur"));
        }
    }
    if let Some(light) = scene.lights.first() {
        let what = match light.kind {
            LightKind::Point { .. } => "a point light",
            LightKind::Directional { .. } => "a directional light",
        };
        return Err(not_supported(scene, light.line, "lights", what));
    }
    Ok(())
}

fn material_of(scene: &Scene, shape: u32) -> u32 {
    scene.shapes[shape as usize].material
}

impl SceneData {
    pub fn new(scene: &Scene) -> Result<Self, SceneError> {
        check_supported(scene)?;
        let bvh = crate::accel::build_bvh(&scene.triangles, &scene.spheres);

        let mut normals = Vec::new();
        let triangles: Vec<GpuTriangle> = scene
            .triangles
            .iter()
            .map(|t| {
                let index = match t.n {
                    Some(n) => {
                        let first = normals.len() as u32;
                        normals.extend(n.iter().map(|v| [v.x, v.y, v.z, 0.0]));
                        first
                    }
                    None => NO_NORMALS,
                };
                GpuTriangle {
                    p0: t.p[0].into(),
                    material: material_of(scene, t.shape),
                    e1: (t.p[1] - t.p[0]).into(),
                    shape: t.shape,
                    e2: (t.p[2] - t.p[0]).into(),
                    normals: index,
                }
            })
            .collect();
        let spheres: Vec<GpuSphere> = scene
            .spheres
            .iter()
            .map(|s| GpuSphere {
                center: s.center.into(),
                radius: s.radius,
                material: material_of(scene, s.shape),
                shape: s.shape,
                _pad: [0; 2],
            })
            .collect();
        let materials = scene
            .materials
            .iter()
            .map(|m| {
                let (kind, albedo, ior) = match m.kind {
                    MaterialKind::Diffuse { albedo, .. } => (MATERIAL_DIFFUSE, albedo, 1.0),
                    MaterialKind::Mirror { albedo } => (MATERIAL_MIRROR, albedo, 1.0),
                    MaterialKind::Dielectric { ior, .. } => (MATERIAL_DIELECTRIC, Vec3::ONE, ior),
                    MaterialKind::Glossy { .. } => unreachable!("rejected by check_supported"),
                };
                GpuMaterial { albedo: albedo.into(), kind, ior, roughness: 0.0, texture: NO_TEXTURE, _pad: 0 }
            })
            .collect();
        let shapes = scene
            .shapes
            .iter()
            .map(|s| GpuShape {
                emission: s.emission.unwrap_or(Vec3::ZERO).into(),
                emits: s.emission.is_some_and(|e| e.max_element() > 0.0) as u32,
            })
            .collect::<Vec<_>>();

        // Emitters, chosen in proportion to power = average(Le) * area * pi.
        let mut emitters = Vec::new();
        let mut powers = Vec::new();
        let emission = |shape: u32| scene.shapes[shape as usize].emission.unwrap_or(Vec3::ZERO);
        for (i, t) in scene.triangles.iter().enumerate() {
            let area = 0.5 * (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).length();
            let power = emission(t.shape).element_sum() / 3.0 * area * std::f32::consts::PI;
            if power > 0.0 {
                emitters.push(Emitter { prim_ref: i as u32, cdf: 0.0, pmf: 0.0, area });
                powers.push(power as f64);
            }
        }
        for (i, s) in scene.spheres.iter().enumerate() {
            let area = 4.0 * std::f32::consts::PI * s.radius * s.radius;
            let power = emission(s.shape).element_sum() / 3.0 * area * std::f32::consts::PI;
            if power > 0.0 {
                emitters.push(Emitter { prim_ref: i as u32 | SPHERE_BIT, cdf: 0.0, pmf: 0.0, area });
                powers.push(power as f64);
            }
        }
        let power_total: f64 = powers.iter().sum();
        if !(power_total > 0.0) || !power_total.is_finite() {
            return Err(SceneError {
                file: scene.path.clone(),
                line: None,
                key: Some("shapes.emission".into()),
                message: "the scene has no light: give a shape an `emission` greater than zero".into(),
            });
        }
        let mut running = 0.0;
        for (e, p) in emitters.iter_mut().zip(&powers) {
            running += p;
            e.pmf = (p / power_total) as f32;
            e.cdf = (running / power_total) as f32;
        }
        // The last interval must hold every u < 1, whatever the rounding.
        if let Some(last) = emitters.last_mut() {
            last.cdf = f32::INFINITY;
        }

        let (bounds_min, bounds_max) = scene_bounds(scene);
        Ok(Self {
            bvh,
            triangles,
            spheres,
            materials,
            shapes,
            normals,
            emitters,
            power_total: power_total as f32,
            bounds_min,
            bounds_max,
        })
    }

    /// Distance to push ray origins off surfaces: small against the scene, large against the
    /// rounding error of single-precision positions in it.
    pub fn ray_epsilon(&self) -> f32 {
        let diagonal = (self.bounds_max - self.bounds_min).length();
        let magnitude = self.bounds_min.abs().max(self.bounds_max.abs()).max_element();
        (1e-5 * diagonal).max(1e-6 * magnitude)
    }
}

fn scene_bounds(scene: &Scene) -> (Vec3, Vec3) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for t in &scene.triangles {
        for p in t.p {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    for s in &scene.spheres {
        lo = lo.min(s.center - s.radius);
        hi = hi.max(s.center + s.radius);
    }
    if lo.x > hi.x {
        return (Vec3::ZERO, Vec3::ZERO);
    }
    (lo, hi)
}

/// Storage buffers of a [`SceneData`]. Empty arrays get one zeroed element, since wgpu
/// cannot bind a zero-sized buffer.
pub struct SceneBuffers {
    pub bvh_nodes: wgpu::Buffer,
    pub prim_refs: wgpu::Buffer,
    pub triangles: wgpu::Buffer,
    pub spheres: wgpu::Buffer,
    pub materials: wgpu::Buffer,
    pub normals: wgpu::Buffer,
    pub shapes: wgpu::Buffer,
    pub emitters: wgpu::Buffer,
}

/// A read-only storage buffer holding `data` (one zeroed element when it is empty).
pub fn storage_buffer<T: bytemuck::Pod>(device: &wgpu::Device, label: &str, data: &[T]) -> wgpu::Buffer {
    let placeholder = [T::zeroed()];
    let data = if data.is_empty() { &placeholder[..] } else { data };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(data),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
    })
}

impl SceneBuffers {
    pub fn new(device: &wgpu::Device, data: &SceneData) -> Self {
        Self {
            bvh_nodes: storage_buffer(device, "bvh_nodes", &data.bvh.nodes),
            prim_refs: storage_buffer(device, "prim_refs", &data.bvh.prim_refs),
            triangles: storage_buffer(device, "triangles", &data.triangles),
            spheres: storage_buffer(device, "spheres", &data.spheres),
            materials: storage_buffer(device, "materials", &data.materials),
            normals: storage_buffer(device, "normals", &data.normals),
            shapes: storage_buffer(device, "shapes", &data.shapes),
            emitters: storage_buffer(device, "emitters", &data.emitters),
        }
    }

    /// The buffers under the names of their WGSL globals.
    pub fn resources(&self) -> Vec<super::Resource<'_>> {
        use super::Resource as R;
        vec![
            R { name: "bvh_nodes", buffer: &self.bvh_nodes },
            R { name: "prim_refs", buffer: &self.prim_refs },
            R { name: "triangles", buffer: &self.triangles },
            R { name: "spheres", buffer: &self.spheres },
            R { name: "materials", buffer: &self.materials },
            R { name: "normals", buffer: &self.normals },
            R { name: "shapes", buffer: &self.shapes },
            R { name: "emitters", buffer: &self.emitters },
        ]
    }
}
