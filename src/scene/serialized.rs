//! Mitsuba's `.serialized` meshes (versions 3 and 4), read into an [`IndexedMesh`].
//!
//! The format, as Mitsuba 3 documents its `serialized` shape plugin (src/shapes/serialized.cpp,
//! <https://mitsuba.readthedocs.io/en/latest/src/generated/plugins_shapes.html>) and reads it:
//! everything little endian. A file holds one shape or more, one after another, each
//!
//! - `u16` format identifier `0x041C`, `u16` version (3 or 4), uncompressed; then a zlib
//!   stream (DEFLATE with the zlib header) holding
//! - `u32` flags: `0x0001` per-vertex normals, `0x0002` texture coordinates, `0x0008` vertex
//!   colours, `0x0010` use face normals, `0x1000` single precision, `0x2000` double precision
//!   (double wins when both are set; single when neither is);
//! - version 4 only: the shape's name, UTF-8, NUL-terminated;
//! - `u64` vertex count, `u64` triangle count;
//! - positions (x, y, z per vertex), then normals (x, y, z) if flagged, texture coordinates
//!   (u, v) if flagged, colours (r, g, b) if flagged, each an array of 32-bit or 64-bit floats
//!   as the precision flags say;
//! - triangles, three `u32` vertex indices each (`u64` when the vertex count exceeds
//!   `0xFFFFFFFF`, which this reader refuses).
//!
//! The file ends with a dictionary: each shape's byte offset from the start of the file
//! (`u64` in version 4, `u32` in version 3; the first is 0), then the `u32` number of shapes
//! as its last 4 bytes. Shape 0 is read from the start of the file without it.
//!
//! Colours are skipped. Texture coordinates are kept as the file stores them (Mitsuba does
//! not flip them for this format).

use super::mesh::IndexedMesh;
use flate2::read::ZlibDecoder;
use glam::{Vec2, Vec3};
use std::io::{ErrorKind, Read};
use std::path::Path;

/// The format identifier each shape starts with.
const MAGIC: u16 = 0x041C;

/// Flag bits (see the module's documentation).
const HAS_NORMALS: u32 = 0x0001;
const HAS_TEXCOORDS: u32 = 0x0002;
const HAS_COLORS: u32 = 0x0008;
/// Face normals asked for: Mitsuba 3 ignores it (its `face_normals` parameter decides), and
/// so do we; the tests write it.
#[cfg(test)]
const FACE_NORMALS: u32 = 0x0010;
const DOUBLE_PRECISION: u32 = 0x2000;

/// DEFLATE expands data at most about 1032 times: counts that need more decompressed bytes
/// than this times the compressed bytes left cannot be true.
const MAX_DEFLATE_RATIO: u128 = 1032;

/// Longest shape name read, in bytes.
const MAX_NAME: usize = 1 << 16;

/// Items read at a time: memory grows with the data actually decompressed, never from a
/// count alone.
const CHUNK: usize = 1 << 14;

/// Reads shape `shape_index` (0 for the first) of a Mitsuba `.serialized` file (see the
/// module's documentation). Errors are plain messages (the caller names the file): not a
/// `.serialized` file, an unsupported version, a shape index beyond the file's shapes (the
/// message says how many it has), a broken dictionary, truncated or corrupt compressed data,
/// counts that the data cannot hold, more than `u32::MAX` vertices, no triangles, an index
/// beyond the vertices, a number that is not finite in 32-bit floats.
pub(super) fn read_serialized(path: &Path, shape_index: u32) -> Result<IndexedMesh, String> {
    let bytes = super::files::read(path)?;
    parse_serialized(&bytes, shape_index)
}

/// Parses the bytes of a `.serialized` file (see [`read_serialized`]).
fn parse_serialized(bytes: &[u8], shape_index: u32) -> Result<IndexedMesh, String> {
    let version = match shape_header(bytes, 0) {
        Some((MAGIC, version @ (3 | 4))) => version,
        Some((MAGIC, version)) => {
            return Err(format!("unsupported .serialized version {version} (versions 3 and 4 are supported)"))
        }
        _ => return Err("not a Mitsuba .serialized file: it does not start with the format identifier 0x041C".into()),
    };
    let start = if shape_index == 0 { 0 } else { shape_offset(bytes, version, shape_index)? };
    if shape_header(bytes, start) != Some((MAGIC, version)) {
        return Err(format!(
            "the end-of-file dictionary gives shape {shape_index} the offset {start}, where no version {version} shape starts"
        ));
    }
    let compressed = &bytes[start + 4..];
    let mut stream = Stream(ZlibDecoder::new(compressed));

    let flags = stream.u32()?;
    if version == 4 {
        // The shape's name, which nothing here needs.
        let mut length = 0;
        while stream.u8()? != 0 {
            length += 1;
            if length > MAX_NAME {
                return Err(format!("the shape's name is not NUL-terminated within {MAX_NAME} bytes"));
            }
        }
    }
    let vertex_count = stream.u64()?;
    let triangle_count = stream.u64()?;
    if vertex_count > u32::MAX.into() {
        return Err(format!("the shape has {vertex_count} vertices; at most {} are supported", u32::MAX));
    }
    if triangle_count == 0 {
        return Err("the shape has no triangles".into());
    }
    let real_size: u128 = if flags & DOUBLE_PRECISION != 0 { 8 } else { 4 };
    let reals_per_vertex = 3 + [(HAS_NORMALS, 3), (HAS_TEXCOORDS, 2), (HAS_COLORS, 3)]
        .iter()
        .filter(|(flag, _)| flags & flag != 0)
        .map(|(_, n)| n)
        .sum::<u128>();
    let needed = u128::from(vertex_count) * reals_per_vertex * real_size + u128::from(triangle_count) * 12;
    if needed > compressed.len() as u128 * MAX_DEFLATE_RATIO + 1024 {
        return Err(format!(
            "the shape claims {vertex_count} vertices and {triangle_count} triangles, more than its {} compressed bytes can hold",
            compressed.len()
        ));
    }
    // Both fit: the vertex count in a u32, the triangle count in what the check above allows.
    let (vertex_count, triangle_count) = (vertex_count as usize, triangle_count as usize);

    let double = flags & DOUBLE_PRECISION != 0;
    let positions = stream.reals::<3>(vertex_count, double)?;
    let normals = (flags & HAS_NORMALS != 0).then(|| stream.reals::<3>(vertex_count, double)).transpose()?;
    let uvs = (flags & HAS_TEXCOORDS != 0).then(|| stream.reals::<2>(vertex_count, double)).transpose()?;
    if flags & HAS_COLORS != 0 {
        stream.skip(vertex_count as u128 * 3 * real_size)?;
    }
    check_finite(&positions, "position")?;
    check_finite(normals.iter().flatten(), "normal")?;
    check_finite(uvs.iter().flatten(), "texture coordinate")?;

    let mut indices = Vec::with_capacity(triangle_count.min(CHUNK));
    let mut buffer = vec![0u8; triangle_count.min(CHUNK) * 12];
    while indices.len() < triangle_count {
        let n = (triangle_count - indices.len()).min(CHUNK);
        stream.fill(&mut buffer[..n * 12])?;
        for triangle in buffer[..n * 12].chunks_exact(12) {
            let corner = |k: usize| u32::from_le_bytes([0, 1, 2, 3].map(|b| triangle[4 * k + b]));
            let face = [corner(0), corner(1), corner(2)];
            if let Some(&index) = face.iter().find(|&&i| i as usize >= vertex_count) {
                return Err(format!(
                    "triangle {} refers to vertex {index}, but the shape has {vertex_count} vertices",
                    indices.len()
                ));
            }
            indices.push(face);
        }
    }

    let mesh = IndexedMesh {
        positions: positions.into_iter().map(Vec3::from_array).collect(),
        normals: normals.map(|n| n.into_iter().map(Vec3::from_array).collect()),
        uvs: uvs.map(|uv| uv.into_iter().map(Vec2::from_array).collect()),
        indices,
    };
    Ok(mesh)
}

/// The format identifier and version at byte `offset`, when the file is that long.
fn shape_header(bytes: &[u8], offset: usize) -> Option<(u16, u16)> {
    let header = bytes.get(offset..offset.checked_add(4)?)?;
    Some((u16::from_le_bytes([header[0], header[1]]), u16::from_le_bytes([header[2], header[3]])))
}

/// The byte offset of shape `shape_index` from the end-of-file dictionary.
fn shape_offset(bytes: &[u8], version: u16, shape_index: u32) -> Result<usize, String> {
    let broken = || "the end-of-file dictionary of shape offsets is missing or broken".to_owned();
    let end = bytes.len().checked_sub(4).filter(|&end| end >= 4).ok_or_else(broken)?;
    let count = u32::from_le_bytes([0, 1, 2, 3].map(|b| bytes[end + b]));
    if shape_index >= count {
        let s = if count == 1 { "" } else { "s" };
        return Err(format!("shape_index {shape_index} is out of range: the file has {count} shape{s}"));
    }
    let entry = if version == 4 { 8 } else { 4 };
    // Shape i's entry sits (count - i) entries before the count.
    let position = (count - shape_index) as usize * entry;
    let at = end.checked_sub(position).filter(|&at| at >= 4).ok_or_else(broken)?;
    let mut offset = [0u8; 8];
    offset[..entry].copy_from_slice(&bytes[at..at + entry]);
    let offset = u64::from_le_bytes(offset);
    usize::try_from(offset).ok().filter(|&offset| offset < at).ok_or_else(|| {
        format!("the end-of-file dictionary gives shape {shape_index} the offset {offset}, beyond the shapes' data")
    })
}

/// The first non-finite value of `values` as an error.
fn check_finite<'a, const N: usize>(values: impl IntoIterator<Item = &'a [f32; N]>, what: &str) -> Result<(), String> {
    match values.into_iter().position(|v| !v.iter().all(|x| x.is_finite())) {
        Some(vertex) => Err(format!("vertex {vertex}: a {what} is not a finite 32-bit number")),
        None => Ok(()),
    }
}

/// The decompressed data of one shape.
struct Stream<R: Read>(R);

impl<R: Read> Stream<R> {
    /// Fills `buffer` from the stream.
    fn fill(&mut self, buffer: &mut [u8]) -> Result<(), String> {
        self.0.read_exact(buffer).map_err(|e| match e.kind() {
            ErrorKind::UnexpectedEof => {
                "the compressed data ends early: the file is truncated, or its counts are wrong".to_owned()
            }
            _ => format!("corrupt compressed data: {e}"),
        })
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N], String> {
        let mut bytes = [0; N];
        self.fill(&mut bytes)?;
        Ok(bytes)
    }

    fn u8(&mut self) -> Result<u8, String> {
        Ok(self.array::<1>()?[0])
    }

    fn u32(&mut self) -> Result<u32, String> {
        self.array().map(u32::from_le_bytes)
    }

    fn u64(&mut self) -> Result<u64, String> {
        self.array().map(u64::from_le_bytes)
    }

    /// `count` vectors of `N` floats (`double`: 64-bit ones, rounded to 32 bits).
    fn reals<const N: usize>(&mut self, count: usize, double: bool) -> Result<Vec<[f32; N]>, String> {
        let size = if double { 8 } else { 4 };
        let mut out = Vec::with_capacity(count.min(CHUNK));
        let mut buffer = vec![0u8; count.min(CHUNK) * N * size];
        while out.len() < count {
            let n = (count - out.len()).min(CHUNK);
            let bytes = &mut buffer[..n * N * size];
            self.fill(bytes)?;
            out.extend(bytes.chunks_exact(N * size).map(|vector| {
                std::array::from_fn(|k| {
                    let real = &vector[k * size..(k + 1) * size];
                    if double {
                        f64::from_le_bytes(std::array::from_fn(|b| real[b])) as f32
                    } else {
                        f32::from_le_bytes(std::array::from_fn(|b| real[b]))
                    }
                })
            }));
        }
        Ok(out)
    }

    /// Reads past `count` bytes.
    fn skip(&mut self, count: u128) -> Result<(), String> {
        let count = u64::try_from(count).map_err(|_| "the shape's colours do not fit in the file".to_owned())?;
        let copied = std::io::copy(&mut (&mut self.0).take(count), &mut std::io::sink())
            .map_err(|e| format!("corrupt compressed data: {e}"))?;
        if copied < count {
            return Err("the compressed data ends early: the file is truncated, or its counts are wrong".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flate2::write::ZlibEncoder;
    use std::io::Write;

    /// A `.serialized` file of a quad (two triangles) with normals and texture coordinates,
    /// then a triangle in double precision with colours and the face-normals flag.
    fn file(version: u16) -> Vec<u8> {
        let mut shapes = Vec::new();
        let mut quad = (HAS_NORMALS | HAS_TEXCOORDS | 0x1000).to_le_bytes().to_vec();
        if version == 4 {
            quad.extend(b"quad\0");
        }
        quad.extend(4u64.to_le_bytes());
        quad.extend(2u64.to_le_bytes());
        let reals: [&[f32]; 3] =
            [&[0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0.], &[0., 0., 1.].repeat(4), &[0., 0., 1., 0., 1., 1., 0., 1.]];
        quad.extend(reals.concat().iter().flat_map(|x| x.to_le_bytes()));
        quad.extend([0u32, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
        shapes.push(quad);
        let mut triangle = (HAS_COLORS | FACE_NORMALS | DOUBLE_PRECISION).to_le_bytes().to_vec();
        if version == 4 {
            triangle.extend(b"\0");
        }
        triangle.extend(3u64.to_le_bytes());
        triangle.extend(1u64.to_le_bytes());
        let reals = [0f64, 0., 0., 2., 0., 0., 0., 2., 0., 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5];
        triangle.extend(reals.iter().flat_map(|x| x.to_le_bytes()));
        triangle.extend([0u32, 1, 2].iter().flat_map(|i| i.to_le_bytes()));
        shapes.push(triangle);

        let mut out = Vec::new();
        let mut offsets = Vec::new();
        for shape in shapes {
            offsets.push(out.len() as u64);
            out.extend(MAGIC.to_le_bytes());
            out.extend(version.to_le_bytes());
            let mut encoder = ZlibEncoder::new(Vec::new(), flate2::Compression::default());
            encoder.write_all(&shape).unwrap();
            out.extend(encoder.finish().unwrap());
        }
        for offset in &offsets {
            out.extend(if version == 4 { offset.to_le_bytes().to_vec() } else { (*offset as u32).to_le_bytes().to_vec() });
        }
        out.extend((offsets.len() as u32).to_le_bytes());
        out
    }

    #[test]
    fn reads_each_shape_of_both_versions() {
        for version in [3, 4] {
            let bytes = file(version);
            let quad = parse_serialized(&bytes, 0).unwrap();
            quad.assert_valid();
            assert_eq!(quad.indices, [[0, 1, 2], [0, 2, 3]]);
            assert_eq!(quad.positions[2], Vec3::new(1.0, 1.0, 0.0));
            assert_eq!(quad.normals.as_ref().unwrap(), &[Vec3::Z; 4]);
            assert_eq!(quad.uvs.as_ref().unwrap()[3], Vec2::Y);
            let triangle = parse_serialized(&bytes, 1).unwrap();
            triangle.assert_valid();
            assert!(triangle.normals.is_none() && triangle.uvs.is_none());
            assert_eq!(triangle.positions, [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0)]);
            let error = parse_serialized(&bytes, 2).unwrap_err();
            assert!(error.contains("the file has 2 shapes"), "{error}");
        }
    }

    /// Every prefix of the files, and the files with any one byte garbled, for every shape
    /// index: a sound mesh or an error, never a panic.
    #[test]
    fn truncated_and_garbled_bytes_never_panic() {
        for bytes in [file(3), file(4)] {
            let mut variants: Vec<Vec<u8>> = (0..bytes.len()).map(|n| bytes[..n].to_vec()).collect();
            for i in 0..bytes.len() {
                for flip in [0x01, 0x02, 0x10, 0x80, 0xff] {
                    let mut garbled = bytes.clone();
                    garbled[i] ^= flip;
                    variants.push(garbled);
                }
            }
            for variant in variants {
                for shape_index in [0, 1, 2, u32::MAX] {
                    match parse_serialized(&variant, shape_index) {
                        Ok(read) => read.assert_valid(),
                        Err(message) => assert!(!message.is_empty()),
                    }
                }
            }
        }
    }
}
