//! The `envmap` environment: an equirectangular image of the radiance that arrives from every
//! direction at infinity (Mitsuba 3's `envmap`), and the piecewise-constant distribution by
//! which the kernels sample it (`shaders/shared/envmap.wgsl` mirrors [`Envmap::radiance`],
//! [`EnvmapDistribution::pdf`] and [`EnvmapDistribution::sample`]).
//!
//! Orientation, as Mitsuba 3's `envmap.cpp` (checked against Mitsuba 3.9.1 renders, see
//! docs/journal/session-12.md "The `envmap` environment (issue 25)"): a world direction w is carried into the map's frame, d =
//! to_world^-1 w, and read at u = atan2(d.x, -d.z) / 2 pi (wrapped into [0, 1)), v =
//! acos(d.y) / pi: +y is the top row, the left edge of the image looks along -z, its centre along
//! +z, a quarter across along +x. Texels are filtered bilinearly: in texel units x = u W - 1/2, periodic, and
//! y = v (H - 1), clamped, so rows 0 and H - 1 sit on the poles.
//!
//! Sampling (after pbrt-v4 sec. A.5.2 and 12.5.2, our own code): the cells between texel
//! centres, W columns by H - 1 rows, each weighed by the mean luminance of its four corners
//! (the integral of the bilinear luminance over the cell) times the mean of sin(theta) over
//! its rows, (cos theta_0 - cos theta_1) / (theta_1 - theta_0). A row is chosen from the
//! marginal CDF, a cell in it from its conditional CDF, a point uniformly in the cell: density
//! p(u, v) = pmf(row) pmf(cell | row) W (H - 1) over [0, 1]^2, and over solid angle p(u, v) /
//! (2 pi^2 sin theta), since d omega = sin theta d theta d phi = 2 pi^2 sin theta du dv.

use glam::{Mat3, Vec2, Vec3};
use std::f64::consts::PI;
use std::path::PathBuf;

/// Rec. 709 luminance of linear RGB, Mitsuba's `luminance`.
pub fn luminance(c: Vec3) -> f32 {
    0.212671 * c.x + 0.715160 * c.y + 0.072169 * c.z
}

/// An equirectangular environment map, loaded and checked.
#[derive(Clone, PartialEq)]
pub struct Envmap {
    /// The image file (for messages and digests).
    pub path: PathBuf,
    /// Width in texels (azimuth), at least 1.
    pub width: u32,
    /// Height in texels (polar angle), at least 2: a map of one row is stored twice.
    pub height: u32,
    /// Linear RGB radiance before `scale`, row-major, row 0 at the top (+y).
    pub texels: Vec<Vec3>,
    /// Factor on every texel (Mitsuba's `scale`).
    pub scale: f32,
    /// Rotation (or reflection) from the map's frame to the world; orthonormal.
    pub to_world: Mat3,
}

impl std::fmt::Debug for Envmap {
    /// The texels by a digest (FNV-1a of their bits), not one by one: a checkpoint's digest of
    /// the lights formats them, and a map may hold millions.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut hash = 0xcbf29ce484222325u64;
        for t in &self.texels {
            for c in t.to_array() {
                hash = (hash ^ c.to_bits() as u64).wrapping_mul(0x100000001b3);
            }
        }
        f.debug_struct("Envmap")
            .field("path", &self.path)
            .field("width", &self.width)
            .field("height", &self.height)
            .field("texels", &format_args!("fnv1a:{hash:016x}"))
            .field("scale", &self.scale)
            .field("to_world", &self.to_world)
            .finish()
    }
}

impl Envmap {
    /// A map of `width` x `height` texels (row 0 at the top). Errors name what is wrong: no
    /// texels, a texel count that does not match, a texel that is negative or not finite, a
    /// scale that is negative or not finite, a `to_world` that is not orthonormal.
    pub fn new(path: PathBuf, width: u32, height: u32, texels: Vec<Vec3>, scale: f32, to_world: Mat3) -> Result<Self, String> {
        if width == 0 || height == 0 {
            return Err(format!("{}: the environment map has no texels", path.display()));
        }
        if texels.len() != width as usize * height as usize {
            return Err(format!("{}: {} texels for a map of {width}x{height}", path.display(), texels.len()));
        }
        if let Some(i) = texels.iter().position(|t| !t.is_finite() || t.min_element() < 0.0) {
            let (x, y) = (i as u32 % width, i as u32 / width);
            return Err(format!(
                "{}: texel ({x}, {y}) is {}: an environment map's radiance is finite and at least 0",
                path.display(),
                texels[i]
            ));
        }
        if !scale.is_finite() || scale < 0.0 {
            return Err(format!("scale {scale}: an environment map's scale is finite and at least 0"));
        }
        if !is_orthonormal(to_world) {
            return Err("an environment map's to_world must be a rotation (no scale, shear or projection)".into());
        }
        let (height, texels) = if height == 1 { (2, [texels.clone(), texels].concat()) } else { (height, texels) };
        Ok(Envmap { path, width, height, texels, scale, to_world })
    }

    /// Texel (x, y), x taken modulo the width, y clamped.
    fn texel(&self, x: i64, y: i64) -> Vec3 {
        let x = x.rem_euclid(self.width as i64) as usize;
        let y = y.clamp(0, self.height as i64 - 1) as usize;
        self.texels[y * self.width as usize + x]
    }

    /// The map's (u, v) of world direction `w` (unit).
    pub fn uv(&self, w: Vec3) -> Vec2 {
        let d = self.to_world.transpose() * w;
        let u = d.x.atan2(-d.z) * (0.5 / std::f32::consts::PI);
        Vec2::new(u - u.floor(), d.y.clamp(-1.0, 1.0).acos() * std::f32::consts::FRAC_1_PI)
    }

    /// The world direction at (u, v), and sin(theta).
    pub fn direction(&self, uv: Vec2) -> (Vec3, f32) {
        let (theta, phi) = (uv.y * std::f32::consts::PI, uv.x * 2.0 * std::f32::consts::PI);
        let (sin_t, cos_t) = theta.sin_cos();
        let (sin_p, cos_p) = phi.sin_cos();
        (self.to_world * Vec3::new(sin_p * sin_t, cos_t, -cos_p * sin_t), sin_t)
    }

    /// The bilinear lookup at (u, v), before `scale`.
    pub fn lookup(&self, uv: Vec2) -> Vec3 {
        let x = uv.x * self.width as f32 - 0.5;
        let y = (uv.y.clamp(0.0, 1.0) * (self.height - 1) as f32).min((self.height - 1) as f32);
        let (x0, y0) = (x.floor(), y.floor().min((self.height - 2) as f32));
        let (fx, fy) = (x - x0, y - y0);
        let (i, j) = (x0 as i64, y0 as i64);
        let top = self.texel(i, j) * (1.0 - fx) + self.texel(i + 1, j) * fx;
        let bottom = self.texel(i, j + 1) * (1.0 - fx) + self.texel(i + 1, j + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }

    /// The largest channel of any texel, before `scale`.
    pub fn brightest_texel(&self) -> f32 {
        self.texels.iter().fold(0.0, |m, t| m.max(t.max_element()))
    }

    /// The largest radiance the map gives in any channel, `scale` included: bilinear
    /// weights are convex, so no lookup exceeds the brightest texel.
    pub fn max_radiance(&self) -> f64 {
        self.brightest_texel() as f64 * self.scale as f64
    }

    /// Radiance arriving from world direction `w` (unit), `scale` included.
    pub fn radiance(&self, w: Vec3) -> Vec3 {
        self.scale * self.lookup(self.uv(w))
    }

    /// The integral of the radiance (`scale` included) over the sphere of directions, per
    /// channel. Along a row the bilinear radiance averages to the row's mean; between rows j
    /// and j + 1 (theta_0 to theta_1, width D) it is (1 - s) L_j + s L_j+1 with theta =
    /// theta_0 + s D, and integral_0^1 s sin(theta) D ds = -cos theta_1 + (sin theta_1 -
    /// sin theta_0) / D, integral_0^1 sin(theta) D ds = cos theta_0 - cos theta_1.
    pub fn integral(&self) -> [f64; 3] {
        let (w, h) = (self.width as usize, self.height as usize);
        let row_sum = |j: usize| {
            self.texels[j * w..(j + 1) * w]
                .iter()
                .fold([0.0f64; 3], |a, t| [a[0] + t.x as f64, a[1] + t.y as f64, a[2] + t.z as f64])
        };
        let d = PI / (h - 1) as f64;
        let mut total = [0.0; 3];
        for j in 0..h - 1 {
            let (t0, t1) = (j as f64 * d, (j + 1) as f64 * d);
            let i1 = -t1.cos() + (t1.sin() - t0.sin()) / d;
            let i0 = (t0.cos() - t1.cos()) - i1;
            let (a, b) = (row_sum(j), row_sum(j + 1));
            for c in 0..3 {
                total[c] += 2.0 * PI / w as f64 * (a[c] * i0 + b[c] * i1);
            }
        }
        total.map(|t| t * self.scale as f64)
    }
}

/// The rotation of TOML's `rotate` (degrees about x, y and z), as a shape's: Rz Ry Rx.
pub fn rotation_degrees(r: Vec3) -> Mat3 {
    let r = r * (std::f32::consts::PI / 180.0);
    Mat3::from_rotation_z(r.z) * Mat3::from_rotation_y(r.y) * Mat3::from_rotation_x(r.x)
}

/// Whether `m` is orthonormal to within 1e-4.
fn is_orthonormal(m: Mat3) -> bool {
    let g = m.transpose() * m;
    (0..3).all(|i| (0..3).all(|j| (g.col(i)[j] - if i == j { 1.0 } else { 0.0 }).abs() <= 1e-4))
}

/// The sampling distribution of an [`Envmap`]: W x (H - 1) cells between texel centres.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvmapDistribution {
    /// Cells across (the map's width).
    pub columns: u32,
    /// Cell rows (the map's height - 1).
    pub rows: u32,
    /// Per row, the inclusive running sums of its cells' probabilities given the row, the last
    /// exactly 1; row-major.
    pub conditional: Vec<f32>,
    /// Inclusive running sums of the rows' probabilities, the last exactly 1.
    pub marginal: Vec<f32>,
}

/// Inclusive running sums of `weights`, normalized, the last exactly 1; uniform where they sum
/// to 0.
fn cdf(weights: &[f64]) -> Vec<f32> {
    let total: f64 = weights.iter().sum();
    let n = weights.len();
    let mut running = 0.0;
    let mut out: Vec<f32> = weights
        .iter()
        .enumerate()
        .map(|(i, &w)| {
            running += w;
            if total > 0.0 {
                (running / total) as f32
            } else {
                ((i + 1) as f64 / n as f64) as f32
            }
        })
        .collect();
    if let Some(last) = out.last_mut() {
        *last = 1.0;
    }
    out
}

/// First index whose inclusive CDF value exceeds u (u < 1; the last value is 1).
fn find(cdf: impl Fn(usize) -> f32, n: usize, u: f32) -> usize {
    let (mut lo, mut hi) = (0, n - 1);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if cdf(mid) <= u {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    lo
}

impl EnvmapDistribution {
    /// The distribution of `map` by luminance: cell (i, j) weighs the mean luminance of its
    /// four corner texels times the mean of sin(theta) over its rows.
    pub fn new(map: &Envmap) -> Self {
        let (w, rows) = (map.width as usize, map.height as usize - 1);
        let d = PI / rows as f64;
        let lum: Vec<f64> = map.texels.iter().map(|&t| luminance(t) as f64).collect();
        let mut conditional = Vec::with_capacity(w * rows);
        let mut row_weights = Vec::with_capacity(rows);
        for j in 0..rows {
            let sin_mean = ((j as f64 * d).cos() - ((j + 1) as f64 * d).cos()) / d;
            let cells: Vec<f64> = (0..w)
                .map(|i| {
                    let i1 = (i + 1) % w;
                    let corners = lum[j * w + i] + lum[j * w + i1] + lum[(j + 1) * w + i] + lum[(j + 1) * w + i1];
                    0.25 * corners * sin_mean
                })
                .collect();
            row_weights.push(cells.iter().sum());
            conditional.extend(cdf(&cells));
        }
        EnvmapDistribution { columns: w as u32, rows: rows as u32, conditional, marginal: cdf(&row_weights) }
    }

    /// Probability of cell row j, and of cell i given row j, as the kernels compute them: by
    /// differences of the f32 running sums.
    fn pmfs(&self, i: usize, j: usize) -> (f32, f32) {
        let w = self.columns as usize;
        let pm = self.marginal[j] - if j > 0 { self.marginal[j - 1] } else { 0.0 };
        let row = &self.conditional[j * w..(j + 1) * w];
        let pc = row[i] - if i > 0 { row[i - 1] } else { 0.0 };
        (pm, pc)
    }

    /// The cell holding (u, v) and the position in it: x = u W - 1/2 (wrapped), y = v (H - 1).
    fn cell(&self, uv: Vec2) -> (usize, usize) {
        let (w, rows) = (self.columns as f32, self.rows as f32);
        let mut x = uv.x * w - 0.5;
        if x < 0.0 {
            x += w;
        }
        let i = (x.max(0.0) as usize).min(self.columns as usize - 1);
        let j = ((uv.y * rows).max(0.0) as usize).min(self.rows as usize - 1);
        (i, j)
    }

    /// Density over [0, 1]^2 at (u, v).
    pub fn pdf_uv(&self, uv: Vec2) -> f32 {
        let (i, j) = self.cell(uv);
        let (pm, pc) = self.pmfs(i, j);
        pm * pc * (self.columns * self.rows) as f32
    }

    /// Solid-angle density of world direction `w` (unit) in `map`'s frame: pdf_uv / (2 pi^2
    /// sin theta), 0 at the poles.
    pub fn pdf(&self, map: &Envmap, w: Vec3) -> f32 {
        let d = map.to_world.transpose() * w;
        let sin_theta = (d.x * d.x + d.z * d.z).sqrt();
        if sin_theta <= 0.0 {
            return 0.0;
        }
        self.pdf_uv(map.uv(w)) / (2.0 * std::f32::consts::PI * std::f32::consts::PI * sin_theta)
    }

    /// A point (u, v) for the uniform numbers `u` in [0, 1)^2, with its density over [0, 1]^2:
    /// a row by the marginal CDF (u.y), a cell by its conditional CDF (u.x), each number
    /// reused for the position within.
    pub fn sample_uv(&self, u: Vec2) -> (Vec2, f32) {
        let (w, rows) = (self.columns as usize, self.rows as usize);
        let j = find(|k| self.marginal[k], rows, u.y);
        let m0 = if j > 0 { self.marginal[j - 1] } else { 0.0 };
        let row = &self.conditional[j * w..(j + 1) * w];
        let i = find(|k| row[k], w, u.x);
        let c0 = if i > 0 { row[i - 1] } else { 0.0 };
        let (pm, pc) = (self.marginal[j] - m0, row[i] - c0);
        let t = ((u.y - m0) / pm).clamp(0.0, 1.0);
        let s = ((u.x - c0) / pc).clamp(0.0, 1.0);
        let x = (i as f32 + s + 0.5) / w as f32;
        let uv = Vec2::new(x - x.floor(), (j as f32 + t) / rows as f32);
        (uv, pm * pc * (w * rows) as f32)
    }

    /// A world direction for `u` and its solid-angle density.
    pub fn sample(&self, map: &Envmap, u: Vec2) -> (Vec3, f32) {
        let (uv, pdf_uv) = self.sample_uv(u);
        let (w, sin_theta) = map.direction(uv);
        let pdf = if sin_theta > 0.0 { pdf_uv / (2.0 * std::f32::consts::PI * std::f32::consts::PI * sin_theta) } else { 0.0 };
        (w, pdf)
    }

    /// The map and its distribution in the kernels' layout, appended to `texels` (see
    /// `shaders/shared/envmap.wgsl`): a header (W and H as bits), the three columns of
    /// to_world, the W H texels with the conditional running sum of cell (x, y) in the fourth
    /// lane (rows 0 to H - 2), then the marginal running sums four to an entry. Returns the
    /// header's index.
    pub fn pack(&self, map: &Envmap, texels: &mut Vec<[f32; 4]>) -> u32 {
        let base = texels.len() as u32;
        texels.push([f32::from_bits(map.width), f32::from_bits(map.height), 0.0, 0.0]);
        for c in [map.to_world.x_axis, map.to_world.y_axis, map.to_world.z_axis] {
            texels.push([c.x, c.y, c.z, 0.0]);
        }
        let cells = self.conditional.len();
        texels.extend(
            map.texels.iter().enumerate().map(|(k, t)| [t.x, t.y, t.z, if k < cells { self.conditional[k] } else { 0.0 }]),
        );
        texels.extend(self.marginal.chunks(4).map(|c| std::array::from_fn(|k| c.get(k).copied().unwrap_or(1.0))));
        base
    }

    /// Entries [`Self::pack`] appends.
    pub fn packed_len(map: &Envmap) -> usize {
        4 + map.texels.len() + (map.height as usize - 1).div_ceil(4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 16x8 map with a bright spot, colours by quadrant and a black band.
    fn test_map(to_world: Mat3) -> Envmap {
        let (w, h) = (16u32, 8u32);
        let texels = (0..w * h)
            .map(|k| {
                let (x, y) = (k % w, k / w);
                let base = match (x < w / 2, y < h / 2) {
                    (true, true) => Vec3::new(1.0, 0.2, 0.1),
                    (false, true) => Vec3::new(0.1, 0.8, 0.2),
                    (true, false) => Vec3::new(0.2, 0.1, 0.9),
                    (false, false) => Vec3::new(0.5, 0.5, 0.5),
                };
                if (x, y) == (11, 2) {
                    Vec3::splat(40.0)
                } else if y == 5 {
                    Vec3::ZERO
                } else {
                    base
                }
            })
            .collect();
        Envmap::new("test.exr".into(), w, h, texels, 1.5, to_world).unwrap()
    }

    fn rotation() -> Mat3 {
        Mat3::from_rotation_y(0.7) * Mat3::from_rotation_x(-0.4)
    }

    /// Directions on a (theta, phi) grid with their solid angle.
    fn quadrature(n: usize) -> impl Iterator<Item = (Vec3, f64)> {
        (0..n).flat_map(move |a| {
            (0..2 * n).map(move |b| {
                let theta = (a as f64 + 0.5) * PI / n as f64;
                let phi = (b as f64 + 0.5) * PI / n as f64;
                let w = Vec3::new((theta.sin() * phi.cos()) as f32, theta.cos() as f32, (theta.sin() * phi.sin()) as f32);
                (w, theta.sin() * (PI / n as f64).powi(2))
            })
        })
    }

    /// The density integrates to 1 over the sphere, and the radiance to [`Envmap::integral`].
    #[test]
    fn density_and_radiance_integrate() {
        let map = test_map(rotation());
        let dist = EnvmapDistribution::new(&map);
        let (mut pdf_sum, mut l_sum) = (0.0, [0.0f64; 3]);
        for (w, d_omega) in quadrature(800) {
            pdf_sum += dist.pdf(&map, w) as f64 * d_omega;
            let l = map.radiance(w);
            for c in 0..3 {
                l_sum[c] += l[c] as f64 * d_omega;
            }
        }
        assert!((pdf_sum - 1.0).abs() < 2e-3, "{pdf_sum}");
        let exact = map.integral();
        for c in 0..3 {
            assert!((l_sum[c] / exact[c] - 1.0).abs() < 2e-3, "{l_sum:?} {exact:?}");
        }
    }

    /// The density is positive wherever the radiance is, and proportional within a cell to
    /// the cell's mean luminance over sin(theta): the band of black texels has none.
    #[test]
    fn density_follows_luminance() {
        let map = test_map(Mat3::IDENTITY);
        let dist = EnvmapDistribution::new(&map);
        for (w, _) in quadrature(100) {
            let (l, p) = (map.radiance(w), dist.pdf(&map, w));
            assert!(l.max_element() == 0.0 || p > 0.0, "{w} {l} {p}");
        }
        // Cells between rows 4, 5 and 5, 6 have black corners but light ones too; the spot's
        // cells are the likeliest.
        let prob = |(i, j): (usize, usize)| {
            let (pm, pc) = dist.pmfs(i, j);
            pm * pc
        };
        let cells = (0..dist.rows as usize).flat_map(|j| (0..dist.columns as usize).map(move |i| (i, j)));
        let best = cells.max_by(|&a, &b| prob(a).total_cmp(&prob(b))).unwrap();
        assert!(best == (10, 1) || best == (11, 1) || best == (10, 2) || best == (11, 2), "{best:?}");
    }

    /// Samples: their density agrees with pdf(), and their histogram over cells with the
    /// cells' probabilities (a chi-square-like bound per cell at many samples).
    #[test]
    fn sampling_matches_density() {
        let map = test_map(rotation());
        let dist = EnvmapDistribution::new(&map);
        let n = 200_000;
        let (w, rows) = (dist.columns as usize, dist.rows as usize);
        let mut counts = vec![0u32; w * rows];
        let mut state = 0x1234_5678_9abc_def0u64;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 40) as f32) / (1u64 << 24) as f32
        };
        for _ in 0..n {
            let u = Vec2::new(next(), next());
            let (uv, pdf_uv) = dist.sample_uv(u);
            assert!(pdf_uv > 0.0);
            let (i, j) = dist.cell(uv);
            counts[j * w + i] += 1;
            let (dir, pdf) = dist.sample(&map, u);
            let back = dist.pdf(&map, dir);
            assert!((back / pdf - 1.0).abs() < 1e-3 || pdf < 1e-3, "{u} {pdf} {back}");
        }
        let mut chi2 = 0.0;
        for j in 0..rows {
            for i in 0..w {
                let (pm, pc) = dist.pmfs(i, j);
                let expected = (pm * pc) as f64 * n as f64;
                let o = counts[j * w + i] as f64;
                if expected == 0.0 {
                    assert_eq!(o, 0.0);
                } else {
                    chi2 += (o - expected).powi(2) / expected;
                }
            }
        }
        // 112 cells: chi2 has mean about 111 and standard deviation about 15.
        assert!(chi2 < 200.0, "chi2 {chi2}");
    }

    /// A texel that is NaN or negative, a count that does not match, a scale: errors.
    #[test]
    fn bad_maps_are_refused() {
        let ok = vec![Vec3::ONE; 8];
        assert!(Envmap::new("a.exr".into(), 4, 2, ok.clone(), 1.0, Mat3::IDENTITY).is_ok());
        let mut nan = ok.clone();
        nan[5] = Vec3::new(1.0, f32::NAN, 0.0);
        let e = Envmap::new("a.exr".into(), 4, 2, nan, 1.0, Mat3::IDENTITY).unwrap_err();
        assert!(e.contains("a.exr") && e.contains("texel (1, 1)"), "{e}");
        let mut neg = ok.clone();
        neg[0] = Vec3::new(-1.0, 0.0, 0.0);
        assert!(Envmap::new("a.exr".into(), 4, 2, neg, 1.0, Mat3::IDENTITY).unwrap_err().contains("texel (0, 0)"));
        assert!(Envmap::new("a.exr".into(), 4, 3, ok.clone(), 1.0, Mat3::IDENTITY).unwrap_err().contains("8 texels"));
        assert!(Envmap::new("a.exr".into(), 4, 2, ok.clone(), -1.0, Mat3::IDENTITY).is_err());
        assert!(Envmap::new("a.exr".into(), 4, 2, ok, 1.0, Mat3::from_diagonal(Vec3::splat(2.0))).is_err());
    }

    /// A constant map gives its value from every direction, integrates to 4 pi times it, and
    /// is sampled uniformly in (u, v).
    #[test]
    fn constant_map_is_uniform() {
        let map = Envmap::new("c.exr".into(), 8, 1, vec![Vec3::splat(2.0); 8], 0.5, Mat3::IDENTITY).unwrap();
        assert_eq!(map.height, 2);
        let dist = EnvmapDistribution::new(&map);
        for (w, _) in quadrature(20) {
            assert!((map.radiance(w) - Vec3::ONE).abs().max_element() < 1e-6);
        }
        let i = map.integral();
        assert!((i[0] - 4.0 * PI).abs() < 1e-9, "{i:?}");
        // One row of cells weighed by sin's mean over [0, pi]: pdf_uv = 1, solid angle
        // 1 / (2 pi^2 sin theta).
        assert!((dist.pdf_uv(Vec2::new(0.3, 0.4)) - 1.0).abs() < 1e-6);
    }
}
