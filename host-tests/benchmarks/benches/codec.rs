//! Instruction counts (gungraun, Callgrind) of the four codecs' stages, of rust-mavlink
//! on an equivalent MAVLink v2 stream, and of the MAVLink 2 codec with its two candidate
//! crates (rust-mavlink, mavio) on the bridge's message set: `scripts/bench` runs this at
//! opt-level z (the firmware's release profile) and 3 and prints one table. The streams
//! and stages: `benchmarks` (src/lib.rs). Each benchmark's input is built in its setup,
//! which Callgrind does not count.

use std::hint::black_box;
use std::io::Read;

use benchmarks::bridge::{self, BridgeRun};
use benchmarks::{CHUNK, Stream, camera, deframe, signing};
use gungraun::{library_benchmark, library_benchmark_group};
use mavlink::dialects::common::MavMessage;
use mavlink::{MavlinkReader, MavlinkVersion, MessageData};

/// A benchmark's input, leaked: freeing it would be counted in the benchmark.
fn leak<T>(value: T) -> &'static T {
    Box::leak(Box::new(value))
}

/// A message's id, CRC_EXTRA and full payload length.
fn message<M: MessageData>() -> (u32, u8, usize) {
    (M::ID, M::EXTRA_CRC, M::ENCODED_LEN)
}

/// Reads a slice at most [`CHUNK`] bytes at a time, as the deframers are fed.
struct Chunked<'a>(&'a [u8]);

impl Read for Chunked<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = buf.len().min(CHUNK).min(self.0.len());
        let (head, rest) = self.0.split_at(n);
        buf[..n].copy_from_slice(head);
        self.0 = rest;
        Ok(n)
    }
}

/// A MAVLink v2 stream with the K40T stream's frame count and payload lengths: each
/// frame a common-dialect message without enumerations (any payload bytes parse), the
/// shortest whose full length holds the payload; pseudo-random payload bytes, the last
/// one non-zero (a v2 sender drops trailing zeros); CRC with the message's CRC_EXTRA.
fn mavlink_stream() -> Vec<u8> {
    use mavlink::dialects::common::*;
    // (id, CRC_EXTRA, full payload length), shortest first.
    let mut messages = [
        message::<SYSTEM_TIME_DATA>(),
        message::<TIMESYNC_DATA>(),
        message::<VFR_HUD_DATA>(),
        message::<RC_CHANNELS_RAW_DATA>(),
        message::<ATTITUDE_DATA>(),
        message::<RAW_IMU_DATA>(),
        message::<MEMORY_VECT_DATA>(),
        message::<SERVO_OUTPUT_RAW_DATA>(),
        message::<RC_CHANNELS_DATA>(),
        message::<ATTITUDE_QUATERNION_DATA>(),
        message::<ATT_POS_MOCAP_DATA>(),
        message::<ENCAPSULATED_DATA_DATA>(),
    ];
    messages.sort_by_key(|m| m.2);
    let k40t = benchmarks::k40t_stream();
    let mut rng = 0x4D41_564Cu64;
    let mut out = Vec::new();
    for (seq, len) in k40t.payload_lens().enumerate() {
        let (id, extra, _) = *messages
            .iter()
            .find(|m| m.2 >= len)
            .expect("a message long enough");
        let id = id.to_le_bytes();
        let start = out.len();
        out.extend_from_slice(&[
            0xFD, len as u8, 0, 0, seq as u8, 0x01, 0x01, id[0], id[1], id[2],
        ]);
        for i in 0..len {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            let b = (rng >> 24) as u8;
            out.push(if i + 1 == len && b == 0 { 1 } else { b });
        }
        let crc = mavlink::calculate_crc(&out[start + 1..], extra);
        out.extend_from_slice(&crc.to_le_bytes());
    }
    // Both readers must take every frame (checked here, in the setup, not measured).
    let frames = k40t.frames.len();
    assert_eq!(mavlink_raw_frames(&out), frames, "rust-mavlink raw reader");
    assert_eq!(mavlink_messages(&out), frames, "rust-mavlink parse");
    out
}

/// Frames rust-mavlink's raw reader takes from `stream`.
fn mavlink_raw_frames(stream: &[u8]) -> usize {
    let mut reader = MavlinkReader::new(Chunked(stream));
    let mut n = 0;
    while let Ok(raw) = reader.read_raw_message::<MavMessage>(MavlinkVersion::V2) {
        black_box(&raw);
        n += 1;
    }
    n
}

/// Messages rust-mavlink parses from `stream`.
fn mavlink_messages(stream: &[u8]) -> usize {
    let mut reader = MavlinkReader::new(Chunked(stream));
    let mut n = 0;
    while let Ok(message) = reader.read_message::<MavMessage>(MavlinkVersion::V2) {
        black_box(&message);
        n += 1;
    }
    n
}

/// Declares, for one protocol, its four stages as benchmarks over one stream.
macro_rules! protocol_benches {
    (
        $stream:ident, checksum: $checksum:expr, deframe: $deframe:expr,
        decode: $decode:expr,
        [$cs:ident, $df:ident, $dc:ident, $rt:ident]
    ) => {
        #[library_benchmark]
        #[bench::stream(leak(benchmarks::$stream()))]
        fn $cs(s: &Stream) -> u32 {
            let checksum = $checksum;
            black_box(s.covered.iter().fold(0u32, |acc, r| {
                acc.wrapping_add(u32::from(checksum(&s.bytes[r.clone()])))
            }))
        }

        #[library_benchmark]
        #[bench::stream(leak(benchmarks::$stream()))]
        fn $df(s: &Stream) -> usize {
            let deframe = $deframe;
            let frames = deframe(black_box(&s.bytes[..]));
            assert_eq!(frames, s.frames.len());
            frames
        }

        #[library_benchmark]
        #[bench::stream(leak(benchmarks::$stream()))]
        fn $dc(s: &Stream) -> usize {
            let decode = $decode;
            black_box(s.frames().filter(|f| decode(black_box(f)).is_ok()).count())
        }

        #[library_benchmark]
        #[bench::stream(leak(benchmarks::$stream()))]
        fn $rt(s: &Stream) -> usize {
            let decode = $decode;
            let mut out = [0u8; 300];
            black_box(
                s.frames()
                    .map(|f| {
                        decode(black_box(f))
                            .and_then(|p| p.emit(&mut out))
                            .unwrap_or(0)
                    })
                    .sum(),
            )
        }
    };
}

protocol_benches!(
    k40t_stream,
    checksum: protocol_core::wire::crc16_mcrf4xx,
    deframe: |b| deframe::<_, { protocol_core::k40t::MAX_FRAME_LEN }>(protocol_core::k40t::K40tFraming::any(), b),
    decode: protocol_core::k40t::Packet::decode,
    [k40t_checksum, k40t_deframe, k40t_decode, k40t_decode_encode]
);

protocol_benches!(
    siyi_stream,
    checksum: protocol_core::wire::crc16_xmodem,
    deframe: |b| deframe::<_, { protocol_core::siyi::DEFAULT_MAX_FRAME_LEN }>(protocol_core::siyi::SiyiFraming::default(), b),
    decode: protocol_core::siyi::Packet::decode_auto,
    [siyi_checksum, siyi_deframe, siyi_decode, siyi_decode_encode]
);

protocol_benches!(
    viewlink_stream,
    checksum: protocol_core::wire::xor8,
    deframe: |b| deframe::<_, { protocol_core::viewlink::MAX_FRAME_LEN }>(protocol_core::viewlink::ViewlinkFraming::new(), b),
    decode: protocol_core::viewlink::Packet::decode,
    [viewlink_checksum, viewlink_deframe, viewlink_decode, viewlink_decode_encode]
);

protocol_benches!(
    gcu_host_stream,
    checksum: protocol_core::wire::crc16_xmodem,
    deframe: |b| deframe::<_, { protocol_core::gcu::MAX_FRAME_LEN }>(protocol_core::gcu::GcuFraming::host(), b),
    decode: protocol_core::gcu::Packet::decode,
    [gcu_host_checksum, gcu_host_deframe, gcu_host_decode, gcu_host_decode_encode]
);

protocol_benches!(
    gcu_reply_stream,
    checksum: protocol_core::wire::crc16_xmodem,
    deframe: |b| deframe::<_, { protocol_core::gcu::MAX_FRAME_LEN }>(protocol_core::gcu::GcuFraming::gcu(), b),
    decode: protocol_core::gcu::Packet::decode,
    [gcu_reply_checksum, gcu_reply_deframe, gcu_reply_decode, gcu_reply_decode_encode]
);

// K40T as a receiver runs it: deframe, then decode each frame.
#[library_benchmark]
#[bench::stream(leak(benchmarks::k40t_stream()))]
fn k40t_deframe_decode(s: &Stream) -> usize {
    use protocol_core::k40t::{K40tFraming, MAX_FRAME_LEN, Packet};
    use protocol_core::wire::{Deframer, Event};
    let mut d = Deframer::<_, MAX_FRAME_LEN>::new(K40tFraming::any());
    let mut n = 0;
    for chunk in black_box(&s.bytes[..]).chunks(CHUNK) {
        d.push(chunk, |e| {
            if let Event::Frame(f) = e {
                n += usize::from(Packet::decode(f).is_ok());
            }
        });
    }
    assert_eq!(n, s.frames.len());
    n
}

// rust-mavlink's raw-frame reader: frames with a valid CRC (CRC_EXTRA looked up per id).
#[library_benchmark]
#[bench::stream(leak(mavlink_stream()))]
fn mavlink_raw(stream: &[u8]) -> usize {
    mavlink_raw_frames(black_box(stream))
}

// rust-mavlink's full parse: frames, CRC, and the typed message.
#[library_benchmark]
#[bench::stream(leak(mavlink_stream()))]
fn mavlink_parse(stream: &[u8]) -> usize {
    mavlink_messages(black_box(stream))
}

// MAVLink 2, the bridge's message set (protocol_core::mavlink over rust-mavlink's generated
// types), and the two candidate crates' own readers and encoders on the same stream.
type MavlinkInput = (
    Stream,
    Vec<(
        protocol_core::mavlink::Header,
        protocol_core::mavlink::MavMessage,
    )>,
);

fn mavlink_set() -> &'static MavlinkInput {
    leak(benchmarks::mavlink_stream())
}

// The floor: the checksum of each frame, with its message's CRC_EXTRA looked up.
#[library_benchmark]
#[bench::stream(mavlink_set())]
fn mavlink_checksum(input: &MavlinkInput) -> u32 {
    use protocol_core::mavlink::{checksum, message_info};
    let s = &input.0;
    black_box(s.frames.iter().zip(&s.covered).fold(0u32, |acc, (f, c)| {
        let b = &s.bytes[f.clone()];
        let id = u32::from_le_bytes([b[7], b[8], b[9], 0]);
        let extra = message_info(id).map_or(0, |i| i.crc_extra);
        acc.wrapping_add(u32::from(checksum(&s.bytes[c.clone()], extra)))
    }))
}

#[library_benchmark]
#[bench::stream(mavlink_set())]
fn mavlink_deframe(input: &MavlinkInput) -> usize {
    use protocol_core::mavlink::{MAX_FRAME_LEN, MavlinkFraming};
    let n = deframe::<_, MAX_FRAME_LEN>(MavlinkFraming::new(), black_box(&input.0.bytes));
    assert_eq!(n, input.0.frames.len());
    n
}

#[library_benchmark]
#[bench::stream(mavlink_set())]
fn mavlink_decode(input: &MavlinkInput) -> usize {
    use protocol_core::mavlink::Packet;
    let n = black_box(&input.0)
        .frames()
        .filter(|f| black_box(Packet::decode(f)).is_ok())
        .count();
    assert_eq!(n, input.0.frames.len());
    n
}

#[library_benchmark]
#[bench::stream(mavlink_set())]
fn mavlink_decode_encode(input: &MavlinkInput) -> usize {
    use protocol_core::mavlink::{MAX_FRAME_LEN, Packet};
    let mut out = [0u8; MAX_FRAME_LEN];
    black_box(&input.0)
        .frames()
        .map(|f| Packet::decode(f).map_or(0, |p| p.emit(&mut out).unwrap_or(0)))
        .sum()
}

// Encoding alone: each typed message into a whole frame.
#[library_benchmark]
#[bench::stream(mavlink_set())]
fn mavlink_encode(input: &MavlinkInput) -> usize {
    use protocol_core::mavlink::{MAX_FRAME_LEN, encode};
    let mut out = [0u8; MAX_FRAME_LEN];
    black_box(&input.1)
        .iter()
        .map(|(h, m)| encode(m, h, black_box(&mut out)).unwrap_or(0))
        .sum()
}

// Encoding with signing: each typed message into a whole signed frame (SHA-256 included).
#[library_benchmark]
#[bench::stream(mavlink_set())]
fn mavlink_encode_signed(input: &MavlinkInput) -> usize {
    use protocol_core::mavlink::{MAX_FRAME_LEN, SecretKey, Signer, encode_signed};
    let key = SecretKey::new(bridge::BENCH_KEY);
    let mut out = [0u8; MAX_FRAME_LEN];
    black_box(&input.1)
        .iter()
        .enumerate()
        .map(|(i, (h, m))| {
            let signer = Signer {
                key: &key,
                link_id: 0,
                timestamp: 3_500_000_000_000 + i as u64,
            };
            encode_signed(m, h, &signer, black_box(&mut out)).unwrap_or(0)
        })
        .sum()
}

// rust-mavlink 0.21's own reader and parser (MavlinkReader::read_message) over the same
// stream and the same generated types.
#[library_benchmark]
#[bench::stream(mavlink_set())]
fn rmav_set_parse(input: &MavlinkInput) -> usize {
    let mut reader = MavlinkReader::new(Chunked(black_box(&input.0.bytes)));
    let mut n = 0;
    while let Ok(m) = reader.read_message::<protocol_core::mavlink::MavMessage>(MavlinkVersion::V2)
    {
        black_box(&m);
        n += 1;
    }
    assert_eq!(n, input.0.frames.len());
    n
}

// rust-mavlink 0.21's own frame encoder (MAVLinkV2MessageRaw::serialize_message).
#[library_benchmark]
#[bench::stream(mavlink_set())]
fn rmav_set_encode(input: &MavlinkInput) -> usize {
    let mut n = 0;
    for (h, m) in black_box(&input.1) {
        let mut raw = mavlink::MAVLinkV2MessageRaw::new();
        let header = mavlink::MavHeader {
            system_id: u32::from(h.system_id),
            component_id: h.component_id,
            sequence: h.sequence,
        };
        raw.serialize_message(header, m);
        n += black_box(raw.raw_bytes()).len();
    }
    n
}

/// mavio's receiver over a byte slice.
struct MavioSlice<'a>(&'a [u8]);

impl mavio::io::Read<mavio::error::IoError> for MavioSlice<'_> {
    fn read_exact(&mut self, buf: &mut [u8]) -> Result<(), mavio::error::IoError> {
        let Some((head, tail)) = self.0.split_at_checked(buf.len()) else {
            return Err(mavio::error::IoErrorKind::UnexpectedEof.into());
        };
        buf.copy_from_slice(head);
        self.0 = tail;
        Ok(())
    }
}

/// Every frame mavio's receiver takes from `stream`, decoded into its common dialect.
fn mavio_messages(stream: &[u8]) -> Vec<mavio::dialects::common::Common> {
    use mavio::protocol::V2;
    let mut receiver = mavio::Receiver::versioned(MavioSlice(stream), V2);
    let mut out = Vec::new();
    while let Ok(frame) = receiver.recv() {
        if let Ok(m) = frame.decode::<mavio::dialects::common::Common>() {
            out.push(m);
        }
    }
    out
}

/// The frames of `s` that mavio decodes, each given alone to a receiver of its own.
fn mavio_decodable(s: &Stream) -> usize {
    s.frames().map(|f| mavio_messages(f).len()).sum()
}

/// The bridge's set, and how many of its frames mavio decodes.
fn mavio_input() -> &'static (MavlinkInput, usize) {
    let set = benchmarks::mavlink_stream();
    let decodable = mavio_decodable(&set.0);
    leak((set, decodable))
}

// mavio 0.5's receiver and decoder (mavspec's common dialect) over the same stream. It
// decodes fewer frames than the set has: its common.xml is older (MAV_CMD and
// VIDEO_STREAM_TYPE values it does not list), and it refuses a payload longer than its
// definition (GIMBAL_DEVICE_INFORMATION with the newer gimbal_device_id extension:
// `V2PayloadIsTooLong`), where MAVLink 2 says to ignore unknown extensions. The streaming
// receiver must decode every frame that a receiver of its own decodes (counted in the
// setup): none lost beside one it refuses.
#[library_benchmark]
#[bench::stream(mavio_input())]
fn mavio_set_parse(input: &(MavlinkInput, usize)) -> usize {
    let n = black_box(mavio_messages(black_box(&input.0.0.bytes))).len();
    assert_eq!(n, input.1, "frames mavio decodes in the stream");
    n
}

/// A message of mavio's common dialect as the `&dyn Message` its frame builder takes
/// (the dialect's enum implements the message traits, not `Message` itself): each call
/// goes to the enum's own.
struct AnyCommon<'a>(&'a mavio::dialects::common::Common);

impl mavio::protocol::MessageSpec for AnyCommon<'_> {
    fn id(&self) -> mavio::protocol::MessageId {
        self.0.id()
    }

    fn min_supported_mavlink_version(&self) -> mavio::protocol::MavLinkVersion {
        self.0.min_supported_mavlink_version()
    }

    fn crc_extra(&self) -> mavio::protocol::CrcExtra {
        self.0.crc_extra()
    }
}

impl mavio::protocol::IntoPayload for AnyCommon<'_> {
    fn encode(
        &self,
        version: mavio::protocol::MavLinkVersion,
    ) -> Result<mavio::protocol::Payload, mavio::error::SpecError> {
        self.0.encode(version)
    }
}

impl mavio::Message for AnyCommon<'_> {}

// mavio 0.5's frame builder and serializer (each message of the stream, decoded by mavio
// in the setup).
#[library_benchmark]
#[bench::stream(leak(mavio_messages(&mavlink_set().0.bytes)))]
fn mavio_set_encode(messages: &Vec<mavio::dialects::common::Common>) -> usize {
    use mavio::protocol::V2;
    let mut out = [0u8; 280];
    let (mut n, mut frames) = (0, 0);
    for (i, m) in black_box(messages).iter().enumerate() {
        let Ok(builder) = mavio::Frame::builder()
            .sequence(i as u8)
            .system_id(1)
            .component_id(154)
            .version(V2)
            .message(&AnyCommon(m))
        else {
            continue;
        };
        n += builder.build().serialize(&mut out).unwrap_or(0);
        frames += 1;
    }
    assert_eq!(
        frames,
        messages.len(),
        "every message mavio decoded builds a frame"
    );
    n
}

/// A bridge run, measured: replayed, and the same frames out as in the recording.
fn replay(run: &mut BridgeRun) -> (usize, usize) {
    let out = run.run();
    assert_eq!(
        out,
        run.expected(),
        "the replay sends what the recording sent"
    );
    black_box(out)
}

/// A bridge run of the benchmarks' library, leaked.
fn bridge(run: BridgeRun) -> &'static mut BridgeRun {
    Box::leak(Box::new(run))
}

/// Declares a benchmark per bridge run: `name: constructor(args)`.
macro_rules! bridge_benches {
    ($($name:ident: $run:expr;)*) => {$(
        #[library_benchmark]
        #[bench::run(bridge($run))]
        fn $name(run: &mut BridgeRun) -> (usize, usize) {
            replay(run)
        }
    )*};
}

bridge_benches! {
    // A SIYI 0x07 rate command in (deframe, decode, translate), a K40T gimbal control out
    // (encode, queue, taken by the driver).
    bridge_siyi_rate: bridge::bridge_siyi_rates();
    // A MAVLink GIMBAL_DEVICE_SET_ATTITUDE in (deframe, check, decode, quaternion to
    // angles, translate), a K40T angle command out.
    bridge_mavlink_set_attitude: bridge::bridge_mavlink_set_attitudes(false);
    // The same on a link that requires signing: each SET_ATTITUDE signed and checked,
    // every frame the engine sends signed.
    bridge_mavlink_set_attitude_signed: bridge::bridge_mavlink_set_attitudes(true);
    // A pod attitude report absorbed (deframe, check, decode, pod state updated).
    bridge_pod_attitude: bridge::bridge_pod_attitudes();
    // The camera (component 100): a PARAM_EXT_REQUEST_READ in, its PARAM_EXT_VALUE out.
    camera_param_read: camera::settings_reads();
    // A PARAM_EXT_SET in, the K40T set command out, the pod's ACK in, PARAM_EXT_ACK out.
    camera_param_set: camera::settings_sets();
    // An FTP ReadFile of the camera definition in, 239 bytes of it out.
    camera_ftp_read: camera::definition_reads(false);
    // The same, signing required.
    camera_ftp_read_signed: camera::definition_reads(true);
    // CAMERA_TRACK_RECTANGLE in, the K40T box out, the pod's ACK in, COMMAND_ACK and
    // CAMERA_TRACKING_IMAGE_STATUS out.
    camera_track_rectangle: camera::tracking_rectangles();
    // REQUEST_MESSAGE(VIDEO_STREAM_INFORMATION) in, COMMAND_ACK and the information out.
    camera_video_information: camera::video_information_requests();
}

// One SHA-256 compression (sha2's `compress256`, software, as on the MCU), one block a
// call as the signing code calls it: the floor under MAVLink 2 signing.
#[library_benchmark]
#[bench::blocks(leak(signing::compress_input()))]
fn sha256_compress(blocks: &Vec<[u8; 64]>) -> [u32; 8] {
    // Any state: a compression's work does not depend on its values.
    let mut state = [0u32; 8];
    for block in black_box(blocks) {
        sha2::compress256(&mut state, &[(*block).into()]);
    }
    black_box(state)
}

library_benchmark_group!(
    name = codec,
    benchmarks = [
        k40t_checksum,
        k40t_deframe,
        k40t_decode,
        k40t_decode_encode,
        k40t_deframe_decode,
        siyi_checksum,
        siyi_deframe,
        siyi_decode,
        siyi_decode_encode,
        viewlink_checksum,
        viewlink_deframe,
        viewlink_decode,
        viewlink_decode_encode,
        gcu_host_checksum,
        gcu_host_deframe,
        gcu_host_decode,
        gcu_host_decode_encode,
        gcu_reply_checksum,
        gcu_reply_deframe,
        gcu_reply_decode,
        gcu_reply_decode_encode,
        mavlink_raw,
        mavlink_parse,
        mavlink_checksum,
        mavlink_deframe,
        mavlink_decode,
        mavlink_decode_encode,
        mavlink_encode,
        mavlink_encode_signed,
        rmav_set_parse,
        rmav_set_encode,
        mavio_set_parse,
        mavio_set_encode,
        bridge_siyi_rate,
        bridge_mavlink_set_attitude,
        bridge_mavlink_set_attitude_signed,
        bridge_pod_attitude,
        camera_param_read,
        camera_param_set,
        camera_ftp_read,
        camera_ftp_read_signed,
        camera_track_rectangle,
        camera_video_information,
        sha256_compress
    ]
);

/// gungraun's harness (`cargo bench`, and gungraun-runner running this binary under
/// Callgrind).
mod harness {
    use super::codec;

    gungraun::main!(library_benchmark_groups = codec);

    pub fn run() {
        main();
    }
}

/// The smoke run: every benchmark of the group once, natively, without Callgrind or
/// gungraun-runner (its setup, the measured function and their checks), each named as it
/// runs; a benchmark that panics fails the run.
fn smoke() {
    use gungraun::__internal::InternalBenchRunMode;
    let mut count = 0;
    for (group, (name, _, benches)) in codec::__BENCHES.iter().enumerate() {
        for bench in 0..benches.len() {
            println!("smoke: {name}");
            codec::__run(InternalBenchRunMode::Default, group, bench, None);
            count += 1;
        }
    }
    let set = benchmarks::mavlink_stream().0;
    println!(
        "smoke: mavio decodes {} of the set's {} frames",
        mavio_decodable(&set),
        set.frames.len()
    );
    println!("smoke: {count} benchmarks ran once");
}

/// `cargo bench` (which passes `--bench`) and gungraun-runner (`--gungraun-run`) get
/// gungraun's harness; anything else (`cargo test --benches`, `-- --smoke`) the smoke run.
fn main() {
    let measured = std::env::args()
        .skip(1)
        .any(|a| a == "--bench" || a == "--gungraun-run");
    let smoke_asked = std::env::args().skip(1).any(|a| a == "--smoke");
    if measured && !smoke_asked {
        harness::run();
    } else {
        smoke();
    }
}
