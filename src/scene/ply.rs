//! PLY meshes (the Stanford polygon file format), ASCII and binary in either byte order,
//! read with the `ply-rs-bw` crate into an [`IndexedMesh`].
//!
//! The format (Greg Turk, "The PLY Polygon File Format", 1994; see
//! <https://paulbourke.net/dataformats/ply/>): a text header, starting with the line `ply`,
//! names the encoding (`format ascii 1.0`, `format binary_little_endian 1.0` or
//! `format binary_big_endian 1.0`) and declares elements (`element vertex 8`) with their
//! properties (`property float x`, `property list uchar int vertex_indices`), up to
//! `end_header`. The payload then holds each element's instances in header order: one line
//! each in ASCII, packed fields in binary.
//!
//! What is read follows Mitsuba 3's `ply` shape (src/shapes/ply.cpp): the `vertex` element's
//! `x`, `y`, `z`, its normals `nx`, `ny`, `nz` when all three are present, and its texture
//! coordinates under the first pair present of `u`/`v`, `texture_u`/`texture_v`, `s`/`t` (and
//! here also `texture_s`/`texture_t`); the `face` element's list `vertex_indices` (or
//! `vertex_index`). Any numeric type is accepted for each. Mitsuba reads only triangles;
//! faces with more vertices are triangulated here as a fan around their first vertex. Other
//! elements and properties (colours, edges, materials) are skipped. Texture coordinates are
//! kept as the file stores them.

use super::mesh::IndexedMesh;
use glam::{Vec2, Vec3};
use ply_rs_bw::parser::{ParseError, Parser, Reader};
use ply_rs_bw::ply::{ElementDef, Encoding, Property, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType};
use std::io::ErrorKind;
use std::path::Path;

/// Reads a PLY file into an indexed triangle mesh: positions, normals and texture
/// coordinates when the file has them, and its faces triangulated (see the module's
/// documentation). Errors are plain messages (the caller names the file): not a PLY file, a
/// broken header, no `x`, `y` or `z`, a truncated payload, a number that is not finite in
/// 32-bit floats, a face with fewer than 3 vertices or one that refers to a vertex that does
/// not exist, no faces at all.
pub(super) fn read_ply(path: &Path) -> Result<IndexedMesh, String> {
    let bytes = super::files::read(path)?;
    parse_ply(&bytes)
}

/// The vertex properties read, by slot: position, normal, and every texture-coordinate name.
const VERTEX_PROPERTIES: [&str; 14] =
    ["x", "y", "z", "nx", "ny", "nz", "u", "v", "texture_u", "texture_v", "s", "t", "texture_s", "texture_t"];

/// Slots of the texture-coordinate pairs in [`VERTEX_PROPERTIES`], in order of preference
/// (Mitsuba 3's, then `texture_s`/`texture_t`).
const UV_SLOTS: [(usize, usize); 4] = [(6, 7), (8, 9), (10, 11), (12, 13)];

/// The names of the face's index list, in order of preference.
const FACE_LISTS: [&str; 2] = ["vertex_indices", "vertex_index"];

/// Parses the bytes of a PLY file (see [`read_ply`]).
fn parse_ply(bytes: &[u8]) -> Result<IndexedMesh, String> {
    if !(bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r")) {
        return Err("not a PLY file: it does not start with the line `ply`".into());
    }
    let mut reader = Reader::new(bytes);
    let header = Parser::<Skipped>::new().read_header(&mut reader).map_err(|e| format!("invalid PLY header: {}", message(&e)))?;
    let payload = reader.into_inner();
    let header_lines = bytes[..bytes.len() - payload.len()].iter().filter(|&&b| b == b'\n').count();

    let vertex = header.elements.get("vertex").ok_or("the file has no `vertex` element")?;
    for name in ["x", "y", "z"] {
        match vertex.properties.get(name).map(|p| &p.data_type) {
            Some(PropertyType::Scalar(_)) => {}
            Some(PropertyType::List(..)) => return Err(format!("the vertex property `{name}` is a list, not a number")),
            None => return Err(format!("the vertex element has no `{name}` property")),
        }
    }
    let is_number = |slot: usize| {
        matches!(vertex.properties.get(VERTEX_PROPERTIES[slot]).map(|p| &p.data_type), Some(PropertyType::Scalar(_)))
    };
    let has_normals = (3..6).all(is_number);
    let uv_slots = UV_SLOTS.into_iter().find(|&(u, v)| is_number(u) && is_number(v));
    let vertex_count = vertex.count;
    if vertex_count > u32::MAX as usize {
        return Err(format!("the file declares {vertex_count} vertices; at most {} are supported", u32::MAX));
    }

    let face = header.elements.get("face").ok_or("the file has no `face` element, so no triangles")?;
    let list = FACE_LISTS
        .iter()
        .position(|name| face.properties.contains_key(*name))
        .ok_or("the face element has no `vertex_indices` (or `vertex_index`) list")?;
    match &face.properties[FACE_LISTS[list]].data_type {
        PropertyType::List(_, ScalarType::Float | ScalarType::Double) => {
            return Err(format!("the face list `{}` holds floats; vertex indices must be integers", FACE_LISTS[list]))
        }
        PropertyType::List(..) => {}
        PropertyType::Scalar(_) => return Err(format!("the face property `{}` is a number, not a list", FACE_LISTS[list])),
    }

    let mut mesh = IndexedMesh {
        positions: Vec::with_capacity(vertex_count.min(1 << 16)),
        normals: has_normals.then(Vec::new),
        uvs: uv_slots.map(|_| Vec::new()),
        indices: Vec::new(),
    };
    let mut elements = Elements { rest: payload, encoding: header.encoding, line: header_lines };
    for (name, def) in &header.elements {
        if name == "vertex" {
            let parser = Parser::<VertexRecord>::new();
            for i in 0..def.count {
                let VertexRecord(values) = elements.next(&parser, def, i)?;
                let finite = |v: &[f64]| v.iter().all(|&x| (x as f32).is_finite());
                let vec3 = |s: usize| Vec3::new(values[s] as f32, values[s + 1] as f32, values[s + 2] as f32);
                if !finite(&values[0..3]) {
                    return Err(format!("vertex {i}: the position is not a finite 32-bit number"));
                }
                mesh.positions.push(vec3(0));
                if let Some(normals) = &mut mesh.normals {
                    if !finite(&values[3..6]) {
                        return Err(format!("vertex {i}: the normal is not a finite 32-bit number"));
                    }
                    normals.push(vec3(3));
                }
                if let (Some(uvs), Some((u, v))) = (&mut mesh.uvs, uv_slots) {
                    if !finite(&[values[u], values[v]]) {
                        return Err(format!("vertex {i}: the texture coordinates are not finite 32-bit numbers"));
                    }
                    uvs.push(Vec2::new(values[u] as f32, values[v] as f32));
                }
            }
        } else if name == "face" {
            let parser = Parser::<FaceRecord>::new();
            for i in 0..def.count {
                let FaceRecord(lists) = elements.next(&parser, def, i)?;
                let Some(Some(face)) = &lists[list] else {
                    return Err(format!("face {i}: a vertex index is negative"));
                };
                if face.len() < 3 {
                    return Err(format!("face {i} has {} vertices; a face needs at least 3", face.len()));
                }
                if let Some(&index) = face.iter().find(|&&index| index as usize >= vertex_count) {
                    return Err(format!("face {i} refers to vertex {index}, but the file has {vertex_count} vertices"));
                }
                mesh.indices.extend((1..face.len() - 1).map(|k| [face[0], face[k], face[k + 1]]));
            }
        } else if def.properties.is_empty() && header.encoding != Encoding::Ascii {
            // Nothing to read: an element without properties takes no bytes.
        } else {
            let parser = Parser::<Skipped>::new();
            for i in 0..def.count {
                elements.next(&parser, def, i)?;
            }
        }
    }
    if mesh.indices.is_empty() {
        return Err("the file has no faces, so no triangles".into());
    }
    Ok(mesh)
}

/// The payload, read one element instance at a time.
struct Elements<'a> {
    /// What is left of the file.
    rest: &'a [u8],
    encoding: Encoding,
    /// The 1-based line last read (ASCII).
    line: usize,
}

impl Elements<'_> {
    /// Instance `index` of element `def`.
    fn next<E: PropertyAccess>(&mut self, parser: &Parser<E>, def: &ElementDef, index: usize) -> Result<E, String> {
        let truncated = || format!("the file ends after {index} of its {} `{}` elements", def.count, def.name);
        let result = match self.encoding {
            Encoding::Ascii => {
                if self.rest.is_empty() {
                    return Err(truncated());
                }
                let end = self.rest.iter().position(|&b| b == b'\n').map_or(self.rest.len(), |i| i + 1);
                let (line, rest) = self.rest.split_at(end);
                self.rest = rest;
                self.line += 1;
                let line = std::str::from_utf8(line).map_err(|_| format!("line {}: not ASCII text", self.line))?;
                return parser
                    .read_ascii_element(line, def)
                    .map_err(|e| format!("line {} ({} {index}): {}", self.line, def.name, message(&e)));
            }
            Encoding::BinaryLittleEndian => parser.read_little_endian_element(&mut self.rest, def),
            Encoding::BinaryBigEndian => parser.read_big_endian_element(&mut self.rest, def),
        };
        result.map_err(|e| match e.kind() {
            ErrorKind::UnexpectedEof => truncated(),
            _ => format!("{} {index}: {}", def.name, message(&e)),
        })
    }
}

/// A parser error on one line, and not too long (it may quote a garbled line), without the
/// grammar's internals.
fn message(e: &ParseError) -> String {
    let text = e.to_string().split_whitespace().collect::<Vec<_>>().join(" ");
    let text = text.split(" Error: ParseError {").next().unwrap_or_default();
    match text.char_indices().nth(200) {
        Some((end, _)) => format!("{}...", &text[..end]),
        None => text.to_owned(),
    }
}

/// A number property as a double; `None` for a list.
fn number(property: &Property) -> Option<f64> {
    Some(match *property {
        Property::Char(x) => x.into(),
        Property::UChar(x) => x.into(),
        Property::Short(x) => x.into(),
        Property::UShort(x) => x.into(),
        Property::Int(x) => x.into(),
        Property::UInt(x) => x.into(),
        Property::Float(x) => x.into(),
        Property::Double(x) => x,
        _ => return None,
    })
}

/// One vertex: the value of each of [`VERTEX_PROPERTIES`] (0 where absent).
struct VertexRecord([f64; VERTEX_PROPERTIES.len()]);

impl PropertyAccess for VertexRecord {
    fn new() -> Self {
        VertexRecord([0.0; VERTEX_PROPERTIES.len()])
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        match (VERTEX_PROPERTIES.iter().position(|&p| p == name), number(&property)) {
            (Some(slot), Some(x)) => {
                self.0[slot] = x;
                PropertyAccessResult::Set
            }
            _ => PropertyAccessResult::Ignored,
        }
    }
}

/// One face: each of the [`FACE_LISTS`] it has, as unsigned indices (`Some(None)` when one
/// of them is negative).
struct FaceRecord([Option<Option<Vec<u32>>>; FACE_LISTS.len()]);

impl PropertyAccess for FaceRecord {
    fn new() -> Self {
        FaceRecord([None, None])
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        match FACE_LISTS.iter().position(|&list| list == name) {
            Some(slot) => {
                self.0[slot] = Some(property.to_u32_list());
                PropertyAccessResult::Set
            }
            None => PropertyAccessResult::Ignored,
        }
    }
}

/// An element that is read past and dropped.
struct Skipped;

impl PropertyAccess for Skipped {
    fn new() -> Self {
        Skipped
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quad (one four-sided face) and a triangle over it, with normals and texture
    /// coordinates.
    const ASCII: &str = "ply\nformat ascii 1.0\ncomment a quad\nelement vertex 4\nproperty float x\nproperty float y\n\
        property float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float s\nproperty float t\n\
        element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n\
        1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n4 0 1 2 3\n3 0 2 3\n";

    /// The same as binary PLY, in either byte order.
    fn binary(big_endian: bool) -> Vec<u8> {
        let order = if big_endian { "big" } else { "little" };
        let (header, payload) = ASCII.split_once("end_header\n").unwrap();
        let mut out = header.replace("format ascii", &format!("format binary_{order}_endian")).into_bytes();
        out.extend(b"end_header\n");
        let lines: Vec<&str> = payload.lines().collect();
        for line in &lines[..4] {
            for x in line.split(' ') {
                let x: f32 = x.parse().unwrap();
                out.extend(if big_endian { x.to_be_bytes() } else { x.to_le_bytes() });
            }
        }
        for line in &lines[4..] {
            let mut words = line.split(' ');
            out.push(words.next().unwrap().parse().unwrap());
            for i in words {
                let i: i32 = i.parse().unwrap();
                out.extend(if big_endian { i.to_be_bytes() } else { i.to_le_bytes() });
            }
        }
        out
    }

    #[test]
    fn ascii_and_binary_read_alike() {
        let mesh = parse_ply(ASCII.as_bytes()).unwrap();
        mesh.assert_valid();
        assert_eq!(mesh.indices, [[0, 1, 2], [0, 2, 3], [0, 2, 3]]);
        assert_eq!(mesh.positions[2], Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(mesh.normals.as_ref().unwrap()[3], Vec3::Z);
        assert_eq!(mesh.uvs.as_ref().unwrap()[1], Vec2::X);
        for big_endian in [false, true] {
            let other = parse_ply(&binary(big_endian)).unwrap();
            assert_eq!((&other.positions, &other.normals, &other.uvs), (&mesh.positions, &mesh.normals, &mesh.uvs));
            assert_eq!(other.indices, mesh.indices);
        }
    }

    /// Every prefix of the files, and the files with any one byte garbled: a sound mesh or
    /// an error, never a panic.
    #[test]
    fn truncated_and_garbled_bytes_never_panic() {
        for bytes in [ASCII.as_bytes().to_vec(), binary(false), binary(true)] {
            let mut variants: Vec<Vec<u8>> = (0..bytes.len()).map(|n| bytes[..n].to_vec()).collect();
            for i in 0..bytes.len() {
                for flip in [0x01, 0x02, 0x10, 0x80, 0xff] {
                    let mut garbled = bytes.clone();
                    garbled[i] ^= flip;
                    variants.push(garbled);
                }
            }
            for variant in variants {
                match parse_ply(&variant) {
                    Ok(mesh) => mesh.assert_valid(),
                    Err(message) => assert!(!message.is_empty() && !message.contains('\n'), "{message:?}"),
                }
            }
        }
    }
}
