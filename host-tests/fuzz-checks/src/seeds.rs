//! Seed inputs for every target, in the target's input format: the documents' example
//! frames (`host-tests/fixtures/seed_vectors.json`, through `codec-cases`), the
//! K40T reference frames of docs/src/protocols/k40t.md, and frames the encoder builds for every message of
//! each catalogue.

use protocol_core::Direction;
use protocol_core::k40t::CrcCoverage;
use protocol_core::viewlink::SyncOrder;

use crate::input::Plan;

/// The K40T reference frames of docs/src/protocols/k40t.md (zoom, its ACK, a gimbal attitude report).
const K40T_REFERENCE: [&[u8]; 3] = [
    &[
        0xFD, 0x03, 0x04, 0x01, 0x07, 0x02, 0x01, 0x04, 0x03, 0x00, 0x00, 0x2D, 0x00, 0xCE, 0x89,
    ],
    &[
        0xFD, 0x02, 0x02, 0x01, 0x07, 0x04, 0x01, 0x04, 0x03, 0x01, 0x00, 0x00, 0xE8, 0xEB,
    ],
    &[
        0xFD, 0x10, 0x04, 0x01, 0x09, 0x02, 0x01, 0x0E, 0x03, 0x00, 0x00, 0xA8, 0xDA, 0x76, 0x9B,
        0x01, 0x00, 0x00, 0x20, 0xFE, 0xFF, 0xFF, 0x00, 0x00, 0x00, 0x00, 0x7D, 0xE5,
    ],
];

/// Payload patterns the encoder fills messages with.
fn fills() -> [Vec<u8>; 3] {
    [
        vec![0; 256],
        (0..=255u8).collect(),
        (0..=255u8).map(|i| i.wrapping_mul(151) ^ 0x5A).collect(),
    ]
}

/// The example frames of one protocol in the seed-vector fixture: as used, as
/// printed, and as the document's tables describe them.
fn vectors(protocol: &'static str) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for v in codec_cases::vectors(protocol) {
        out.push(v.bytes.to_vec());
        out.extend(v.doc_bytes.map(<[u8]>::to_vec));
        out.extend(v.alt_semantic.map(<[u8]>::to_vec));
    }
    out
}

/// Every K40T frame: reference frames and the catalogue under both coverages, and one
/// with a payload shorter than its layout.
#[must_use]
pub fn k40t_frames() -> Vec<Vec<u8>> {
    let mut out: Vec<Vec<u8>> = K40T_REFERENCE.iter().map(|f| f.to_vec()).collect();
    for (i, fill) in fills().iter().enumerate() {
        let coverage = if i == 1 {
            CrcCoverage::IncludeStx
        } else {
            CrcCoverage::ExcludeStx
        };
        out.extend(crate::k40t::catalogue_frames(fill, coverage));
    }
    // A truncated payload (MAVLink v2 drops trailing zeros): the last reference frame
    // without its last four payload bytes.
    let mut short = K40T_REFERENCE[2][..22].to_vec();
    short[1] = 0x0C;
    let crc = codec_cases::oracle::k40t_crc(&short[1..]);
    short.extend(crc.to_le_bytes());
    out.push(short);
    out
}

/// Every SIYI frame: the document's examples and the catalogue in both directions.
#[must_use]
pub fn siyi_frames() -> Vec<Vec<u8>> {
    let mut out = vectors("SIYI");
    for fill in fills() {
        out.extend(crate::siyi::catalogue_frames(&fill));
    }
    out
}

/// Every Viewlink serial frame (both sync orders) and envelope of the document, and
/// the catalogue.
#[must_use]
pub fn viewlink_frames() -> Vec<Vec<u8>> {
    let mut out = vectors("Viewlink");
    for fill in fills() {
        out.extend(crate::viewlink::catalogue_frames(
            &fill,
            SyncOrder::Standard,
        ));
    }
    out.extend(crate::viewlink::catalogue_frames(
        &fills()[1],
        SyncOrder::Swapped,
    ));
    out
}

/// Every GCU package: the document's host packages, the catalogue, and the answers.
#[must_use]
pub fn gcu_frames() -> Vec<Vec<u8>> {
    let mut out = vectors("GCU");
    for fill in fills() {
        let (host, answers) = crate::gcu::catalogue_frames(&fill);
        out.extend(host);
        out.extend(answers);
    }
    out
}

/// Deframer inputs: a plan with `selector` and a few chunkings, over the frames
/// concatenated in groups with garbage and a broken copy between them.
fn streams(selector: u8, frames: &[Vec<u8>]) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for (i, group) in frames.chunks(12).enumerate() {
        let sizes: &[u8] = match i % 4 {
            0 => &[63],
            1 => &[0],
            2 => &[7, 200, 1],
            _ => &[255, 31],
        };
        let mut s = Plan::encode(selector, sizes);
        for (j, f) in group.iter().enumerate() {
            s.extend_from_slice(f);
            if j % 3 == 1 {
                // A corrupted copy, then garbage.
                let mut bad = f.clone();
                let last = bad.len() - 1;
                bad[last] ^= 0x40;
                s.extend_from_slice(&bad);
                s.extend_from_slice(&[0x00, 0xFF, f[0], 0x13]);
            }
        }
        // The start of one more frame (cut off by the end of the stream).
        if let Some(f) = group.first() {
            s.extend_from_slice(&f[..f.len() / 2]);
        }
        out.push(s);
    }
    out
}

/// The seeds of target `name`.
///
/// # Panics
/// For an unknown target name.
#[must_use]
pub fn seeds(name: &str) -> Vec<Vec<u8>> {
    match name {
        "k40t_decode" => k40t_frames(),
        "k40t_deframe" => (0..8).flat_map(|s| streams(s, &k40t_frames())).collect(),
        "siyi_decode" => siyi_frames(),
        "siyi_deframe" => (0..2).flat_map(|s| streams(s, &siyi_frames())).collect(),
        "viewlink_decode" => viewlink_frames(),
        "viewlink_deframe" => {
            let (standard, swapped): (Vec<_>, Vec<_>) = viewlink_frames()
                .into_iter()
                .filter(|f| f.first() != Some(&0xEB))
                .partition(|f| f.first() == Some(&0x55));
            let mut out = streams(0, &standard);
            out.extend(streams(1, &swapped));
            // The swapped-order deframer among standard frames, and the reverse.
            out.extend(streams(1, &standard[..12]));
            out
        }
        "viewlink_tcp" => {
            let serial = viewlink_frames();
            let mut envelopes: Vec<Vec<u8>> = serial
                .iter()
                .filter(|f| f.first() == Some(&0xEB))
                .cloned()
                .collect();
            envelopes.extend(
                serial
                    .iter()
                    .filter(|f| f.first() != Some(&0xEB))
                    .map(|f| crate::viewlink::envelope(f)),
            );
            let mut out: Vec<Vec<u8>> =
                envelopes.iter().map(|e| [&[0u8][..], e].concat()).collect();
            out.extend(
                streams(0, &envelopes)
                    .into_iter()
                    .map(|s| [vec![1u8], s].concat()),
            );
            out
        }
        "gcu_decode" => gcu_frames(),
        "gcu_deframe" => {
            let (host, gcu): (Vec<_>, Vec<_>) = gcu_frames().into_iter().partition(|f| {
                protocol_core::gcu::direction_of([f[0], f[1]]) == Some(Direction::ToGimbal)
            });
            let mut out = streams(0, &host);
            out.extend(streams(1, &gcu));
            out
        }
        "mavlink_decode" => crate::mavlink::frames(),
        "mavlink_deframe" => {
            let frames = crate::mavlink::frames();
            let mut out = streams(0, &frames);
            out.extend(streams(1, &frames[..24]));
            out
        }
        "resync" => crate::resync::seeds(),
        "bridge" => crate::bridge::seeds(),
        "bridge_mavlink" => crate::bridge_mavlink::seeds(),
        "bridge_signed" => crate::bridge_mavlink::signed_seeds(),
        "bridge_k40t_allow" => crate::bridge::k40t_allow_seeds(),
        "bridge_forged" => crate::bridge_mavlink::forged_seeds(),
        "console" => crate::console::seeds(),
        _ => panic!("no target {name}"),
    }
}
