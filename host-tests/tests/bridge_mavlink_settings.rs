//! scratch
mod engine_scenarios;
use engine_scenarios::S;
use gimbal::sim::ap_mavlink::{ApMavlink, ApMavlinkConfig};
use gimbal::sim::pod::PodSimConfig;
use gimbal::sim::qgc::{Qgc, QgcConfig};

#[test]
fn scratch() {
    let mut s = engine_scenarios::scenario(
        ApMavlink::new(ApMavlinkConfig::default()),
        PodSimConfig::default(),
        25,
    );
    s.fc.gcs = Some(Qgc::new(QgcConfig::default()));
    for t in 1..12 {
        s.run_until(t * S);
        let q = s.fc.gcs.as_mut().unwrap();
        let info = q.camera.as_ref().map(|c| c.info.is_some());
        let d = q.definition();
        eprintln!(
            "t={t} info={info:?} def={:?}",
            d.map(|d| (d.ops.clone(), d.failed(), d.loaded(), d.values_received))
        );
    }
}
