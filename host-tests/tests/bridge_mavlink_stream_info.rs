//! What a client that never asks for the stream gets (MAVSDK 4.1: it reads the camera's
//! CAMERA_INFORMATION and builds its stream information from what comes, never asking
//! for VIDEO_STREAM_INFORMATION), and the focal length the pod reports
//! (docs/src/bridge/mavlink.md, "Video stream"): the engine between the simulated
//! ArduPilot, a ground station on its routing that does not ask, and the simulated pod.

use crate::engine_scenarios;

use bridge_engine::{Config, FcProtocol};
use gimbal::sim::ap_mavlink::{ApMavlink, ApMavlinkConfig};
use gimbal::sim::camera_settings::ClientStyle;
use gimbal::sim::pod::PodSimConfig;
use gimbal::sim::qgc::{Qgc, QgcConfig};
use gimbal::sim::scenario::Scenario;

use engine_scenarios::S;

/// ArduPilot with a MAVSDK-like ground station (never asks for the stream).
fn scenario(config: Config, pod: PodSimConfig) -> Scenario<ApMavlink> {
    let mut s = engine_scenarios::scenario_with(
        config,
        ApMavlink::new(ApMavlinkConfig::default()),
        pod,
        25,
    );
    s.fc.gcs = Some(Qgc::new(QgcConfig {
        client: ClientStyle::Mavsdk,
        asks_for_streams: false,
        ..QgcConfig::default()
    }));
    s
}

fn gcs(s: &Scenario<ApMavlink>) -> &Qgc {
    s.fc.gcs.as_ref().expect("a ground station")
}

/// The stream's address the ground station holds.
fn uri(s: &Scenario<ApMavlink>) -> Option<String> {
    let st = gcs(s).streams.get(&1)?;
    let n = st.uri.iter().position(|&b| b == 0).unwrap_or(st.uri.len());
    Some(String::from_utf8_lossy(&st.uri[..n]).into_owned())
}

/// VIDEO_STREAM_INFORMATION messages the ground station got.
fn informations(s: &Scenario<ApMavlink>) -> usize {
    gcs(s)
        .received
        .iter()
        .filter(|(_, _, id)| *id == 269)
        .count()
}

#[test]
fn a_client_that_never_asks_gets_the_stream_address_and_its_changes() {
    let mut s = scenario(Config::for_fc(FcProtocol::Mavlink), PodSimConfig::default());
    s.run_until(10 * S);
    assert_eq!(
        uri(&s).as_deref(),
        Some("rtsp://192.168.144.64:558/live/single")
    );
    // It followed CAMERA_INFORMATION (and the address when it became known).
    assert!(informations(&s) >= 1);
    // The pod comes back from a reboot on another address: told unasked, once.
    let before = informations(&s);
    s.pod.set_ip([[10, 1, 2, 3], [255, 0, 0, 0], [10, 0, 0, 1]]);
    let now = s.now_us;
    s.pod.reboot(now, 3 * S);
    s.run_for(8 * S);
    assert_eq!(uri(&s).as_deref(), Some("rtsp://10.1.2.3:558/live/single"));
    assert_eq!(informations(&s), before + 1, "one unasked, on the change");
    // Nothing changes: nothing more unasked.
    s.run_for(20 * S);
    assert_eq!(informations(&s), before + 1);
}

/// The focal length of the CAMERA_INFORMATION the ground station got, 10 s after the
/// start with the bridge configured as `config`.
fn focal_length_mm(config: Config) -> f32 {
    let mut s = scenario(config, PodSimConfig::default());
    s.run_until(10 * S);
    gcs(&s)
        .camera
        .as_ref()
        .and_then(|c| c.info.clone())
        .expect("camera information")
        .focal_length
}

#[test]
fn camera_information_carries_the_focal_length_the_pod_reports() {
    // The simulated pod reports 4.50 mm at 1x in its 0x000005 (0.01 mm); the bridge's
    // lens configuration has no focal length.
    let f = focal_length_mm(Config::for_fc(FcProtocol::Mavlink));
    assert!((f - 4.5).abs() < 1e-6, "{f}");
    // A configured focal length wins over the pod's.
    let mut config = Config::for_fc(FcProtocol::Mavlink);
    config.lens.focal_length_min_um = 6_300;
    let f = focal_length_mm(config);
    assert!((f - 6.3).abs() < 1e-6, "{f}");
}
