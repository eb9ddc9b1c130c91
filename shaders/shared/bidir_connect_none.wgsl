// What kernels without light vertices (path_trace.wgsl, camera_pass.wgsl) import in place of
// bidir_connect.wgsl: shared/camera_path.wgsl calls connect_light_subpath only under
// CAMERA_PATH_BIDIR, and this keeps the light-vertex buffers out of those kernels' bindings.

#import types
#import scene
#import vcm

fn connect_light_subpath(s: Surface, m: Material, albedo: vec3f, wo: vec3f, camera: SubpathMis, camera_length: u32, camera_merges: bool,
    camera_merged: u32) -> vec3f {
    return vec3f(0.0);
}

fn merge_light_vertices(s: Surface, m: Material, albedo: vec3f, wo: vec3f, camera: SubpathMis, camera_length: u32,
    camera_merged: u32) -> vec3f {
    return vec3f(0.0);
}
