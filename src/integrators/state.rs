//! An integrator's state as bytes (checkpoints, batches): its pass count and work so far,
//! then one buffer.

use crate::error::Error;

/// The bytes of an integrator's state: its pass count and work so far, then one buffer.
pub(super) fn encode_state(passes: u32, work: u64, buffer: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(12 + buffer.len());
    out.extend_from_slice(&passes.to_le_bytes());
    out.extend_from_slice(&work.to_le_bytes());
    out.extend_from_slice(buffer);
    out
}

/// (passes, work, buffer) of [`encode_state`]'s bytes, the buffer `expected` bytes long.
pub(super) fn decode_state(state: &[u8], expected: u64) -> Result<(u32, u64, &[u8]), Error> {
    if state.len() as u64 != 12 + expected {
        return Err(Error::Setting(format!(
            "the saved state holds {} bytes where this render needs {}: made for another image size",
            state.len(),
            12 + expected
        )));
    }
    let passes = u32::from_le_bytes(state[0..4].try_into().expect("4 bytes"));
    let work = u64::from_le_bytes(state[4..12].try_into().expect("8 bytes"));
    // The next pass would count past the largest pass count.
    if passes == u32::MAX {
        return Err(Error::Setting(format!("the saved state is corrupt: its pass count {passes} leaves no pass to run")));
    }
    Ok((passes, work, &state[12..]))
}
