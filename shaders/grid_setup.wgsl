// Grid build, step 1 of 4 (one thread): the grid's parameters for this pass's visible points,
// from the scene's bounds and the largest radius that camera_pass recorded. The same as
// GridParams::covering in src/accel/grid.rs.

#import types

@group(0) @binding(0) var<storage, read> grid_scene: GridScene;
@group(0) @binding(1) var<storage, read> grid_max_radius: array<u32>;
@group(0) @binding(2) var<storage, read_write> grid_params: GridParams;

const CELL_RADII: f32 = 2.002;
const MAX_RES: u32 = 1048576u;

@compute @workgroup_size(1)
fn grid_setup() {
    // Radii are positive, and positive floats order like their bits.
    let max_r = bitcast<f32>(grid_max_radius[0]);
    if !(max_r > 0.0) {
        grid_params = GridParams(vec3f(0.0), 1.0, vec3u(0u), grid_scene.table_size - 1u);
        return;
    }
    let origin = grid_scene.lo - max_r;
    let extent = grid_scene.hi + max_r - origin;
    let cell_size = max(CELL_RADII * max_r, max(extent.x, max(extent.y, extent.z)) / f32(MAX_RES));
    let res = min(vec3u(max((grid_scene.hi + max_r - origin) / cell_size, vec3f(0.0))) + 1u, vec3u(MAX_RES));
    grid_params = GridParams(origin, cell_size, res, grid_scene.table_size - 1u);
}
