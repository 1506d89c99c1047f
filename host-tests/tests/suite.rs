//! Every integration test of the suite in one test binary (`cargo test -p host-tests
//! --test suite`; one file's tests: `--test suite <file>::`). One binary links once and
//! compiles the shared scenario modules once: against a binary per file (42, each with its
//! own copy of the scenarios it used) it saves about two minutes of every CI run. The
//! codec cases keep their own binary (`--test cases`: libtest-mimic, one test per case).

// Shared by the test files below.
mod common;
mod engine_scenarios;
mod px4_capture;
mod spread;
mod task_scenarios;

mod book;
mod bridge_gcu;
mod bridge_k40t;
mod bridge_mavlink;
mod bridge_mavlink_captures;
mod bridge_mavlink_photo_order;
mod bridge_mavlink_sensors;
mod bridge_mavlink_settings;
mod bridge_mavlink_stream_info;
mod bridge_px4_time;
mod bridge_siyi;
mod bridge_telemetry;
mod bridge_version;
mod bridge_viewlink;
mod demo;
mod first_sync;
mod fuzz_replay;
mod gcu_props;
mod gimbal_report;
mod k40t_props;
mod long_run;
mod markdown_links;
mod mavlink;
mod mavlink_unknown_ids;
mod pps_figures;
mod security;
mod sim_pod;
mod siyi_props;
mod tasks_faults;
mod tasks_gcu;
mod tasks_k40t;
mod tasks_mavlink;
mod tasks_px4_modes;
mod tasks_siyi;
mod tasks_telemetry;
mod tasks_viewlink;
mod timesync_sim;
mod utc_figures;
mod viewlink_props;
mod viewlink_vectors;
mod wraps;
