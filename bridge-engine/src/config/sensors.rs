//! What the bridge is told of the pod's sensors: the lens facts the K40T does not report
//! ([`LensConfig`]), the video stream's address ([`VideoConfig`]) and the laser
//! rangefinder ([`LaserConfig`]). See docs/src/firmware/configuration.md (the keys) and
//! docs/src/bridge/mavlink.md (what the MAVLink side makes of them).
//!
//! The K40T's vendor publishes no lens facts (focal lengths, sensor size, fields of view)
//! and no laser range that we could find: every such key defaults to 0, "unknown", which
//! the MAVLink side sends as the MAVLink spec's invalid value (NaN, 0). The one fact the
//! K40T external protocol gives is the visible photo resolution, 4000 × 3000 (3.2.4.3).

#[cfg(feature = "serde")]
use super::de;

protocol_core::wire_derive! {
    custom_serde [Eq]
    /// The cameras' lens facts (`[lens]`). 0 is unknown everywhere.
    #[cfg_attr(
        feature = "serde",
        derive(serde::Deserialize),
        serde(default, deny_unknown_fields)
    )]
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine::config))]
    pub struct LensConfig {
        /// The visible camera's horizontal field of view at 1x hybrid zoom, 0.01°. The
        /// field of view at zoom z is 2·atan(tan(hfov/2)/z).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub visible_hfov_1x_cdeg: u32,
        /// The thermal camera's horizontal field of view without digital zoom, 0.01°
        /// (divided by the pod's IR digital zoom, 0x000105).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub ir_hfov_cdeg: u32,
        /// The visible camera's shortest focal length (1x), µm: CAMERA_INFORMATION's
        /// `focal_length`, and the start of the optical zoom.
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub focal_length_min_um: u32,
        /// Its longest optical focal length, µm (beyond it the hybrid zoom is digital).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub focal_length_max_um: u32,
        /// The visible sensor's width, µm: with the focal length the pod reports
        /// (0x000005), the field of view exactly.
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub sensor_width_um: u32,
        /// The visible sensor's height, µm.
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub sensor_height_um: u32,
        /// The visible camera's image width, pixels (default 4000: K40T external
        /// protocol, 3.2.4.3, "visible light photography (resolution: 4000*3000)").
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub resolution_h: u32,
        /// Its image height, pixels (default 3000).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub resolution_v: u32,
    }
}

impl LensConfig {
    /// Every fact unknown but the documented photo resolution.
    pub const DEFAULT: Self = Self {
        visible_hfov_1x_cdeg: 0,
        ir_hfov_cdeg: 0,
        focal_length_min_um: 0,
        focal_length_max_um: 0,
        sensor_width_um: 0,
        sensor_height_um: 0,
        resolution_h: 4000,
        resolution_v: 3000,
    };
}

impl Default for LensConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Bytes of [`VideoConfig::uri`] (MAVLink's VIDEO_STREAM_INFORMATION `uri`, `char[160]`).
pub const URI_LEN: usize = 160;

protocol_core::wire_derive! {
    custom_serde [Eq]
    /// The pod's video stream (`[video]`).
    #[cfg_attr(
        feature = "serde",
        derive(serde::Deserialize),
        serde(default, deny_unknown_fields)
    )]
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine::config))]
    pub struct VideoConfig {
        /// The stream's address, padded with zeros; empty (all zeros, the default): built
        /// from the address the pod reports to 0x000312 as `rtsp://IP:558/live/single`
        /// (K40T external protocol, 2.3.2). Up to 160 printable ASCII characters.
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::uri"))]
        pub uri: [u8; URI_LEN],
    }
}

impl VideoConfig {
    /// No address configured: the pod's.
    pub const DEFAULT: Self = Self { uri: [0; URI_LEN] };

    /// The configured address, when one is.
    #[must_use]
    pub fn configured_uri(&self) -> Option<&[u8]> {
        let len = self.uri.iter().position(|&b| b == 0).unwrap_or(URI_LEN);
        self.uri.get(..len).filter(|u| !u.is_empty())
    }

    /// The address from its text (`video.uri`): 0 to 160 printable ASCII characters,
    /// padded with zeros.
    ///
    /// # Errors
    /// Any other text ([`Problem::Text`](super::Problem::Text)).
    pub fn parse_uri(text: &str) -> Result<[u8; URI_LEN], super::ConfigError> {
        let mut uri = [0u8; URI_LEN];
        let bad = super::ConfigError {
            key: "video.uri",
            problem: super::Problem::Text(super::TextRule::Uri),
        };
        if text.len() > URI_LEN || !text.bytes().all(|b| b.is_ascii_graphic()) {
            return Err(bad);
        }
        for (slot, b) in uri.iter_mut().zip(text.bytes()) {
            *slot = b;
        }
        Ok(uri)
    }

    /// The address is empty or printable ASCII then zeros.
    pub(super) fn is_valid(&self) -> bool {
        let len = self.uri.iter().position(|&b| b == 0).unwrap_or(URI_LEN);
        self.uri.iter().take(len).all(u8::is_ascii_graphic)
            && self.uri.iter().skip(len).all(|&b| b == 0)
    }
}

impl Default for VideoConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

protocol_core::wire_derive! {
    custom_serde [Eq]
    /// The laser rangefinder (`[laser]`).
    #[cfg_attr(
        feature = "serde",
        derive(serde::Deserialize),
        serde(default, deny_unknown_fields)
    )]
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine::config))]
    pub struct LaserConfig {
        /// Switch the pod's periodic (1 s) ranging on (0x000406) at every link-up, so that
        /// distances and look-at points come without being asked (default false: the
        /// laser ranges when an FC asks, e.g. MAVLink's SET_MESSAGE_INTERVAL for
        /// DISTANCE_SENSOR).
        pub periodic: bool,
        /// The shortest distance it measures, cm (DISTANCE_SENSOR `min_distance`;
        /// default 0: unknown).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub min_distance_cm: u32,
        /// The longest, cm (default 65535, what DISTANCE_SENSOR can carry: unknown).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub max_distance_cm: u32,
    }
}

impl LaserConfig {
    /// Ranging on request; range unknown.
    pub const DEFAULT: Self = Self {
        periodic: false,
        min_distance_cm: 0,
        max_distance_cm: 65_535,
    };
}

impl Default for LaserConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}
