// The camera seen from the scene: where a point projects on the image and how much of the
// light leaving it towards the camera a pixel measures (the pinhole's importance), for light
// subpaths that are joined to the camera (light tracing; Veach 1997 sec. 10.2, pbrt-v4 sec.
// 5.1.4 and 16.1), and the pixel filter's weight for splatting what they carry.
//
// A pixel measures I = integral of g(r - c) L ds over the image plane at distance 1 (s in
// raster units of area A_pix on that plane, g the pixel filter's normalized density, c the
// pixel's centre), as camera_ray samples it. On that plane a point at angle theta from the
// view direction lies at distance 1 / cos theta, so ds = dw / cos^3 theta, and a surface
// point x at distance d seen at cos_x: dw = cos_x dA / d^2. Light L leaving x towards the
// camera therefore adds g L cos_x / (d^2 cos^3 theta A_pix) dA to the pixel.

#import types
#import sampling
#import camera
#import splat

// A point as the camera sees it through one point of its lens (frame.cam_position for a
// pinhole).
struct CameraView {
    // Raster position: pixels from the image's top left corner (row 0 at +cam_up).
    raster: vec2f,
    // Unit direction from the point to the lens point, and the distance.
    wi: vec3f,
    dist: f32,
    // 1 / (d^2 cos^3 theta A_pix): what g L cos_x is multiplied by (see the top); 0 where the
    // point lies behind the lens.
    importance: f32,
    // The lens point the view is through.
    lens: vec3f,
}

// A point on the camera's lens for a view: the pinhole, or with a thin lens a point uniform on
// its disk from u (camera_ray's, sample_disk over frame.lens_radius).
fn lens_point(u: vec2f) -> vec3f {
    if frame.lens_radius > 0.0 {
        let q = frame.lens_radius * sample_disk(u);
        return frame.cam_position + q.x * normalize(frame.cam_right) + q.y * normalize(frame.cam_up);
    }
    return frame.cam_position;
}

// The view axis: cam_right x cam_up point right and up, so up x right is forward; the image
// plane's centre frame.cam_forward lies at distance 1 along it (off the axis only for a crop
// window).
fn view_axis() -> vec3f {
    return normalize(cross(frame.cam_up, frame.cam_right));
}

// A pixel's area on the image plane at distance 1.
fn pixel_area() -> f32 {
    return 4.0 * length(frame.cam_right) * length(frame.cam_up) / (f32(frame.width) * f32(frame.image_height));
}

// Point p seen through lens point `lens`. A thin lens focuses the plane at axial distance
// frame.focus_distance: the ray from the lens point through p crosses that plane where the
// pinhole ray of the same image point does (camera_ray aims there), so p's image point is the
// pinhole's view of that crossing. For a given lens point, image area maps to solid angle at
// the lens point as for a pinhole there (dw = ds cos^3 theta, theta from the axis), and a lens
// point drawn uniformly is the camera's own density over the lens: the importance is the
// pinhole's, from the lens point.
fn camera_view(p: vec3f, lens: vec3f) -> CameraView {
    let v = p - lens;
    let dist = length(v);
    let axis = view_axis();
    let t = dot(v, axis);
    if !(t > 0.0) || !(dist > 0.0) {
        return CameraView(vec2f(-1.0e9), vec3f(0.0), dist, 0.0, lens);
    }
    // The pinhole direction of p's image point, at distance 1 along the axis: v / t from a
    // pinhole; from a lens point, towards where the ray crosses the plane in focus.
    var dir = v / t;
    if frame.lens_radius > 0.0 {
        let fd = frame.focus_distance;
        dir = ((lens - frame.cam_position) + v * (fd / t)) / fd;
    }
    // In the image's coordinates sx, sy in [-1, 1] (camera_ray's).
    let q = dir - frame.cam_forward;
    let sx = dot(q, frame.cam_right) / dot(frame.cam_right, frame.cam_right);
    let sy = dot(q, frame.cam_up) / dot(frame.cam_up, frame.cam_up);
    let raster = vec2f(0.5 * (sx + 1.0) * f32(frame.width), 0.5 * (1.0 - sy) * f32(frame.image_height));
    // 1 / (d^2 cos^3 A_pix) = d / (t^3 A_pix).
    return CameraView(raster, -v / dist, dist, dist / (t * t * t * pixel_area()), lens);
}

// Add radiance c, arriving at raster position `raster`, to every pixel of this renderer's rows
// whose filter reaches it, weighted by the filter (splat.wgsl). The box filter's pixel is the
// one camera_ray's jitter covers, [px, px + 1) x [py, py + 1).
fn splat_filtered(raster: vec2f, c: vec3f) {
    let rows = vec2i(i32(frame.row_offset), i32(frame.row_offset + frame.height));
    if !((USES_TENT_FILTER && frame.pixel_filter == FILTER_TENT) || (USES_GAUSSIAN_FILTER && frame.pixel_filter == FILTER_GAUSSIAN)) {
        if raster.x >= 0.0 && raster.y >= 0.0 {
            let px = i32(raster.x);
            let py = i32(raster.y);
            if px < i32(frame.width) && py >= rows.x && py < rows.y {
                splat_add(u32(py - rows.x) * frame.width + u32(px), c);
            }
        }
        return;
    }
    let reach = filter_radius();
    let lo = vec2i(ceil(raster - 0.5 - reach));
    let hi = vec2i(floor(raster - 0.5 + reach));
    for (var py = max(lo.y, rows.x); py <= min(hi.y, rows.y - 1); py++) {
        let wy = filter_density(raster.y - (f32(py) + 0.5));
        for (var px = max(lo.x, 0); px <= min(hi.x, i32(frame.width) - 1); px++) {
            let w = wy * filter_density(raster.x - (f32(px) + 0.5));
            if w > 0.0 {
                splat_add(u32(py - rows.x) * frame.width + u32(px), c * w);
            }
        }
    }
}
