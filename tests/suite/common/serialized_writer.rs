//! Mitsuba `.serialized` files for the tests that read them (tests/suite/mesh_formats.rs,
//! tests/suite/fuzz.rs): each shape's uncompressed body as given, behind its format id and version,
//! zlib-compressed, then the shapes' offsets (u64 in version 4, u32 in 3) and their count.

use std::io::Write;

/// A `.serialized` file of the shapes whose uncompressed bodies are `bodies`.
pub fn serialized_file(bodies: &[Vec<u8>], version: u16) -> Vec<u8> {
    let mut out = Vec::new();
    let mut offsets = Vec::new();
    for body in bodies {
        offsets.push(out.len() as u64);
        out.extend(0x041Cu16.to_le_bytes());
        out.extend(version.to_le_bytes());
        let mut encoder = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        encoder.write_all(body).unwrap();
        out.extend(encoder.finish().unwrap());
    }
    for offset in offsets {
        if version == 4 {
            out.extend(offset.to_le_bytes());
        } else {
            out.extend((offset as u32).to_le_bytes());
        }
    }
    out.extend((bodies.len() as u32).to_le_bytes());
    out
}
